/*
 * The pthread pool (negobs_port/pool.h) behind the matcher's row bands:
 * every job runs exactly once on a worker index below the thread count,
 * and the disparities, confidences and statistics are bit-identical for
 * 1, 2, 3 and 4 threads against the bands run in order without an
 * executor, with band counts that do not divide the thread count (3, 5)
 * and over several frames; and the whole pipeline over the generated curb
 * walk, whose stereo ROI moves the band borders after the first frame (the
 * band dispatch order then comes from a frame with other borders). Native
 * builds only (threads; see meson.build).
 */
#include <stdlib.h>
#include <string.h>

#include "scene_pair.h"
#include "walk.h"
#include "cmocka_all.h"
#include "negobs/pipeline.h"
#include "negobs/stereo.h"
#include "negobs_port/pool.h"

#define W 320
#define H 240
#define DMAX 63
#define MAXT 4

static uint8_t left[W * H];
static uint8_t right[W * H];
static int16_t gt[W * H];
static uint8_t occ[W * H];
static uint8_t tex[W * H];

#define WS_BYTES                                                              \
    ((NEGOBS_STEREO_WORKSPACE_MAX_COMPACT(W, H, DMAX) +                       \
      (MAXT - 1) * NEGOBS_STEREO_WORKSPACE_WORKER_MAX(W, DMAX) +              \
      NEGOBS_STEREO_WORKSPACE_BANDS_MAX(H, DMAX) + 15u) &                     \
     ~(size_t)15u)
static uint8_t ws_buf[2][WS_BYTES] __attribute__((aligned(16)));

typedef struct run {
    negobs_stereo_t ctx;
    int16_t disp[W * H];
    uint8_t conf[W * H];
    negobs_stereo_stats_t st;
} run_t;

static run_t g_run[2];

/* ---- the pool alone -------------------------------------------------- */

typedef struct count_arg {
    int32_t threads;
    int32_t hits[200];
    int bad_worker;
} count_arg_t;

static void count_job(void *arg, int32_t job, int32_t worker)
{
    count_arg_t *c = (count_arg_t *)arg;
    c->hits[job]++; /* one writer per job: no race */
    if (worker < 0 || worker >= c->threads) {
        c->bad_worker = 1;
    }
}

static void test_every_job_once(void **state)
{
    int32_t t;
    (void)state;
    for (t = 1; t <= MAXT; t++) {
        negobs_pool_t *pool = NULL;
        negobs_executor_t e;
        int32_t round;
        assert_int_equal(negobs_pool_create(&pool, t), NEGOBS_OK);
        e = negobs_pool_executor(pool);
        assert_int_equal(e.workers, t);
        for (round = 0; round < 50; round++) {
            static count_arg_t c;
            int32_t n = 1 + (round * 7) % 200;
            int32_t j;
            memset(&c, 0, sizeof c);
            c.threads = t;
            e.run(e.user, n, count_job, &c);
            for (j = 0; j < 200; j++) {
                assert_int_equal(c.hits[j], j < n ? 1 : 0);
            }
            assert_int_equal(c.bad_worker, 0);
        }
        negobs_pool_destroy(pool);
    }
}

static void test_bad_arguments(void **state)
{
    negobs_pool_t *pool = NULL;
    (void)state;
    assert_int_equal(negobs_pool_create(&pool, 0), NEGOBS_ERR_INVAL);
    assert_null(pool);
    assert_int_equal(negobs_pool_create(&pool, NEGOBS_POOL_MAX_THREADS + 1),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_pool_create(NULL, 2), NEGOBS_ERR_INVAL);
    negobs_pool_destroy(NULL);
    assert_true(negobs_pool_online_cores() >= 1);
}

/* ---- the matcher on the pool ------------------------------------------ */

