/* Gap fill (stage 5b): which runs are filled, with what, and their
 * confidence. */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "stereo/stereo_int.h"

#define W 64
#define H 16
#define INV NEGOBS_DISP_INVALID

static int16_t disp[H * W];
static uint8_t conf[H * W];
static uint8_t ws[NEGOBS_STEREO_WORKSPACE_MAX(W, H, 31)]
    __attribute__((aligned(16)));
static negobs_image_s16_t di;
/* The left image the fill reads grey-level steps from: flat unless a test
 * draws an object border into it. */
static uint8_t grey[H * W];
static negobs_image_u8_t gi;

static stx_t *setup(int32_t gap_fill)
{
    static negobs_stereo_t ctx;
    negobs_stereo_config_t cfg;
    int32_t i;
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = 31;
    cfg.gap_fill = gap_fill;
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws), NEGOBS_OK);
    for (i = 0; i < W * H; i++) {
        disp[i] = 10 * 16;
        conf[i] = 200;
    }
    di.data = disp;
    di.width = W;
    di.height = H;
    di.stride = W;
    memset(grey, 100, sizeof grey);
    gi.data = grey;
    gi.width = W;
    gi.height = H;
    gi.stride = W;
    ((stx_t *)ctx.priv)->left = &gi;
    return (stx_t *)ctx.priv;
}

/* Row y, columns [x0, x1): a measured surface at d_px whole pixels. */
static void span(int32_t y, int32_t x0, int32_t x1, int32_t d_px)
{
    int32_t x;
    for (x = x0; x < x1; x++) {
        disp[y * W + x] = (int16_t)(d_px * 16);
    }
}

static void hole(int32_t y, int32_t x0, int32_t x1)
{
    int32_t x;
    for (x = x0; x < x1; x++) {
        disp[y * W + x] = INV;
        conf[y * W + x] = 0;
    }
}

static void test_gap_between_agreeing_ends_is_interpolated(void **state)
{
    stx_t *s = setup(8);
    int32_t x;
    (void)state;
    /* ends 10 px and 10 15/16 px: a slanted surface, joined linearly */
    disp[3 * W + 19] = 10 * 16 + 15;
    hole(3, 20, 25);
    disp[3 * W + 25] = 10 * 16;
    stx_gap_fill(s, &di, conf, W);
    for (x = 20; x < 25; x++) {
        int32_t k = x - 19;
        int32_t want = 10 * 16 + 15 +
                       (int32_t)negobs_div_round_s64(-15 * k, 6);
        assert_int_equal(disp[3 * W + x], want);
        assert_int_equal(conf[3 * W + x], NEGOBS_STEREO_CONF_FILLED);
    }
    /* strictly between the ends and decreasing: a ramp, not a step */
    for (x = 20; x < 25; x++) {
        assert_true(disp[3 * W + x] < disp[3 * W + x - 1]);
        assert_true(disp[3 * W + x] > 10 * 16);
    }
    assert_int_equal(s->st.gap_filled, 5);
}

static void test_gap_between_near_and_far_gets_the_far_end(void **state)
{
    stx_t *s = setup(8);
    int32_t x;
    (void)state;
    /* near object (20 px) on the right of the hole: background (10) */
    span(5, 30, W, 20);
    hole(5, 24, 30);
    /* mirror: near object (20 px) on the left of a hole in row 6 */
    span(6, 0, 40, 20);
    hole(6, 40, 44);
    stx_gap_fill(s, &di, conf, W);
    for (x = 24; x < 30; x++) {
        assert_int_equal(disp[5 * W + x], 10 * 16);
        assert_int_equal(conf[5 * W + x], NEGOBS_STEREO_CONF_FILLED);
    }
    /* the near surface's first pixel goes to the background too, only it */
    assert_int_equal(disp[5 * W + 30], 10 * 16);
    assert_int_equal(conf[5 * W + 30], NEGOBS_STEREO_CONF_FILLED);
    assert_int_equal(disp[5 * W + 31], 20 * 16);
    assert_int_equal(conf[5 * W + 31], 200);
    /* mirror: the hole gets the background, the near side is untouched */
    for (x = 40; x < 44; x++) {
        assert_int_equal(disp[6 * W + x], 10 * 16);
    }
    assert_int_equal(disp[6 * W + 39], 20 * 16);
    assert_int_equal(disp[6 * W + 44], 10 * 16);
    assert_int_equal(conf[6 * W + 39], 200);
    assert_int_equal(s->st.gap_filled, 6 + 1 + 4);
}

/* A run much wider than the disparity step between its ends is not an
 * occlusion (that would be as wide as the step) but a surface without
 * texture: it is joined linearly, and the near end keeps its value. */
