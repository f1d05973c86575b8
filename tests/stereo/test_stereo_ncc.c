/* Integer MNCC and window statistics against direct references. */
#include <string.h>

#include "cmocka_all.h"
#include "stereo/stereo_int.h"

#define W 40
#define H 30
#define STRIDE 44

static uint8_t a[H * STRIDE];
static uint8_t b[H * STRIDE];
static uint16_t s_sum[H * W];
static uint32_t s_var[H * W];

static negobs_image_u8_t img(uint8_t *p)
{
    negobs_image_u8_t i;
    i.data = p;
    i.width = W;
    i.height = H;
    i.stride = STRIDE;
    return i;
}

static void fill_noise(uint8_t *p, uint32_t seed)
{
    int32_t i;
    for (i = 0; i < H * STRIDE; i++) {
        p[i] = (uint8_t)test_lcg_next(&seed);
    }
}

/* Reference: sums straight from the definition, int64. */
static void ref_sums(const uint8_t *p, int32_t x, int32_t y, int64_t *s,
                     int64_t *q)
{
    int32_t i;
    int32_t j;
    *s = 0;
    *q = 0;
    for (i = -2; i <= 2; i++) {
        for (j = -2; j <= 2; j++) {
            int64_t v = p[(y + i) * STRIDE + x + j];
            *s += v;
            *q += v * v;
        }
    }
}

static int64_t ref_cross(const uint8_t *p, int32_t x, int32_t y,
                         const uint8_t *r, int32_t xr, int32_t yr)
{
    int64_t acc = 0;
    int32_t i;
    int32_t j;
    for (i = -2; i <= 2; i++) {
        for (j = -2; j <= 2; j++) {
            acc += (int64_t)p[(y + i) * STRIDE + x + j] *
                   r[(yr + i) * STRIDE + xr + j];
        }
    }
    return acc;
}

static void test_stats_rows_match_direct_sums(void **state)
{
    negobs_image_u8_t i = img(a);
    int32_t x;
    int32_t y;
    (void)state;
    fill_noise(a, 11u);
    stx_stats_rows(&i, 0, H, s_sum, s_var);
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            int64_t s;
            int64_t q;
            if (x < 2 || y < 2 || x >= W - 2 || y >= H - 2) {
                assert_int_equal(s_var[y * W + x], 0);
                continue;
            }
            ref_sums(a, x, y, &s, &q);
            assert_int_equal(s_sum[y * W + x], s);
            assert_int_equal(s_var[y * W + x], 25 * q - s * s);
        }
    }
}

static void test_mncc_matches_reference_within_one_lsb(void **state)
{
    stx_t s;
    negobs_image_u8_t li = img(a);
    negobs_image_u8_t ri = img(b);
    int32_t x;
    int32_t y;
    int32_t d;
    (void)state;
    fill_noise(a, 5u);
    fill_noise(b, 6u);
    /* make b partly a copy of a (shift 3) so high scores occur too */
    for (y = 0; y < H; y++) {
        for (x = 0; x + 3 < W; x++) {
            if (y < H / 2) {
                b[y * STRIDE + x] = a[y * STRIDE + x + 3];
            }
        }
    }
    memset(&s, 0, sizeof s);
    s.left = &li;
    s.right = &ri;
    s.w = W;
    s.h = H;
    s.cfg.texture_min = 1;
    for (y = 2; y < H - 2; y++) {
        for (x = 2; x < W - 2; x++) {
            for (d = 0; d <= 6 && x - d >= 2; d++) {
                int64_t sl;
                int64_t ql;
                int64_t sr;
                int64_t qr;
                int64_t num;
                int64_t den;
                int64_t ref;
                int32_t c = stx_mncc_direct(&s, x, y, d, 0);
                ref_sums(a, x, y, &sl, &ql);
                ref_sums(b, x - d, y, &sr, &qr);
                num = 25 * ref_cross(a, x, y, b, x - d, y) - sl * sr;
                den = (25 * ql - sl * sl) + (25 * qr - sr * sr);
                ref = (2 * num * 16384) / den; /* truncation toward 0 */
                assert_true(c >= -16384 && c <= 16384);
                assert_true(c - ref <= 1 && ref - c <= 1);
                if (y + 2 < H / 2 && d == 3) {
                    assert_int_equal(c, 16384); /* identical windows */
                }
            }
        }
    }
}