static void init_run(run_t *r, int32_t bands, int32_t workers)
{
    negobs_stereo_config_t cfg;
    size_t bytes = 0;
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = DMAX;
    cfg.bands = bands;
    cfg.band_workers = workers;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &bytes), NEGOBS_OK);
    assert_true(bytes <= WS_BYTES);
    assert_int_equal(
        negobs_stereo_init(&r->ctx, &cfg, ws_buf[r == &g_run[1]], bytes),
        NEGOBS_OK);
}

static void process(run_t *r)
{
    negobs_image_u8_t li = {left, W, H, W};
    negobs_image_u8_t ri = {right, W, H, W};
    negobs_image_s16_t di = {r->disp, W, H, W};
    negobs_image_u8_t ci = {r->conf, W, H, W};
    assert_int_equal(
        negobs_stereo_process(&r->ctx, &li, &ri, &di, &ci, &r->st), NEGOBS_OK);
    memset(r->st.stage_ticks, 0, sizeof r->st.stage_ticks);
}

static void render(uint32_t seed, int32_t voff)
{
    synth_scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.w = W;
    sc.h = H;
    sc.d_top_q8 = 10 * 256;
    sc.d_bottom_q8 = 40 * 256;
    sc.drop_q8 = 8 * 256;
    sc.box_q8 = 48 * 256;
    sc.voff = voff;
    sc.seed = seed;
    synth_render(&sc, left, right, gt, occ, tex);
}

static void same_for_threads(int32_t bands)
{
    int32_t t;
    for (t = 1; t <= MAXT; t++) {
        negobs_pool_t *pool = NULL;
        negobs_executor_t e;
        int frame;
        assert_int_equal(negobs_pool_create(&pool, t), NEGOBS_OK);
        e = negobs_pool_executor(pool);
        init_run(&g_run[0], bands, 1);
        init_run(&g_run[1], bands, MAXT);
        assert_int_equal(negobs_stereo_set_executor(&g_run[1].ctx, &e),
                         NEGOBS_OK);
        for (frame = 0; frame < 3; frame++) {
            render(40u + (uint32_t)frame, frame - 1);
            process(&g_run[0]);
            process(&g_run[1]);
            assert_true(g_run[0].st.grown > 1000u);
            /* the band stages really ran: speckles were removed, and the
             * offset search found the rendered row offset */
            assert_true(g_run[0].st.speckles_removed > 0u);
            assert_int_equal(g_run[0].st.vertical_offset, frame - 1);
            assert_memory_equal(g_run[0].disp, g_run[1].disp,
                                sizeof g_run[0].disp);
            assert_memory_equal(g_run[0].conf, g_run[1].conf,
                                sizeof g_run[0].conf);
            assert_memory_equal(&g_run[0].st, &g_run[1].st,
                                sizeof g_run[0].st);
        }
        negobs_pool_destroy(pool);
    }
}

/* The fast profile on 3 workers at 320x240x64: three whole memos would
 * pass NEGOBS_STEREO_FAST_BUDGET, so each narrows (to 21 levels); the
 * maps stay those of the compact profile on one worker, for 1-3 threads.
 * (With 4 workers the memo goes: narrower than 16 levels.) */
