/*
 * Bad-input table rows that concern the whole pipeline (docs/ROBUSTNESS.md):
 * swapped cameras, identical frames, odd sizes, stride below width, huge
 * sizes, missing images. None may crash, and none may read as "clear".
 */
#include <stdlib.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs/pipeline.h"

#define W 161 /* odd on purpose */
#define H 121

static uint8_t scene[H * (W + 40)];
static uint8_t left_px[H * W];
static uint8_t right_px[H * W];

typedef struct rig {
    void *raw;
    negobs_pipeline_t *ctx;
} rig_t;

static rig_t rig_open(int32_t w, int32_t h)
{
    rig_t r;
    negobs_pipeline_config_t cfg;
    size_t bytes = 0;
    uint8_t *ws;
    negobs_pipeline_config_default(&cfg, w, h);
    cfg.stereo.max_disp = 31;
    cfg.detect.max_disp_q4 = 32 * 16;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    r.raw = malloc(sizeof(negobs_pipeline_t) + bytes + 16u);
    assert_non_null(r.raw);
    r.ctx = (negobs_pipeline_t *)r.raw;
    ws = (uint8_t *)(((uintptr_t)((uint8_t *)r.raw +
                                  sizeof(negobs_pipeline_t)) +
                      15u) &
                     ~(uintptr_t)15u);
    assert_int_equal(negobs_pipeline_init(r.ctx, &cfg, ws, bytes), NEGOBS_OK);
    return r;
}

/* A textured scene seen with a constant 12 px disparity. */
static void make_pair(void)
{
    uint32_t s = 99;
    int32_t x;
    int32_t y;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W + 40; x++) {
            scene[y * (W + 40) + x] =
                (uint8_t)(64u + ((test_lcg_next(&s) >> 16) & 127u));
        }
    }
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            left_px[y * W + x] = scene[y * (W + 40) + x + 12];
            right_px[y * W + x] = scene[y * (W + 40) + x];
        }
    }
}

static negobs_detect_state_t run(rig_t *r, const negobs_image_u8_t *l,
                                 const negobs_image_u8_t *rr, int frames)
{
    negobs_pipeline_frame_t fr;
    negobs_pipeline_result_t res;
    int i;
    memset(&res, 0, sizeof res);
    memset(&fr, 0, sizeof fr);
    fr.left = l;
    fr.right = rr;
    for (i = 0; i < frames; i++) {
        fr.now_ms = (uint32_t)i * 100u;
        fr.t_left_ms = fr.now_ms;
        fr.t_right_ms = fr.now_ms;
        assert_int_equal(negobs_pipeline_process(r->ctx, &fr, &res),
                         NEGOBS_OK);
    }
    return res.detect.state;
}

static void test_swapped_cameras_are_not_clear(void **state)
{
    rig_t r = rig_open(W, H);
    negobs_image_u8_t l = {right_px, W, H, W}; /* swapped */
    negobs_image_u8_t rr = {left_px, W, H, W};
    (void)state;
    make_pair();
    assert_int_equal(run(&r, &l, &rr, 3), NEGOBS_DETECT_NO_INFO);
    free(r.raw);
}

static void test_identical_frames_are_not_clear(void **state)
{
    /* One camera's frame delivered twice (driver or wiring fault): every
     * disparity is zero, there is no ground in front of the user. */
    rig_t r = rig_open(W, H);
    negobs_image_u8_t l = {left_px, W, H, W};
    (void)state;
    make_pair();
    assert_int_equal(run(&r, &l, &l, 3), NEGOBS_DETECT_NO_INFO);
    free(r.raw);
}

static void test_fronto_parallel_wall_of_texture_is_not_clear(void **state)
{
    /* A constant disparity is a wall, not walkable ground: no ground fit,
     * so no "clear" verdict (odd width, 161 px). */
    rig_t r = rig_open(W, H);
    negobs_image_u8_t l = {left_px, W, H, W};
    negobs_image_u8_t rr = {right_px, W, H, W};
    (void)state;
    make_pair();
    assert_int_not_equal(run(&r, &l, &rr, 3), NEGOBS_DETECT_CLEAR);
    free(r.raw);
}

static void test_wrong_size_and_bad_stride_give_no_info(void **state)
{
    rig_t r = rig_open(W, H);
    negobs_image_u8_t l = {left_px, W, H, W};
    negobs_image_u8_t small = {right_px, W - 1, H, W};
    negobs_image_u8_t bad_stride = {right_px, W, H, W - 1};
    negobs_image_u8_t huge = {right_px, 100000, H, 100000};
    (void)state;
    make_pair();
    assert_int_equal(run(&r, &l, &small, 1), NEGOBS_DETECT_NO_INFO);
    assert_int_equal(run(&r, &l, &bad_stride, 1), NEGOBS_DETECT_NO_INFO);
    assert_int_equal(run(&r, &huge, &l, 1), NEGOBS_DETECT_NO_INFO);
    assert_int_equal(run(&r, NULL, &l, 1), NEGOBS_DETECT_NO_INFO);
    free(r.raw);
}

static void test_null_arguments_are_refused(void **state)
{
    rig_t r = rig_open(W, H);
    negobs_pipeline_frame_t fr;
    negobs_pipeline_result_t res;
    negobs_pipeline_config_t cfg;
    size_t bytes;
    (void)state;
    memset(&fr, 0, sizeof fr);
    assert_int_equal(negobs_pipeline_process(NULL, &fr, &res),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_pipeline_process(r.ctx, NULL, &res),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_pipeline_process(r.ctx, &fr, NULL),
                     NEGOBS_ERR_INVAL);
    negobs_pipeline_config_default(&cfg, 0, 0);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
    negobs_pipeline_config_default(&cfg, 100000, 10);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
    free(r.raw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_swapped_cameras_are_not_clear),
        cmocka_unit_test(test_identical_frames_are_not_clear),
        cmocka_unit_test(test_fronto_parallel_wall_of_texture_is_not_clear),
        cmocka_unit_test(test_wrong_size_and_bad_stride_give_no_info),
        cmocka_unit_test(test_null_arguments_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
