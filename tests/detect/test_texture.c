/*
 * Texture under a candidate (detect/detect_texture.c): the left image's
 * noise estimate and the box test. Images are generated here with a known
 * noise and known texture contrast, so each expectation follows from the
 * numbers that made the image.
 */
#include <math.h>
#include <string.h>

#include "cmocka_all.h"
#include "detect/detect_internal.h"
#include "test_rng.h"

#define W 160
#define H 120

static uint8_t px[W * H];
static const negobs_image_u8_t img = {px, W, H, W};
static uint32_t rng = 12345u;

static double gauss(void)
{
    return test_gauss12(&rng);
}

static uint8_t clamp_u8(double v)
{
    return (uint8_t)(v < 0.0 ? 0.0 : (v > 255.0 ? 255.0 : v + 0.5));
}

/* Grey 128 plus noise of sigma `noise`; the rectangle [u0, u1) x [v0, v1)
 * also carries a texture of sigma `tex` (independent per pixel). */
static void render(double noise, double tex, int u0, int v0, int u1, int v1)
{
    int x;
    int y;
    rng = 12345u;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            double t = (x >= u0 && x < u1 && y >= v0 && y < v1) ? tex * gauss()
                                                                : 0.0;
            px[y * W + x] = clamp_u8(128.0 + t + noise * gauss());
        }
    }
}

/* The median |second difference| of pure noise is 4.05 sigma: sigma 2
 * reads 8 (+-1 for the integer bins and the sample), sigma 4 reads 16,
 * and a noise-free flat image reads 0. */
static void test_noise_median_follows_the_noise(void **state)
{
    int32_t m;
    (void)state;
    render(2.0, 0.0, 0, 0, 0, 0);
    m = det_noise_median(&img);
    print_message("sigma 2: median %d\n", (int)m);
    assert_true(m >= 7 && m <= 9);
    render(4.0, 0.0, 0, 0, 0, 0);
    m = det_noise_median(&img);
    print_message("sigma 4: median %d\n", (int)m);
    assert_true(m >= 15 && m <= 17);
    render(0.0, 0.0, 0, 0, 0, 0);
    assert_int_equal(det_noise_median(&img), 0);
}

/* A quarter of the image textured hardly moves the estimate (a median). */
static void test_noise_median_resists_some_texture(void **state)
{
    int32_t m;
    (void)state;
    render(2.0, 10.0, 0, 0, W / 2, H / 2);
    m = det_noise_median(&img);
    print_message("sigma 2, a quarter textured: median %d\n", (int)m);
    assert_true(m >= 7 && m <= 11);
}

/* With noise 2 and a quarter of the image carrying a texture of sigma 5
 * (the estimate reads 10, sigma 2.5: texture raises it, which makes the
 * test stricter): a box of flat paint (noise only) fails, a box in the
 * texture (variance 29 against the threshold 4 x 2.5^2 = 25) passes, a
 * box mostly on the flat side fails, and a texture of sigma 1.2 (variance
 * 5.4) fails. With no noise measured (median 0) every box passes. */
static void test_box_texture_against_the_noise(void **state)
{
    int32_t m;
    (void)state;
    render(2.0, 5.0, 120, 0, W, H);
    m = det_noise_median(&img);
    print_message("sigma 2, a quarter textured (5): median %d\n", (int)m);
    assert_false(det_box_textured(&img, m, 10, 20, 60, 60));
    assert_true(det_box_textured(&img, m, 124, 20, 155, 60));
    /* a box mostly on the flat side */
    assert_false(det_box_textured(&img, m, 60, 20, 130, 60));
    render(2.0, 1.2, 120, 0, W, H);
    assert_false(det_box_textured(&img, m, 124, 20, 155, 60));
    assert_true(det_box_textured(&img, 0, 10, 20, 60, 60));
    /* a box at the image border is clipped, not read outside */
    render(2.0, 5.0, 0, 0, W, H);
    assert_true(det_box_textured(&img, m, -10, -10, W + 10, H + 10));
}

/* A hazard merged from four 16-px strips over columns 64-127 whose box
 * spans rows 20-99, textured (sigma 5) only in columns 96-127 and rows
 * 60-99, where the two right strips read their deficit: the whole box is
 * a quarter textured and fails, the two strips over their own rows pass.
 * With texture in only one strip (columns 112-127) no two adjacent
 * strips hold it and the run fails; with a run of one it passes. */
static void test_run_of_strips_textured(void **state)
{
    strip_hit_t hits[4];
    int32_t m;
    int k;
    (void)state;
    memset(hits, 0, sizeof hits);
    for (k = 0; k < 4; k++) {
        hits[k].found = 1;
        hits[k].u0 = 64 + 16 * k;
        hits[k].u1 = 80 + 16 * k;
        hits[k].top_v = (k < 2) ? 20 : 60;
        hits[k].edge_v = 99;
    }
    render(2.0, 5.0, 96, 60, 128, 100);
    m = det_noise_median(&img);
    assert_false(det_box_textured(&img, m, 64, 20, 127, 99));
    assert_true(det_run_textured(&img, m, hits, 0, 4, 2));
    assert_false(det_run_textured(&img, m, hits, 0, 2, 2));
    assert_false(det_run_textured(&img, m, hits, 0, 4, 5));
    render(2.0, 5.0, 112, 60, 128, 100);
    m = det_noise_median(&img);
    assert_false(det_run_textured(&img, m, hits, 0, 4, 2));
    assert_true(det_run_textured(&img, m, hits, 0, 4, 1));
}