static void test_fast_profile_narrowed_memo(void **state)
{
    negobs_stereo_config_t cfg;
    size_t bytes = 0;
    size_t one = 0;
    static uint8_t ws[NEGOBS_STEREO_FAST_BUDGET] __attribute__((aligned(16)));
    int32_t t;
    (void)state;
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = DMAX;
    cfg.memory_profile = NEGOBS_STEREO_PROFILE_FAST;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &one), NEGOBS_OK);
    cfg.band_workers = 3;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &bytes), NEGOBS_OK);
    /* 3 full memos would take about 3 x one; a narrowed memo is still
     * there (more than the compact workspace of 3 workers) */
    assert_true(bytes <= NEGOBS_STEREO_FAST_BUDGET);
    assert_true(3u * one > NEGOBS_STEREO_FAST_BUDGET);
    {
        size_t comp = 0;
        cfg.memory_profile = NEGOBS_STEREO_PROFILE_COMPACT;
        assert_int_equal(negobs_stereo_workspace_size(&cfg, &comp), NEGOBS_OK);
        assert_true(bytes >
                    comp + 3u * W * 32u * 4u * NEGOBS_STEREO_MEMO_MIN_LEVELS);
        cfg.memory_profile = NEGOBS_STEREO_PROFILE_FAST;
    }
    init_run(&g_run[0], 4, 1);
    for (t = 1; t <= 3; t++) {
        negobs_pool_t *pool = NULL;
        negobs_executor_t e;
        int frame;
        assert_int_equal(negobs_pool_create(&pool, t), NEGOBS_OK);
        e = negobs_pool_executor(pool);
        assert_int_equal(negobs_stereo_init(&g_run[1].ctx, &cfg, ws, bytes),
                         NEGOBS_OK);
        assert_int_equal(negobs_stereo_set_executor(&g_run[1].ctx, &e),
                         NEGOBS_OK);
        for (frame = 0; frame < 2; frame++) {
            render(60u + (uint32_t)frame, frame);
            process(&g_run[0]);
            process(&g_run[1]);
            assert_memory_equal(g_run[0].disp, g_run[1].disp,
                                sizeof g_run[0].disp);
            assert_memory_equal(g_run[0].conf, g_run[1].conf,
                                sizeof g_run[0].conf);
            assert_memory_equal(&g_run[0].st, &g_run[1].st,
                                sizeof g_run[0].st);
        }
        negobs_pool_destroy(pool);
    }
}

static void test_stereo_bands3(void **state)
{
    (void)state;
    same_for_threads(3);
}

static void test_stereo_bands4(void **state)
{
    (void)state;
    same_for_threads(4);
}

static void test_stereo_bands5(void **state)
{
    (void)state;
    same_for_threads(5);
}

/* ---- the pipeline on the pool ------------------------------------------ */

typedef struct walk_out {
    int16_t disp[WALK_FRAMES][W * H];
    uint8_t conf[WALK_FRAMES][W * H];
    negobs_stereo_stats_t st[WALK_FRAMES];
    int32_t state[WALK_FRAMES];
    int32_t level[WALK_FRAMES];
    /* the detector's own work (its strip scans and pooled frames run on
     * the executor too): reasons, vouched range, and every candidate */
    uint32_t reasons[WALK_FRAMES];
    int32_t clear_to_mm[WALK_FRAMES];
    int32_t noise_vouch_mm[WALK_FRAMES];
    uint32_t candidates[WALK_FRAMES];
} walk_out_t;

/* FNV-1a over the candidates' fields (not their padding). */
static uint32_t candidates_hash(const negobs_detect_result_t *r)
{
    uint32_t h = 2166136261u;
    uint32_t i;
    for (i = 0; i < r->n_candidates && i < NEGOBS_DETECT_MAX_HAZARDS; i++) {
        const negobs_hazard_t *c = &r->candidates[i];
        const int32_t v[12] = {(int32_t)c->type,
                               (int32_t)c->flags,
                               c->range_mm,
                               c->lateral_mm,
                               c->depth_mm,
                               c->drop_mm,
                               c->u0,
                               c->v0,
                               c->u1,
                               c->v1,
                               c->conf_q15,
                               c->strips};
        int32_t k;
        for (k = 0; k < 12; k++) {
            h = (h ^ (uint32_t)v[k]) * 16777619u;
        }
    }
    return (h ^ r->n_candidates) * 16777619u;
}

/* The walk through one pipeline on `threads` pool threads (1: no
 * executor, the bands in order on this thread). */
