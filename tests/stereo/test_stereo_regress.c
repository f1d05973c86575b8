/*
 * Regression on generated pairs with exact ground truth (scene_pair.h): slanted
 * ground plane, a 5 px drop-off and a fronto-parallel box, with and without
 * a 2-row vertical misalignment. Thresholds are pinned a little above what
 * the engine achieves (see docs/DISPARITY.md), so a quality regression
 * fails the test.
 */
#include <stdio.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "scene_pair.h"

/* pinned near the measured values (see the printed "#" lines) */
#define BAD1_MAX_PERMILLE 8
#define BAD05_MAX_PERMILLE 10
#define DENS_MIN_PERMILLE 995

#define W 160
#define H 120
#define WS_BYTES (NEGOBS_STEREO_WORKSPACE_MAX(W, H, 47))

static uint8_t left[W * H];
static uint8_t right[W * H];
static uint8_t tex[W * H];
static uint8_t occ[W * H];
static int16_t gt[W * H];
static int16_t disp[W * H];
static uint8_t conf[W * H];
static uint8_t ws[WS_BYTES] __attribute__((aligned(16)));

typedef struct result {
    int32_t bad1;  /* permille of valid visible pixels off by > 1 px */
    int32_t bad05; /* ... off by > 0.5 px                           */
    int32_t dens;  /* permille of visible pixels with a value        */
    negobs_stereo_stats_t st;
    int32_t next_offset; /* g_hold_offset: the next frame's offset (found) */
} result_t;

static int g_flat_scene;
static int g_near_scene;    /* floor 8 .. 44 px, bottom 48 rows flat at 1/4 */
static int32_t g_first_row; /* negobs_stereo_set_first_row before a run */
/* > 1: both images' contrast about grey 128 divided by this (a dim or
 * low-contrast camera); the texture keeps its shape, its gradients shrink */
static int32_t g_contrast_div;
/* >= 0: cfg.canny_top_permille for the run (else the default) */
static int32_t g_top_permille = -1;
/* negobs_stereo_hold_vertical_offset before the run (NO_HOLD: none); the
 * same pair is then matched once more without a hold (next_offset) */
#define NO_HOLD (-100)
static int32_t g_hold_offset = NO_HOLD;
static int16_t disp_held[W * H];

/* The confidence scale of negobs/stereo.h: 0 exactly where there is no
 * value; a value is filled (2), textureless (4) or matched (8..255). Run
 * on every scene, the negative control included. */
static void check_confidence_scale(void)
{
    int32_t i;
    int32_t filled = 0;
    int32_t matched = 0;
    for (i = 0; i < W * H; i++) {
        if (disp[i] == NEGOBS_DISP_INVALID) {
            assert_int_equal(conf[i], NEGOBS_STEREO_CONF_NONE);
            continue;
        }
        assert_true(conf[i] == NEGOBS_STEREO_CONF_FILLED ||
                    conf[i] == NEGOBS_STEREO_CONF_FLAT ||
                    conf[i] >= NEGOBS_STEREO_CONF_MATCHED_MIN);
        filled += conf[i] == NEGOBS_STEREO_CONF_FILLED;
        matched += conf[i] >= NEGOBS_STEREO_CONF_MATCHED_MIN;
    }
    printf("# confidence: %d matched, %d filled\n", (int)matched, (int)filled);
} /* 1: constant disparity 20 px, no drop, no box */