static void test_wide_gap_across_a_small_step_is_a_surface(void **state)
{
    stx_t *s = setup(32);
    int32_t x;
    (void)state;
    /* row 4: ends 10 px and 12 px, 11 px apart: 11 > 3 * 2 + 4 */
    span(4, 31, W, 12);
    hole(4, 20, 31);
    /* row 8: the same step, run of exactly 3 * 2 + 4 = 10 px: occlusion */
    span(8, 30, W, 12);
    hole(8, 20, 30);
    stx_gap_fill(s, &di, conf, W);
    for (x = 20; x < 31; x++) {
        int32_t k = x - 19;
        int32_t want = 10 * 16 + (int32_t)negobs_div_round_s64(32 * k, 12);
        assert_int_equal(disp[4 * W + x], want);
        assert_int_equal(conf[4 * W + x], NEGOBS_STEREO_CONF_FILLED);
    }
    assert_true(disp[4 * W + 20] > 10 * 16);
    assert_true(disp[4 * W + 30] < 12 * 16);
    assert_int_equal(disp[4 * W + 31], 12 * 16); /* not an occlusion edge */
    assert_int_equal(conf[4 * W + 31], 200);
    for (x = 20; x < 31; x++) {
        assert_int_equal(disp[8 * W + x], 10 * 16); /* incl. the edge px */
    }
    assert_int_equal(disp[8 * W + 31], 12 * 16);
    assert_int_equal(s->st.gap_filled, 11 + 10 + 1);
}

/* Where the left image shows the object's border, the fill puts the
 * depth edge there: inside a run with the near surface on its left, and
 * among the first pixels of a near surface after an occlusion run. */
static void test_grey_level_step_places_the_depth_edge(void **state)
{
    stx_t *s = setup(8);
    int32_t x;
    (void)state;
    /* row 6: near object (20 px) up to column 41 in the image, its value
     * measured up to 39, hole 40..43, background from 44 */
    for (x = 0; x < 40; x++) {
        disp[6 * W + x] = 20 * 16;
        grey[6 * W + x] = 180;
    }
    grey[6 * W + 40] = 180;
    grey[6 * W + 41] = 180; /* border between 41 and 42 */
    hole(6, 40, 44);
    /* row 5: occlusion run 24..29 (background 10 px on the left), near
     * surface (20 px) measured from 30, but its border in the image lies
     * between 31 and 32: 30 and 31 are fattened background */
    span(5, 30, W, 20);
    for (x = 32; x < W; x++) {
        grey[5 * W + x] = 30;
    }
    hole(5, 24, 30);
    stx_gap_fill(s, &di, conf, W);
    assert_int_equal(disp[6 * W + 40], 20 * 16);
    assert_int_equal(disp[6 * W + 41], 20 * 16);
    assert_int_equal(disp[6 * W + 42], 10 * 16);
    assert_int_equal(disp[6 * W + 43], 10 * 16);
    for (x = 40; x < 44; x++) {
        assert_int_equal(conf[6 * W + x], NEGOBS_STEREO_CONF_FILLED);
    }
    for (x = 24; x < 32; x++) {
        assert_int_equal(disp[5 * W + x], 10 * 16);
        assert_int_equal(conf[5 * W + x], NEGOBS_STEREO_CONF_FILLED);
    }
    assert_int_equal(disp[5 * W + 32], 20 * 16);
    assert_int_equal(conf[5 * W + 32], 200);
    assert_int_equal(s->st.gap_filled, 4 + 6 + 2);
}

static void test_long_gap_and_empty_row_stay_invalid(void **state)
{
    stx_t *s = setup(8);
    int32_t x;
    (void)state;
    hole(2, 10, 19); /* 9 px > gap_fill */
    hole(7, 0, W);   /* no value at all on the row */
    stx_gap_fill(s, &di, conf, W);
    for (x = 10; x < 19; x++) {
        assert_int_equal(disp[2 * W + x], INV);
        assert_int_equal(conf[2 * W + x], 0);
    }
    for (x = 0; x < W; x++) {
        assert_int_equal(disp[7 * W + x], INV);
    }
    assert_int_equal(s->st.gap_filled, 0);
}

static void test_border_run_takes_its_only_end(void **state)
{
    stx_t *s = setup(8);
    int32_t x;
    (void)state;
    hole(9, 0, 6);
    disp[9 * W + 6] = 12 * 16;
    hole(9, W - 3, W);
    disp[9 * W + W - 4] = 7 * 16;
    stx_gap_fill(s, &di, conf, W);
    for (x = 0; x < 6; x++) {
        assert_int_equal(disp[9 * W + x], 12 * 16);
    }
    for (x = W - 3; x < W; x++) {
        assert_int_equal(disp[9 * W + x], 7 * 16);
    }
    assert_int_equal(s->st.gap_filled, 9);
}

