/*
 * The pipeline's half-resolution pass (lib/src/pipeline/coarse.c): its
 * kernels on hand-made images, then the whole pipeline on a generated
 * smooth floor (faint blotches under sensor noise, where 5x5 windows see
 * mostly noise) and on the textured curb walk, which must not change.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs/pipeline.h"
#include "pipeline/coarse.h"
#include "scene_disp.h"
#include "test_rng.h"
#include "test_ws.h"
#include "walk.h"

#define W 320
#define H 240

static uint8_t left_px[W * H];
static uint8_t right_px[W * H];
static int16_t gt_q4[W * H];

static uint8_t clamp_u8(double v)
{
    return (uint8_t)(v < 0.0 ? 0.0 : (v > 255.0 ? 255.0 : v + 0.5));
}

static void test_bin2_rounds_the_mean_and_drops_an_odd_edge(void **state)
{
    /* 5 x 3: the last column and row have no partner and are dropped */
    static uint8_t src[15] = {1,  2,  10, 11, 99, /* row 0 */
                              2,  2,  12, 13, 99, /* row 1 */
                              99, 99, 99, 99, 99};
    uint8_t dst[2] = {0, 0};
    negobs_image_u8_t s = {src, 5, 3, 5};
    negobs_image_u8_t d = {dst, 2, 1, 2};
    (void)state;
    pl_bin2_u8(&s, &d);
    assert_int_equal(dst[0], 2);  /* 7 / 4 = 1.75 -> 2 */
    assert_int_equal(dst[1], 12); /* 46 / 4 = 11.5 -> 12 (half up) */
}

static void test_weak_share_counts_the_area_right_of_x0(void **state)
{
    static uint8_t c[4 * 4];
    negobs_image_u8_t img = {c, 4, 4, 4};
    (void)state;
    memset(c, 200, sizeof c);
    c[0] = 0;      /* left of x0: not counted               */
    c[4 + 1] = 50; /* weak                                  */
    c[8 + 3] = 2;  /* filled: weak                          */
    c[3] = 4;      /* row 0 is above y0: not counted        */
    assert_int_equal(pl_weak_permille(&img, 1, 1, 120), 2 * 1000 / 9);
    assert_int_equal(pl_weak_permille(&img, 4, 0, 120), 0);
}

static void test_fuse_takes_confident_half_values_only_where_weak(void **state)
{
    static int16_t d[4 * 2];
    static uint8_t c[4 * 2];
    static int16_t hd[2] = {100, NEGOBS_DISP_INVALID};
    static uint8_t hc[2] = {200, 250};
    negobs_image_s16_t disp = {d, 4, 2, 4};
    negobs_image_u8_t conf = {c, 4, 2, 4};
    negobs_image_s16_t hdisp = {hd, 2, 1, 2};
    negobs_image_u8_t hconf = {hc, 2, 1, 2};
    int i;
    (void)state;
    for (i = 0; i < 8; i++) {
        d[i] = 7;
        c[i] = 30;
    }
    c[1] = 180; /* confident at full size: kept */
    assert_int_equal(
        pl_coarse_fuse(NULL, &disp, &conf, &hdisp, &hconf, 0, 120, 0, 1024),
        3);
    assert_int_equal(d[0], 200); /* doubled */
    assert_int_equal(c[0], 200);
    assert_int_equal(d[1], 7);
    assert_int_equal(d[4], 200);
    assert_int_equal(d[5], 200);
    assert_int_equal(d[2], 7); /* the half-size pixel has no value */
    /* a weak half-size value is not taken, nor one outside the range */
    hc[0] = 100;
    assert_int_equal(
        pl_coarse_fuse(NULL, &disp, &conf, &hdisp, &hconf, 0, 120, 0, 1024),
        0);
    hc[0] = 200;
    d[0] = 7;
    c[0] = 30;
    assert_int_equal(
        pl_coarse_fuse(NULL, &disp, &conf, &hdisp, &hconf, 0, 120, 0, 100), 0);
}

/* A confident full-size value measured in a window without texture takes
 * the half-size value; one in a textured window keeps its own. The left
 * image: vertical stripes (a 6 px period, +-40 grey) in columns 0-31, a
 * flat grey in columns 32-63, both under sensor noise of sigma 2. Every
 * full-size value is confident (200), every half-size one too. */
