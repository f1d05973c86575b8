/*
 * Row bands on threads (Meson benchmark(), prints figures): wall time of
 * one negobs_stereo_process with 1, 2 and 4 threads of the port/ pool on
 *  - the typical generated 320x240 frame (range 0-63),
 *  - Middlebury Cones (450x375, range 0-63) from $NEGOBS_DATA when present,
 *  - and of negobs_pipeline_process over the 24-frame generated curb walk
 *    (tests/support/walk.c, 320x240, mean per frame),
 * with the CPU time of the whole process beside it (all threads), the
 * ratio to one thread, and a check that every thread count gives the same
 * disparities and statistics bit for bit. Wall time on a shared machine is
 * noisy: the best of REPS runs is kept and the online cores printed, and
 * an idle-core projection is printed beside it; for the walk also pass by
 * pass (each parallel run's band jobs in dispatch order, its projected
 * span and the caller's serial time before it) and the pipeline's stages.
 *
 * `bench_threads --once N` runs one 320x240 frame on N threads of the pool
 * and nothing else (no projection) (callgrind --separate-threads=yes counts instructions per
 * thread; tools/negobs bench prints them).
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../support/walk.h"
#include "../support/scene_pair.h"
#include "negobs/pipeline.h"
#include "negobs/stereo.h"
#include "negobs_port/pool.h"

#define QW 320
#define QH 240
#define REPS 7
#define MAXT 4
#define MAXPX (SYNTH_MAX_W * SYNTH_MAX_H * 4)

static uint8_t lpx[MAXPX];
static uint8_t rpx[MAXPX];
static int16_t gt[MAXPX];
static uint8_t occ[MAXPX];
static uint8_t tex[MAXPX];
static int16_t disp[MAXPX];
static int16_t disp_ref[MAXPX];
static uint8_t conf[MAXPX];

static double wall_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static void *aligned(size_t bytes, void **raw)
{
    *raw = malloc(bytes + 16u);
    if (*raw == NULL) {
        return NULL;
    }
    return (void *)(((uintptr_t)*raw + 15u) & ~(uintptr_t)15u);
}

static double thread_cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/*
 * Projection for an idle machine: an executor that runs every job on the
 * calling thread, times it (thread CPU time, which the other programs on a
 * shared machine hardly disturb) and books it on the simulated worker that
 * is free first, as the pool hands out jobs. A run then lasts as long as
 * its busiest worker; the frame as its serial part plus its runs.
 */
typedef struct sim_exec {
    int32_t workers;
    double load[MAXT];
    double jobs_ms; /* CPU ms of every job of the frame          */
    double span_ms; /* sum over runs of the busiest worker's ms  */
} sim_exec_t;

/* Run the n_jobs jobs of one run on x's simulated workers, each on the
 * worker free first; job_ms (or NULL) gets each job's CPU ms for its first
 * n_keep jobs. Returns the run's span (its busiest worker's ms). */
static double sim_schedule(sim_exec_t *x, int32_t n_jobs, negobs_job_fn fn,
                           void *arg, double *job_ms, int32_t n_keep)
{
    int32_t j;
    int32_t k;
    double span = 0.0;
    for (k = 0; k < x->workers; k++) {
        x->load[k] = 0.0;
    }
    for (j = 0; j < n_jobs; j++) {
        int32_t free_first = 0;
        double t0;
        double dt;
        for (k = 1; k < x->workers; k++) {
            if (x->load[k] < x->load[free_first]) {
                free_first = k;
            }
        }
        t0 = thread_cpu_ms();
        fn(arg, j, free_first);
        dt = thread_cpu_ms() - t0;
        x->load[free_first] += dt;
        x->jobs_ms += dt;
        if (job_ms != NULL && j < n_keep) {
            job_ms[j] += dt;
        }
    }
    for (k = 0; k < x->workers; k++) {
        span = (x->load[k] > span) ? x->load[k] : span;
    }
    x->span_ms += span;
    return span;
}

static void sim_run(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg)
{
    (void)sim_schedule((sim_exec_t *)user, n_jobs, fn, arg, NULL, 0);
}

