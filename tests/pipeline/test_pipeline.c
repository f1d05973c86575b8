/*
 * Pipeline glue: exact workspace, consistent stage configs, and the
 * fail-safe path (a lost camera or a refused frame becomes the
 * no-information pattern, never silence).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs/pipeline.h"
#include "scene_valign.h"
#include "test_ws.h"

#define W 160
#define H 120

static uint8_t left_px[W * H];
static uint8_t right_px[W * H];

static void test_pipeline_workspace_is_exact(void **state)
{
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    size_t bytes = 0;
    void *raw;
    void *ws;
    (void)state;
    assert_non_null(ctx);
    negobs_pipeline_config_default(&cfg, W, H);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    assert_true(bytes > (size_t)W * H * 3u);
    ws = test_aligned_ws(bytes, &raw);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes - 1),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    assert_int_equal(negobs_pipeline_disparity(ctx)->width, W);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, (uint8_t *)ws + 1, bytes),
                     NEGOBS_ERR_ALIGN);
    free(raw);
    free(ctx);
}

static void test_pipeline_rejects_mismatched_stage_sizes(void **state)
{
    negobs_pipeline_config_t cfg;
    size_t bytes;
    (void)state;
    negobs_pipeline_config_default(&cfg, W, H);
    cfg.detect.rig.width = W + 2;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_pipeline_workspace_size(NULL, &bytes),
                     NEGOBS_ERR_INVAL);
}

/* Runs n frames of the pair with a whole-row misalignment of off_rows
 * (off_rows2 from frame `knock` on) through a pipeline searching the
 * offset every `every` frames; the offsets each frame matched with go to
 * offs, the last frame's disparity map to last. */
static void run_vertical(int32_t every, int32_t off_rows, int32_t off_rows2,
                         int32_t knock, int32_t n, int32_t *offs,
                         int16_t *last)
{
    static uint8_t gl[GEN_W * GEN_H];
    static uint8_t gr[GEN_W * GEN_H];
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_pipeline_result_t *res = malloc(sizeof *res);
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    size_t bytes = 0;
    void *raw;
    void *ws;
    int32_t k;
    assert_non_null(ctx);
    assert_non_null(res);
    negobs_pipeline_config_default(&cfg, GEN_W, GEN_H);
    cfg.vertical_every_frames = every;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    ws = test_aligned_ws(bytes, &raw);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    gen_texture(11u);
    l.data = gl;
    l.width = GEN_W;
    l.height = GEN_H;
    l.stride = GEN_W;
    r = l;
    r.data = gr;
    for (k = 0; k < n; k++) {
        gen_model_t t = {(k < knock ? off_rows : off_rows2) * 65536, 0, 0};
        gen_pair(&t, 4, 20, gl, gr);
        memset(&fr, 0, sizeof fr);
        fr.left = &l;
        fr.right = &r;
        fr.t_left_ms = fr.t_right_ms = fr.now_ms = 1000u + 100u * (uint32_t)k;
        assert_int_equal(negobs_pipeline_process(ctx, &fr, res), NEGOBS_OK);
        assert_int_equal(res->stereo_status, NEGOBS_OK);
        offs[k] = res->stereo.vertical_offset;
    }
    memcpy(last, negobs_pipeline_disparity(ctx)->data,
           (size_t)GEN_W * GEN_H * sizeof *last);
    free(raw);
    free(res);
    free(ctx);
}

/* vertical_every_frames: the search runs on the first frame and every
 * N-th; between them the last offset found is used. On a rig whose
 * misalignment stays put, every frame is the same as with a search on
 * every frame (bit for bit); after a knock (2 rows -> -1 row at frame 3)
 * the frames before the next search keep the old offset, and that search
 * finds the new one. The period is range-checked. */
