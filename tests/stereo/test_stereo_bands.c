/*
 * Row bands: the band layout depends on the config and the rows only, and
 * the output is the same bit for bit whether the bands run in order on the
 * caller's thread or out of order on any number of workers (here a
 * single-threaded executor that runs them backwards and rotates the
 * workers; tests/port/test_pool.c does the same with real threads). Band
 * counts that do not divide the workers (3, 5) and a crop are included,
 * and so is the dispatch order (costliest band first, from the last
 * frame's work) over frames whose content and crop change. The fast
 * profile's runs (whose bands share the memo the DP borrows) must match
 * the compact profile's in-order run.
 */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "scene_pair.h"
#include "stereo/stereo_int.h"

#define W 160
#define H 120
#define WORKERS 4

static uint8_t left[W * H];
static uint8_t right[W * H];
static int16_t gt[W * H];
static uint8_t occ[W * H];
static uint8_t tex[W * H];

/* the fast profile's bound: a memo per worker */
#define WS_BYTES                                                              \
    ((NEGOBS_STEREO_WORKSPACE_MAX_FAST(W, H, 47) +                            \
      (WORKERS - 1) *                                                         \
          (NEGOBS_STEREO_WORKSPACE_WORKER_MAX(W, 47) +                        \
           (size_t)W * 32u * (4u * NEGOBS_STEREO_MEMO_LEVELS + 1u)) +         \
      NEGOBS_STEREO_WORKSPACE_BANDS_MAX(H, 47) + 15u) &                       \
     ~(size_t)15u)
static uint8_t ws_buf[2][WS_BYTES] __attribute__((aligned(16)));

typedef struct run {
    negobs_stereo_t ctx;
    int16_t disp[W * H];
    uint8_t conf[W * H];
    negobs_stereo_stats_t st;
} run_t;

static run_t g_run[2];

/* memory profile of g_run[1] (g_run[0] keeps the default, compact) */
static int32_t g_profile = NEGOBS_STEREO_PROFILE_COMPACT;

/* Runs every job backwards, job j on worker (j + runs) % workers. */
typedef struct fake_exec {
    int32_t workers;
    int32_t runs;
    int32_t jobs_seen;
} fake_exec_t;

static void fake_run(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg)
{
    fake_exec_t *f = (fake_exec_t *)user;
    int32_t j;
    for (j = n_jobs - 1; j >= 0; j--) {
        fn(arg, j, (j + f->runs) % f->workers);
        f->jobs_seen++;
    }
    f->runs++;
}

/* 1: the runs use Canny's fixed thresholds (canny_top_permille 0) */
static int g_fixed_canny;

static void init_run(run_t *r, int32_t bands, int32_t workers,
                     int32_t strip_rows)
{
    negobs_stereo_config_t cfg;
    size_t bytes = 0;
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = 47;
    if (g_fixed_canny) {
        cfg.canny_top_permille = 0;
    }
    cfg.strip_rows = strip_rows;
    cfg.bands = bands;
    cfg.band_workers = workers;
    if (r == &g_run[1]) {
        cfg.memory_profile = g_profile;
    }
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
    /* stale values from the last run must not leak into this one */
    memset(r->disp, 0x55, sizeof r->disp);
    assert_int_equal(
        negobs_stereo_process(&r->ctx, &li, &ri, &di, &ci, &r->st), NEGOBS_OK);
    memset(r->st.stage_ticks, 0, sizeof r->st.stage_ticks);
}

static void render(uint32_t seed)
{
    synth_scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.w = W;
    sc.h = H;
    sc.d_top_q8 = 8 * 256;
    sc.d_bottom_q8 = 30 * 256;
    sc.drop_q8 = 6 * 256;
    sc.box_q8 = 36 * 256;
    sc.voff = 1;
    sc.seed = seed;
    synth_render(&sc, left, right, gt, occ, tex);
}

static void assert_same(void)
{
    assert_memory_equal(g_run[0].disp, g_run[1].disp, sizeof g_run[0].disp);
    assert_memory_equal(g_run[0].conf, g_run[1].conf, sizeof g_run[0].conf);
    assert_memory_equal(&g_run[0].st, &g_run[1].st, sizeof g_run[0].st);
}