/* Thread CPU time in microseconds, as the engine's profiling clock. */
static uint32_t clock_us(void *user)
{
    (void)user;
    return (uint32_t)(thread_cpu_ms() * 1000.0);
}

static const char *const stage_names[NEGOBS_STEREO_STAGE_COUNT] = {
    "vertical", "range",   "windows",  "canny", "gcs",   "dp",
    "lr",       "speckle", "gap fill", "mean",  "output"};

typedef struct timing {
    double stage_ms[NEGOBS_STEREO_STAGE_COUNT]; /* 1 thread, best run */
    double wall;                                /* best wall ms per frame */
    double cpu;    /* process CPU ms of that run */
    double proj;   /* projected ms on `threads` idle cores (best run) */
    double serial; /* of which on the calling thread, outside band jobs */
    int same;      /* output equal to the one-thread run */
    uint32_t seam_regrown;
} timing_t;

/* One engine on w x h (pixels already in lpx/rpx), `threads` threads;
 * first = 1 keeps the result as the reference. Returns -1 on failure. */
static int time_stereo(int32_t w, int32_t h, int32_t threads, int reps,
                       int first, timing_t *t)
{
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_stereo_stats_t st;
    static negobs_stereo_stats_t st_ref;
    negobs_pool_t *pool = NULL;
    negobs_executor_t e;
    size_t bytes = 0;
    void *raw = NULL;
    void *ws;
    int r;
    negobs_image_u8_t li = {lpx, w, h, w};
    negobs_image_u8_t ri = {rpx, w, h, w};
    negobs_image_s16_t di = {disp, w, h, w};
    negobs_image_u8_t ci = {conf, w, h, w};

    negobs_stereo_config_default(&cfg, w, h);
    cfg.band_workers = threads;
    t->proj = 1e30;
    if (negobs_stereo_workspace_size(&cfg, &bytes) != NEGOBS_OK ||
        (ws = aligned(bytes, &raw)) == NULL ||
        negobs_stereo_init(&ctx, &cfg, ws, bytes) != NEGOBS_OK) {
        free(raw);
        return -1;
    }
    if (threads > 1) {
        if (negobs_pool_create(&pool, threads) != NEGOBS_OK) {
            free(raw);
            return -1;
        }
        e = negobs_pool_executor(pool);
        (void)negobs_stereo_set_executor(&ctx, &e);
    }
    t->wall = 1e30;
    if (threads == 1) {
        (void)negobs_stereo_set_clock(&ctx, clock_us, NULL);
    }
    for (r = 0; r < reps; r++) {
        double w0 = wall_ms();
        double c0 = cpu_ms();
        double tc0 = thread_cpu_ms();
        if (negobs_stereo_process(&ctx, &li, &ri, &di, &ci, &st) !=
            NEGOBS_OK) {
            negobs_pool_destroy(pool);
            free(raw);
            return -1;
        }
        if (wall_ms() - w0 < t->wall) {
            t->wall = wall_ms() - w0;
            t->cpu = cpu_ms() - c0;
        }
        if (threads == 1 && thread_cpu_ms() - tc0 < t->proj) {
            int i;
            t->proj = thread_cpu_ms() - tc0; /* one core: its CPU time */
            for (i = 0; i < NEGOBS_STEREO_STAGE_COUNT; i++) {
                t->stage_ms[i] = (double)st.stage_ticks[i] / 1000.0;
            }
        }
    }
    /* the projection: the same engine on the simulating executor */
    if (threads > 1 && reps > 1) {
        t->proj = 1e30;
        for (r = 0; r < reps; r++) {
            sim_exec_t sim;
            double c0;
            double frame;
            memset(&sim, 0, sizeof sim);
            sim.workers = threads;
            e.workers = threads;
            e.run = sim_run;
            e.user = &sim;
            (void)negobs_stereo_set_executor(&ctx, &e);
            c0 = thread_cpu_ms();
            (void)negobs_stereo_process(&ctx, &li, &ri, &di, &ci, &st);
            frame = thread_cpu_ms() - c0;
            frame = frame - sim.jobs_ms + sim.span_ms;
            if (frame < t->proj) {
                t->proj = frame;
                t->serial = frame - sim.span_ms;
            }
        }
    }
    memset(st.stage_ticks, 0, sizeof st.stage_ticks);
    if (first) {
        memcpy(disp_ref, disp, (size_t)w * (size_t)h * sizeof *disp);
        st_ref = st;
    }
    t->same = memcmp(disp_ref, disp, (size_t)w * (size_t)h * sizeof *disp) ==
                  0 &&
              memcmp(&st_ref, &st, sizeof st) == 0;
    t->seam_regrown = st.seam_regrown;
    negobs_pool_destroy(pool);
    free(raw);
    return 0;
}