/* Grain weaker than the noise: noise of sigma 4 everywhere, and in the
 * right quarter also a texture of sigma 4 (each window's variance about
 * twice the noise's, half of what det_box_textured asks). The box there
 * fails det_box_textured and passes det_box_weak_textured (most windows
 * above 1.5 x the noise's variance); a box of noise alone fails both
 * (about 5 % of its windows above), and so does grain of sigma 1.5 (1.14
 * x the noise's variance). An empty box holds no grain. */
static void test_box_weak_grain(void **state)
{
    int32_t m;
    (void)state;
    render(4.0, 4.0, 120, 0, W, H);
    m = det_noise_median(&img);
    print_message("sigma 4, a quarter with grain 4: median %d\n", (int)m);
    assert_false(det_box_textured(&img, m, 124, 20, 155, 100));
    assert_true(det_box_weak_textured(&img, m, 124, 20, 155, 100));
    assert_false(det_box_weak_textured(&img, m, 10, 20, 100, 100));
    render(4.0, 1.5, 120, 0, W, H);
    assert_false(det_box_weak_textured(&img, m, 124, 20, 155, 100));
    assert_false(det_box_weak_textured(&img, m, 60, 20, 50, 100));
}

/* Texture as fine as the pixels cannot be told from noise: an image
 * covered by it reads the cap (24, a noise of 6 grey levels), and a box of
 * that texture with a deviation of 20 grey levels still passes, where an
 * uncapped estimate (about 80) would fail every window of the frame. */
static void test_noise_median_is_capped(void **state)
{
    int32_t m;
    int x;
    (void)state;
    rng = 99u;
    for (x = 0; x < W * H; x++) {
        px[x] = clamp_u8(128.0 + 20.0 * gauss());
    }
    m = det_noise_median(&img);
    assert_int_equal(m, 24);
    assert_true(det_box_textured(&img, m, 20, 20, 140, 100));
    assert_false(det_box_textured(&img, 80, 20, 20, 140, 100));
}

/* Bars of grey 98 and 158, 4 px each (every 5x5 window holds an edge, a
 * variance near 900 against the 4 x 2.5^2 = 25 the noise asks), plus
 * noise of sigma 2. Horizontal bars (a painted stripe's long edges, rows
 * of the same grey) match every disparity along the row about as well:
 * the box fails. The same bars upright pass. */
static void render_bars(int horizontal)
{
    int x;
    int y;
    rng = 777u;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            int k = horizontal ? y : x;
            px[y * W + x] = clamp_u8(((k / 4) % 2 ? 158.0 : 98.0) +
                                     2.0 * gauss());
        }
    }
}

static void test_box_horizontal_edges_fail(void **state)
{
    (void)state;
    render_bars(1);
    assert_false(det_box_textured(&img, 10, 20, 20, 140, 100));
    assert_false(det_box_textured(&img, 0, 20, 20, 140, 100));
    render_bars(0);
    assert_true(det_box_textured(&img, 10, 20, 20, 140, 100));
}

/* A floor seen at a slant: its texture is foreshortened vertically, so
 * the vertical gradient outweighs the horizontal one. Texture of sigma
 * 12, each pixel the normalised sum of `len` independent samples along
 * the row: a 2-px horizontal difference then has a variance of
 * 4 x 144 / len, a vertical one 2 x 144, so len 5 gives 2.5 times more
 * vertical energy and len 15 (with the noise of sigma 2) about 6 times,
 * both inside the 1/10 the test allows for grazing views: both pass. */
static void render_streaks(int len)
{
    static double t[W * H];
    int x;
    int y;
    int i;
    rng = 4242u;
    for (x = 0; x < W * H; x++) {
        t[x] = 12.0 * gauss();
    }
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            double a = 0.0;
            for (i = 0; i < len; i++) {
                a += t[y * W + (x + i) % W];
            }
            px[y * W + x] = clamp_u8(128.0 + a / sqrt((double)len) +
                                     2.0 * gauss());
        }
    }
}

static void test_box_foreshortened_texture_passes(void **state)
{
    int32_t m;
    (void)state;
    render_streaks(5);
    m = det_noise_median(&img);
    print_message("streaks 5: median %d\n", (int)m);
    assert_true(det_box_textured(&img, m, 20, 20, 140, 100));
    render_streaks(15);
    m = det_noise_median(&img);
    print_message("streaks 15: median %d\n", (int)m);
    assert_true(det_box_textured(&img, m, 20, 20, 140, 100));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_noise_median_follows_the_noise),
        cmocka_unit_test(test_noise_median_resists_some_texture),
        cmocka_unit_test(test_box_texture_against_the_noise),
        cmocka_unit_test(test_noise_median_is_capped),
        cmocka_unit_test(test_box_horizontal_edges_fail),
        cmocka_unit_test(test_box_foreshortened_texture_passes),
        cmocka_unit_test(test_run_of_strips_textured),
        cmocka_unit_test(test_box_weak_grain),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
