/*
 * Vertical alignment stage: model recovery on pairs with a known sub-pixel
 * misalignment, the warp against an independent per-pixel reference,
 * tracking, bad input, and the matcher's accuracy with and without it.
 */
#include "cmocka_all.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_valign.h"
#include "negobs/stereo.h"
#include "negobs/valign.h"
#include "valign/valign_int.h"

static uint8_t g_left[GEN_W * GEN_H];
static uint8_t g_right[GEN_W * GEN_H];
static uint8_t g_out[GEN_W * GEN_H];
static uint8_t g_ref[GEN_W * GEN_H];
static uint8_t g_ws[8192] __attribute__((aligned(16)));

static negobs_image_u8_t img(uint8_t *p)
{
    negobs_image_u8_t i;
    i.data = p;
    i.width = GEN_W;
    i.height = GEN_H;
    i.stride = GEN_W;
    return i;
}

static void setup_ctx(negobs_valign_t *ctx, negobs_valign_config_t *cfg)
{
    size_t n = 0;
    assert_int_equal(negobs_valign_workspace_size(cfg, &n), NEGOBS_OK);
    assert_true(n <= sizeof g_ws);
    assert_int_equal(negobs_valign_init(ctx, cfg, g_ws, n), NEGOBS_OK);
}

static void default_cfg(negobs_valign_config_t *cfg)
{
    negobs_valign_config_default(cfg, GEN_W, GEN_H);
    cfg->max_disp = 31;
}

/* Largest error of the model's offset over the frame, Q16. */
static int32_t worst_err_q16(const negobs_valign_model_t *m,
                             const gen_model_t *t)
{
    int32_t worst = 0;
    int32_t cy;
    int32_t cx;
    for (cy = 0; cy < GEN_H; cy += GEN_H - 1) {
        for (cx = 0; cx < GEN_W; cx += GEN_W - 1) {
            int32_t e = (m->offset_q16 - t->off_q16) +
                        (m->slope_y_q16 - t->slope_y_q16) * (cy - GEN_H / 2) +
                        (m->slope_x_q16 - t->slope_x_q16) * (cx - GEN_W / 2);
            e = e < 0 ? -e : e;
            worst = e > worst ? e : worst;
        }
    }
    return worst;
}

static void recovers(const gen_model_t *t, int32_t kind, int32_t tol_q16)
{
    negobs_valign_config_t cfg;
    negobs_valign_t ctx;
    negobs_valign_model_t m;
    negobs_valign_stats_t st;
    negobs_image_u8_t l = img(g_left);
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    int32_t err;

    gen_texture(777u);
    gen_pair(t, 4, 20, g_left, g_right);
    default_cfg(&cfg);
    cfg.kind = kind;
    setup_ctx(&ctx, &cfg);
    assert_int_equal(negobs_valign_estimate(&ctx, &l, &r, &o, &m, &st),
                     NEGOBS_OK);
    assert_int_equal(st.accepted, 1);
    err = worst_err_q16(&m, t);
    printf("truth %.3f %+.5f %+.5f -> %.3f %+.5f %+.5f, tiles %d, worst "
           "corner error %.3f px\n",
           t->off_q16 / 65536.0, t->slope_y_q16 / 65536.0,
           t->slope_x_q16 / 65536.0, m.offset_q16 / 65536.0,
           m.slope_y_q16 / 65536.0, m.slope_x_q16 / 65536.0, st.tiles_used,
           err / 65536.0);
    assert_true(st.tiles_used >= 40);
    assert_true(err <= tol_q16);
}

/* 0.08 px everywhere in the frame, corners included (measured: 0.03 to
 * 0.063 px on these pairs; the bilinear render itself smooths the right
 * image a little). */
#define TOL_Q16 5243

static void test_recovers_constant_fraction(void **state)
{
    gen_model_t t = {32768, 0, 0}; /* half a row: the hardest fraction */
    (void)state;
    recovers(&t, NEGOBS_VALIGN_AFFINE, TOL_Q16);
}

static void test_recovers_quarter_and_negative(void **state)
{
    gen_model_t a = {16384, 0, 0};
    gen_model_t b = {-150733, 0, 0}; /* -2.3 rows */
    (void)state;
    recovers(&a, NEGOBS_VALIGN_CONST, TOL_Q16);
    recovers(&b, NEGOBS_VALIGN_AFFINE, TOL_Q16);
}