static void test_pipeline_vertical_search_every_n_frames(void **state)
{
    static int16_t d1[GEN_W * GEN_H];
    static int16_t d10[GEN_W * GEN_H];
    int32_t o1[12];
    int32_t o10[12];
    negobs_pipeline_config_t cfg;
    size_t bytes;
    int32_t k;
    (void)state;
    negobs_pipeline_config_default(&cfg, GEN_W, GEN_H);
    assert_int_equal(cfg.vertical_every_frames, 10);
    cfg.vertical_every_frames = 0;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
    cfg.vertical_every_frames = 1001;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);

    run_vertical(1, 2, 2, 12, 6, o1, d1);
    run_vertical(10, 2, 2, 12, 6, o10, d10);
    for (k = 0; k < 6; k++) {
        assert_int_equal(o1[k], 2);
        assert_int_equal(o10[k], 2);
    }
    assert_memory_equal(d1, d10, sizeof d1);

    run_vertical(1, 2, -1, 3, 12, o1, d1);
    run_vertical(10, 2, -1, 3, 12, o10, d10);
    for (k = 0; k < 12; k++) {
        assert_int_equal(o1[k], k < 3 ? 2 : -1);
        assert_int_equal(o10[k], k < 10 ? 2 : -1);
    }
    assert_memory_equal(d1, d10, sizeof d1);
}

/* valign.enable: its workspace and the aligned image are part of the exact
 * size, the stage runs before the matcher, the matcher's integer search
 * is off. */
static void test_pipeline_runs_alignment_stage(void **state)
{
    static uint8_t gl[GEN_W * GEN_H];
    static uint8_t gr[GEN_W * GEN_H];
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_pipeline_result_t *res = malloc(sizeof *res);
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    gen_model_t t = {98304, -200, 0}; /* 1.5 rows at the centre */
    size_t off_bytes = 0;
    size_t bytes = 0;
    void *raw;
    void *ws;
    (void)state;
    assert_non_null(ctx);
    assert_non_null(res);
    negobs_pipeline_config_default(&cfg, GEN_W, GEN_H);
    assert_int_equal(cfg.valign.enable, 0);
    assert_int_equal(cfg.valign.max_disp, cfg.stereo.max_disp);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &off_bytes),
                     NEGOBS_OK);
    cfg.valign.enable = 1;
    cfg.valign.width = GEN_W + 1;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
    cfg.valign.width = GEN_W;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    assert_true(bytes >= off_bytes + (size_t)GEN_W * GEN_H);
    ws = test_aligned_ws(bytes, &raw);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes - 1),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);

    gen_texture(11u);
    gen_pair(&t, 4, 20, gl, gr);
    l.data = gl;
    l.width = GEN_W;
    l.height = GEN_H;
    l.stride = GEN_W;
    r = l;
    r.data = gr;
    memset(&fr, 0, sizeof fr);
    fr.left = &l;
    fr.right = &r;
    fr.t_left_ms = fr.t_right_ms = fr.now_ms = 1000;
    assert_int_equal(negobs_pipeline_process(ctx, &fr, res), NEGOBS_OK);
    assert_int_equal(res->stereo_status, NEGOBS_OK);
    assert_int_equal(res->valign.accepted, 1);
    assert_true(abs(res->valign.model.offset_q16 - t.off_q16) <= 5243);
    assert_true(abs(res->valign.model.slope_y_q16 - t.slope_y_q16) <= 40);
    assert_int_equal(res->stereo.vertical_offset, 0);
    assert_true(res->stereo.valid > (uint32_t)(GEN_W * GEN_H / 2));
    /* the caller's right image is not touched */
    {
        static uint8_t again[GEN_W * GEN_H];
        static uint8_t dummy[GEN_W * GEN_H];
        gen_pair(&t, 4, 20, dummy, again);
        assert_memory_equal(again, gr, sizeof again);
    }
    free(raw);
    free(res);
    free(ctx);
}

