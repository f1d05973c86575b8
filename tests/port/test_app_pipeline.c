/* negobs_run's processing hook: the detector's photometric gate on both
 * images, the left/right check, and their verdicts. */
#include <string.h>

#include "app_pipeline.h"
#include "cmocka_all.h"

#define W 64
#define H 48
#define S 80 /* padded stride */

static uint8_t left_px[H * S];
static uint8_t right_px[H * S];
static uint8_t big[800 * 1280];

/* Fill w x h (stride s) with values lo..lo+span-1; padding gets 255. */
static void fill(uint8_t *px, int32_t w, int32_t h, int32_t s, uint32_t seed,
                 uint32_t lo, uint32_t span)
{
    int32_t x;
    int32_t y;
    for (y = 0; y < h; y++) {
        for (x = 0; x < s; x++) {
            uint32_t v = span > 0 ? lo + test_lcg_next(&seed) % span : lo;
            px[y * s + x] = x < w ? (uint8_t)v : 255;
        }
    }
}

static negobs_image_u8_t img(uint8_t *px)
{
    negobs_image_u8_t i = {px, W, H, S};
    return i;
}

static app_pipeline_t pipe_init(void)
{
    app_pipeline_t p;
    app_pipeline_config_t c;
    app_pipeline_config_default(&c);
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
    return p;
}

static app_verdict_t run(app_pipeline_t *p)
{
    negobs_image_u8_t l = img(left_px);
    negobs_image_u8_t r = img(right_px);
    return app_process_pair(p, &l, &r);
}

static void test_unrelated_textured_pair_is_never_clear(void **state)
{
    app_pipeline_t p = pipe_init();
    (void)state;
    fill(left_px, W, H, S, 1, 40, 160);
    fill(right_px, W, H, S, 2, 40, 160);
    /* Passes the photometric gate, but two unrelated noise images show no
     * ground: the detector must say no-information, not clear. */
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_DETECTOR);
    assert_true(p.last.detect_reasons != 0);
    assert_in_range(p.last.mean[0], 110, 130);
    /* The 255 padding beyond the width is not counted as saturation. */
    assert_int_equal(p.last.sat_permille[0], 0);
    assert_true(p.last.texture_q4[1] > 16 * 24);
}

/* The right image alone decides each of these: the pipeline's one gate
 * judges both images (it judged only the left before the app's own gate
 * was folded into it). */
static void test_unusable_images_give_no_info_with_reason(void **state)
{
    app_pipeline_t p = pipe_init();
    (void)state;
    fill(left_px, W, H, S, 1, 40, 160);
    fill(right_px, W, H, S, 2, 0, 10); /* dark */
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_DARK);
    fill(right_px, W, H, S, 2, 250, 6); /* blinded */
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_SATURATED);
    fill(right_px, W, H, S, 2, 128, 0); /* flat: lens covered, fog */
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_TEXTURELESS);
    assert_int_equal(p.last.texture_q4[1], 0);
    fill(left_px, W, H, S, 1, 40, 100);   /* mean ~90 */
    fill(right_px, W, H, S, 2, 140, 100); /* mean ~190 */
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_MISMATCH);
    assert_string_equal(app_reason_name(p.last.reason), "lr-mismatch");
}

static void test_bad_input_gives_no_info(void **state)
{
    app_pipeline_t p = pipe_init();
    negobs_image_u8_t l = img(left_px);
    negobs_image_u8_t r = img(right_px);
    app_pipeline_config_t c;
    (void)state;
    fill(left_px, W, H, S, 1, 40, 160);
    fill(right_px, W, H, S, 2, 40, 160);
    r.width = W - 2;
    assert_int_equal(app_process_pair(&p, &l, &r), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_BAD_INPUT);
    l.data = NULL;
    r.width = W;
    assert_int_equal(app_process_pair(&p, &l, &r), APP_VERDICT_NO_INFO);
    assert_int_equal(app_process_pair(&p, NULL, &r), APP_VERDICT_NO_INFO);
    app_pipeline_config_default(&c);
    c.sat_permille_max = 1001;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_ERR_INVAL);
    app_pipeline_config_default(&c);
    assert_int_equal(c.row_crop, 1);
    c.row_crop = 2;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_ERR_INVAL);
    c.row_crop = 0;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
}