static void test_recovers_surdis_like_scale(void **state)
{
    /* the SurDis rig: 1.2 rows at the centre, -0.0045 per row, a little
     * roll: 2.3 rows at the top, 0.1 at the bottom */
    gen_model_t t = {78643, -295, 20};
    (void)state;
    recovers(&t, NEGOBS_VALIGN_AFFINE, TOL_Q16);
}

static void test_recovers_zero(void **state)
{
    gen_model_t t = {0, 0, 0};
    (void)state;
    recovers(&t, NEGOBS_VALIGN_AFFINE, TOL_Q16);
}

/* Independent reference of the warp: per pixel, from the header's formula. */
static uint8_t ref_pixel(const negobs_valign_model_t *m, int32_t x, int32_t y)
{
    int64_t o = (int64_t)m->offset_q16 +
                (int64_t)m->slope_y_q16 * (y - GEN_H / 2) +
                (int64_t)m->slope_x_q16 * (x - GEN_W / 2);
    /* round half-up to 1/16: floor((o + 2048) / 4096) */
    int64_t q4 = (o + 2048) >= 0 ? (o + 2048) / 4096
                                 : -((-(o + 2048) + 4095) / 4096);
    int64_t k = q4 >= 0 ? q4 / 16 : -((-q4 + 15) / 16);
    int64_t f = q4 - 16 * k;
    int64_t y0 = y + k;
    int64_t y1 = y + k + 1;
    y0 = y0 < 0 ? 0 : (y0 > GEN_H - 1 ? GEN_H - 1 : y0);
    y1 = y1 < 0 ? 0 : (y1 > GEN_H - 1 ? GEN_H - 1 : y1);
    return (uint8_t)((g_right[y0 * GEN_W + x] * (16 - f) +
                      g_right[y1 * GEN_W + x] * f + 8) /
                     16);
}

static void test_warp_matches_reference(void **state)
{
    static const negobs_valign_model_t models[] = {
        {0, 0, 0},         {65536, 0, 0},       {32768, 0, 0},
        {-98304, 0, 0},    {78643, -295, 20},   {-4000, 311, -97},
        {262144, 1024, 0}, {-262144, 0, -1024}, {2048, 0, 0},
        {-2048, 0, 0},
    };
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    size_t k;
    (void)state;
    gen_texture(99u);
    {
        gen_model_t z = {0, 0, 0};
        gen_pair(&z, 3, 9, g_left, g_right);
    }
    for (k = 0; k < sizeof models / sizeof models[0]; k++) {
        int32_t x;
        int32_t y;
        assert_int_equal(negobs_valign_warp(&models[k], &r, &o), NEGOBS_OK);
        for (y = 0; y < GEN_H; y++) {
            for (x = 0; x < GEN_W; x++) {
                g_ref[y * GEN_W + x] = ref_pixel(&models[k], x, y);
            }
        }
        assert_memory_equal(g_out, g_ref, sizeof g_out);
    }
    /* the zero model is a copy */
    assert_int_equal(negobs_valign_warp(&models[0], &r, &o), NEGOBS_OK);
    assert_memory_equal(g_out, g_right, sizeof g_out);
}

static void test_warp_honours_stride(void **state)
{
    static uint8_t wide[(GEN_W + 7) * GEN_H];
    static uint8_t wide_out[(GEN_W + 5) * GEN_H];
    negobs_valign_model_t m = {40000, -200, 33};
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    negobs_image_u8_t rw;
    negobs_image_u8_t ow;
    int32_t y;
    (void)state;
    gen_texture(5u);
    {
        gen_model_t z = {0, 0, 0};
        gen_pair(&z, 3, 9, g_left, g_right);
    }
    memset(wide, 0xA5, sizeof wide);
    memset(wide_out, 0x5A, sizeof wide_out);
    for (y = 0; y < GEN_H; y++) {
        memcpy(wide + y * (GEN_W + 7), g_right + y * GEN_W, GEN_W);
    }
    rw = r;
    rw.data = wide;
    rw.stride = GEN_W + 7;
    ow = o;
    ow.data = wide_out;
    ow.stride = GEN_W + 5;
    assert_int_equal(negobs_valign_warp(&m, &r, &o), NEGOBS_OK);
    assert_int_equal(negobs_valign_warp(&m, &rw, &ow), NEGOBS_OK);
    for (y = 0; y < GEN_H; y++) {
        assert_memory_equal(wide_out + y * (GEN_W + 5), g_out + y * GEN_W,
                            GEN_W);
        /* padding untouched */
        assert_int_equal(wide_out[y * (GEN_W + 5) + GEN_W], 0x5A);
    }
}