/* stereo_roi: the first row the next frame needs, from a ground model */
static void test_pipeline_roi_first_row_follows_the_ground(void **state)
{
    negobs_pipeline_config_t cfg;
    negobs_detect_result_t det;
    negobs_ground_pose_t pose = {1200, 20000, 0};
    int32_t top;
    int32_t top_roll;
    int32_t top_down;
    int32_t d_far;
    int32_t v;
    (void)state;
    negobs_pipeline_config_default(&cfg, 320, 240);
    assert_int_equal(cfg.stereo_roi, 1);
    assert_int_equal(cfg.roi_margin_rows, 30);
    memset(&det, 0, sizeof det);
    /* no ground model: every row */
    assert_int_equal(negobs_pipeline_roi_first_row(&cfg, &det), 0);
    det.ground_valid = 1;
    assert_int_equal(
        negobs_ground_plane_from_pose(&cfg.detect.rig, &pose, &det.plane),
        NEGOBS_OK);
    top = negobs_pipeline_roi_first_row(&cfg, &det);
    /* the row 30 below the top is still nearer than range_max on the
     * model, the row 30 above the top (if any) no longer */
    d_far = negobs_disp_q4_from_depth_mm(&cfg.detect.rig,
                                         cfg.detect.range_max_mm);
    v = top + cfg.roi_margin_rows;
    assert_true(negobs_ground_disp_q4(&det.plane, 160, v) >= d_far);
    assert_true(negobs_ground_disp_q4(&det.plane, 160, v - 2) < d_far);
    printf("# first row %d of 240 (5 m ground row %d)\n", (int)top, (int)v);
    assert_true(top > 40 && top < 120);
    /* roll: the higher edge decides, so the crop starts higher */
    pose.roll_mdeg = 5000;
    assert_int_equal(
        negobs_ground_plane_from_pose(&cfg.detect.rig, &pose, &det.plane),
        NEGOBS_OK);
    top_roll = negobs_pipeline_roi_first_row(&cfg, &det);
    assert_true(top_roll < top);
    /* pitched far down (looking at the feet): every row is near ground */
    pose.roll_mdeg = 0;
    pose.pitch_mdeg = 60000;
    assert_int_equal(
        negobs_ground_plane_from_pose(&cfg.detect.rig, &pose, &det.plane),
        NEGOBS_OK);
    top_down = negobs_pipeline_roi_first_row(&cfg, &det);
    assert_int_equal(top_down, 0);
    /* pitched up: the crop never reaches into the ground fit's rows */
    pose.pitch_mdeg = 2000;
    assert_int_equal(
        negobs_ground_plane_from_pose(&cfg.detect.rig, &pose, &det.plane),
        NEGOBS_OK);
    assert_true(negobs_pipeline_roi_first_row(&cfg, &det) <=
                240 - 240 * cfg.detect.fit_rows_pct / 100 -
                    cfg.roi_margin_rows);
    /* off, or a plane that does not descend: every row */
    cfg.stereo_roi = 0;
    assert_int_equal(negobs_pipeline_roi_first_row(&cfg, &det), 0);
    cfg.stereo_roi = 1;
    det.plane.b_q20 = -det.plane.b_q20;
    assert_int_equal(negobs_pipeline_roi_first_row(&cfg, &det), 0);
    assert_int_equal(negobs_pipeline_roi_first_row(NULL, &det), 0);
    assert_int_equal(negobs_pipeline_roi_first_row(&cfg, NULL), 0);
    /* the config is checked */
    {
        size_t bytes;
        cfg.roi_margin_rows = -1;
        assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                         NEGOBS_ERR_INVAL);
        cfg.roi_margin_rows = 30;
        cfg.stereo_roi = 2;
        assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                         NEGOBS_ERR_INVAL);
    }
}