static void test_adaptive_mean_marks_the_holes_it_fills(void **state)
{
    /* a one-pixel hole between agreeing neighbours (row 2, the row pass)
     * and a hole too wide for the row pass (rows 6-7, x 34-46) that the
     * column pass fills at x 40: the mean fills both; their confidence was left
     * stale (200) by whatever removed the value, and must become FILLED.
     * Untouched pixels keep theirs. */
    stx_t *s = setup(64);
    (void)state;
    disp[2 * W + 20] = INV;
    hole(6, 34, 47);
    hole(7, 34, 47);
    conf[2 * W + 20] = 200;
    conf[6 * W + 40] = 200;
    conf[7 * W + 40] = 200;
    stx_adaptive_mean(s, &di, conf, W);
    assert_int_equal(disp[2 * W + 20], 10 * 16);
    assert_int_equal(conf[2 * W + 20], NEGOBS_STEREO_CONF_FILLED);
    assert_int_equal(disp[6 * W + 40], 10 * 16);
    assert_int_equal(conf[6 * W + 40], NEGOBS_STEREO_CONF_FILLED);
    assert_int_equal(conf[7 * W + 40], NEGOBS_STEREO_CONF_FILLED);
    assert_int_equal(conf[2 * W + 21], 200);
    assert_int_equal(conf[5 * W + 40], 200);
}

/* A slanted surface (the ground: disparity grows 3 q4 per row, and 1 q4
 * per column here) keeps its values under the adaptive mean, also
 * within 4 px of the frame border and beside a hole: the taps of a
 * missing side must not leave the other side pulling the centre. Each
 * tap weighed on its own, the last rows of a 320x240 ground map came out
 * 0.07-0.17 px low and tilted the ground fit by 0.2 deg. */
static void test_adaptive_mean_keeps_a_slanted_surface_at_borders_and_holes(
    void **state)
{
    stx_t *s = setup(64);
    int32_t x;
    int32_t y;
    int32_t worst = 0;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            disp[y * W + x] = (int16_t)(320 + 3 * y + x);
        }
    }
    /* too wide for the row pass; its borders are what is tested (the
     * column pass may fill it: pixels that were holes are not compared) */
    hole(8, 20, 30);
    {
        static int16_t before[H * W];
        memcpy(before, disp, sizeof disp);
        stx_adaptive_mean(s, &di, conf, W);
        for (y = 0; y < H; y++) {
            for (x = 0; x < W; x++) {
                int32_t e;
                if (before[y * W + x] == INV) {
                    continue;
                }
                e = disp[y * W + x] - before[y * W + x];
                e = (e < 0) ? -e : e;
                worst = (e > worst) ? e : worst;
            }
        }
    }
    print_message("slanted surface under the adaptive mean: worst change %d "
                  "q4\n",
                  worst);
    assert_int_equal(worst, 0);
}

static void test_flat_frame_stays_invalid_and_range_is_checked(void **state)
{
    /* through the public API: a frame without texture stays all-invalid
     * whatever gap_fill says (no end to fill from) */
    static uint8_t flat[W * H];
    negobs_stereo_t ctx;
    negobs_stereo_config_t cfg;
    negobs_image_u8_t im;
    negobs_stereo_stats_t st;
    int32_t i;
    (void)state;
    memset(flat, 128, sizeof flat);
    im.data = flat;
    im.width = W;
    im.height = H;
    im.stride = W;
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = 31;
    assert_int_equal(cfg.gap_fill, 64);
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws), NEGOBS_OK);
    di.data = disp;
    di.width = W;
    di.height = H;
    di.stride = W;
    assert_int_equal(negobs_stereo_process(&ctx, &im, &im, &di, NULL, &st),
                     NEGOBS_OK);
    for (i = 0; i < W * H; i++) {
        assert_int_equal(disp[i], INV);
    }
    assert_int_equal(st.gap_filled, 0);
    cfg.gap_fill = 1025;
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gap_between_agreeing_ends_is_interpolated),
        cmocka_unit_test(test_gap_between_near_and_far_gets_the_far_end),
        cmocka_unit_test(test_wide_gap_across_a_small_step_is_a_surface),
        cmocka_unit_test(test_grey_level_step_places_the_depth_edge),
        cmocka_unit_test(test_long_gap_and_empty_row_stay_invalid),
        cmocka_unit_test(test_border_run_takes_its_only_end),
        cmocka_unit_test(test_adaptive_mean_marks_the_holes_it_fills),
        cmocka_unit_test(
            test_adaptive_mean_keeps_a_slanted_surface_at_borders_and_holes),
        cmocka_unit_test(test_flat_frame_stays_invalid_and_range_is_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