static void test_tracking_and_textureless_frames(void **state)
{
    negobs_valign_config_t cfg;
    negobs_valign_t ctx;
    negobs_valign_stats_t st;
    negobs_valign_model_t m;
    negobs_image_u8_t l = img(g_left);
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    gen_model_t a = {65536, 0, 0};
    gen_model_t b = {131072, 0, 0};
    (void)state;

    default_cfg(&cfg);
    cfg.smooth_q15 = 16384; /* half */
    setup_ctx(&ctx, &cfg);
    m = negobs_valign_model(&ctx);
    assert_int_equal(m.offset_q16, 0);

    gen_texture(31u);
    gen_pair(&a, 4, 20, g_left, g_right);
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st), NEGOBS_OK);
    assert_int_equal(st.accepted, 1);
    /* the first accepted frame is taken whole */
    assert_int_equal(st.model.offset_q16, st.frame.offset_q16);
    assert_true(abs(st.model.offset_q16 - 65536) <= TOL_Q16);
    /* the output is the right image warped by the tracked model */
    assert_int_equal(
        negobs_valign_warp(&st.model, &r,
                           &(negobs_image_u8_t){g_ref, GEN_W, GEN_H, GEN_W}),
        NEGOBS_OK);
    assert_memory_equal(g_out, g_ref, sizeof g_out);

    /* a second frame at 2 rows: the model moves half way */
    gen_pair(&b, 4, 20, g_left, g_right);
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st), NEGOBS_OK);
    assert_int_equal(st.accepted, 1);
    assert_true(abs(st.model.offset_q16 - 98304) <= TOL_Q16);

    /* a flat frame says nothing: the model stays */
    m = st.model;
    memset(g_left, 90, sizeof g_left);
    memset(g_right, 90, sizeof g_right);
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st), NEGOBS_OK);
    assert_int_equal(st.accepted, 0);
    assert_int_equal(st.samples_used, 0);
    assert_int_equal(st.model.offset_q16, m.offset_q16);
    assert_int_equal(negobs_valign_model(&ctx).offset_q16, m.offset_q16);
}

/* The cameras jolt by 3.5 rows, beyond the +-2 rows the steady state
 * searches around its model: frames fail until the full search takes over
 * (after 4), then the model follows. */
static void test_reacquires_after_a_jolt(void **state)
{
    negobs_valign_config_t cfg;
    negobs_valign_t ctx;
    negobs_valign_stats_t st;
    negobs_image_u8_t l = img(g_left);
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    gen_model_t zero = {0, 0, 0};
    gen_model_t jolt = {229376, 0, 0}; /* 3.5 rows */
    int32_t i;
    int32_t failed = 0;
    (void)state;
    default_cfg(&cfg);
    cfg.smooth_q15 = 32768; /* no memory: the jump shows at once */
    setup_ctx(&ctx, &cfg);
    gen_texture(404u);
    gen_pair(&zero, 4, 20, g_left, g_right);
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st), NEGOBS_OK);
    assert_int_equal(st.accepted, 1);
    assert_true(abs(st.model.offset_q16) <= TOL_Q16);
    gen_pair(&jolt, 4, 20, g_left, g_right);
    /* run until accepted (at most 4 failures, then the full search) */
    for (i = 0; i < 6; i++) {
        assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st),
                         NEGOBS_OK);
        if (st.accepted) {
            break;
        }
        failed++;
    }
    printf("jolt of 3.5 rows: %d frames without an estimate, then %.3f\n",
           failed, st.model.offset_q16 / 65536.0);
    assert_true(st.accepted);
    assert_true(failed <= 4);
    assert_true(abs(st.model.offset_q16 - jolt.off_q16) <= TOL_Q16);
}

