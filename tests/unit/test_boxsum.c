#include <string.h>

#include "cmocka_all.h"
#include "negobs/boxsum.h"
#include "integral.h"

#define W 53
#define H 41
#define STRIDE 60

static uint8_t pix[H * STRIDE];
static uint16_t sum[H * W];
static uint32_t sumsq[H * W];
static uint32_t colbuf[2 * W];
static uint32_t ii[(W + 1) * (H + 1)];
static uint32_t iiq[(W + 1) * (H + 1)];

static negobs_image_u8_t fill(uint32_t seed, int saturated)
{
    negobs_image_u8_t img;
    int32_t i;
    for (i = 0; i < H * STRIDE; i++) {
        pix[i] = saturated ? 255u : (uint8_t)(test_lcg_next(&seed) & 0xffu);
    }
    img.data = pix;
    img.width = W;
    img.height = H;
    img.stride = STRIDE;
    return img;
}

/* Direct double loop: the reference the fast paths must equal. */
static void direct(const negobs_image_u8_t *img, int32_t x, int32_t y,
                   int32_t r, uint32_t *s, uint32_t *q)
{
    int32_t dx;
    int32_t dy;
    *s = 0;
    *q = 0;
    for (dy = -r; dy <= r; dy++) {
        for (dx = -r; dx <= r; dx++) {
            uint32_t v = negobs_image_u8_row(img, y + dy)[x + dx];
            *s += v;
            *q += v * v;
        }
    }
}

static void check_boxsum(int32_t r, int saturated)
{
    negobs_image_u8_t img = fill(7u + (uint32_t)r, saturated);
    int32_t x;
    int32_t y;
    assert_int_equal(negobs_boxsum_u8(&img, r, sum, W, sumsq, W, colbuf),
                     NEGOBS_OK);
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            uint32_t s;
            uint32_t q;
            if (x < r || y < r || x >= W - r || y >= H - r) {
                assert_int_equal(sum[y * W + x], 0);
                assert_int_equal(sumsq[y * W + x], 0);
                continue;
            }
            direct(&img, x, y, r, &s, &q);
            assert_int_equal(sum[y * W + x], s);
            assert_int_equal(sumsq[y * W + x], q);
        }
    }
}

static void test_boxsum_matches_direct_sums(void **state)
{
    int32_t r;
    (void)state;
    for (r = 1; r <= NEGOBS_BOXSUM_MAX_RADIUS; r++) {
        check_boxsum(r, 0);
    }
}

static void test_boxsum_saturated_worst_case_fits(void **state)
{
    (void)state;
    check_boxsum(2, 1);
    assert_int_equal(sum[20 * W + 20], 25 * 255);
    assert_int_equal(sumsq[20 * W + 20], 25u * 255u * 255u);
    check_boxsum(NEGOBS_BOXSUM_MAX_RADIUS, 1);
    assert_int_equal(sum[20 * W + 20], 225 * 255);
}

static void test_integral_box_equals_direct(void **state)
{
    negobs_image_u8_t img = fill(99u, 0);
    int32_t x;
    int32_t y;
    (void)state;
    assert_int_equal(negobs_integral_u8(&img, ii, iiq, sizeof ii / 4),
                     NEGOBS_OK);
    for (y = 2; y < H - 2; y++) {
        for (x = 2; x < W - 2; x++) {
            uint32_t s;
            uint32_t q;
            direct(&img, x, y, 2, &s, &q);
            assert_int_equal(
                negobs_integral_box(ii, W + 1, x - 2, y - 2, x + 3, y + 3), s);
            assert_int_equal(
                negobs_integral_box(iiq, W + 1, x - 2, y - 2, x + 3, y + 3),
                q);
        }
    }
}

/*
 * A frame large enough that the integral of squares wraps 2^32 many times:
 * window sums must still be exact (modular arithmetic argument).
 */
static uint8_t big[480][640];
static uint32_t bigii[481 * 641];

static void test_integral_wraps_but_boxes_stay_exact(void **state)
{
    negobs_image_u8_t img;
    (void)state;
    memset(big, 255, sizeof big);
    img.data = &big[0][0];
    img.width = 640;
    img.height = 480;
    img.stride = 640;
    assert_int_equal(negobs_integral_u8(&img, ii, NULL, 0),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(
        negobs_integral_u8(&img, bigii, NULL, sizeof bigii / sizeof bigii[0]),
        NEGOBS_OK);
    /* Total 640*480*255 < 2^32 here; use the squares path for wrap. */
    assert_int_equal(negobs_integral_box(bigii, 641, 600, 440, 605, 445),
                     25 * 255);
}

static uint32_t bigsq[481 * 641];

static void test_integral_of_squares_wraps(void **state)
{
    negobs_image_u8_t img;
    uint64_t total = 640ull * 480ull * 255ull * 255ull;
    (void)state;
    memset(big, 255, sizeof big);
    img.data = &big[0][0];
    img.width = 640;
    img.height = 480;
    img.stride = 640;
    assert_true(total > UINT32_MAX);
    assert_int_equal(
        negobs_integral_u8(&img, bigii, bigsq, sizeof bigii / sizeof bigii[0]),
        NEGOBS_OK);
    assert_int_equal(bigsq[480 * 641 + 640], (uint32_t)total);
    assert_int_equal(negobs_integral_box(bigsq, 641, 630, 470, 635, 475),
                     25u * 255u * 255u);
}

static void test_boxsum_rejects_bad_arguments(void **state)
{
    negobs_image_u8_t img = fill(3u, 0);
    negobs_image_u8_t tiny = img;
    (void)state;
    assert_int_equal(negobs_boxsum_u8(&img, 0, sum, W, sumsq, W, colbuf),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_boxsum_u8(&img, 8, sum, W, sumsq, W, colbuf),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_boxsum_u8(&img, 2, sum, W - 1, sumsq, W, colbuf),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_boxsum_u8(&img, 2, NULL, W, sumsq, W, colbuf),
                     NEGOBS_ERR_INVAL);
    tiny.width = 4;
    assert_int_equal(negobs_boxsum_u8(&tiny, 2, sum, W, sumsq, W, colbuf),
                     NEGOBS_ERR_INVAL);
    /* sumsq is optional. */
    assert_int_equal(negobs_boxsum_u8(&img, 2, sum, W, NULL, 0, colbuf),
                     NEGOBS_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_boxsum_matches_direct_sums),
        cmocka_unit_test(test_boxsum_saturated_worst_case_fits),
        cmocka_unit_test(test_integral_box_equals_direct),
        cmocka_unit_test(test_integral_wraps_but_boxes_stay_exact),
        cmocka_unit_test(test_integral_of_squares_wraps),
        cmocka_unit_test(test_boxsum_rejects_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
