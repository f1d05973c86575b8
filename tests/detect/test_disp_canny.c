/*
 * Canny on the disparity map (detect/disp_canny.c): the cue that supports
 * a hazard. Maps are built here with known steps, so every count below is
 * derived from the geometry of the map, not read off a run.
 */
#include "cmocka_all.h"
#include "detect/disp_canny.h"
#include "negobs/fixed.h"

#define W 96
#define H 64

static int16_t map[W * H];
static uint16_t mag[(DCANNY_WIN_ROWS + 2) * W];
static uint8_t lab[DCANNY_WIN_ROWS * W];
static const negobs_image_s16_t img = {map, W, H, W};
static const dcanny_scratch_t sc = {mag, lab, W};

/* Ground-like map: 20 px below row `edge`, 20 - step_px[u] px from it up
 * (the far side of a drop reads a smaller disparity). */
static void drop_map(int32_t edge, const int32_t *step_q4)
{
    int32_t u;
    int32_t v;
    for (v = 0; v < H; v++) {
        for (u = 0; u < W; u++) {
            map[v * W + u] = (int16_t)((v >= edge) ? 20 * 16
                                                   : 20 * 16 - step_q4[u]);
        }
    }
}

/* drop_map with the same step in every column */
static void uniform_drop_map(int32_t edge, int32_t step_q4)
{
    int32_t step[W];
    int32_t u;
    for (u = 0; u < W; u++) {
        step[u] = step_q4;
    }
    drop_map(edge, step);
}

static void test_straight_drop_gives_one_edge_row(void **state)
{
    int32_t gmax;
    (void)state;
    uniform_drop_map(30, 3 * 16);
    /* a row step of s (1/16 px) gives |gy| = 4 s on the two rows beside
     * it, so the band's largest magnitude is 4 * 48 */
    gmax = dcanny_band_max(&img, 2);
    assert_int_equal(gmax, 4 * 48);
    /* NMS keeps exactly one of the two equal rows per column: every column
     * of the hazard counts once, wherever the edge row is taken from */
    assert_int_equal(dcanny_support(&img, gmax, 70, 400, 20, 59, 30, &sc), 40);
    assert_int_equal(dcanny_support(&img, gmax, 70, 400, 20, 59, 29, &sc), 40);
    /* rows 32 and below (edge row - 2 > 30) hold no edge */
    assert_int_equal(dcanny_support(&img, gmax, 70, 400, 20, 59, 33, &sc), 0);
    /* a threshold above the step's own magnitude: nothing */
    assert_int_equal(dcanny_support(&img, 4 * 48 * 1000 / 70 + 1000, 70, 400,
                                    20, 59, 30, &sc),
                     0);
}

/* Hysteresis: a drop whose step weakens along the edge keeps its weak
 * part when it joins the strong part, and loses it without hysteresis. */
static void test_weak_part_joined_to_strong_part_counts(void **state)
{
    int32_t step[W];
    int32_t u;
    int32_t gmax;
    int32_t both;
    int32_t strong_only;
    (void)state;
    for (u = 0; u < W; u++) {
        step[u] = (u < 40) ? 48 : 24;
    }
    drop_map(30, step);
    /* gmax such that high = 7 % of it lies between the weak part's 4*24
     * and the strong part's 4*48, and low = 40 % of high below 4*24 */
    gmax = 2000; /* high 140, low 56 */
    both = dcanny_support(&img, gmax, 70, 400, 10, 79, 30, &sc);
    strong_only = dcanny_support(&img, gmax, 70, 1000, 10, 79, 30, &sc);
    /* the strong part is columns 10..39 (30; where the step changes the
     * gradient turns diagonal and the joint may keep one more pixel); the
     * hysteresis adds the weak part, columns 40..79, one pixel each */
    assert_in_range(strong_only, 30, 32);
    assert_int_equal(both, strong_only + 40);
    /* the weak part alone, with no strong pixel in the window: nothing */
    assert_int_equal(
        dcanny_support(&img, gmax, 70, 400, 50 + DCANNY_MARGIN, 79, 30, &sc),
        0);
}

/* An edge between valid ground and a hole is no disparity edge (its
 * magnitude is 0 next to invalid pixels): the cue must not fire on the
 * missing-ground case, which has no measured far side. */
static void test_invalid_far_side_gives_no_edge(void **state)
{
    int32_t u;
    int32_t v;
    (void)state;
    uniform_drop_map(30, 48);
    for (v = 0; v < 30; v++) {
        for (u = 0; u < W; u++) {
            map[v * W + u] = NEGOBS_DISP_INVALID;
        }
    }
    assert_int_equal(dcanny_support(&img, 1000, 70, 400, 10, 79, 30, &sc), 0);
    assert_int_equal(dcanny_band_max(&img, 0), 0);
}

/* An oblique curb: the edge row climbs one row every 8 columns. Gradient
 * direction NMS still leaves one edge pixel per column within the
 * counted rows around the hazard's edge row. */
static void test_oblique_drop(void **state)
{
    int32_t u;
    int32_t v;
    int32_t n;
    (void)state;
    for (v = 0; v < H; v++) {
        for (u = 0; u < W; u++) {
            int32_t edge = 34 - u / 8;
            map[v * W + u] = (int16_t)((v >= edge) ? 320 : 320 - 64);
        }
    }
    /* columns 16..23 step at row 32, 24..31 at row 31: both inside the
     * counted rows 30..33 of edge row 32, one edge pixel per column */
    n = dcanny_support(&img, dcanny_band_max(&img, 2), 70, 400, 16, 31, 32,
                       &sc);
    assert_int_equal(n, 16);
}

/* Windows that leave the image or name no columns: 0, never a read out of
 * the map (the sanitizer build runs this). */
static void test_borders_and_bad_boxes(void **state)
{
    int32_t step[W];
    int32_t u;
    dcanny_scratch_t small = {mag, lab, W - 1};
    (void)state;
    for (u = 0; u < W; u++) {
        step[u] = 48;
    }
    drop_map(1, step);
    assert_true(dcanny_support(&img, 200, 70, 400, 0, W - 1, 0, &sc) >= 0);
    assert_true(dcanny_support(&img, 200, 70, 400, -50, W + 50, 1, &sc) >= 0);
    drop_map(H - 1, step);
    assert_true(dcanny_support(&img, 200, 70, 400, 0, W - 1, H - 1, &sc) >= 0);
    assert_true(dcanny_support(&img, 200, 70, 400, 0, W - 1, H + 40, &sc) ==
                0);
    assert_int_equal(dcanny_support(&img, 200, 70, 400, 40, 30, 30, &sc), 0);
    assert_int_equal(dcanny_support(&img, 0, 70, 400, 0, W - 1, 30, &sc), 0);
    /* scratch sized for a narrower image */
    assert_int_equal(dcanny_support(&img, 200, 70, 400, 0, W - 1, 30, &small),
                     0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_straight_drop_gives_one_edge_row),
        cmocka_unit_test(test_weak_part_joined_to_strong_part_counts),
        cmocka_unit_test(test_invalid_far_side_gives_no_edge),
        cmocka_unit_test(test_oblique_drop),
        cmocka_unit_test(test_borders_and_bad_boxes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