static void test_too_large_frames_give_no_info(void **state)
{
    app_pipeline_t p;
    app_pipeline_config_t c;
    negobs_image_u8_t l = {big, 1280, 800, 1280};
    (void)state;
    app_pipeline_config_default(&c);
    c.max_disp = 127;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
    fill(big, 1280, 800, 1280, 3, 40, 160);
    /* The pipeline's static workspace does not fit 1280x800 with 128
     * disparities (about 8 MB), which must give no-info, not a crash or
     * "clear". */
    assert_int_equal(app_process_pair(&p, &l, &l), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_BAD_INPUT);
}

/* The matcher gets the fast profile's memo where the static workspace
 * holds it beside the threads asked for: at 320x240 with 1 or 2 threads
 * it does (about 2.4 / 4.4 MB of the 7). The largest supported frame
 * with 4 threads still runs, on what fits. The cases with threads run in
 * native builds only (qemu-user hangs in clone(); tests/port/meson.build). */
static void test_matcher_setup_follows_the_workspace(void **state)
{
    app_pipeline_t p;
    app_pipeline_config_t c;
    negobs_image_u8_t small = {big, 320, 240, 320};
    (void)state;
    app_pipeline_config_default(&c);
    c.threads = 1;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
    fill(big, 320, 240, 320, 5, 40, 160);
    (void)app_process_pair(&p, &small, &small);
    assert_int_not_equal(p.last.reason, APP_REASON_BAD_INPUT);
    assert_int_equal(p.last.matcher_threads, 1);
    assert_int_equal(p.last.memory_profile, NEGOBS_STEREO_PROFILE_FAST);
#if defined(NEGOBS_TEST_THREADS)
    {
        negobs_image_u8_t duo = {big, 752, 480, 752};
        c.threads = 2;
        assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
        (void)app_process_pair(&p, &small, &small);
        assert_int_not_equal(p.last.reason, APP_REASON_BAD_INPUT);
        assert_int_equal(p.last.matcher_threads, 2);
        assert_int_equal(p.last.memory_profile, NEGOBS_STEREO_PROFILE_FAST);

        c.threads = 4;
        assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
        fill(big, 752, 480, 752, 6, 40, 160);
        (void)app_process_pair(&p, &duo, &duo);
        assert_int_not_equal(p.last.reason, APP_REASON_BAD_INPUT);
        assert_in_range(p.last.matcher_threads, 1, 4);
        assert_true(p.last.memory_profile == NEGOBS_STEREO_PROFILE_FAST ||
                    p.last.memory_profile == NEGOBS_STEREO_PROFILE_COMPACT);
    }
#endif
}

/* One home for the photometric thresholds: the app's defaults are the
 * detector's, and what the user sets reaches the detector's gate. */
static void test_gate_thresholds_are_the_detectors(void **state)
{
    app_pipeline_t p = pipe_init();
    app_pipeline_config_t c;
    negobs_detect_config_t d;
    (void)state;
    negobs_detect_config_default(&d, W, H);
    app_pipeline_config_default(&c);
    assert_int_equal(c.dark_mean_min, d.dark_mean_min);
    assert_int_equal(c.sat_permille_max, d.saturated_max_permille);
    assert_int_equal(c.texture_min_q4, d.texture_min_q4);
    fill(left_px, W, H, S, 1, 40, 160);
    fill(right_px, W, H, S, 2, 40, 160);
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_DETECTOR);
    c.texture_min_q4 = 4096; /* no image is that textured */
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_TEXTURELESS);
    app_pipeline_config_default(&c);
    c.dark_mean_min = 200; /* both images have a mean near 120 */
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
    assert_int_equal(run(&p), APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_DARK);
}