static void test_layout(void **state)
{
    negobs_stereo_config_t cfg;
    int32_t rows;
    int32_t bands;
    (void)state;
    negobs_stereo_config_default(&cfg, W, H);
    for (cfg.strip_rows = 8; cfg.strip_rows <= 32; cfg.strip_rows += 24) {
        for (rows = 1; rows <= 300; rows++) {
            int32_t strips = (rows + cfg.strip_rows - 1) / cfg.strip_rows;
            for (bands = 1; bands <= 9; bands++) {
                int32_t n;
                int32_t b;
                int32_t next = 0;
                int32_t y0;
                int32_t y1;
                cfg.bands = bands;
                n = negobs_stereo_band_count(&cfg, rows);
                assert_int_equal(n, bands < strips ? bands : strips);
                for (b = 0; b < n; b++) {
                    assert_int_equal(
                        negobs_stereo_band_rows(&cfg, rows, b, &y0, &y1),
                        NEGOBS_OK);
                    assert_int_equal(y0, next); /* contiguous */
                    assert_true(y1 > y0);
                    assert_int_equal(y0 % cfg.strip_rows, 0);
                    next = y1;
                }
                assert_int_equal(next, rows);
                assert_int_equal(
                    negobs_stereo_band_rows(&cfg, rows, n, &y0, &y1),
                    NEGOBS_ERR_INVAL);
            }
        }
    }
    assert_int_equal(negobs_stereo_band_count(NULL, 10), 0);
    assert_int_equal(negobs_stereo_band_count(&cfg, 0), 0);
}

/* One band count: in order on one worker against backwards on 1..4. */
static void same_for_every_worker_count(int32_t bands, int32_t strip_rows,
                                        int32_t first_row)
{
    int32_t n;
    init_run(&g_run[0], bands, 1, strip_rows);
    assert_int_equal(negobs_stereo_set_first_row(&g_run[0].ctx, first_row),
                     NEGOBS_OK);
    render(7u + (uint32_t)bands);
    process(&g_run[0]);
    assert_true(g_run[0].st.grown > 1000u); /* the growth really ran */
    /* and so did the band stages before and after it */
    assert_true(g_run[0].st.speckles_removed > 0u);
    assert_int_equal(g_run[0].st.vertical_offset, 1);
    for (n = 1; n <= WORKERS; n++) {
        fake_exec_t f = {n, 0, 0};
        negobs_executor_t e;
        e.workers = n;
        e.run = fake_run;
        e.user = &f;
        init_run(&g_run[1], bands, WORKERS, strip_rows);
        assert_int_equal(negobs_stereo_set_first_row(&g_run[1].ctx, first_row),
                         NEGOBS_OK);
        assert_int_equal(negobs_stereo_set_executor(&g_run[1].ctx, &e),
                         NEGOBS_OK);
        process(&g_run[1]);
        assert_same();
        /* a second frame on the same context (worker state reused) */
        process(&g_run[1]);
        assert_same();
        if (n > 1 && bands > 1) {
            /* vertical offset, 4x4 means, 1/4-scale matches, growth,
             * DP stage 1, back-track, LR check, speckle marks and
             * clears, gap fill, the mean by rows and by columns: 12
             * runs a frame, 2 frames */
            assert_int_equal(f.jobs_seen,
                             24 * negobs_stereo_band_count(&g_run[1].ctx.cfg,
                                                           H - first_row));
        }
    }
}

static void test_same_bands1(void **state)
{
    (void)state;
    same_for_every_worker_count(1, 32, 0);
}

static void test_same_bands3(void **state)
{
    (void)state;
    same_for_every_worker_count(3, 16, 0);
}

static void test_same_bands4(void **state)
{
    (void)state;
    same_for_every_worker_count(4, 32, 0);
}

static void test_same_bands5_crop(void **state)
{
    (void)state;
    /* 104 rows of 8-row strips: 13 strips in 5 bands (2, 3, 2, 3, 3) */
    same_for_every_worker_count(5, 8, 16);
}