static void report(const char *what, int32_t w, int32_t h)
{
    static const int32_t counts[] = {1, 2, 4};
    timing_t t1;
    memset(&t1, 0, sizeof t1);
    size_t i;
    printf("\n%s %dx%d, range 0-63, %d bands, best of %d (wall ms per "
           "frame; CPU = all threads):\n",
           what, w, h, NEGOBS_STEREO_BANDS_DEFAULT, REPS);
    for (i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        timing_t t;
        memset(&t, 0, sizeof t);
        if (time_stereo(w, h, counts[i], REPS, i == 0, &t) != 0) {
            printf("  %d threads: failed\n", (int)counts[i]);
            return;
        }
        if (i == 0) {
            t1 = t;
        }
        printf("  %d thread%s: idle-core projection %7.2f ms (x%.2f, serial "
               "%.2f), wall %7.2f ms (x%.2f), CPU %7.2f ms, output %s, seam "
               "regrowths %u\n",
               (int)counts[i], counts[i] > 1 ? "s" : " ", t.proj,
               t.proj / t1.proj, counts[i] > 1 ? t.serial : t.proj, t.wall,
               t.wall / t1.wall, t.cpu, t.same ? "identical" : "DIFFERENT",
               (unsigned)t.seam_regrown);
        if (i == 0) {
            int k;
            printf("    1 thread by stage (thread CPU ms):");
            for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
                printf(" %s %.2f", stage_names[k], t.stage_ms[k]);
            }
            printf("\n");
        }
    }
}

/* Binary PPM (P6, maxval 255) to grey, BT.601 weights; 0 on success. */
static int read_ppm_grey(const char *path, uint8_t *out, int32_t *w,
                         int32_t *h)
{
    FILE *f = fopen(path, "rb");
    int mw = 0;
    int mh = 0;
    int mv = 0;
    int32_t i;
    if (f == NULL) {
        return -1;
    }
    if (fscanf(f, "P6 %d %d %d", &mw, &mh, &mv) != 3 || mv != 255 || mw < 1 ||
        mh < 1 || (size_t)mw * (size_t)mh > MAXPX || fgetc(f) == EOF) {
        fclose(f);
        return -1;
    }
    for (i = 0; i < mw * mh; i++) {
        int r = fgetc(f);
        int g = fgetc(f);
        int b = fgetc(f);
        if (b == EOF) {
            fclose(f);
            return -1;
        }
        out[i] = (uint8_t)((299 * r + 587 * g + 114 * b + 500) / 1000);
    }
    fclose(f);
    *w = mw;
    *h = mh;
    return 0;
}

static void typical(void)
{
    synth_scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.w = QW;
    sc.h = QH;
    sc.d_top_q8 = 4 * 256;
    sc.d_bottom_q8 = 40 * 256;
    sc.drop_q8 = 3 * 256;
    sc.seed = 11;
    synth_render(&sc, lpx, rpx, gt, occ, tex);
}

static void cones(void)
{
    const char *data = getenv("NEGOBS_DATA");
    char lp[1024];
    char rp[1024];
    int32_t w = 0;
    int32_t h = 0;
    int32_t w2 = 0;
    int32_t h2 = 0;
    if (data == NULL) {
        printf("\nMiddlebury Cones: NEGOBS_DATA not set\n");
        return;
    }
    snprintf(lp, sizeof lp, "%s/middlebury/cones/im2.ppm", data);
    snprintf(rp, sizeof rp, "%s/middlebury/cones/im6.ppm", data);
    if (read_ppm_grey(lp, lpx, &w, &h) != 0 ||
        read_ppm_grey(rp, rpx, &w2, &h2) != 0 || w != w2 || h != h2) {
        printf("\nMiddlebury Cones: not found under %s\n", data);
        return;
    }
    report("Middlebury Cones", w, h);
}