static void test_late_clear_is_not_trusted(void **state)
{
    /* The budget (250 ms by default) applies to "clear" only: one over
     * it is no-info with reason "late"; warnings pass however late; at
     * the budget, or with the guard off, nothing changes. */
    app_pipeline_t p = pipe_init();
    app_pipeline_config_t c;
    (void)state;
    assert_int_equal(p.cfg.latency_budget_ms, 250);
    assert_int_equal(app_pipeline_latency_gate(&p, APP_VERDICT_CLEAR, 250),
                     APP_VERDICT_CLEAR);
    assert_int_equal(p.last.latency_ms, 250);
    assert_int_equal(app_pipeline_latency_gate(&p, APP_VERDICT_CLEAR, 251),
                     APP_VERDICT_NO_INFO);
    assert_int_equal(p.last.reason, APP_REASON_LATE);
    assert_string_equal(app_reason_name(p.last.reason), "late");
    assert_int_equal(app_pipeline_latency_gate(&p, APP_VERDICT_CAUTION, 5000),
                     APP_VERDICT_CAUTION);
    assert_int_equal(app_pipeline_latency_gate(&p, APP_VERDICT_IMMINENT, 5000),
                     APP_VERDICT_IMMINENT);
    assert_int_equal(app_pipeline_latency_gate(&p, APP_VERDICT_NO_INFO, 5000),
                     APP_VERDICT_NO_INFO);
    /* a clock that went backwards is not "late" */
    assert_int_equal(app_pipeline_latency_gate(&p, APP_VERDICT_CLEAR, -40),
                     APP_VERDICT_CLEAR);
    assert_int_equal(p.last.latency_ms, 0);
    app_pipeline_config_default(&c);
    c.latency_budget_ms = 0;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_OK);
    assert_int_equal(app_pipeline_latency_gate(&p, APP_VERDICT_CLEAR, 60000),
                     APP_VERDICT_CLEAR);
    c.latency_budget_ms = -1;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_ERR_INVAL);
    c.latency_budget_ms = 60001;
    assert_int_equal(app_pipeline_init(&p, &c), NEGOBS_ERR_INVAL);
    assert_int_equal(app_pipeline_latency_gate(NULL, APP_VERDICT_CLEAR, 0),
                     APP_VERDICT_NO_INFO);
}

/* Fake nanosecond counter: 1000 ns (1 us) per read. */
static uint32_t fake_ns(void *user)
{
    uint32_t *t = (uint32_t *)user;
    *t += 1000u;
    return *t;
}

static void test_stage_clock_fills_stage_times(void **state)
{
    app_pipeline_t p = pipe_init();
    uint32_t t = 0;
    uint32_t sum = 0;
    app_verdict_t v0;
    int k;
    (void)state;
    fill(left_px, W, H, S, 1, 40, 160);
    fill(right_px, W, H, S, 2, 40, 160);
    v0 = run(&p);
    assert_int_equal(p.last.stereo_us, 0u); /* no clock: nothing timed */
    assert_int_equal(p.last.stage_us[NEGOBS_STEREO_STAGE_GCS], 0u);

    app_pipeline_set_clock(&p, fake_ns, &t);
    assert_int_equal(run(&p), v0);
    for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
        sum += p.last.stage_us[k];
    }
    /* every read after the first closes one stage: 1 us each; the
     * pipeline reads the same clock around its own stages, so the
     * matcher's share is less than all the reads */
    assert_true(p.last.stage_us[NEGOBS_STEREO_STAGE_GCS] >= 1u);
    assert_true(p.last.stage_us[NEGOBS_STEREO_STAGE_DP] >= 2u);
    assert_int_equal(p.last.stereo_us, sum);
    assert_true(p.last.stereo_us + 1u < t / 1000u);
    assert_true(p.last.stereo_us + 8u >= t / 1000u);

    /* an init clears it */
    p = pipe_init();
    assert_int_equal(run(&p), v0);
    assert_int_equal(p.last.stereo_us, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unrelated_textured_pair_is_never_clear),
        cmocka_unit_test(test_unusable_images_give_no_info_with_reason),
        cmocka_unit_test(test_bad_input_gives_no_info),
        cmocka_unit_test(test_too_large_frames_give_no_info),
        cmocka_unit_test(test_matcher_setup_follows_the_workspace),
        cmocka_unit_test(test_gate_thresholds_are_the_detectors),
        cmocka_unit_test(test_late_clear_is_not_trusted),
        cmocka_unit_test(test_stage_clock_fills_stage_times),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