static void test_bad_input(void **state)
{
    negobs_valign_config_t cfg;
    negobs_valign_config_t bad;
    negobs_valign_t ctx;
    negobs_valign_model_t m;
    negobs_valign_model_t big = {0, 0, NEGOBS_VALIGN_SLOPE_LIMIT_Q16 + 1};
    negobs_image_u8_t l = img(g_left);
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    negobs_image_u8_t small = img(g_out);
    size_t n;
    (void)state;

    default_cfg(&cfg);
    memset(&ctx, 0, sizeof ctx);
    /* no init */
    assert_int_equal(negobs_valign_estimate(&ctx, &l, &r, &o, &m, NULL),
                     NEGOBS_ERR_STATE);
    assert_int_equal(negobs_valign_process(NULL, &l, &r, &o, NULL),
                     NEGOBS_ERR_STATE);
    /* configs */
    assert_int_equal(negobs_valign_workspace_size(NULL, &n), NEGOBS_ERR_INVAL);
    bad = cfg;
    bad.max_offset = NEGOBS_VALIGN_MAX_OFFSET + 1;
    assert_int_equal(negobs_valign_workspace_size(&bad, &n), NEGOBS_ERR_INVAL);
    bad = cfg;
    bad.tiles_x = NEGOBS_VALIGN_MAX_TILES + 1;
    assert_int_equal(negobs_valign_workspace_size(&bad, &n), NEGOBS_ERR_INVAL);
    bad = cfg;
    bad.tiles_y = GEN_H / 6; /* tiles smaller than the window */
    assert_int_equal(negobs_valign_workspace_size(&bad, &n), NEGOBS_ERR_INVAL);
    bad = cfg;
    bad.max_disp = GEN_W;
    assert_int_equal(negobs_valign_workspace_size(&bad, &n), NEGOBS_ERR_INVAL);
    bad = cfg;
    bad.smooth_q15 = 0;
    assert_int_equal(negobs_valign_workspace_size(&bad, &n), NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_valign_workspace_size(&cfg, &n), NEGOBS_OK);
    assert_int_equal(negobs_valign_init(&ctx, &cfg, g_ws, n - 1),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(negobs_valign_init(&ctx, &cfg, g_ws + 1, n),
                     NEGOBS_ERR_ALIGN);
    setup_ctx(&ctx, &cfg);
    /* images */
    small.height = GEN_H - 1;
    assert_int_equal(negobs_valign_estimate(&ctx, &l, &r, &small, &m, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_valign_process(&ctx, &l, &small, &o, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &r, NULL),
                     NEGOBS_ERR_INVAL); /* in place */
    assert_int_equal(negobs_valign_estimate(&ctx, &l, &r, &o, NULL, NULL),
                     NEGOBS_ERR_INVAL);
    o.stride = GEN_W - 1;
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, NULL),
                     NEGOBS_ERR_INVAL);
    o = img(g_out);
    /* overlapping buffers and out-of-range models */
    small = img(g_right + GEN_W);
    small.height = GEN_H - 1;
    r.height = GEN_H - 1;
    assert_int_equal(negobs_valign_warp(&big, &r, &o), NEGOBS_ERR_INVAL);
    big.slope_x_q16 = 0;
    assert_int_equal(negobs_valign_warp(&big, &r, &small), NEGOBS_ERR_INVAL);
    big.offset_q16 = 65 * 65536;
    r = img(g_right);
    assert_int_equal(negobs_valign_warp(&big, &r, &o), NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_valign_warp(NULL, &r, &o), NEGOBS_ERR_INVAL);
}

/* Pure noise on both sides and saturated frames: a defined answer, a model
 * within the limits, never a crash (the sanitizer build runs this). */
static void test_noise_and_saturation(void **state)
{
    negobs_valign_config_t cfg;
    negobs_valign_t ctx;
    negobs_valign_stats_t st;
    negobs_image_u8_t l = img(g_left);
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    uint32_t s = 4242u;
    size_t i;
    (void)state;
    default_cfg(&cfg);
    setup_ctx(&ctx, &cfg);
    for (i = 0; i < sizeof g_left; i++) {
        g_left[i] = (uint8_t)(test_lcg_next(&s) >> 16);
        g_right[i] = (uint8_t)(test_lcg_next(&s) >> 16);
    }
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st), NEGOBS_OK);
    printf("noise: accepted %d, samples %d, tiles %d\n", st.accepted,
           st.samples_used, st.tiles_used);
    assert_true(abs(st.model.offset_q16) <= 5 * 65536);
    memset(g_left, 255, sizeof g_left);
    memset(g_right, 255, sizeof g_right);
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st), NEGOBS_OK);
    assert_int_equal(st.accepted, 0);
}