static result_t run(int32_t voff, int32_t vsearch, int32_t fixed_off)
{
    synth_scene_t sc;
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_image_u8_t li;
    negobs_image_u8_t ri;
    negobs_image_u8_t ci;
    negobs_image_s16_t di;
    size_t need;
    result_t r;

    sc.w = W;
    sc.h = H;
    sc.d_top_q8 = 8 * 256;
    sc.d_bottom_q8 = 28 * 256;
    sc.drop_q8 = 5 * 256;
    sc.box_q8 = 36 * 256;
    sc.voff = voff;
    sc.seed = 4242u;
    if (g_flat_scene) {
        sc.d_top_q8 = 20 * 256;
        sc.d_bottom_q8 = 20 * 256;
        sc.drop_q8 = 0;
        sc.box_q8 = 0;
    }
    if (g_near_scene) {
        sc.d_bottom_q8 = 44 * 256;
        sc.drop_q8 = 0;
        sc.box_q8 = 0;
    }
    synth_render_fine(&sc, g_near_scene ? 48 : 0, left, right, gt, occ, tex);
    if (g_contrast_div > 1) {
        int32_t i;
        for (i = 0; i < W * H; i++) {
            left[i] = (uint8_t)(128 +
                                ((int32_t)left[i] - 128) / g_contrast_div);
            right[i] = (uint8_t)(128 +
                                 ((int32_t)right[i] - 128) / g_contrast_div);
        }
    }

    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = 47;
    cfg.vertical_search = vsearch;
    cfg.vertical_offset = fixed_off;
    if (g_top_permille >= 0) {
        cfg.canny_top_permille = g_top_permille;
    }
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &need), NEGOBS_OK);
    assert_true(need <= sizeof ws);
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws), NEGOBS_OK);
    assert_int_equal(negobs_stereo_set_first_row(&ctx, g_first_row),
                     NEGOBS_OK);
    if (g_hold_offset != NO_HOLD) {
        assert_int_equal(
            negobs_stereo_hold_vertical_offset(&ctx, g_hold_offset),
            NEGOBS_OK);
    }
    li.data = left;
    li.width = W;
    li.height = H;
    li.stride = W;
    ri = li;
    ri.data = right;
    ci = li;
    ci.data = conf;
    di.data = disp;
    di.width = W;
    di.height = H;
    di.stride = W;
    assert_int_equal(negobs_stereo_process(&ctx, &li, &ri, &di, &ci, &r.st),
                     NEGOBS_OK);
    check_confidence_scale();
    r.next_offset = r.st.vertical_offset;
    if (g_hold_offset != NO_HOLD) {
        negobs_stereo_stats_t st2;
        memcpy(disp_held, disp, sizeof disp);
        assert_int_equal(negobs_stereo_process(&ctx, &li, &ri, &di, &ci, &st2),
                         NEGOBS_OK);
        r.next_offset = st2.vertical_offset;
        memcpy(disp, disp_held, sizeof disp);
    }
    synth_score(&sc, disp, gt, occ, 6, 16, &r.bad1, &r.dens);
    synth_score(&sc, disp, gt, occ, 6, 8, &r.bad05, &r.dens);
    printf("# voff=%d search=%d: bad1=%d.%d%% bad0.5=%d.%d%% density=%d.%d%% "
           "seeds=%u grown=%u found_off=%d range=[%d,%d]\n",
           (int)voff, (int)vsearch, (int)(r.bad1 / 10), (int)(r.bad1 % 10),
           (int)(r.bad05 / 10), (int)(r.bad05 % 10), (int)(r.dens / 10),
           (int)(r.dens % 10), (unsigned)r.st.seeds, (unsigned)r.st.grown,
           (int)r.st.vertical_offset, (int)r.st.range_min,
           (int)r.st.range_max);
    return r;
}

/* bad1 (permille) and density over rows [y0, H - 6) only */
static void score_rows(int32_t y0, int32_t *bad1, int32_t *dens)
{
    synth_scene_t sc;
    static int16_t d2[W * H];
    static uint8_t o2[W * H];
    int32_t i;
    memset(&sc, 0, sizeof sc);
    sc.w = W;
    sc.h = H;
    /* rows above y0 are marked occluded, i.e. not scored */
    for (i = 0; i < W * H; i++) {
        d2[i] = disp[i];
        o2[i] = (uint8_t)(occ[i] || i / W < y0);
    }
    synth_score(&sc, d2, gt, o2, 6, 16, bad1, dens);
}

