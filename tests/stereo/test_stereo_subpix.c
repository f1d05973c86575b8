/*
 * Sub-pixel with the half-pixel shift (subpixel_halfshift): on a slanted
 * generated plane, whose disparity runs through every fraction of a
 * pixel, the parabola's estimate is pulled towards whole pixels (its error
 * depends on the fraction of the true disparity); the half-shift estimate
 * cancels most of that pull, leaves the integer disparities alone and is
 * the same on every target (integers only).
 */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "scene_pair.h"

#define W 200
#define H 160
#define DMAX 31
#define BINS 8

static uint8_t left[W * H];
static uint8_t right[W * H];
static int16_t gt[W * H];
static uint8_t occ[W * H];
static uint8_t tex[W * H];
static int16_t disp[2][W * H];
static uint8_t conf[2][W * H];
static uint8_t ws[NEGOBS_STEREO_WORKSPACE_MAX(W, H, DMAX)]
    __attribute__((aligned(16)));

static void run(int32_t halfshift, int k)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_image_u8_t li = {left, W, H, W};
    negobs_image_u8_t ri = {right, W, H, W};
    negobs_image_s16_t di = {disp[k], W, H, W};
    negobs_image_u8_t ci = {conf[k], W, H, W};
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = DMAX;
    cfg.subpixel_halfshift = halfshift;
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws), NEGOBS_OK);
    assert_int_equal(negobs_stereo_process(&ctx, &li, &ri, &di, &ci, NULL),
                     NEGOBS_OK);
}

/* Mean error (px) of map k per eighth of a pixel of the true disparity
 * (q8 truth, so the fraction is exact); returns half the spread between
 * the most positive and the most negative eighth: the pull's amplitude. */
static double pull_amplitude(const synth_scene_t *sc, int k, double *mean_abs)
{
    double sum[BINS] = {0};
    long n[BINS] = {0};
    double lo = 1e9;
    double hi = -1e9;
    double abs_sum = 0;
    long abs_n = 0;
    int32_t x;
    int32_t y;
    int b;
    for (y = 4; y < H - 4; y++) {
        for (x = DMAX + 8; x < W - 8; x++) {
            int32_t i = y * W + x;
            int32_t t = synth_disp_q8(sc, x, y);
            double e;
            if (disp[k][i] == NEGOBS_DISP_INVALID || conf[k][i] < 120) {
                continue;
            }
            e = disp[k][i] / 16.0 - t / 256.0;
            if (e > 1.0 || e < -1.0) {
                continue; /* a mismatch, not a sub-pixel error */
            }
            b = (t & 255) / (256 / BINS);
            sum[b] += e;
            n[b]++;
            abs_sum += (e < 0) ? -e : e;
            abs_n++;
        }
    }
    for (b = 0; b < BINS; b++) {
        double m;
        assert_true(n[b] > 200); /* every fraction is on the plane */
        m = sum[b] / (double)n[b];
        lo = (m < lo) ? m : lo;
        hi = (m > hi) ? m : hi;
    }
    *mean_abs = abs_sum / (double)abs_n;
    return 0.5 * (hi - lo);
}

static void test_halfshift_cancels_the_pull_to_whole_pixels(void **state)
{
    synth_scene_t sc;
    double a_par;
    double a_half;
    double m_par;
    double m_half;
    int32_t i;
    long same_int = 0;
    long both = 0;
    (void)state;
    memset(&sc, 0, sizeof sc);
    sc.w = W;
    sc.h = H;
    /* 6 -> 18 px over 160 rows: each fraction of a pixel ~12 times */
    sc.d_top_q8 = 6 * 256;
    sc.d_bottom_q8 = 18 * 256;
    sc.seed = 11u;
    synth_render(&sc, left, right, gt, occ, tex);
    run(0, 0);
    run(1, 1);
    a_par = pull_amplitude(&sc, 0, &m_par);
    a_half = pull_amplitude(&sc, 1, &m_half);
    print_message("pull amplitude: parabola %.3f px, half shift %.3f px; "
                  "mean |error| %.3f -> %.3f px\n",
                  a_par, a_half, m_par, m_half);
    /* the texture's peak is sharp enough for a visible pull (else the
     * test could not fail) */
    assert_true(a_par > 0.02);
    /* the half-pixel estimate removes at least half of it, and the maps
     * are no worse overall */
    assert_true(a_half < 0.5 * a_par);
    assert_true(m_half <= m_par);
    /* only the fraction moves: the integer part stays within one step */
    for (i = 0; i < W * H; i++) {
        if (disp[0][i] != NEGOBS_DISP_INVALID &&
            disp[1][i] != NEGOBS_DISP_INVALID) {
            int32_t dd = disp[1][i] - disp[0][i];
            both++;
            if (dd >= -NEGOBS_DISP_ONE && dd <= NEGOBS_DISP_ONE) {
                same_int++;
            }
        }
    }
    assert_true(both > W * H / 2);
    assert_true(same_int * 100 >= both * 99);
}

static void test_halfshift_config_checked(void **state)
{
    negobs_stereo_config_t cfg;
    size_t bytes;
    (void)state;
    negobs_stereo_config_default(&cfg, W, H);
    assert_int_equal(cfg.subpixel_halfshift, 0);
    cfg.subpixel_halfshift = 2;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
    cfg.subpixel_halfshift = -1;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_halfshift_cancels_the_pull_to_whole_pixels),
        cmocka_unit_test(test_halfshift_config_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