/* The fast profile with several workers: pass 0 and pass 1 of a band run
 * on different workers, and all keep their DP pointers in worker 0's memo,
 * each band in its own part. */
static void test_same_bands4_fast(void **state)
{
    (void)state;
    g_profile = NEGOBS_STEREO_PROFILE_FAST;
    same_for_every_worker_count(4, 32, 0);
    g_profile = NEGOBS_STEREO_PROFILE_COMPACT;
}

static void test_same_bands5_crop_fast(void **state)
{
    (void)state;
    g_profile = NEGOBS_STEREO_PROFILE_FAST;
    same_for_every_worker_count(5, 8, 16);
    g_profile = NEGOBS_STEREO_PROFILE_COMPACT;
}

/* xorshift32: repeatable texture */
static uint32_t rnd(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}

/*
 * The seam rule. A fronto-parallel plane at 12 px: full-contrast random
 * texture in rows 0-31 (the first band), below a texture of 6 grey levels,
 * whose Sobel magnitude (at most 48) stays under canny_low (60): with the
 * fixed thresholds (canny_top_permille 0) no edges, so the lower bands
 * have no seed of their own, yet their windows correlate perfectly.
 * Growth from the first band carries down strip by strip in a sequential
 * run; with bands, the seam rule must grow the seedless bands again from
 * the rows above their borders, or they stay empty. With the strips' own
 * strongest share (the default) the lower bands seed themselves.
 */
static void test_seam_rule_fills_seedless_bands(void **state)
{
    uint32_t seed = 12345u;
    int32_t x;
    int32_t y;
    int i;
    uint32_t regrown[3];
    uint32_t seeds[3];
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            uint32_t r = rnd(&seed);
            left[y * W + x] = (y < 32) ? (uint8_t)(r & 255u)
                                       : (uint8_t)(100u + r % 6u);
        }
    }
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            right[y * W + x] = left[y * W + (x + 12 < W ? x + 12 : W - 1)];
        }
    }
    for (i = 0; i < 3; i++) {
        negobs_image_u8_t li = {left, W, H, W};
        negobs_image_u8_t ri = {right, W, H, W};
        run_t *r = &g_run[i == 1];
        negobs_image_s16_t di = {r->disp, W, H, W};
        int32_t good = 0;
        g_fixed_canny = i < 2;
        init_run(r, i == 0 ? 1 : 4, 1, 16);
        g_fixed_canny = 0;
        assert_int_equal(
            negobs_stereo_process(&r->ctx, &li, &ri, &di, NULL, &r->st),
            NEGOBS_OK);
        regrown[i] = r->st.seam_regrown;
        seeds[i] = r->st.seeds;
        /* rows 64.. (bands 2 and 3 of 4): the plane, nearly everywhere */
        for (y = 64; y < H - 4; y++) {
            for (x = 20; x < W - 4; x++) {
                int32_t d = r->disp[y * W + x];
                good += (d != NEGOBS_DISP_INVALID && d >= 11 * 16 &&
                         d <= 13 * 16);
            }
        }
        assert_true(good * 10 >= (H - 68) * (W - 24) * 9);
    }
    assert_int_equal(regrown[0], 0);
    /* bands 2 and 3; band 1 has seeds on its first rows, whose Sobel
     * window reaches the textured band above */
    assert_int_equal(regrown[1], 2);
    assert_int_equal(regrown[2], 0);
    assert_true(seeds[2] > seeds[1]);
}

/* Runs the jobs in index order, job j on worker j % workers: the
 * pool's hand-out order, so band_order[0] really runs first. */
static void in_order_run(void *user, int32_t n_jobs, negobs_job_fn fn,
                         void *arg)
{
    fake_exec_t *f = (fake_exec_t *)user;
    int32_t j;
    for (j = 0; j < n_jobs; j++) {
        fn(arg, j, j % f->workers);
        f->jobs_seen++;
    }
    f->runs++;
}

/* The crops of a short sequence whose scene changes every frame, so each
 * frame's dispatch order comes from a different last frame. */