static void test_regress_first_row_crop(void **state)
{
    /* Matching only rows [40, 120): nothing above, the same quality below
     * the crop's border, and fewer cells visited. */
    result_t full;
    result_t crop;
    int32_t bad1;
    int32_t dens;
    int32_t i;
    negobs_stereo_t none;
    (void)state;
    full = run(0, 4, 0);
    g_first_row = 40;
    crop = run(0, 4, 0);
    g_first_row = 0;
    assert_int_equal(crop.st.first_row, 40);
    assert_int_equal(full.st.first_row, 0);
    for (i = 0; i < 40 * W; i++) {
        assert_int_equal(disp[i], NEGOBS_DISP_INVALID);
        assert_int_equal(conf[i], NEGOBS_STEREO_CONF_NONE);
    }
    /* like the frame's own border, the crop's first rows are not scored:
     * the 5x5 window does not fit there */
    score_rows(40 + 6, &bad1, &dens);
    printf("# first row 40: bad1 %d permille, density %d permille, visited "
           "%u (full frame %u)\n",
           (int)bad1, (int)dens, (unsigned)crop.st.visited_cells,
           (unsigned)full.st.visited_cells);
    assert_true(bad1 <= BAD1_MAX_PERMILLE);
    assert_true(dens >= DENS_MIN_PERMILLE);
    assert_true((uint64_t)crop.st.visited_cells * 100u <
                (uint64_t)full.st.visited_cells * 80u);
    /* bounds: a crop must keep the engine's smallest frame */
    none.priv = NULL;
    assert_int_equal(negobs_stereo_set_first_row(&none, 0), NEGOBS_ERR_STATE);
    assert_int_equal(negobs_stereo_set_first_row(NULL, 0), NEGOBS_ERR_STATE);
    {
        negobs_stereo_t ctx;
        negobs_stereo_config_t cfg;
        negobs_stereo_config_default(&cfg, W, H);
        cfg.max_disp = 47;
        assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws),
                         NEGOBS_OK);
        assert_int_equal(negobs_stereo_set_first_row(&ctx, -1),
                         NEGOBS_ERR_INVAL);
        assert_int_equal(negobs_stereo_set_first_row(
                             &ctx, H - NEGOBS_STEREO_MIN_HEIGHT + 1),
                         NEGOBS_ERR_INVAL);
        assert_int_equal(
            negobs_stereo_set_first_row(&ctx, H - NEGOBS_STEREO_MIN_HEIGHT),
            NEGOBS_OK);
    }
}

static void test_regress_rectified_pair(void **state)
{
    result_t r = run(0, 4, 0);
    (void)state;
    assert_int_equal(r.st.vertical_offset, 0);
    assert_true(r.bad1 <= BAD1_MAX_PERMILLE);
    assert_true(r.bad05 <= BAD05_MAX_PERMILLE);
    assert_true(r.dens >= DENS_MIN_PERMILLE);
    /* the range estimate must cover the scene (8 .. 36 px) and narrow the
     * configured 0 .. 47 (measured [2, 42]) */
    assert_true(r.st.range_min <= 8 && r.st.range_max >= 36);
    assert_true(r.st.range_min >= 2 && r.st.range_max <= 44);
    assert_int_equal(r.st.queue_overflows, 0);
}

static void test_regress_two_row_offset_is_found(void **state)
{
    result_t r = run(2, 4, 0);
    (void)state;
    assert_int_equal(r.st.vertical_offset, 2);
    assert_true(r.bad1 <= BAD1_MAX_PERMILLE);
    assert_true(r.dens >= DENS_MIN_PERMILLE - 20);
}

static void test_regress_negative_offset_is_found(void **state)
{
    result_t r = run(-3, 4, 0);
    (void)state;
    assert_int_equal(r.st.vertical_offset, -3);
    assert_true(r.bad1 <= BAD1_MAX_PERMILLE);
}

static void test_regress_uncompensated_offset_fails(void **state)
{
    /* Sanity of the test itself: with the offset ignored the map is bad. */
    result_t r = run(2, 0, 0);
    (void)state;
    assert_true(r.bad1 > BAD1_MAX_PERMILLE ||
                r.dens < DENS_MIN_PERMILLE - 200);
}

static void test_regress_fixed_offset(void **state)
{
    result_t r = run(2, 0, 2);
    (void)state;
    assert_int_equal(r.st.vertical_offset, 2);
    assert_true(r.bad1 <= BAD1_MAX_PERMILLE);
}

/* A held offset is the frame matched with that offset fixed (the same
 * map, bit for bit, as vertical_search = 0 with it configured); the hold
 * lasts one frame, the next one searches again; an offset outside the
 * search range is refused. */
