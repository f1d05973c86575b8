/*
 * The vectorised kernels of lib/src/stereo/stereo_simd.h against their
 * plain C references, bit for bit: random and disparity-like data, every
 * width from the smallest to past several vector blocks (odd ones
 * included), padded strides, holes, and values at the int16 extremes.
 * On a target without SIMD (or -Dsimd=false) the dispatching functions
 * are the references and the 8-lane test is skipped.
 */
#include <stdlib.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs/fixed.h"
#include "stereo/stereo_int.h"
#include "stereo/stereo_simd.h"

#define MAXW 80
#define PAD 7

/* ---- window statistics ----------------------------------------------- */

/* rows[k] of width w with nothing readable after them but PAD guard bytes
 * (ASan builds see any read past the end). */
static void check_stats(uint32_t seed, int32_t w, int smooth)
{
    uint8_t *buf[5];
    const uint8_t *rows[5];
    uint16_t so_ref[MAXW];
    uint16_t so[MAXW];
    uint32_t vo_ref[MAXW];
    uint32_t vo[MAXW];
    int32_t k;
    int32_t x;
    for (k = 0; k < 5; k++) {
        buf[k] = malloc((size_t)w);
        assert_non_null(buf[k]);
        for (x = 0; x < w; x++) {
            uint32_t r = test_lcg_next(&seed);
            /* smooth: a ramp with +-3 noise, as a textured surface */
            buf[k][x] = smooth
                            ? (uint8_t)((x * 3 + k * 5 + (int32_t)(r % 7u)) &
                                        0xFF)
                            : (uint8_t)r;
        }
        rows[k] = buf[k];
    }
    /* saturated rows in some cases: the extreme sums */
    if (seed % 5u == 0u) {
        memset(buf[2], 255, (size_t)w);
    }
    memset(so_ref, 0xA5, sizeof so_ref);
    memset(so, 0xA5, sizeof so);
    memset(vo_ref, 0xA5, sizeof vo_ref);
    memset(vo, 0xA5, sizeof vo);
    stx_stats_row_ref(rows, w, so_ref, vo_ref);
    stx_stats_row(rows, w, so, vo);
    /* the same entries written, the others untouched */
    assert_memory_equal(so, so_ref, sizeof so);
    assert_memory_equal(vo, vo_ref, sizeof vo);
    for (k = 0; k < 5; k++) {
        free(buf[k]);
    }
}

static void test_stats_row_matches_reference(void **state)
{
    int32_t w;
    uint32_t rep;
    (void)state;
    for (w = 5; w <= MAXW; w++) {
        for (rep = 0; rep < 6; rep++) {
            check_stats(1000u * (uint32_t)w + rep, w, (int)(rep & 1u));
        }
    }
}

/* stx_stats_rows on a strided image against the definition (the window
 * of 25 pixels summed directly), border rows zero. */
static void test_stats_rows_strided(void **state)
{
    enum { IW = 37, IH = 11, IS = 37 + PAD };
    static uint8_t px[IH * IS];
    static uint16_t s[IH * IW];
    static uint32_t v[IH * IW];
    negobs_image_u8_t im;
    uint32_t seed = 99u;
    int32_t x;
    int32_t y;
    (void)state;
    for (x = 0; x < IH * IS; x++) {
        px[x] = (uint8_t)test_lcg_next(&seed);
    }
    im.data = px;
    im.width = IW;
    im.height = IH;
    im.stride = IS;
    stx_stats_rows(&im, 0, IH, s, v);
    for (y = 0; y < IH; y++) {
        for (x = 0; x < IW; x++) {
            uint32_t ws = 0;
            uint32_t wq = 0;
            int32_t i;
            int32_t j;
            if (y >= 2 && y < IH - 2 && x >= 2 && x < IW - 2) {
                for (i = -2; i <= 2; i++) {
                    for (j = -2; j <= 2; j++) {
                        uint32_t p = px[(y + i) * IS + x + j];
                        ws += p;
                        wq += p * p;
                    }
                }
            }
            assert_int_equal(s[y * IW + x], ws);
            assert_int_equal(v[y * IW + x], 25u * wq - ws * ws);
        }
    }
}

/* ---- 1/4-scale zero-mean SAD runs -------------------------------------- */