static const int32_t seq_first_row[] = {0, 24, 8, 8, 0};

/*
 * The dispatch order: a fresh context orders by rows (bands of 2, 3 and 3
 * strips of 16 rows, the last strip 8 rows: 32, 48 and 40 rows), later
 * frames by the last frame's cells scored per band, costliest first; on
 * one worker the bands keep their order (DP stage 1 then feeds stage 2
 * top to bottom). Whatever the order, every frame's output equals the
 * one-worker, in-order run bit for bit, on in-order and on backwards
 * executors.
 */
static void test_dispatch_order(void **state)
{
    int32_t k;
    int backwards;
    (void)state;
    for (backwards = 0; backwards < 2; backwards++) {
        fake_exec_t f = {2, 0, 0};
        negobs_executor_t e;
        const stx_t *s1;
        const stx_t *s0;
        e.workers = 2;
        e.run = backwards ? fake_run : in_order_run;
        e.user = &f;
        init_run(&g_run[0], 3, 1, 16);
        init_run(&g_run[1], 3, 2, 16);
        assert_int_equal(negobs_stereo_set_executor(&g_run[1].ctx, &e),
                         NEGOBS_OK);
        s0 = (const stx_t *)g_run[0].ctx.priv;
        s1 = (const stx_t *)g_run[1].ctx.priv;
        for (k = 0; k < 5; k++) {
            uint32_t work[3];
            int32_t top = seq_first_row[k];
            int32_t b;
            render(40u + (uint32_t)k);
            memcpy(work, s1->band_work, sizeof work);
            assert_int_equal(negobs_stereo_set_first_row(&g_run[0].ctx, top),
                             NEGOBS_OK);
            assert_int_equal(negobs_stereo_set_first_row(&g_run[1].ctx, top),
                             NEGOBS_OK);
            process(&g_run[0]);
            process(&g_run[1]);
            assert_same();
            for (b = 0; b < 3; b++) {
                assert_int_equal(s0->band_order[b], b);
            }
            if (k == 0) {
                assert_int_equal(s1->band_order[0], 1);
                assert_int_equal(s1->band_order[1], 2);
                assert_int_equal(s1->band_order[2], 0);
            } else if (top == seq_first_row[k - 1]) {
                /* same crop: the last frame's counts rank the bands */
                assert_true(work[s1->band_order[0]] >=
                            work[s1->band_order[1]]);
                assert_true(work[s1->band_order[1]] >=
                            work[s1->band_order[2]]);
                assert_true(work[s1->band_order[2]] > 0u);
            }
            /* this frame's counts, for the next frame's order */
            for (b = 0; b < 3; b++) {
                assert_true(s1->band_work[b] > 0u);
            }
        }
        assert_true(f.runs >= 5 * 11);
    }
}

/* A per-worker clock, like thread CPU time: worker k's counter starts
 * near k x 2^30 and each read advances it; the executor names the
 * worker whose "thread" runs. */
static uint32_t g_clock[WORKERS];
static int32_t g_clock_worker;

static uint32_t worker_clock(void *user)
{
    (void)user;
    g_clock[g_clock_worker] += 3u;
    return g_clock[g_clock_worker];
}

static void clocked_run(void *user, int32_t n_jobs, negobs_job_fn fn,
                        void *arg)
{
    fake_exec_t *f = (fake_exec_t *)user;
    int32_t j;
    for (j = 0; j < n_jobs; j++) {
        g_clock_worker = j % f->workers;
        fn(arg, j, g_clock_worker);
        g_clock_worker = 0;
    }
    f->runs++;
}

/* Stage ticks with a per-thread clock on several workers: each worker's
 * ticks come from its own clock, so every stage gets a few ticks per
 * read, never a difference between two workers' counters. */