static void test_fuse_replaces_values_measured_without_texture(void **state)
{
    enum { FW = 64, FH = 16 };
    static uint8_t lp[FW * FH];
    static int16_t d[FW * FH];
    static uint8_t c[FW * FH];
    static int16_t hd[(FW / 2) * (FH / 2)];
    static uint8_t hc[(FW / 2) * (FH / 2)];
    negobs_image_u8_t left = {lp, FW, FH, FW};
    negobs_image_s16_t disp = {d, FW, FH, FW};
    negobs_image_u8_t conf = {c, FW, FH, FW};
    negobs_image_s16_t hdisp = {hd, FW / 2, FH / 2, FW / 2};
    negobs_image_u8_t hconf = {hc, FW / 2, FH / 2, FW / 2};
    uint32_t st = 99u;
    int32_t striped = 0;
    int32_t flat = 0;
    int32_t x;
    int32_t y;
    (void)state;
    for (y = 0; y < FH; y++) {
        for (x = 0; x < FW; x++) {
            const double stripe = (x < 32 && (x / 3) % 2 == 0) ? 40.0 : -40.0;
            lp[y * FW + x] = clamp_u8(128.0 + ((x < 32) ? stripe : 0.0) +
                                      2.0 * test_gauss12(&st));
            d[y * FW + x] = 160;
            c[y * FW + x] = 200;
        }
    }
    memset(hc, 200, sizeof hc);
    for (x = 0; x < (FW / 2) * (FH / 2); x++) {
        hd[x] = 96; /* doubled: 192 */
    }
    assert_true(pl_coarse_fuse(&left, &disp, &conf, &hdisp, &hconf, 0, 120, 0,
                               1024) > 0);
    /* inside the image by the window's reach: the striped half keeps its
     * values, the flat half takes the half-size ones */
    for (y = 2; y < FH - 2; y++) {
        for (x = 2; x < FW - 2; x++) {
            if (x < 28) {
                striped += d[y * FW + x] == 160;
            } else if (x >= 36) {
                flat += d[y * FW + x] == 192;
            }
        }
    }
    assert_int_equal(striped, 26 * (FH - 4));
    assert_int_equal(flat, 26 * (FH - 4));
    /* without the image the confident values all stay */
    for (x = 0; x < FW * FH; x++) {
        d[x] = 160;
        c[x] = 200;
    }
    assert_int_equal(
        pl_coarse_fuse(NULL, &disp, &conf, &hdisp, &hconf, 0, 120, 0, 1024),
        0);
}

static void test_config_checks_and_small_frames(void **state)
{
    negobs_pipeline_config_t cfg;
    negobs_stereo_config_t half;
    size_t on = 0;
    size_t off = 0;
    (void)state;
    negobs_pipeline_config_default(&cfg, W, H);
    assert_int_equal(cfg.coarse_pass, 1);
    assert_int_equal(pl_coarse_config(&cfg, &half), 1);
    assert_int_equal(half.width, W / 2);
    assert_int_equal(half.max_disp, (cfg.stereo.max_disp + 1) / 2);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &on), NEGOBS_OK);
    cfg.coarse_pass = 0;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &off), NEGOBS_OK);
    assert_true(on > off);
    cfg.coarse_pass = 2;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &on),
                     NEGOBS_ERR_INVAL);
    cfg.coarse_pass = 1;
    cfg.coarse_weak_permille = 1001;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &on),
                     NEGOBS_ERR_INVAL);
    /* a frame whose half the matcher refuses: no pass, no extra memory */
    negobs_pipeline_config_default(&cfg, 48, 24);
    cfg.stereo.max_disp = 31;
    cfg.valign.max_disp = 31;
    cfg.detect.max_disp_q4 = 32 * NEGOBS_DISP_ONE;
    assert_int_equal(pl_coarse_config(&cfg, &half), 0);
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &on), NEGOBS_OK);
    cfg.coarse_pass = 0;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &off), NEGOBS_OK);
    assert_true(on == off);
}

/* Value noise with 8 px cells, bilinear, at column x_q4 (1/16 px), row y:
 * grey 128 +- amp. */