static void walk_pipeline(int32_t threads, walk_out_t *out)
{
    negobs_pipeline_config_t pc;
    negobs_pipeline_t p;
    negobs_pool_t *pool = NULL;
    negobs_executor_t e;
    size_t bytes = 0;
    void *raw;
    void *ws;
    int32_t f;
    negobs_pipeline_config_default(&pc, W, H);
    pc.stereo.band_workers = threads;
    assert_int_equal(negobs_pipeline_workspace_size(&pc, &bytes), NEGOBS_OK);
    raw = malloc(bytes + 16u);
    assert_non_null(raw);
    ws = (void *)(((uintptr_t)raw + 15u) & ~(uintptr_t)15u);
    assert_int_equal(negobs_pipeline_init(&p, &pc, ws, bytes), NEGOBS_OK);
    if (threads > 1) {
        assert_int_equal(negobs_pool_create(&pool, threads), NEGOBS_OK);
        e = negobs_pool_executor(pool);
        assert_int_equal(negobs_pipeline_set_executor(&p, &e), NEGOBS_OK);
    }
    for (f = 0; f < WALK_FRAMES; f++) {
        negobs_image_u8_t li = {left, W, H, W};
        negobs_image_u8_t ri = {right, W, H, W};
        negobs_pipeline_frame_t fr;
        negobs_pipeline_result_t res;
        assert_int_equal(walk_render(&pc.detect.rig, f, left, right), 0);
        memset(&fr, 0, sizeof fr);
        fr.left = &li;
        fr.right = &ri;
        fr.t_left_ms = (uint32_t)f * 100u;
        fr.t_right_ms = fr.t_left_ms;
        fr.now_ms = fr.t_left_ms + 20u;
        assert_int_equal(negobs_pipeline_process(&p, &fr, &res), NEGOBS_OK);
        assert_int_equal(res.stereo_status, NEGOBS_OK);
        memcpy(out->disp[f], negobs_pipeline_disparity(&p)->data,
               sizeof out->disp[f]);
        memcpy(out->conf[f], negobs_pipeline_confidence(&p)->data,
               sizeof out->conf[f]);
        out->st[f] = res.stereo;
        out->state[f] = (int32_t)res.detect.state;
        out->level[f] = (int32_t)res.detect.level;
        out->reasons[f] = res.detect.reasons;
        out->clear_to_mm[f] = res.detect.clear_to_mm;
        out->noise_vouch_mm[f] = res.detect.noise_vouch_mm;
        out->candidates[f] = candidates_hash(&res.detect);
    }
    negobs_pool_destroy(pool);
    free(raw);
}

static void test_pipeline_walk(void **state)
{
    static walk_out_t one;
    static walk_out_t many;
    int32_t t;
    int32_t f;
    int32_t crops = 0;
    (void)state;
    walk_pipeline(1, &one);
    /* the ROI really moves the band borders: the first frame matches every
     * row (8 strips, 2 per band), the next ones a crop (1, 2, 1 and 2) */
    for (f = 1; f < WALK_FRAMES; f++) {
        crops += one.st[f].first_row != one.st[f - 1].first_row;
    }
    assert_int_equal(one.st[0].first_row, 0);
    assert_true(crops >= 1);
    assert_true(one.st[WALK_FRAMES - 1].first_row > 0);
    for (t = 2; t <= MAXT; t += 2) {
        walk_pipeline(t, &many);
        for (f = 0; f < WALK_FRAMES; f++) {
            assert_memory_equal(one.disp[f], many.disp[f], sizeof one.disp[f]);
            assert_memory_equal(one.conf[f], many.conf[f], sizeof one.conf[f]);
            assert_memory_equal(&one.st[f], &many.st[f], sizeof one.st[f]);
            assert_int_equal(one.state[f], many.state[f]);
            assert_int_equal(one.level[f], many.level[f]);
            assert_int_equal(one.reasons[f], many.reasons[f]);
            assert_int_equal(one.clear_to_mm[f], many.clear_to_mm[f]);
            assert_int_equal(one.noise_vouch_mm[f], many.noise_vouch_mm[f]);
            assert_int_equal(one.candidates[f], many.candidates[f]);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_job_once),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_stereo_bands3),
        cmocka_unit_test(test_stereo_bands4),
        cmocka_unit_test(test_stereo_bands5),
        cmocka_unit_test(test_fast_profile_narrowed_memo),
        cmocka_unit_test(test_pipeline_walk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