static void test_per_thread_clock(void **state)
{
    fake_exec_t f = {WORKERS, 0, 0};
    negobs_executor_t e;
    negobs_image_u8_t li = {left, W, H, W};
    negobs_image_u8_t ri = {right, W, H, W};
    negobs_image_s16_t di = {g_run[0].disp, W, H, W};
    uint64_t total = 0;
    int32_t k;
    (void)state;
    render(5u);
    for (k = 0; k < WORKERS; k++) {
        g_clock[k] = (uint32_t)k << 30;
    }
    g_clock_worker = 0;
    init_run(&g_run[0], 4, WORKERS, 16);
    e.workers = WORKERS;
    e.run = clocked_run;
    e.user = &f;
    assert_int_equal(negobs_stereo_set_executor(&g_run[0].ctx, &e), NEGOBS_OK);
    assert_int_equal(
        negobs_stereo_set_clock(&g_run[0].ctx, worker_clock, NULL), NEGOBS_OK);
    assert_int_equal(negobs_stereo_process(&g_run[0].ctx, &li, &ri, &di, NULL,
                                           &g_run[0].st),
                     NEGOBS_OK);
    for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
        /* a few hundred reads of 3 ticks; a cross-worker difference
         * would be about 2^30 */
        assert_true(g_run[0].st.stage_ticks[k] < 100000u);
        total += g_run[0].st.stage_ticks[k];
    }
    assert_true(total > 0u);
    assert_true(g_run[0].st.stage_ticks[NEGOBS_STEREO_STAGE_GCS] > 0u);
}

/* An executor that skips the last job (mode 0), hands one job a worker
 * index outside [0, workers) (mode 1) or names a job index past the last
 * one instead of the last (mode 2). */
typedef struct broken_exec {
    int mode;
    int32_t workers;
} broken_exec_t;

static void broken_run(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg)
{
    broken_exec_t *b = (broken_exec_t *)user;
    int32_t j;
    for (j = 0; j < n_jobs; j++) {
        if (b->mode == 0 && j == n_jobs - 1) {
            continue;
        }
        if (b->mode == 2 && j == n_jobs - 1) {
            fn(arg, n_jobs, 0);
            continue;
        }
        fn(arg, j, (b->mode == 1 && j == 1) ? b->workers : 0);
    }
}

/* One frame of run r on an executor that breaks in `mode`: the frame
 * fails (never a map with holes of unknown content). Then the sound fake
 * executor f is installed for the frames after it. */
static void fail_one_frame(run_t *r, int mode, fake_exec_t *f)
{
    broken_exec_t b = {mode, 2};
    negobs_executor_t e;
    negobs_image_u8_t li = {left, W, H, W};
    negobs_image_u8_t ri = {right, W, H, W};
    negobs_image_s16_t di = {r->disp, W, H, W};
    e.workers = 2;
    e.run = broken_run;
    e.user = &b;
    assert_int_equal(negobs_stereo_set_executor(&r->ctx, &e), NEGOBS_OK);
    assert_int_equal(
        negobs_stereo_process(&r->ctx, &li, &ri, &di, NULL, &r->st),
        NEGOBS_ERR_STATE);
    e.run = fake_run;
    e.user = f;
    assert_int_equal(negobs_stereo_set_executor(&r->ctx, &e), NEGOBS_OK);
}

/* A broken executor makes the frame fail, and the next frame on a sound
 * one succeeds. */
static void test_broken_executor_fails_the_frame(void **state)
{
    int mode;
    (void)state;
    render(21u);
    for (mode = 0; mode < 3; mode++) {
        fake_exec_t f = {2, 0, 0};
        init_run(&g_run[0], 4, 2, 32);
        fail_one_frame(&g_run[0], mode, &f);
        process(&g_run[0]);
    }
}

/* The same in the fast profile, whose DP borrows the memo: whichever
 * job was skipped, the memo comes back empty, so the frames after the
 * failed one match the compact profile's. */
static void test_broken_executor_fast(void **state)
{
    int mode;
    (void)state;
    render(22u);
    init_run(&g_run[0], 4, 1, 32);
    process(&g_run[0]);
    g_profile = NEGOBS_STEREO_PROFILE_FAST;
    for (mode = 0; mode < 3; mode++) {
        fake_exec_t f = {2, 0, 0};
        init_run(&g_run[1], 4, 2, 32);
        fail_one_frame(&g_run[1], mode, &f);
        process(&g_run[1]);
        process(&g_run[1]);
        assert_same();
    }
    g_profile = NEGOBS_STEREO_PROFILE_COMPACT;
}