static void test_pipeline_lost_camera_gives_no_info_pattern(void **state)
{
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_pipeline_result_t res;
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t left = {left_px, W, H, W};
    size_t bytes;
    void *raw;
    void *ws;
    uint32_t t;
    int saw_no_info = 0;
    int motor_on = 0;
    (void)state;
    assert_non_null(ctx);
    negobs_pipeline_config_default(&cfg, W, H);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    ws = test_aligned_ws(bytes, &raw);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    memset(&fr, 0, sizeof fr);
    fr.left = &left;
    fr.right = NULL; /* right camera gone */
    for (t = 0; t < 3000; t += 100) {
        fr.t_left_ms = t;
        fr.t_right_ms = t;
        fr.now_ms = t;
        assert_int_equal(negobs_pipeline_process(ctx, &fr, &res), NEGOBS_OK);
        assert_int_equal(res.stereo_status, NEGOBS_ERR_INVAL);
        assert_int_equal(res.detect.state, NEGOBS_DETECT_NO_INFO);
        assert_true(res.detect.reasons & NEGOBS_DEGRADED_BAD_INPUT);
        if (res.motor.pattern == NEGOBS_PATTERN_NO_INFO ||
            res.motor.pattern == NEGOBS_PATTERN_NO_INFO_ENTRY) {
            saw_no_info = 1;
        }
        motor_on |= res.motor.on;
    }
    assert_true(saw_no_info);
    assert_true(motor_on); /* the user feels it */
    free(raw);
    free(ctx);
}

static void test_pipeline_flat_grey_frames_are_not_clear(void **state)
{
    /* Textureless frames: the matcher finds nothing, the verdict must be
     * no-information, not "clear". */
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_pipeline_result_t res;
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t left = {left_px, W, H, W};
    negobs_image_u8_t right = {right_px, W, H, W};
    size_t bytes;
    void *raw;
    void *ws;
    (void)state;
    assert_non_null(ctx);
    memset(left_px, 128, sizeof left_px);
    memset(right_px, 128, sizeof right_px);
    negobs_pipeline_config_default(&cfg, W, H);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    ws = test_aligned_ws(bytes, &raw);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    memset(&fr, 0, sizeof fr);
    fr.left = &left;
    fr.right = &right;
    fr.now_ms = 10;
    fr.t_left_ms = 10;
    fr.t_right_ms = 10;
    assert_int_equal(negobs_pipeline_process(ctx, &fr, &res), NEGOBS_OK);
    assert_int_not_equal(res.detect.state, NEGOBS_DETECT_CLEAR);
    assert_int_equal(res.detect.state, NEGOBS_DETECT_NO_INFO);
    free(raw);
    free(ctx);
}

static void test_pipeline_tick_without_frames_falls_to_no_info(void **state)
{
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_motor_cmd_t cmd;
    size_t bytes;
    void *raw;
    void *ws;
    uint32_t t;
    int saw = 0;
    (void)state;
    assert_non_null(ctx);
    negobs_pipeline_config_default(&cfg, W, H);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    ws = test_aligned_ws(bytes, &raw);
    memset(ctx, 0, sizeof *ctx); /* never initialised */
    assert_int_equal(negobs_pipeline_tick(ctx, 0, &cmd), NEGOBS_ERR_STATE);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    for (t = 0; t <= 2000; t += 50) {
        assert_int_equal(negobs_pipeline_tick(ctx, t, &cmd), NEGOBS_OK);
        if (cmd.pattern == NEGOBS_PATTERN_NO_INFO ||
            cmd.pattern == NEGOBS_PATTERN_NO_INFO_ENTRY) {
            saw = 1;
        }
    }
    assert_true(saw);
    free(raw);
    free(ctx);
}

/* A clock that moves one tick per read: every tick between the first and
 * the last read of a frame lands in exactly one stage. */
static uint32_t counting_clock(void *user)
{
    uint32_t *n = (uint32_t *)user;
    return (*n)++;
}

/* negobs_pipeline_set_clock: per-stage ticks in the result (the matcher's
 * too), nothing else changes, and NULL turns it off. */