/*
 * The pipeline's idle-core projection, pass by pass: the simulating
 * executor above, plus which parallel pass each run is (its job function
 * and how many runs of that function came before it in the frame), each
 * band job's thread CPU time and the caller's serial time before the run.
 */
#define PASS_MAX 16
#define PASS_BANDS 8

typedef struct pass_sim {
    sim_exec_t sim;
    negobs_job_fn fn[PASS_MAX];
    int32_t nth[PASS_MAX];
    int32_t passes;
    int32_t seq_fn_count; /* runs seen this frame */
    negobs_job_fn seq_fn[PASS_MAX];
    double band_ms[PASS_MAX][PASS_BANDS]; /* summed over frames */
    double span_ms[PASS_MAX];
    double serial_ms[PASS_MAX + 1]; /* before pass k; [PASS_MAX]: after */
    double runs[PASS_MAX];
    double last_exit; /* thread CPU ms when the last run returned */
} pass_sim_t;

/* Runs in the order frame 0 (which searches the vertical offset) makes
 * them with the default configuration: the matcher's, then the
 * detector's. */
static const char *const pass_names[] = {
    "vertical search", "low-res means", "low-res match", "grow (GCS)",
    "DP stage 1",      "back-track",    "LR check",      "speckle marks",
    "speckle clears",  "gap fill",      "mean rows",     "mean columns",
    "pooled frames"};

static void pass_run(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg)
{
    pass_sim_t *ps = (pass_sim_t *)user;
    sim_exec_t *x = &ps->sim;
    double entry = thread_cpu_ms();
    int32_t nth = 0;
    int32_t key;
    int32_t k;
    double span = 0.0;
    for (k = 0; k < ps->seq_fn_count; k++) {
        nth += ps->seq_fn[k] == fn;
    }
    if (ps->seq_fn_count < PASS_MAX) {
        ps->seq_fn[ps->seq_fn_count++] = fn;
    }
    for (key = 0; key < ps->passes; key++) {
        if (ps->fn[key] == fn && ps->nth[key] == nth) {
            break;
        }
    }
    if (key == ps->passes && ps->passes < PASS_MAX) {
        ps->fn[key] = fn;
        ps->nth[key] = nth;
        ps->passes++;
    }
    if (key < PASS_MAX) {
        ps->serial_ms[key] += entry - ps->last_exit;
        ps->runs[key] += 1.0;
    }
    span = sim_schedule(x, n_jobs, fn, arg,
                        (key < PASS_MAX) ? ps->band_ms[key] : NULL,
                        PASS_BANDS);
    if (key < PASS_MAX) {
        ps->span_ms[key] += span;
    }
    ps->last_exit = thread_cpu_ms();
}

/* The walk on the simulating executor with `threads` simulated workers:
 * projected ms per frame (mean), and the pass table when `table`. */
