/* Integer Canny on synthetic edges. */
#include <string.h>

#include "cmocka_all.h"
#include "stereo/stereo_int.h"

#define W 64
#define H 40

static uint8_t pix[H * W];
static uint16_t mag[(H + 2) * W];
static uint8_t edge[H * W];

static stx_t make(negobs_image_u8_t *img)
{
    stx_t s;
    memset(&s, 0, sizeof s);
    img->data = pix;
    img->width = W;
    img->height = H;
    img->stride = W;
    s.left = img;
    s.w = W;
    s.h = H;
    s.mag = mag;
    s.edge = edge;
    s.cfg.canny_low = 60;
    s.cfg.canny_high = 120;
    return s;
}

/* A vertical step between columns 31 and 32: `a` left of it, `b` right. */
static void fill_vertical_step(uint8_t a, uint8_t b)
{
    int32_t x;
    int32_t y;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            pix[y * W + x] = (x < 32) ? a : b;
        }
    }
}

static void test_canny_vertical_step_gives_one_column(void **state)
{
    negobs_image_u8_t img;
    stx_t s = make(&img);
    int32_t x;
    int32_t y;
    uint32_t n;
    (void)state;
    fill_vertical_step(50, 200);
    n = stx_canny_strip(&s, 0, H);
    /* rows 1..H-2 have a full Sobel; exactly one edge pixel each */
    assert_int_equal(n, H - 2);
    for (y = 1; y < H - 1; y++) {
        int32_t cnt = 0;
        for (x = 0; x < W; x++) {
            if (edge[y * W + x]) {
                cnt++;
                assert_true(x == 31 || x == 32);
            }
        }
        assert_int_equal(cnt, 1);
    }
}

static void test_canny_horizontal_step_in_a_strip(void **state)
{
    negobs_image_u8_t img;
    stx_t s = make(&img);
    int32_t x;
    int32_t y;
    uint32_t n;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            pix[y * W + x] = (uint8_t)((y < 20) ? 30 : 220);
        }
    }
    /* strip rows 16..24: the edge row is inside, halo rows are read */
    n = stx_canny_strip(&s, 16, 24);
    assert_int_equal(n, W - 2);
    for (x = 1; x < W - 1; x++) {
        int32_t r = 0;
        int32_t cnt = 0;
        for (r = 0; r < 8; r++) {
            if (edge[r * W + x]) {
                cnt++;
                assert_true(16 + r == 19 || 16 + r == 20);
            }
        }
        assert_int_equal(cnt, 1);
    }
}

static void test_canny_flat_and_weak_edges_give_nothing(void **state)
{
    negobs_image_u8_t img;
    stx_t s = make(&img);
    (void)state;
    memset(pix, 90, sizeof pix);
    assert_int_equal(stx_canny_strip(&s, 0, H), 0);
    /* step of 10 grey levels: L1 magnitude 40 < low threshold */
    fill_vertical_step(90, 100);
    assert_int_equal(stx_canny_strip(&s, 0, H), 0);
}

static void test_canny_hysteresis_keeps_weak_pixels_next_to_strong(
    void **state)
{
    negobs_image_u8_t img;
    stx_t s = make(&img);
    int32_t x;
    int32_t y;
    uint32_t n;
    (void)state;
    /* step of 20 (magnitude 80: weak) everywhere, 60 (strong) on rows
     * 0..3 only: the weak column below is connected to the strong part */
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            int32_t hi = (y < 4) ? 160 : 120;
            pix[y * W + x] = (uint8_t)((x < 32) ? 100 : hi);
        }
    }
    n = stx_canny_strip(&s, 0, H);
    assert_true(n >= H - 2);
    for (y = 8; y < H - 1; y++) {
        assert_true(edge[y * W + 31] || edge[y * W + 32]);
    }
    /* without the strong part nothing survives */
    for (y = 0; y < 4; y++) {
        for (x = 32; x < W; x++) {
            pix[y * W + x] = 120;
        }
    }
    assert_int_equal(stx_canny_strip(&s, 0, H), 0);
}

/* A strip whose strongest gradients stay below canny_high takes its own
 * strongest share as the strong threshold: the 10-level step that the
 * fixed thresholds miss (above) is found, one pixel a row. */
static void test_canny_top_share_finds_a_weak_step(void **state)
{
    negobs_image_u8_t img;
    stx_t s = make(&img);
    int32_t y;
    (void)state;
    fill_vertical_step(90, 100);
    assert_int_equal(stx_canny_strip(&s, 0, H), 0);
    s.cfg.canny_top_permille = 3;
    assert_int_equal(stx_canny_strip(&s, 0, H), H - 2);
    for (y = 1; y < H - 1; y++) {
        assert_true(edge[y * W + 31] || edge[y * W + 32]);
    }
    /* a flat strip stays without edges: the threshold's floor */
    memset(pix, 90, sizeof pix);
    assert_int_equal(stx_canny_strip(&s, 0, H), 0);
    /* two grey levels of step (magnitude 8) lie below that floor */
    fill_vertical_step(90, 92);
    assert_int_equal(stx_canny_strip(&s, 0, H), 0);
}

/* Where the strongest share reaches canny_high the fixed thresholds hold
 * exactly: beside a strong step, a weak one stays unmarked. */
static void test_canny_top_share_keeps_textured_strips(void **state)
{
    negobs_image_u8_t img;
    stx_t s = make(&img);
    static uint8_t fixed[H * W];
    int32_t x;
    int32_t y;
    uint32_t n;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            int32_t v = (x < 16) ? 40 : 200; /* magnitude 640 at 15-16 */
            v += (x >= 48) ? 10 : 0;         /* magnitude 40 at 47-48 */
            pix[y * W + x] = (uint8_t)v;
        }
    }
    n = stx_canny_strip(&s, 0, H);
    memcpy(fixed, edge, sizeof fixed);
    s.cfg.canny_top_permille = 3;
    assert_int_equal(stx_canny_strip(&s, 0, H), n);
    assert_memory_equal(edge, fixed, sizeof fixed);
    for (y = 1; y < H - 1; y++) {
        assert_false(edge[y * W + 47] || edge[y * W + 48]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_canny_vertical_step_gives_one_column),
        cmocka_unit_test(test_canny_horizontal_step_in_a_strip),
        cmocka_unit_test(test_canny_flat_and_weak_edges_give_nothing),
        cmocka_unit_test(
            test_canny_hysteresis_keeps_weak_pixels_next_to_strong),
        cmocka_unit_test(test_canny_top_share_finds_a_weak_step),
        cmocka_unit_test(test_canny_top_share_keeps_textured_strips),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