static int32_t blotch(int32_t x_q4, int32_t y, int32_t amp)
{
    int32_t cx = x_q4 / 128;
    int32_t fx = x_q4 % 128;
    int32_t cy = y / 8;
    int32_t fy = (y % 8) * 16;
    int32_t k[4];
    int32_t i;
    int32_t top;
    int32_t bot;
    for (i = 0; i < 4; i++) {
        uint32_t h = (uint32_t)(cx + (i & 1)) * 73856093u ^
                     (uint32_t)(cy + (i >> 1)) * 19349663u;
        h ^= h >> 13;
        h *= 0x5bd1e995u;
        h ^= h >> 15;
        k[i] = (int32_t)(h & 0xffu) - 128;
    }
    top = k[0] * (128 - fx) + k[1] * fx;
    bot = k[2] * (128 - fx) + k[3] * fx;
    return 128 + ((top * (128 - fy) + bot * fy) / 16384) * amp / 128;
}

/* A smooth level floor seen by the default rig (1.2 m, 20 deg): blotches
 * of +-amp grey and independent noise of sigma grey levels per image. */
static void render_smooth_floor(const negobs_rig_t *cam, uint32_t seed,
                                int32_t amp, double sigma)
{
    synth_scene_t s;
    uint32_t st = seed;
    int32_t u;
    int32_t v;
    synth_flat(&s, 1.2, 20.0);
    synth_render(&s, cam, gt_q4, W);
    for (v = 0; v < H; v++) {
        for (u = 0; u < W; u++) {
            int32_t d = gt_q4[v * W + u];
            d = (d == NEGOBS_DISP_INVALID || d < 0) ? 0 : d;
            left_px[v * W + u] = clamp_u8(blotch(u * 16 + 4096, v, amp) +
                                          sigma * test_gauss12(&st));
            right_px[v * W + u] = clamp_u8(blotch(u * 16 + 4096 + d, v, amp) +
                                           sigma * test_gauss12(&st));
        }
    }
}

typedef struct floor_score {
    int32_t good;    /* confident and within 1 px of the truth */
    int32_t wrong;   /* confident and more than 1 px off       */
    int32_t coarse;  /* frames the pass ran on                 */
    int32_t not_noi; /* frames whose verdict was not NO_INFO   */
} floor_score_t;

/* Five frames of the smooth floor; the last frame's bottom quarter right
 * of the columns no disparity can match is scored. */
static void run_floor(int coarse, floor_score_t *sc)
{
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_pipeline_result_t res;
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t l = {left_px, W, H, W};
    negobs_image_u8_t r = {right_px, W, H, W};
    const negobs_image_s16_t *disp;
    const negobs_image_u8_t *conf;
    size_t bytes = 0;
    void *raw;
    void *ws;
    int32_t i;
    int32_t u;
    int32_t v;
    assert_non_null(ctx);
    memset(sc, 0, sizeof *sc);
    negobs_pipeline_config_default(&cfg, W, H);
    cfg.coarse_pass = coarse;
    assert_int_equal(negobs_pipeline_workspace_size(&cfg, &bytes), NEGOBS_OK);
    ws = test_aligned_ws(bytes, &raw);
    assert_int_equal(negobs_pipeline_init(ctx, &cfg, ws, bytes), NEGOBS_OK);
    for (i = 0; i < 5; i++) {
        render_smooth_floor(&cfg.detect.rig, 1000u + (uint32_t)i, 24, 3.0);
        memset(&fr, 0, sizeof fr);
        fr.left = &l;
        fr.right = &r;
        fr.t_left_ms = fr.t_right_ms = fr.now_ms = 1000u + 100u * (uint32_t)i;
        assert_int_equal(negobs_pipeline_process(ctx, &fr, &res), NEGOBS_OK);
        sc->coarse += res.coarse_ran;
        sc->not_noi += res.detect.state != NEGOBS_DETECT_NO_INFO;
        if (!coarse) {
            assert_int_equal(res.coarse_ran, 0);
            assert_int_equal((int32_t)res.coarse_replaced, 0);
        }
    }
    disp = negobs_pipeline_disparity(ctx);
    conf = negobs_pipeline_confidence(ctx);
    for (v = (3 * H) / 4; v < H; v++) {
        for (u = cfg.stereo.max_disp; u < W; u++) {
            int32_t d = negobs_image_s16_row(disp, v)[u];
            int32_t g = gt_q4[v * W + u];
            if (negobs_image_u8_row(conf, v)[u] < cfg.detect.min_confidence ||
                d == NEGOBS_DISP_INVALID) {
                continue;
            }
            if (d - g <= 16 && g - d <= 16) {
                sc->good++;
            } else {
                sc->wrong++;
            }
        }
    }
    free(raw);
    free(ctx);
}