static int walk_project(int32_t threads, int table, double *proj)
{
    negobs_pipeline_config_t pc;
    negobs_pipeline_t p;
    negobs_executor_t e;
    static pass_sim_t ps;
    size_t bytes = 0;
    void *raw = NULL;
    void *ws;
    int32_t f;
    int32_t k;
    double frames_ms = 0.0;
    double jobs = 0.0;
    double after = 0.0;
    double stage_ms[NEGOBS_PIPELINE_STAGE_COUNT];
    negobs_pipeline_config_default(&pc, QW, QH);
    pc.stereo.band_workers = threads;
    if (negobs_pipeline_workspace_size(&pc, &bytes) != NEGOBS_OK ||
        (ws = aligned(bytes, &raw)) == NULL ||
        negobs_pipeline_init(&p, &pc, ws, bytes) != NEGOBS_OK) {
        free(raw);
        return -1;
    }
    memset(&ps, 0, sizeof ps);
    ps.sim.workers = threads;
    e.workers = threads;
    e.run = pass_run;
    e.user = &ps;
    (void)negobs_pipeline_set_executor(&p, &e);
    (void)negobs_pipeline_set_clock(&p, clock_us, NULL);
    memset(stage_ms, 0, sizeof stage_ms);
    for (f = 0; f < WALK_FRAMES; f++) {
        negobs_image_u8_t li = {lpx, QW, QH, QW};
        negobs_image_u8_t ri = {rpx, QW, QH, QW};
        negobs_pipeline_frame_t fr;
        negobs_pipeline_result_t res;
        double c0;
        double span0 = ps.sim.span_ms;
        double jobs0 = ps.sim.jobs_ms;
        double frame;
        if (walk_render(&pc.detect.rig, f, lpx, rpx) != 0) {
            break;
        }
        memset(&fr, 0, sizeof fr);
        fr.left = &li;
        fr.right = &ri;
        fr.t_left_ms = (uint32_t)f * 100u;
        fr.t_right_ms = fr.t_left_ms;
        fr.now_ms = fr.t_left_ms + 20u;
        ps.seq_fn_count = 0;
        c0 = thread_cpu_ms();
        ps.last_exit = c0;
        (void)negobs_pipeline_process(&p, &fr, &res);
        frame = thread_cpu_ms() - c0;
        after += thread_cpu_ms() - ps.last_exit;
        for (k = 0; k < NEGOBS_PIPELINE_STAGE_COUNT; k++) {
            stage_ms[k] += (double)res.stage_ticks[k] / 1000.0;
        }
        frames_ms += frame - (ps.sim.jobs_ms - jobs0) +
                     (ps.sim.span_ms - span0);
    }
    *proj = frames_ms / WALK_FRAMES;
    if (table) {
        printf(
            "    by pass (ms per frame over the walk; serial = caller's "
            "time before the run; band jobs in dispatch order, costliest first):\n");
        for (k = 0; k < ps.passes; k++) {
            int32_t b;
            const char *name = (ps.passes == 13) ? pass_names[k] : "run";
            double sum = 0.0;
            for (b = 0; b < PASS_BANDS; b++) {
                sum += ps.band_ms[k][b];
            }
            jobs += sum;
            printf("      %-16s x%4.1f/frame serial before %5.2f | jobs %5.2f "
                   "span(%d) %5.2f | bands",
                   name, ps.runs[k] / WALK_FRAMES,
                   ps.serial_ms[k] / WALK_FRAMES, sum / WALK_FRAMES,
                   (int)threads, ps.span_ms[k] / WALK_FRAMES);
            for (b = 0; b < PASS_BANDS && ps.band_ms[k][b] > 0.0; b++) {
                printf(" %5.2f", ps.band_ms[k][b] / WALK_FRAMES);
            }
            printf("\n");
        }
        printf("      after the last run (the detector after its pooled "
               "frames, alert) "
               "%5.2f; all band jobs %5.2f\n",
               after / WALK_FRAMES, jobs / WALK_FRAMES);
        printf("      pipeline stages (thread CPU ms per frame, band jobs "
               "included): valign %.2f stereo %.2f detect %.2f alert "
               "%.2f\n",
               stage_ms[NEGOBS_PIPELINE_STAGE_VALIGN] / WALK_FRAMES,
               stage_ms[NEGOBS_PIPELINE_STAGE_STEREO] / WALK_FRAMES,
               stage_ms[NEGOBS_PIPELINE_STAGE_DETECT] / WALK_FRAMES,
               stage_ms[NEGOBS_PIPELINE_STAGE_ALERT] / WALK_FRAMES);
    }
    free(raw);
    return 0;
}

