/*
 * The engine's probes:
 *  - per-stage profiling clock (negobs_stereo_set_clock): a fake clock
 *    that advances a fixed step per read shows which stage every read
 *    closes, so the attribution is checked exactly; the output must not
 *    depend on the clock; the counter may wrap;
 *  - observer of intermediate maps (negobs_stereo_set_observer): the
 *    stages it reports, and each snapshot equals the final output of a
 *    run with the later stages switched off.
 */
#include <stdio.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "scene_pair.h"

#define W 160
#define H 120
#define DMAX 47
#define STRIP 32

static uint8_t left[W * H];
static uint8_t right[W * H];
static uint8_t tex[W * H];
static uint8_t occ[W * H];
static int16_t gt[W * H];
static int16_t disp[W * H];
static int16_t disp_ref[W * H];
static uint8_t conf[W * H];
static uint8_t conf_ref[W * H];
static uint8_t ws[NEGOBS_STEREO_WORKSPACE_MAX(W, H, DMAX)]
    __attribute__((aligned(16)));

typedef struct fake_clock {
    uint32_t now;
    uint32_t step;
    uint32_t reads;
} fake_clock_t;

static uint32_t fake_read(void *user)
{
    fake_clock_t *c = (fake_clock_t *)user;
    uint32_t t = c->now;
    c->now += c->step;
    c->reads++;
    return t;
}

static void render(void)
{
    synth_scene_t sc;
    sc.w = W;
    sc.h = H;
    sc.d_top_q8 = 8 * 256;
    sc.d_bottom_q8 = 28 * 256;
    sc.drop_q8 = 5 * 256;
    sc.box_q8 = 36 * 256;
    sc.voff = 2;
    sc.seed = 777u;
    synth_render(&sc, left, right, gt, occ, tex);
}

static void setup_ctx(negobs_stereo_t *ctx, negobs_stereo_config_t *cfg)
{
    size_t need;
    assert_int_equal(negobs_stereo_workspace_size(cfg, &need), NEGOBS_OK);
    assert_true(need <= sizeof ws);
    assert_int_equal(negobs_stereo_init(ctx, cfg, ws, sizeof ws), NEGOBS_OK);
}

static void run(negobs_stereo_t *ctx, int16_t *d, uint8_t *c,
                negobs_stereo_stats_t *st)
{
    negobs_image_u8_t li = {left, W, H, W};
    negobs_image_u8_t ri = {right, W, H, W};
    negobs_image_u8_t ci = {c, W, H, W};
    negobs_image_s16_t di = {d, W, H, W};
    assert_int_equal(negobs_stereo_process(ctx, &li, &ri, &di, &ci, st),
                     NEGOBS_OK);
}

static void base_config(negobs_stereo_config_t *cfg)
{
    negobs_stereo_config_default(cfg, W, H);
    cfg->max_disp = DMAX;
    cfg->strip_rows = STRIP;
}

/* Reads that close each stage, for `rows` matched rows. */
static void expected_laps(const negobs_stereo_config_t *cfg, int32_t rows,
                          uint32_t laps[NEGOBS_STEREO_STAGE_COUNT])
{
    uint32_t strips = (uint32_t)((rows + cfg->strip_rows - 1) /
                                 cfg->strip_rows);
    memset(laps, 0, sizeof(uint32_t) * NEGOBS_STEREO_STAGE_COUNT);
    laps[NEGOBS_STEREO_STAGE_VERTICAL] = 1u;
    laps[NEGOBS_STEREO_STAGE_RANGE] = 1u;
    laps[NEGOBS_STEREO_STAGE_WINDOWS] = 2u * strips; /* both passes */
    laps[NEGOBS_STEREO_STAGE_CANNY] = strips;
    laps[NEGOBS_STEREO_STAGE_GCS] = strips + 1u;     /* + the seam rule */
    laps[NEGOBS_STEREO_STAGE_DP] = 2u * strips + 1u; /* + stage 2 */
    laps[NEGOBS_STEREO_STAGE_LR] = cfg->lr_check ? 1u : 0u;
    laps[NEGOBS_STEREO_STAGE_SPECKLE] = 1u;
    laps[NEGOBS_STEREO_STAGE_GAP_FILL] = cfg->gap_fill > 0 ? 1u : 0u;
    laps[NEGOBS_STEREO_STAGE_MEAN] = cfg->adaptive_mean ? 1u : 0u;
    laps[NEGOBS_STEREO_STAGE_OUTPUT] = 1u;
}