static void test_smooth_floor_is_read_at_half_resolution(void **state)
{
    floor_score_t off;
    floor_score_t on;
    const int32_t area = (H / 4) * (W - 63);
    (void)state;
    run_floor(0, &off);
    run_floor(1, &on);
    printf("smooth floor, bottom quarter: confident and right %d / %d px "
           "(wrong %d) with the pass, %d (wrong %d) without; pass ran on "
           "%d of 5 frames; verdicts other than NO_INFO %d vs %d\n",
           on.good, area, on.wrong, off.good, off.wrong, on.coarse, on.not_noi,
           off.not_noi);
    assert_int_equal(on.coarse, 5);
    /* the full-size matcher alone leaves most of the near floor unusable */
    assert_true(off.good * 4 < area);
    assert_true(on.good * 2 > area);
    assert_true(on.good > 2 * off.good);
    /* and what the pass adds is right: under 2 % of it more than 1 px off */
    assert_true(on.wrong * 50 < on.good);
}

/* The textured curb walk: the full-size map leaves few weak pixels, the
 * pass does not run, and every output is as without it. */
static void test_textured_walk_is_unchanged(void **state)
{
    negobs_pipeline_config_t cfg[2];
    negobs_pipeline_t *ctx[2];
    void *raw[2];
    int32_t i;
    int k;
    (void)state;
    for (k = 0; k < 2; k++) {
        size_t bytes = 0;
        void *ws;
        negobs_pipeline_config_default(&cfg[k], W, H);
        cfg[k].coarse_pass = k;
        ctx[k] = malloc(sizeof *ctx[k]);
        assert_non_null(ctx[k]);
        assert_int_equal(negobs_pipeline_workspace_size(&cfg[k], &bytes),
                         NEGOBS_OK);
        ws = test_aligned_ws(bytes, &raw[k]);
        assert_int_equal(negobs_pipeline_init(ctx[k], &cfg[k], ws, bytes),
                         NEGOBS_OK);
    }
    for (i = 0; i < WALK_FRAMES; i += 4) {
        negobs_image_u8_t l = {left_px, W, H, W};
        negobs_image_u8_t r = {right_px, W, H, W};
        negobs_pipeline_frame_t fr;
        negobs_pipeline_result_t res[2];
        int32_t v;
        assert_int_equal(walk_render(&cfg[0].detect.rig, i, left_px, right_px),
                         0);
        memset(&fr, 0, sizeof fr);
        fr.left = &l;
        fr.right = &r;
        fr.t_left_ms = fr.t_right_ms = fr.now_ms = 1000u + 100u * (uint32_t)i;
        for (k = 0; k < 2; k++) {
            assert_int_equal(negobs_pipeline_process(ctx[k], &fr, &res[k]),
                             NEGOBS_OK);
        }
        assert_int_equal(res[1].coarse_ran, 0);
        assert_true(res[1].weak_permille <= cfg[1].coarse_weak_permille);
        assert_int_equal(res[0].detect.state, res[1].detect.state);
        assert_int_equal(res[0].detect.clear_to_mm, res[1].detect.clear_to_mm);
        for (v = 0; v < H; v++) {
            assert_memory_equal(
                negobs_image_s16_row(negobs_pipeline_disparity(ctx[0]), v),
                negobs_image_s16_row(negobs_pipeline_disparity(ctx[1]), v),
                W * sizeof(int16_t));
        }
    }
    for (k = 0; k < 2; k++) {
        free(raw[k]);
        free(ctx[k]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bin2_rounds_the_mean_and_drops_an_odd_edge),
        cmocka_unit_test(test_weak_share_counts_the_area_right_of_x0),
        cmocka_unit_test(
            test_fuse_takes_confident_half_values_only_where_weak),
        cmocka_unit_test(test_fuse_replaces_values_measured_without_texture),
        cmocka_unit_test(test_config_checks_and_small_frames),
        cmocka_unit_test(test_smooth_floor_is_read_at_half_resolution),
        cmocka_unit_test(test_textured_walk_is_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