/* The whole pipeline over the generated walk: mean wall ms per frame. */
static int walk_run(int32_t threads, double *wall, double *cpu, uint32_t *hash)
{
    negobs_pipeline_config_t pc;
    negobs_pipeline_t p;
    negobs_pool_t *pool = NULL;
    negobs_executor_t e;
    size_t bytes = 0;
    void *raw = NULL;
    void *ws;
    int32_t f;
    double w0;
    double c0;
    negobs_pipeline_config_default(&pc, QW, QH);
    pc.stereo.band_workers = threads;
    if (negobs_pipeline_workspace_size(&pc, &bytes) != NEGOBS_OK ||
        (ws = aligned(bytes, &raw)) == NULL ||
        negobs_pipeline_init(&p, &pc, ws, bytes) != NEGOBS_OK) {
        free(raw);
        return -1;
    }
    if (threads > 1) {
        if (negobs_pool_create(&pool, threads) != NEGOBS_OK) {
            free(raw);
            return -1;
        }
        e = negobs_pool_executor(pool);
        (void)negobs_pipeline_set_executor(&p, &e);
    }
    *wall = 0.0;
    *cpu = 0.0;
    *hash = 2166136261u;
    for (f = 0; f < WALK_FRAMES; f++) {
        negobs_image_u8_t li = {lpx, QW, QH, QW};
        negobs_image_u8_t ri = {rpx, QW, QH, QW};
        negobs_pipeline_frame_t fr;
        negobs_pipeline_result_t res;
        const negobs_image_s16_t *d;
        int32_t i;
        if (walk_render(&pc.detect.rig, f, lpx, rpx) != 0) {
            break;
        }
        memset(&fr, 0, sizeof fr);
        fr.left = &li;
        fr.right = &ri;
        fr.t_left_ms = (uint32_t)f * 100u;
        fr.t_right_ms = fr.t_left_ms;
        fr.now_ms = fr.t_left_ms + 20u;
        w0 = wall_ms();
        c0 = cpu_ms();
        (void)negobs_pipeline_process(&p, &fr, &res);
        *wall += wall_ms() - w0;
        *cpu += cpu_ms() - c0;
        d = negobs_pipeline_disparity(&p);
        for (i = 0; i < QW * QH; i++) {
            *hash = (*hash ^ (uint16_t)d->data[i]) * 16777619u;
        }
        *hash = (*hash ^ (uint32_t)res.detect.state) * 16777619u;
    }
    *wall /= WALK_FRAMES;
    *cpu /= WALK_FRAMES;
    negobs_pool_destroy(pool);
    free(raw);
    return 0;
}

static void walk(void)
{
    static const int32_t counts[] = {1, 2, 4};
    double w1 = 0.0;
    double p1 = 1.0;
    uint32_t h1 = 0;
    size_t i;
    printf("\nnegobs_pipeline_process over the generated curb walk (%d "
           "frames, 320x240, D 0-63; mean wall ms per frame, best of 3 "
           "walks):\n",
           WALK_FRAMES);
    for (i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        double best = 1e30;
        double best_cpu = 0.0;
        uint32_t hash = 0;
        int r;
        for (r = 0; r < 3; r++) {
            double w;
            double c;
            if (walk_run(counts[i], &w, &c, &hash) != 0) {
                printf("  %d threads: failed\n", (int)counts[i]);
                return;
            }
            if (w < best) {
                best = w;
                best_cpu = c;
            }
        }
        if (i == 0) {
            w1 = best;
            h1 = hash;
        }
        printf("  %d thread%s: wall %7.2f ms (x%.2f of 1 thread), CPU %7.2f "
               "ms, output %s\n",
               (int)counts[i], counts[i] > 1 ? "s" : " ", best, best / w1,
               best_cpu, hash == h1 ? "identical" : "DIFFERENT");
        if (counts[i] > 1) {
            double proj = 1e30;
            for (r = 0; r < 3; r++) {
                double pr;
                if (walk_project(counts[i], r == 2, &pr) != 0) {
                    printf("    projection failed\n");
                    return;
                }
                proj = (pr < proj) ? pr : proj;
            }
            printf("    idle-core projection %7.2f ms (x%.2f of 1 thread's "
                   "CPU %.2f ms)\n",
                   proj, proj / p1, p1);
        } else {
            p1 = best_cpu;
        }
    }
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--once") == 0) {
        timing_t t;
        typical();
        return time_stereo(QW, QH, atoi(argv[2]), 1, 1, &t) == 0 ? 0 : 1;
    }
    printf("row bands on threads (release figures only mean something from "
           "a release build); online cores: %d\n",
           (int)negobs_pool_online_cores());
    printf("wall time on a shared machine is noisy; the idle-core projection "
           "(each band job's thread CPU time, booked on the simulated worker "
           "free first;\n serial parts as measured) and instruction counts "
           "(callgrind) are the stable figures\n");
    typical();
    report("typical generated frame", QW, QH);
    cones();
    walk();
    return 0;
}
