/*
 * Out-of-view pixels: a value d at column x puts the match at x - d in the
 * right image. With keep_out_of_view = 0 no such value lies left of the
 * right image, the dropped ones are counted and get confidence 0, and
 * nothing else changes; with 1 (the default) the map is dense there.
 */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "scene_pair.h"

#define W 160
#define H 96

static uint8_t left[W * H];
static uint8_t right[W * H];
static int16_t gt[W * H];
static uint8_t occ[W * H];
static uint8_t tex[W * H];
static int16_t disp[2][W * H];
static uint8_t conf[2][W * H];
static uint8_t ws[NEGOBS_STEREO_WORKSPACE_MAX(W, H, 47)]
    __attribute__((aligned(16)));

static void run(int32_t keep, int k, negobs_stereo_stats_t *st)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_image_u8_t li = {left, W, H, W};
    negobs_image_u8_t ri = {right, W, H, W};
    negobs_image_s16_t di = {disp[k], W, H, W};
    negobs_image_u8_t ci = {conf[k], W, H, W};
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = 47;
    cfg.keep_out_of_view = keep;
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws), NEGOBS_OK);
    assert_int_equal(negobs_stereo_process(&ctx, &li, &ri, &di, &ci, st),
                     NEGOBS_OK);
}

static void test_out_of_view_values_dropped_or_kept(void **state)
{
    synth_scene_t sc;
    negobs_stereo_stats_t dense;
    negobs_stereo_stats_t sparse;
    negobs_stereo_config_t cfg;
    uint32_t dropped = 0;
    int32_t x;
    int32_t y;
    (void)state;
    memset(&sc, 0, sizeof sc);
    sc.w = W;
    sc.h = H;
    sc.d_top_q8 = 20 * 256; /* 20..36 px: a wide unseen left band */
    sc.d_bottom_q8 = 36 * 256;
    sc.seed = 5u;
    synth_render(&sc, left, right, gt, occ, tex);
    negobs_stereo_config_default(&cfg, W, H);
    assert_int_equal(cfg.keep_out_of_view, 1);
    run(1, 0, &dense);
    run(0, 1, &sparse);
    assert_int_equal(dense.out_of_view, 0);
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            int32_t i = y * W + x;
            int16_t a = disp[0][i];
            int16_t b = disp[1][i];
            if (b != NEGOBS_DISP_INVALID) {
                assert_true(b <= x * NEGOBS_DISP_ONE);
            } else {
                assert_int_equal(conf[1][i], 0);
            }
            if (a != NEGOBS_DISP_INVALID && a > x * NEGOBS_DISP_ONE) {
                dropped++; /* the dense map fills the unseen band */
            }
            if (x >= 48 + 8) {
                /* far from the band the maps agree (values dropped near
                 * it may shift the refinements by a few pixels) */
                assert_int_equal(a, b);
            }
        }
    }
    /* the dense map has values in most of the unseen band (about 28 px x
     * 96 rows) and the sparse one counted what it dropped */
    assert_true(dropped > (uint32_t)(20 * H));
    print_message(
        "# dense: %u values in the unseen band; sparse: %u dropped, %u valid (dense %u)\n",
        dropped, sparse.out_of_view, sparse.valid, dense.valid);
    assert_true(sparse.out_of_view >= dropped / 2u);
    assert_true(sparse.valid + sparse.out_of_view >= dense.valid - dropped);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_out_of_view_values_dropped_or_kept),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
