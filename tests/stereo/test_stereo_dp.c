/* Banded two-stage DP: bands, confinement, hole filling, empty rows. */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "stereo/stereo_int.h"

#define W 96
#define H 32

static uint8_t left[W * H];
static uint8_t right[W * H];
static int16_t gcs[H * W];
static int16_t out[W];
static uint8_t conf[W];
static uint8_t ws[NEGOBS_STEREO_WORKSPACE_MAX(W, H, 31)]
    __attribute__((aligned(16)));
static negobs_image_u8_t li;
static negobs_image_u8_t ri;

/* Right = left shifted by 5 px: true disparity 5 everywhere. */
static int g_rescore;

static stx_t *setup(int32_t band)
{
    static negobs_stereo_t ctx;
    negobs_stereo_config_t cfg;
    stx_t *s;
    uint32_t seed = 77u;
    int32_t x;
    int32_t y;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            left[y * W + x] = (uint8_t)test_lcg_next(&seed);
        }
        for (x = 0; x < W; x++) {
            right[y * W + x] = left[y * W + ((x + 5 < W) ? x + 5 : W - 1)];
        }
    }
    li.data = left;
    li.width = W;
    li.height = H;
    li.stride = W;
    ri = li;
    ri.data = right;
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = 31;
    cfg.band = band;
    cfg.dp_rescore = g_rescore;
    assert_int_equal(negobs_stereo_init(&ctx, &cfg, ws, sizeof ws), NEGOBS_OK);
    s = (stx_t *)ctx.priv;
    s->left = &li;
    s->right = &ri;
    s->voff = 0;
    s->gdmin = 0;
    s->gdmax = 31;
    stx_strip_stats(s, 0, H);
    return s;
}

static void run_rows(stx_t *s)
{
    int32_t y;
    stx_dp_stage2_reset(s);
    for (y = 0; y < H; y++) {
        stx_dp_row(s, y, gcs + y * W, 0, NULL, NULL);
    }
    stx_dp_stage2_finish(s);
}

static void test_dp_fills_holes_between_matches(void **state)
{
    stx_t *s = setup(2);
    int32_t x;
    int32_t y;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            gcs[y * W + x] = (int16_t)((x % 16 == 8) ? 5
                                                     : NEGOBS_DISP_INVALID);
        }
    }
    run_rows(s);
    stx_dp_row(s, 10, gcs + 10 * W, 1, out, conf);
    /* bands: matched [3, 7]; hole between two 5s: [3, 7] too */
    assert_int_equal(s->blo[8], 3);
    assert_int_equal(s->bhi[8], 7);
    assert_int_equal(s->bscored[8], 1);
    assert_int_equal(s->bscored[9], 0);
    for (x = 8; x < W - 8; x++) {
        assert_true(out[x] >= 5 * 16 - 8 && out[x] <= 5 * 16 + 8);
    }
    assert_true(conf[8] > 200);
}

static void test_dp_stays_inside_the_band(void **state)
{
    stx_t *s = setup(1);
    int32_t x;
    int32_t y;
    (void)state;
    /* a wrong GCS map (d = 12): the band keeps the DP at 11..13 */
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            gcs[y * W + x] = 12;
        }
    }
    run_rows(s);
    stx_dp_row(s, 12, gcs + 12 * W, 1, out, conf);
    for (x = 0; x < W; x++) {
        assert_true(out[x] >= 11 * 16 - 8 && out[x] <= 13 * 16 + 8);
        assert_true(conf[x] < 128);
    }
    /* the right one (d = 5) with band 1 is found, with high confidence */
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            gcs[y * W + x] = 5;
        }
    }
    run_rows(s);
    stx_dp_row(s, 12, gcs + 12 * W, 1, out, conf);
    for (x = 10; x < W - 10; x++) {
        assert_true(out[x] >= 5 * 16 - 8 && out[x] <= 5 * 16 + 8);
        assert_true(conf[x] > 200);
    }
}

static void test_dp_row_without_matches_is_invalid(void **state)
{
    stx_t *s = setup(2);
    int32_t x;
    int32_t y;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            gcs[y * W + x] = (int16_t)((y == 7) ? NEGOBS_DISP_INVALID : 5);
        }
    }
    run_rows(s);
    stx_dp_row(s, 7, gcs + 7 * W, 1, out, conf);
    for (x = 0; x < W; x++) {
        assert_int_equal(out[x], NEGOBS_DISP_INVALID);
        assert_int_equal(conf[x], 0);
    }
    /* stage 2 carried through the empty row */
    assert_int_equal(s->dend[6], s->dend[8]);
}

static void test_dp_jump_follows_a_step_in_the_band(void **state)
{
    stx_t *s = setup(1);
    int32_t x;
    int32_t y;
    (void)state;
    /* band centres jump from 5 to 20 (no |dd| <= 1 path exists) */
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            gcs[y * W + x] = (int16_t)((x < 48) ? 5 : 20);
        }
    }
    run_rows(s);
    stx_dp_row(s, 12, gcs + 12 * W, 1, out, conf);
    print_message("out[30]=%d out[60]=%d\n", out[30], out[60]);
    assert_true(out[30] >= 4 * 16 && out[30] <= 6 * 16);
    assert_true(out[60] >= 19 * 16 - 8 && out[60] <= 21 * 16 + 8);
}

static void test_dp_rescore_corrects_an_off_by_one_gcs_map(void **state)
{
    stx_t *s;
    int32_t x;
    int32_t y;
    uint32_t before;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            gcs[y * W + x] = 4; /* true disparity is 5 */
        }
    }
    /* default: only the GCS cell is scored, the DP keeps 4 */
    s = setup(2);
    run_rows(s);
    stx_dp_row(s, 12, gcs + 12 * W, 1, out, conf);
    assert_true(out[40] >= 4 * 16 - 8 && out[40] <= 4 * 16 + 8);
    /* dp_rescore: every band cell is correlated, 5 wins */
    g_rescore = 1;
    s = setup(2);
    g_rescore = 0;
    before = s->st.visited_cells;
    run_rows(s);
    stx_dp_row(s, 12, gcs + 12 * W, 1, out, conf);
    assert_true(out[40] >= 5 * 16 - 8 && out[40] <= 5 * 16 + 8);
    assert_true(s->st.visited_cells > before);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dp_fills_holes_between_matches),
        cmocka_unit_test(test_dp_stays_inside_the_band),
        cmocka_unit_test(test_dp_row_without_matches_is_invalid),
        cmocka_unit_test(test_dp_jump_follows_a_step_in_the_band),
        cmocka_unit_test(test_dp_rescore_corrects_an_off_by_one_gcs_map),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