/* Share of pixels with a value more than 1 px off (or none), in permille. */
static int32_t bad1_permille(const int16_t *disp, int32_t d_top,
                             int32_t d_bottom)
{
    int32_t bad = 0;
    int32_t n = 0;
    int32_t x;
    int32_t y;
    for (y = 8; y < GEN_H - 8; y++) {
        int32_t gt = gen_disp(y, d_top, d_bottom) * 16;
        for (x = 40; x < GEN_W - 8; x++) {
            int16_t d = disp[y * GEN_W + x];
            n++;
            if (d == NEGOBS_DISP_INVALID || abs(d - gt) > 16) {
                bad++;
            }
        }
    }
    return bad * 1000 / n;
}

static void test_matcher_gains_from_alignment(void **state)
{
    static int16_t disp[GEN_W * GEN_H];
    static uint8_t sws[NEGOBS_STEREO_WORKSPACE_MAX(GEN_W, GEN_H, 31)]
        __attribute__((aligned(16)));
    negobs_stereo_config_t scfg;
    negobs_stereo_t sctx;
    negobs_valign_config_t cfg;
    negobs_valign_t ctx;
    negobs_valign_stats_t st;
    negobs_image_u8_t l = img(g_left);
    negobs_image_u8_t r = img(g_right);
    negobs_image_u8_t o = img(g_out);
    negobs_image_s16_t di;
    gen_model_t t = {78643, -295, 20}; /* SurDis-like */
    size_t n;
    int32_t raw;
    int32_t aligned;
    (void)state;

    gen_texture_joints(2026u);
    gen_pair(&t, 4, 20, g_left, g_right);
    di.data = disp;
    di.width = GEN_W;
    di.height = GEN_H;
    di.stride = GEN_W;
    /* the matcher alone, with its integer vertical search */
    negobs_stereo_config_default(&scfg, GEN_W, GEN_H);
    scfg.max_disp = 31;
    assert_int_equal(negobs_stereo_workspace_size(&scfg, &n), NEGOBS_OK);
    assert_true(n <= sizeof sws);
    assert_int_equal(negobs_stereo_init(&sctx, &scfg, sws, n), NEGOBS_OK);
    assert_int_equal(negobs_stereo_process(&sctx, &l, &r, &di, NULL, NULL),
                     NEGOBS_OK);
    raw = bad1_permille(disp, 4, 20);
    /* aligned first, no vertical search */
    default_cfg(&cfg);
    setup_ctx(&ctx, &cfg);
    assert_int_equal(negobs_valign_process(&ctx, &l, &r, &o, &st), NEGOBS_OK);
    scfg.vertical_search = 0;
    assert_int_equal(negobs_stereo_init(&sctx, &scfg, sws, n), NEGOBS_OK);
    assert_int_equal(negobs_stereo_process(&sctx, &l, &o, &di, NULL, NULL),
                     NEGOBS_OK);
    aligned = bad1_permille(disp, 4, 20);
    printf("alignment %.3f %+.5f %+.5f (truth 1.200 -0.00450 +0.00031); "
           "bad1 (incl. holes): integer search %d.%d %%, aligned %d.%d %%\n",
           st.model.offset_q16 / 65536.0, st.model.slope_y_q16 / 65536.0,
           st.model.slope_x_q16 / 65536.0, raw / 10, raw % 10, aligned / 10,
           aligned % 10);
    assert_true(aligned * 2 < raw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_recovers_constant_fraction),
        cmocka_unit_test(test_recovers_quarter_and_negative),
        cmocka_unit_test(test_recovers_surdis_like_scale),
        cmocka_unit_test(test_recovers_zero),
        cmocka_unit_test(test_warp_matches_reference),
        cmocka_unit_test(test_warp_honours_stride),
        cmocka_unit_test(test_tracking_and_textureless_frames),
        cmocka_unit_test(test_reacquires_after_a_jolt),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_noise_and_saturation),
        cmocka_unit_test(test_matcher_gains_from_alignment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