static void test_mncc_flat_and_inverted_windows(void **state)
{
    stx_t s;
    negobs_image_u8_t li = img(a);
    negobs_image_u8_t ri = img(b);
    int32_t i;
    (void)state;
    fill_noise(a, 9u);
    for (i = 0; i < H * STRIDE; i++) {
        b[i] = (uint8_t)(255u - a[i]);
    }
    memset(&s, 0, sizeof s);
    s.left = &li;
    s.right = &ri;
    s.w = W;
    s.h = H;
    s.cfg.texture_min = 2500;
    assert_int_equal(stx_mncc_direct(&s, 10, 10, 0, 0), -16384);
    memset(b, 77, sizeof b);
    /* one flat window still has the other's variance: score 0, not flat */
    assert_int_equal(stx_mncc_direct(&s, 10, 10, 0, 0), STX_FLAT);
    memset(a, 77, sizeof a);
    assert_int_equal(stx_mncc_direct(&s, 10, 10, 0, 0), STX_FLAT);
    /* out of the image: flat, never a read outside */
    fill_noise(a, 1u);
    fill_noise(b, 2u);
    assert_int_equal(stx_mncc_direct(&s, 1, 10, 0, 0), STX_FLAT);
    assert_int_equal(stx_mncc_direct(&s, 10, 10, 9, 0), STX_FLAT);
    assert_int_equal(stx_mncc_direct(&s, 10, H - 3, 0, 1), STX_FLAT);
    assert_true(stx_mncc_direct(&s, 10, H - 4, 0, 1) != STX_FLAT);
}

static void test_frac_q14_saturates_and_rounds_toward_zero(void **state)
{
    (void)state;
    assert_int_equal(stx_frac_q14(10, 20), 8192);
    assert_int_equal(stx_frac_q14(-10, 20), -8192);
    assert_int_equal(stx_frac_q14(1, 3), 5461);
    assert_int_equal(stx_frac_q14(-1, 3), -5461);
    assert_int_equal(stx_frac_q14(20000000, 20000000), 16384);
    assert_int_equal(stx_frac_q14(-20000000, 20000000), -16384);
}

/* stx_frac_q14 by its definition: shift both by one bit at a time. */
static int32_t frac_q14_loop(int32_t num2, int32_t den)
{
    uint32_t na = (uint32_t)((num2 < 0) ? -num2 : num2);
    uint32_t nd = (uint32_t)den;
    uint32_t q;
    while (nd >= (1u << 17)) {
        nd >>= 1;
        na >>= 1;
    }
    if (na > nd) {
        na = nd;
    }
    q = (na << 14) / nd;
    return (num2 < 0) ? -(int32_t)q : (int32_t)q;
}

static void check_frac(int32_t num2, int32_t den)
{
    static const int32_t taus[] = {-16384, -1,   0,     1,     8191,
                                   8192,   8193, 13107, 16383, 16384};
    int32_t want = frac_q14_loop(num2, den);
    size_t i;
    assert_int_equal(stx_frac_q14(num2, den), want);
    for (i = 0; i < sizeof taus / sizeof taus[0]; i++) {
        assert_int_equal(stx_frac_reaches(num2, den, taus[i]),
                         want >= taus[i]);
    }
    /* the exact threshold of this fraction, from both sides */
    assert_int_equal(stx_frac_reaches(num2, den, want), 1);
    if (want < 16384) {
        assert_int_equal(stx_frac_reaches(num2, den, want + 1), 0);
    }
}

/* The stepped scaling and the division-free threshold test of the growth
 * loop give exactly the loop's quotient and its comparisons, for every
 * denominator bit length (den up to 2^31 - 1, beyond MNCC's 2^25) and at
 * the rounding boundaries. */
static void test_frac_scale_and_threshold_match_definition(void **state)
{
    uint32_t seed = 7u;
    int32_t bits;
    int32_t i;
    (void)state;
    for (bits = 1; bits <= 31; bits++) {
        int32_t lo = (bits == 1) ? 1 : (int32_t)(1u << (bits - 1));
        int32_t hi = (int32_t)((bits == 31) ? 0x7FFFFFFFu : (1u << bits) - 1u);
        check_frac(0, lo);
        check_frac(lo, lo);
        check_frac(-hi, hi);
        check_frac(hi / 2, hi);
        check_frac(hi / 2 + 1, hi);
        check_frac(lo / 3, hi);
        for (i = 0; i < 200; i++) {
            uint32_t r = test_lcg_next(&seed) | (test_lcg_next(&seed) << 16);
            int32_t den = lo + (int32_t)(r % (uint32_t)(hi - lo + 1));
            int32_t num2 = (int32_t)(test_lcg_next(&seed) |
                                     (test_lcg_next(&seed) << 16)) %
                           den;
            check_frac(num2, den);
        }
    }
}