static void test_executor_checks(void **state)
{
    negobs_stereo_t none;
    negobs_executor_t e;
    fake_exec_t f = {2, 0, 0};
    (void)state;
    memset(&none, 0, sizeof none);
    e.workers = 2;
    e.run = fake_run;
    e.user = &f;
    assert_int_equal(negobs_stereo_set_executor(&none, &e), NEGOBS_ERR_STATE);
    init_run(&g_run[0], 4, 2, 32);
    assert_int_equal(negobs_stereo_set_executor(&g_run[0].ctx, &e), NEGOBS_OK);
    e.workers = 3; /* more workers than scratch areas */
    assert_int_equal(negobs_stereo_set_executor(&g_run[0].ctx, &e),
                     NEGOBS_ERR_INVAL);
    e.workers = 0;
    assert_int_equal(negobs_stereo_set_executor(&g_run[0].ctx, &e),
                     NEGOBS_ERR_INVAL);
    e.workers = 1;
    e.run = NULL;
    assert_int_equal(negobs_stereo_set_executor(&g_run[0].ctx, &e),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_stereo_set_executor(&g_run[0].ctx, NULL),
                     NEGOBS_OK);
}

static void test_config_and_workspace(void **state)
{
    negobs_stereo_config_t cfg;
    size_t one = 0;
    size_t more = 0;
    int32_t k;
    (void)state;
    negobs_stereo_config_default(&cfg, 320, 240);
    assert_int_equal(cfg.bands, NEGOBS_STEREO_BANDS_DEFAULT);
    assert_int_equal(cfg.band_workers, 1);
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &one), NEGOBS_OK);
    /* the compact profile's budget holds with the default bands */
    assert_true(one <= 512u * 1024u);
    for (k = 2; k <= 4; k++) {
        cfg.band_workers = k;
        assert_int_equal(negobs_stereo_workspace_size(&cfg, &more), NEGOBS_OK);
        assert_true(more > one);
        assert_true(more - one <=
                    (size_t)(k - 1) *
                            NEGOBS_STEREO_WORKSPACE_WORKER_MAX(320, 63) +
                        NEGOBS_STEREO_WORKSPACE_BANDS_MAX(240, 63));
    }
    /* the most bands and the widest range the macros must cover */
    negobs_stereo_config_default(&cfg, 640, 480);
    cfg.max_disp = 255;
    cfg.bands = NEGOBS_STEREO_MAX_BANDS;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &one), NEGOBS_OK);
    cfg.band_workers = 4;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &more), NEGOBS_OK);
    assert_true(more - one <=
                3u * NEGOBS_STEREO_WORKSPACE_WORKER_MAX(640, 255) +
                    NEGOBS_STEREO_WORKSPACE_BANDS_MAX(480, 255));
    cfg.band_workers = 1;
    cfg.bands = 0;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &more),
                     NEGOBS_ERR_INVAL);
    cfg.bands = NEGOBS_STEREO_MAX_BANDS + 1;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &more),
                     NEGOBS_ERR_INVAL);
    cfg.bands = 4;
    cfg.band_workers = 0;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &more),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layout),
        cmocka_unit_test(test_same_bands1),
        cmocka_unit_test(test_same_bands3),
        cmocka_unit_test(test_same_bands4),
        cmocka_unit_test(test_same_bands5_crop),
        cmocka_unit_test(test_same_bands4_fast),
        cmocka_unit_test(test_same_bands5_crop_fast),
        cmocka_unit_test(test_seam_rule_fills_seedless_bands),
        cmocka_unit_test(test_dispatch_order),
        cmocka_unit_test(test_per_thread_clock),
        cmocka_unit_test(test_broken_executor_fails_the_frame),
        cmocka_unit_test(test_broken_executor_fast),
        cmocka_unit_test(test_executor_checks),
        cmocka_unit_test(test_config_and_workspace),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