static void check_attribution(const negobs_stereo_stats_t *st,
                              const fake_clock_t *fc, uint32_t step,
                              const uint32_t laps[NEGOBS_STEREO_STAGE_COUNT])
{
    uint64_t sum = 0;
    uint32_t total_laps = 0;
    int k;
    for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
        printf("# stage %d: %llu ticks (expected %llu)\n", k,
               (unsigned long long)st->stage_ticks[k],
               (unsigned long long)laps[k] * step);
        assert_int_equal(st->stage_ticks[k], (uint64_t)laps[k] * step);
        sum += st->stage_ticks[k];
        total_laps += laps[k];
    }
    /* one read opens the frame, every other read closes one stage */
    assert_int_equal(fc->reads, total_laps + 1u);
    assert_int_equal(sum, (uint64_t)(fc->reads - 1u) * step);
}

/* Init on cfg, crop to first_row, time one frame with fc and check that
 * every read of fc went to the stage it closes. */
static void timed_frame(negobs_stereo_t *ctx,
                        const negobs_stereo_config_t *cfg, int32_t first_row,
                        fake_clock_t *fc, negobs_stereo_stats_t *st)
{
    uint32_t laps[NEGOBS_STEREO_STAGE_COUNT];
    negobs_stereo_config_t c = *cfg;
    render();
    setup_ctx(ctx, &c);
    assert_int_equal(negobs_stereo_set_first_row(ctx, first_row), NEGOBS_OK);
    assert_int_equal(negobs_stereo_set_clock(ctx, fake_read, fc), NEGOBS_OK);
    run(ctx, disp, conf, st);
    expected_laps(cfg, H - first_row, laps);
    check_attribution(st, fc, fc->step, laps);
}

static void test_every_tick_goes_to_the_stage_that_ran(void **state)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    fake_clock_t fc = {1000u, 7u, 0u};
    uint32_t laps[NEGOBS_STEREO_STAGE_COUNT];
    (void)state;
    base_config(&cfg);
    timed_frame(&ctx, &cfg, 0, &fc, &st);

    /* a second frame starts from zero, not from the first frame's sums */
    fc.reads = 0;
    run(&ctx, disp, conf, &st);
    expected_laps(&cfg, H, laps);
    check_attribution(&st, &fc, 7u, laps);
}

static void test_stages_switched_off_get_no_ticks(void **state)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    fake_clock_t fc = {0u, 1u, 0u};
    (void)state;
    base_config(&cfg);
    cfg.lr_check = 0;
    cfg.gap_fill = 0;
    cfg.adaptive_mean = 0;
    timed_frame(&ctx, &cfg, 0, &fc, &st);
    assert_int_equal(st.stage_ticks[NEGOBS_STEREO_STAGE_LR], 0u);
    assert_int_equal(st.stage_ticks[NEGOBS_STEREO_STAGE_GAP_FILL], 0u);
    assert_int_equal(st.stage_ticks[NEGOBS_STEREO_STAGE_MEAN], 0u);
}

/* A crop matches fewer strips; clearing the rows above is OUTPUT. The
 * counter wraps through 2^32 during the frame. */
static void test_crop_and_wrapping_counter(void **state)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    fake_clock_t fc = {0xFFFFFF00u, 13u, 0u};
    (void)state;
    base_config(&cfg);
    timed_frame(&ctx, &cfg, 50, &fc, &st);
    assert_true(fc.now < 0x1000u); /* it did wrap */
}

/* Each read advances 1.5 * 2^30 ticks: every interval is below 2^32, but
 * the GCS and DP sums pass 2^32 and must not wrap (a nanosecond clock on
 * a slow target does this after 4.3 s of one stage). */
static void test_stage_sums_beyond_32_bits(void **state)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    fake_clock_t fc = {0u, 0x60000000u, 0u};
    (void)state;
    base_config(&cfg);
    timed_frame(&ctx, &cfg, 0, &fc, &st);
    assert_true(st.stage_ticks[NEGOBS_STEREO_STAGE_DP] > 0xFFFFFFFFull);
}