/* A run of n windows in an image of 3 rows exactly n + 2 columns wide
 * (one heap block: a read past the last window's right column or below
 * its bottom row leaves it), the fixed window in a second image. */
static void check_zsad_run(uint32_t seed, int32_t n, int flat)
{
    int32_t stride = n + 2;
    uint8_t *img = malloc((size_t)(3 * stride));
    uint8_t fixed[9];
    int32_t want[64];
    int32_t got[64];
    int32_t i;
    assert_non_null(img);
    for (i = 0; i < 3 * stride; i++) {
        img[i] = flat ? (uint8_t)(200 + (test_lcg_next(&seed) % 3u))
                      : (uint8_t)test_lcg_next(&seed);
    }
    for (i = 0; i < 9; i++) {
        /* the extremes too: 0 and 255 give the largest terms */
        fixed[i] = (seed % 7u == 0u) ? (uint8_t)((i & 1) ? 255 : 0)
                                     : (uint8_t)test_lcg_next(&seed);
    }
    memset(want, 0x5A, sizeof want);
    memset(got, 0x5A, sizeof got);
    /* the fixed window uses the run image's stride */
    {
        uint8_t *fx = malloc((size_t)(3 * stride));
        assert_non_null(fx);
        memset(fx, 0, (size_t)(3 * stride));
        for (i = 0; i < 9; i++) {
            fx[(i / 3) * stride + (i % 3)] = fixed[i];
        }
        stx_zsad3_run_ref(fx + stride + 1, img + stride + 1, stride, n, want);
        stx_zsad3_run(fx + stride + 1, img + stride + 1, stride, n, got);
        free(fx);
    }
    assert_memory_equal(got, want, sizeof want);
    free(img);
}

static void test_zsad3_run_matches_reference(void **state)
{
    int32_t n;
    uint32_t rep;
    (void)state;
    for (n = 1; n <= 64; n++) {
        for (rep = 0; rep < 8; rep++) {
            check_zsad_run(77u * (uint32_t)n + rep, n, rep == 3u);
        }
    }
}

/* ---- adaptive mean --------------------------------------------------- */

static int16_t disp_value(uint32_t *seed, int32_t base, int holes)
{
    uint32_t r = test_lcg_next(seed);
    if (holes && r % 5u == 0u) {
        return NEGOBS_DISP_INVALID;
    }
    switch ((r >> 3) % 8u) {
    case 0: return INT16_MAX;
    case 1: return (int16_t)(INT16_MIN + 1);
    case 2: return (int16_t)((int32_t)(r >> 8) % 65535 - 32767);
    default:
        /* near the centre: weights between 0 and 64 */
        return (int16_t)(base + (int32_t)((r >> 6) % 161u) - 80);
    }
}

static void test_amean8_matches_reference(void **state)
{
#if defined(NEGOBS_SIMD)
    int16_t val[9][8];
    const int16_t *tap[9];
    int16_t want[8];
    int16_t got[8];
    uint32_t seed = 5u;
    int32_t rep;
    int32_t kl;
    int32_t kr;
    int32_t j;
    int32_t l;
    (void)state;
    for (j = 0; j < 9; j++) {
        tap[j] = val[j];
    }
    for (rep = 0; rep < 4000; rep++) {
        int32_t base = (int32_t)(test_lcg_next(&seed) % 2048u) - 512;
        for (j = 0; j < 9; j++) {
            for (l = 0; l < 8; l++) {
                val[j][l] = disp_value(&seed, base, rep % 3 != 0);
            }
        }
        for (kl = 0; kl <= 4; kl++) {
            for (kr = 0; kr <= 4; kr++) {
                stx_amean8_ref(tap, kl, kr, want);
                stx_amean8_simd(tap, kl, kr, got);
                assert_memory_equal(got, want, sizeof want);
            }
        }
    }
#else
    (void)state;
    skip();
#endif
}

/* The reference of one line, one sample at a time through stx_amean8_ref
 * (lane 0; the other lanes are copies). */