static void test_pipeline_clock_times_stages_without_changing_output(
    void **state)
{
    static uint8_t gl[GEN_W * GEN_H];
    static uint8_t gr[GEN_W * GEN_H];
    static int16_t disp_plain[GEN_W * GEN_H];
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_pipeline_result_t *plain = malloc(sizeof *plain);
    negobs_pipeline_result_t *timed = malloc(sizeof *timed);
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    gen_model_t t = {65536, 0, 0};
    const negobs_image_s16_t *d;
    uint32_t reads = 0;
    uint32_t before;
    uint64_t sum = 0;
    uint64_t stereo_sum = 0;
    size_t bytes = 0;
    void *raw;
    void *ws;
    int k;
    (void)state;
    assert_non_null(ctx);
    assert_non_null(plain);
    assert_non_null(timed);
    negobs_pipeline_config_default(&cfg, GEN_W, GEN_H);
    cfg.valign.enable = 1;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    ws = test_aligned_ws(bytes, &raw);
    memset(ctx, 0, sizeof *ctx);
    assert_int_equal(negobs_pipeline_set_clock(ctx, counting_clock, &reads),
                     NEGOBS_ERR_STATE);
    assert_int_equal(negobs_pipeline_set_clock(NULL, counting_clock, &reads),
                     NEGOBS_ERR_INVAL);
    assert_null(negobs_pipeline_aligned_right(ctx));

    gen_texture(5u);
    gen_pair(&t, 4, 20, gl, gr);
    l.data = gl;
    l.width = GEN_W;
    l.height = GEN_H;
    l.stride = GEN_W;
    r = l;
    r.data = gr;
    memset(&fr, 0, sizeof fr);
    fr.left = &l;
    fr.right = &r;
    fr.t_left_ms = fr.t_right_ms = fr.now_ms = 1000;

    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    assert_non_null(negobs_pipeline_aligned_right(ctx));
    assert_int_equal(negobs_pipeline_process(ctx, &fr, plain), NEGOBS_OK);
    for (k = 0; k < NEGOBS_PIPELINE_STAGE_COUNT; k++) {
        assert_true(plain->stage_ticks[k] == 0u);
    }
    d = negobs_pipeline_disparity(ctx);
    memcpy(disp_plain, d->data, sizeof disp_plain);

    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    assert_int_equal(negobs_pipeline_set_clock(ctx, counting_clock, &reads),
                     NEGOBS_OK);
    before = reads;
    assert_int_equal(negobs_pipeline_process(ctx, &fr, timed), NEGOBS_OK);
    for (k = 0; k < NEGOBS_PIPELINE_STAGE_COUNT; k++) {
        assert_true(timed->stage_ticks[k] > 0u);
        sum += timed->stage_ticks[k];
    }
    assert_true(sum == (uint64_t)(reads - before - 1u));
    for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
        stereo_sum += timed->stereo.stage_ticks[k];
    }
    assert_true(stereo_sum > 0u);
    assert_true(stereo_sum < timed->stage_ticks[NEGOBS_PIPELINE_STAGE_STEREO]);
    /* the clock is only read */
    assert_memory_equal(d->data, disp_plain, sizeof disp_plain);
    memset(timed->stage_ticks, 0, sizeof timed->stage_ticks);
    memset(timed->stereo.stage_ticks, 0, sizeof timed->stereo.stage_ticks);
    assert_int_equal(timed->detect.state, plain->detect.state);
    assert_int_equal(timed->detect.nearest_range_mm,
                     plain->detect.nearest_range_mm);
    assert_int_equal(timed->stereo.valid, plain->stereo.valid);
    assert_int_equal(timed->motor.pattern, plain->motor.pattern);

    assert_int_equal(negobs_pipeline_set_clock(ctx, NULL, NULL), NEGOBS_OK);
    before = reads;
    assert_int_equal(negobs_pipeline_process(ctx, &fr, timed), NEGOBS_OK);
    assert_int_equal(reads, before);
    free(raw);
    free(timed);
    free(plain);
    free(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pipeline_workspace_is_exact),
        cmocka_unit_test(test_pipeline_rejects_mismatched_stage_sizes),
        cmocka_unit_test(test_pipeline_runs_alignment_stage),
        cmocka_unit_test(test_pipeline_vertical_search_every_n_frames),
        cmocka_unit_test(test_pipeline_roi_first_row_follows_the_ground),
        cmocka_unit_test(test_pipeline_lost_camera_gives_no_info_pattern),
        cmocka_unit_test(test_pipeline_flat_grey_frames_are_not_clear),
        cmocka_unit_test(test_pipeline_tick_without_frames_falls_to_no_info),
        cmocka_unit_test(
            test_pipeline_clock_times_stages_without_changing_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