static void test_output_does_not_depend_on_the_clock(void **state)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    negobs_stereo_stats_t st_ref;
    fake_clock_t fc = {5u, 3u, 0u};
    int k;
    (void)state;
    render();
    base_config(&cfg);
    setup_ctx(&ctx, &cfg);
    run(&ctx, disp_ref, conf_ref, &st_ref);
    for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
        assert_int_equal(st_ref.stage_ticks[k], 0u); /* no clock: zeros */
    }
    assert_int_equal(negobs_stereo_set_clock(&ctx, fake_read, &fc), NEGOBS_OK);
    run(&ctx, disp, conf, &st);
    assert_true(fc.reads > 0u);
    assert_memory_equal(disp, disp_ref, sizeof disp);
    assert_memory_equal(conf, conf_ref, sizeof conf);
    memset(st.stage_ticks, 0, sizeof st.stage_ticks);
    assert_memory_equal(&st, &st_ref, sizeof st);
    assert_true(st.valid > (uint32_t)(W * H / 2)); /* a real map */

    /* NULL switches it off again */
    assert_int_equal(negobs_stereo_set_clock(&ctx, NULL, NULL), NEGOBS_OK);
    fc.reads = 0;
    run(&ctx, disp, conf, &st);
    assert_int_equal(fc.reads, 0u);
    assert_int_equal(st.stage_ticks[NEGOBS_STEREO_STAGE_GCS], 0u);
}

static void test_clock_without_init_is_a_state_error(void **state)
{
    negobs_stereo_t none;
    (void)state;
    memset(&none, 0, sizeof none);
    assert_int_equal(negobs_stereo_set_clock(&none, fake_read, NULL),
                     NEGOBS_ERR_STATE);
    assert_int_equal(negobs_stereo_set_clock(NULL, fake_read, NULL),
                     NEGOBS_ERR_STATE);
}

#define MAX_CALLS 16

typedef struct observed {
    int n;
    negobs_stereo_stage_t stage[MAX_CALLS];
    int32_t height[MAX_CALLS];
    int16_t map[MAX_CALLS][W * H]; /* rows of the view passed */
} observed_t;

static observed_t g_obs;

static void observe(void *user, negobs_stereo_stage_t stage,
                    const negobs_image_s16_t *d)
{
    observed_t *o = (observed_t *)user;
    int32_t y;
    assert_true(o->n < MAX_CALLS);
    assert_int_equal(d->width, W);
    o->stage[o->n] = stage;
    o->height[o->n] = d->height;
    for (y = 0; y < d->height; y++) {
        memcpy(&o->map[o->n][y * W], negobs_image_s16_row(d, y),
               W * sizeof(int16_t));
    }
    o->n++;
}

/* Final map of a run with only the stages up to `last` switched on. */
static void run_up_to(negobs_stereo_stage_t last, int16_t *out)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    base_config(&cfg);
    cfg.lr_check = last >= NEGOBS_STEREO_STAGE_LR;
    cfg.speckle_size = (last >= NEGOBS_STEREO_STAGE_SPECKLE) ? cfg.speckle_size
                                                             : 0;
    cfg.gap_fill = (last >= NEGOBS_STEREO_STAGE_GAP_FILL) ? cfg.gap_fill : 0;
    cfg.adaptive_mean = last >= NEGOBS_STEREO_STAGE_MEAN;
    setup_ctx(&ctx, &cfg);
    run(&ctx, out, conf_ref, &st);
}

static int32_t count_valid(const int16_t *m, int32_t n)
{
    int32_t i;
    int32_t v = 0;
    for (i = 0; i < n; i++) {
        v += m[i] != NEGOBS_DISP_INVALID;
    }
    return v;
}