static void test_regress_held_offset_is_one_frame_of_fixed_offset(void **state)
{
    static int16_t fixed[W * H];
    result_t r;
    result_t h;
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    size_t need;
    (void)state;
    r = run(2, 0, 2);
    memcpy(fixed, disp, sizeof disp);
    g_hold_offset = 2;
    h = run(2, 4, 0);
    g_hold_offset = NO_HOLD;
    assert_int_equal(h.st.vertical_offset, 2);
    assert_memory_equal(fixed, disp, sizeof disp);
    assert_int_equal(h.bad1, r.bad1);
    assert_int_equal(h.next_offset, 2);
    /* held wrong: that frame is matched with it (and is bad), the next
     * one finds the true offset again */
    g_hold_offset = 0;
    h = run(2, 4, 0);
    g_hold_offset = NO_HOLD;
    assert_int_equal(h.st.vertical_offset, 0);
    assert_true(h.bad1 > BAD1_MAX_PERMILLE ||
                h.dens < DENS_MIN_PERMILLE - 200);
    assert_int_equal(h.next_offset, 2);
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = 47;
    cfg.vertical_search = 2;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &need), NEGOBS_OK);
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws), NEGOBS_OK);
    assert_int_equal(negobs_stereo_hold_vertical_offset(&ctx, 3),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_stereo_hold_vertical_offset(&ctx, -3),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_stereo_hold_vertical_offset(&ctx, -2), NEGOBS_OK);
    assert_int_equal(negobs_stereo_hold_vertical_offset(NULL, 0),
                     NEGOBS_ERR_STATE);
}

static void test_regress_range_narrows_on_constant_scene(void **state)
{
    result_t r;
    (void)state;
    g_flat_scene = 1;
    r = run(0, 0, 0);
    g_flat_scene = 0;
    /* 20 px everywhere: 1/4-scale estimate 20, +-(2 + 4) margin */
    assert_int_equal(r.st.range_min, 14);
    assert_int_equal(r.st.range_max, 26);
    assert_true(r.bad1 <= BAD1_MAX_PERMILLE);
}

static void test_regress_range_covers_floor_unseen_at_quarter_scale(
    void **state)
{
    /* The floor's nearest 48 rows (37 .. 44 px in the bottom tile row)
     * have texture only at full resolution: the 1/4-scale map keeps no
     * value there, and the kept ones end near 30 px. A tile without a
     * value of its own is unknown, not narrow: it must be searched over
     * the configured range, or those rows can only get wrong values.
     * (Middlebury Bowling1's floor: range 2..90 used for GT up to 115 px,
     * 15.6 % of its pixels out of reach.) */
    result_t r;
    int32_t bad1;
    int32_t dens;
    (void)state;
    g_near_scene = 1;
    r = run(0, 0, 0);
    g_near_scene = 0;
    score_rows(96, &bad1, &dens);
    printf("# floor rows 96..113: bad1 %d permille, density %d permille, "
           "range [%d, %d]\n",
           (int)bad1, (int)dens, (int)r.st.range_min, (int)r.st.range_max);
    assert_true(bad1 <= BAD1_MAX_PERMILLE);
    assert_true(dens >= DENS_MIN_PERMILLE);
    assert_true(r.st.range_max >= 44);
}

/* A low-contrast pair (the texture at a sixth of its contrast): no
 * gradient reaches the fixed strong threshold, so without the strips'
 * own strongest share (canny_top_permille 0) there is no seed and
 * nothing is matched; with it the pair is matched almost as well as at
 * full contrast. On the full-contrast pair the share changes nothing. */
static void test_regress_low_contrast_pair_gets_seeds(void **state)
{
    static int16_t full[W * H];
    result_t r;
    (void)state;
    r = run(0, 4, 0);
    memcpy(full, disp, sizeof full);
    g_top_permille = 0;
    r = run(0, 4, 0);
    assert_memory_equal(disp, full, sizeof full);
    g_contrast_div = 6;
    r = run(0, 4, 0);
    assert_int_equal(r.st.seeds, 0);
    assert_true(r.dens < 100);
    g_top_permille = -1;
    r = run(0, 4, 0);
    g_contrast_div = 0;
    assert_true(r.st.seeds > 0);
    assert_true(r.bad1 <= 2 * BAD1_MAX_PERMILLE);
    assert_true(r.dens >= DENS_MIN_PERMILLE - 20);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_regress_rectified_pair),
        cmocka_unit_test(test_regress_two_row_offset_is_found),
        cmocka_unit_test(test_regress_negative_offset_is_found),
        cmocka_unit_test(test_regress_uncompensated_offset_fails),
        cmocka_unit_test(test_regress_fixed_offset),
        cmocka_unit_test(
            test_regress_held_offset_is_one_frame_of_fixed_offset),
        cmocka_unit_test(test_regress_range_narrows_on_constant_scene),
        cmocka_unit_test(test_regress_first_row_crop),
        cmocka_unit_test(
            test_regress_range_covers_floor_unseen_at_quarter_scale),
        cmocka_unit_test(test_regress_low_contrast_pair_gets_seeds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