/* The dispatching stx_cross5 (SIMD where the target has it) against the
 * plain C reference and the definition, at every window position of a
 * tight image (stride == width, buffer ends with the last row) so a load
 * past the window edge shows under the sanitizer / valgrind. */
static uint8_t ta[H * W];
static uint8_t tb[H * W];

static void check_cross5_all_positions(void)
{
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    int32_t y;
    int32_t u;
    int32_t ur;
    l.data = ta;
    l.width = W;
    l.height = H;
    l.stride = W;
    r = l;
    r.data = tb;
    for (y = STX_WIN_R; y < H - STX_WIN_R; y++) {
        for (u = STX_WIN_R; u < W - STX_WIN_R; u++) {
            for (ur = STX_WIN_R; ur <= u; ur++) {
                int32_t yr = (y + 1 < H - STX_WIN_R) ? y + 1 : y;
                uint32_t want = 0;
                int32_t i;
                int32_t j;
                for (i = -STX_WIN_R; i <= STX_WIN_R; i++) {
                    for (j = -STX_WIN_R; j <= STX_WIN_R; j++) {
                        want += (uint32_t)ta[(y + i) * W + u + j] *
                                tb[(yr + i) * W + ur + j];
                    }
                }
                assert_int_equal(stx_cross5(&l, u, y, &r, ur, yr), want);
                assert_int_equal(stx_cross5_ref(ta + (y - 2) * W + u - 2, W,
                                                tb + (yr - 2) * W + ur - 2, W),
                                 want);
            }
        }
    }
}

/* The three-disparity form against three reference sums, at every
 * position whose 8-byte loads stay in the tight image (right: b + 7 <= W
 * - 1; left: the window's column + 5 < W). */
static void check_cross5x3_all_positions(void)
{
    int32_t y;
    int32_t u;
    int32_t bx;
    for (y = STX_WIN_R; y < H - STX_WIN_R; y++) {
        for (u = STX_WIN_R; u + 5 < W; u++) {
            const uint8_t *pa = ta + (y - 2) * W + u - 2;
            for (bx = 0; bx + 7 < W; bx++) {
                uint32_t want[3];
                const uint8_t *pb = tb + (y - 2) * W + bx;
                stx_cross5x3_ref(pa, W, pb, W, want);
                assert_int_equal(want[0], stx_cross5_ref(pa, W, pb, W));
                assert_int_equal(want[2], stx_cross5_ref(pa, W, pb + 2, W));
#if defined(STX_CROSS5X3_SIMD)
                {
                    uint32_t got[3];
                    stx_cross5x3_simd(pa, W, pb, W, got);
                    assert_int_equal(got[0], want[0]);
                    assert_int_equal(got[1], want[1]);
                    assert_int_equal(got[2], want[2]);
                }
#endif
            }
        }
    }
}

static void test_cross5_variants_are_bit_exact(void **state)
{
    uint32_t seed = 99u;
    int32_t i;
    (void)state;
    for (i = 0; i < H * W; i++) {
        ta[i] = (uint8_t)test_lcg_next(&seed);
        tb[i] = (uint8_t)test_lcg_next(&seed);
    }
    check_cross5_all_positions();
    check_cross5x3_all_positions();
    /* largest products: every lane at 255 (sum 1 625 625) */
    memset(ta, 255, sizeof ta);
    memset(tb, 255, sizeof tb);
    check_cross5_all_positions();
    check_cross5x3_all_positions();
    assert_int_equal(stx_cross5_ref(ta, W, tb, W), 25u * 255u * 255u);
    /* bytes beyond the 5 columns must not leak into the sum */
    for (i = 0; i < H * W; i++) {
        ta[i] = (uint8_t)(((i % W) % 8 < 5) ? 1 : 200);
        tb[i] = (uint8_t)(255 - (i % 7));
    }
    check_cross5_all_positions();
    check_cross5x3_all_positions();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stats_rows_match_direct_sums),
        cmocka_unit_test(test_mncc_matches_reference_within_one_lsb),
        cmocka_unit_test(test_mncc_flat_and_inverted_windows),
        cmocka_unit_test(test_frac_q14_saturates_and_rounds_toward_zero),
        cmocka_unit_test(test_frac_scale_and_threshold_match_definition),
        cmocka_unit_test(test_cross5_variants_are_bit_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