static void test_observer_sees_every_stage_in_order(void **state)
{
    static const negobs_stereo_stage_t want[] = {
        NEGOBS_STEREO_STAGE_GCS,      NEGOBS_STEREO_STAGE_DP,
        NEGOBS_STEREO_STAGE_LR,       NEGOBS_STEREO_STAGE_SPECKLE,
        NEGOBS_STEREO_STAGE_GAP_FILL, NEGOBS_STEREO_STAGE_MEAN};
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    int32_t i;
    int32_t k;
    int32_t gcs_valid;
    int32_t gcs_bad = 0;
    (void)state;
    render();
    base_config(&cfg);
    setup_ctx(&ctx, &cfg);
    memset(&g_obs, 0, sizeof g_obs);
    assert_int_equal(negobs_stereo_set_observer(&ctx, observe, &g_obs),
                     NEGOBS_OK);
    run(&ctx, disp, conf, &st);
    assert_int_equal(g_obs.n, 6);
    for (k = 0; k < 6; k++) {
        assert_int_equal(g_obs.stage[k], want[k]);
        assert_int_equal(g_obs.height[k], H);
    }
    /* the last snapshot is the output */
    assert_memory_equal(g_obs.map[5], disp, sizeof disp);
    /* each refinement snapshot is what a run stopping there returns */
    for (k = 1; k < 5; k++) {
        run_up_to(want[k], disp_ref);
        assert_memory_equal(g_obs.map[k], disp_ref, sizeof disp_ref);
    }
    /* after GCS: sparse whole-pixel matches, right where they exist
     * (GT in 1/16 px; the generated pair's occluded strips excluded) */
    gcs_valid = count_valid(g_obs.map[0], W * H);
    for (i = 0; i < W * H; i++) {
        int32_t d = g_obs.map[0][i];
        if (d == NEGOBS_DISP_INVALID || occ[i]) {
            continue;
        }
        assert_true(d >= 0 && d <= DMAX);
        gcs_bad += (d * 16 - gt[i] > 16 || gt[i] - d * 16 > 16);
    }
    printf("# GCS %d valid, %d off by > 1 px; DP %d valid\n", (int)gcs_valid,
           (int)gcs_bad, (int)count_valid(g_obs.map[1], W * H));
    assert_true(gcs_valid > W * H / 4);
    assert_true(gcs_bad * 100 <= gcs_valid); /* <= 1 % wrong */
    assert_true(count_valid(g_obs.map[1], W * H) > gcs_valid);
}

static void test_observer_with_stages_off_crop_and_clock(void **state)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    fake_clock_t fc = {0u, 5u, 0u};
    uint32_t laps[NEGOBS_STEREO_STAGE_COUNT];
    (void)state;
    render();
    base_config(&cfg);
    cfg.lr_check = 0;
    cfg.gap_fill = 0;
    cfg.adaptive_mean = 0;
    setup_ctx(&ctx, &cfg);
    run(&ctx, disp_ref, conf_ref, &st); /* reference without probes */
    memset(&g_obs, 0, sizeof g_obs);
    assert_int_equal(negobs_stereo_set_observer(&ctx, observe, &g_obs),
                     NEGOBS_OK);
    assert_int_equal(negobs_stereo_set_clock(&ctx, fake_read, &fc), NEGOBS_OK);
    run(&ctx, disp, conf, &st);
    assert_memory_equal(disp, disp_ref, sizeof disp);
    assert_int_equal(g_obs.n, 3);
    assert_int_equal(g_obs.stage[0], NEGOBS_STEREO_STAGE_GCS);
    assert_int_equal(g_obs.stage[1], NEGOBS_STEREO_STAGE_DP);
    assert_int_equal(g_obs.stage[2], NEGOBS_STEREO_STAGE_SPECKLE);
    /* one more clock read after each observer call; its time is in no
     * stage, so the per-stage sums are as without the observer */
    expected_laps(&cfg, H, laps);
    {
        uint32_t reads = fc.reads;
        int k;
        uint32_t total = 1u;
        for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
            assert_int_equal(st.stage_ticks[k], (uint64_t)laps[k] * 5u);
            total += laps[k];
        }
        assert_int_equal(reads, total + 3u);
    }

    /* a crop: the observer gets the view of the matched rows */
    memset(&g_obs, 0, sizeof g_obs);
    assert_int_equal(negobs_stereo_set_first_row(&ctx, 40), NEGOBS_OK);
    run(&ctx, disp, conf, &st);
    assert_int_equal(g_obs.n, 3);
    assert_int_equal(g_obs.height[2], H - 40);
    assert_memory_equal(g_obs.map[2], disp + 40 * W,
                        (size_t)(H - 40) * W * sizeof(int16_t));

    assert_int_equal(negobs_stereo_set_observer(&ctx, NULL, NULL), NEGOBS_OK);
    memset(&g_obs, 0, sizeof g_obs);
    run(&ctx, disp, conf, &st);
    assert_int_equal(g_obs.n, 0);
    assert_int_equal(negobs_stereo_set_observer(NULL, observe, &g_obs),
                     NEGOBS_ERR_STATE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_tick_goes_to_the_stage_that_ran),
        cmocka_unit_test(test_stages_switched_off_get_no_ticks),
        cmocka_unit_test(test_crop_and_wrapping_counter),
        cmocka_unit_test(test_stage_sums_beyond_32_bits),
        cmocka_unit_test(test_output_does_not_depend_on_the_clock),
        cmocka_unit_test(test_clock_without_init_is_a_state_error),
        cmocka_unit_test(test_observer_sees_every_stage_in_order),
        cmocka_unit_test(test_observer_with_stages_off_crop_and_clock),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