static void ref_line(const int16_t *in, int16_t *out, int32_t n)
{
    int32_t i;
    for (i = 0; i < n; i++) {
        int16_t val[9][8];
        const int16_t *tap[9];
        int16_t o[8];
        int32_t kl = (i < 4) ? i : 4;
        int32_t kr = (n - 1 - i < 4) ? n - 1 - i : 4;
        int32_t j;
        for (j = 0; j < 9; j++) {
            int32_t l;
            for (l = 0; l < 8; l++) {
                val[j][l] = (j >= 4 - kl && j <= 4 + kr) ? in[i + j - 4] : 0;
            }
            tap[j] = val[j];
        }
        stx_amean8_ref(tap, kl, kr, o);
        out[i] = o[0];
    }
}

/* stx_adaptive_mean (horizontal then vertical pass, SIMD blocks, ring,
 * overlapping last blocks, scalar tails) against the per-sample
 * reference on a strided map with holes, for sizes around the blocks. */
static void check_adaptive_mean(int32_t w, int32_t h, uint32_t seed)
{
    enum { MW = 45, MH = 40 };
    static int16_t map[MH * (MW + PAD)];
    static int16_t want[MH * (MW + PAD)];
    static uint8_t conf[MH * MW];
    static uint8_t conf_want[MH * MW];
    static int16_t line[MH + 16];
    static int16_t line2[MH + 16];
    static int16_t tmp[MH];
    static int16_t tmp2[MH];
    int32_t stride = w + PAD;
    negobs_image_s16_t d;
    stx_t s;
    int32_t x;
    int32_t y;
    int32_t base = (int32_t)(seed % 700u);

    for (y = 0; y < h; y++) {
        for (x = 0; x < stride; x++) {
            /* a slanted surface with noise and holes */
            int16_t v = disp_value(&seed, base + 3 * y, 1);
            if ((seed >> 9) % 4u != 0u && v != NEGOBS_DISP_INVALID) {
                v = (int16_t)(base + 3 * y + x + (int32_t)(seed % 9u));
            }
            map[y * stride + x] = v;
        }
    }
    memcpy(want, map, sizeof map);
    memset(conf, 7, sizeof conf);
    memset(conf_want, 7, sizeof conf_want);
    for (y = 0; y < h; y++) {
        ref_line(map + y * stride, want + y * stride, w);
        for (x = 0; x < w; x++) {
            if (map[y * stride + x] == NEGOBS_DISP_INVALID &&
                want[y * stride + x] != NEGOBS_DISP_INVALID) {
                conf_want[y * w + x] = NEGOBS_STEREO_CONF_FILLED;
            }
        }
    }
    for (x = 0; x < w; x++) {
        for (y = 0; y < h; y++) {
            tmp[y] = want[y * stride + x];
        }
        ref_line(tmp, tmp2, h);
        for (y = 0; y < h; y++) {
            want[y * stride + x] = tmp2[y];
            if (tmp[y] == NEGOBS_DISP_INVALID &&
                tmp2[y] != NEGOBS_DISP_INVALID) {
                conf_want[y * w + x] = NEGOBS_STEREO_CONF_FILLED;
            }
        }
    }
    memset(&s, 0, sizeof s);
    s.w = w;
    s.h = h;
    s.line = line;
    s.line2 = line2;
    d.data = map;
    d.width = w;
    d.height = h;
    d.stride = stride;
    stx_adaptive_mean(&s, &d, conf, w);
    assert_memory_equal(map, want, sizeof map);
    assert_memory_equal(conf, conf_want, sizeof conf);
}

static void test_adaptive_mean_matches_reference(void **state)
{
    static const int32_t ws[] = {1, 3, 8, 9, 12, 15, 16, 17, 23, 31, 45};
    static const int32_t hs[] = {1, 2, 5, 9, 13, 40};
    size_t i;
    size_t j;
    (void)state;
    for (i = 0; i < sizeof ws / sizeof ws[0]; i++) {
        for (j = 0; j < sizeof hs / sizeof hs[0]; j++) {
            check_adaptive_mean(ws[i], hs[j], (uint32_t)(i * 31u + j + 1u));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stats_row_matches_reference),
        cmocka_unit_test(test_stats_rows_strided),
        cmocka_unit_test(test_zsad3_run_matches_reference),
        cmocka_unit_test(test_amean8_matches_reference),
        cmocka_unit_test(test_adaptive_mean_matches_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
