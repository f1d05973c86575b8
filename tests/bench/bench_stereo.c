/*
 * Disparity and detection benchmark (Meson benchmark(), prints figures):
 *  - workspace bytes of the matcher and of the whole pipeline at 320x240
 *    with 64 disparities (target: matcher <= 512 KiB);
 *  - time, visited cells, queue peak and overflows on a typical generated
 *    scene and on adversarial frames (stripes, noise, checkerboard, a
 *    large textureless area), and the worst/typical factors, so the effect
 *    of the queue bound and the DP band on the worst case is visible;
 *  - detection time as a share of the disparity time (target < 15 %);
 *  - Middlebury Cones (450x375, range 0-63) from $NEGOBS_DATA when present;
 *  - the time of every matcher stage (negobs_pipeline_set_clock) on the
 *    typical frame and on Cones.
 * `bench_stereo --once` runs one QVGA frame only (for callgrind).
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../support/scene_pair.h"
#include "../support/test_rng.h"
#include "negobs/pipeline.h"
#include "negobs/valign.h"
#include "negobs/version.h"

#define QW 320
#define QH 240
#define REPS 5

static uint8_t lpx[SYNTH_MAX_W * SYNTH_MAX_H * 4];
static uint8_t rpx[SYNTH_MAX_W * SYNTH_MAX_H * 4];
static int16_t gt[SYNTH_MAX_W * SYNTH_MAX_H];
static uint8_t occ[SYNTH_MAX_W * SYNTH_MAX_H];
static uint8_t tex[SYNTH_MAX_W * SYNTH_MAX_H];

/* CPU time of this thread: the machine is shared, wall time is noisy */
static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* Profiling clock for the matcher: thread CPU time in ns, modulo 2^32
 * (the library takes differences, so the wrap every 4.3 s is harmless). */
static uint32_t clock_ns(void *user)
{
    struct timespec ts;
    (void)user;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (uint32_t)((uint64_t)ts.tv_sec * 1000000000u +
                      (uint64_t)ts.tv_nsec);
}

static const char *const stage_name[NEGOBS_STEREO_STAGE_COUNT] = {
    "vertical offset (6)",
    "1/4 map + ranges (1)",
    "window sums",
    "Canny (2)",
    "GCS seeds + growth (3)",
    "DP + sub-pixel (4)",
    "LR check (5)",
    "speckles (5)",
    "gap fill (5)",
    "adaptive mean (5)",
    "output",
};

typedef struct figures {
    double stereo_ms;
    double stage_ms[NEGOBS_STEREO_STAGE_COUNT]; /* best of the runs each */
    double detect_ms;
    negobs_stereo_stats_t st;
    negobs_detect_state_t state; /* detector verdict on the frame */
} figures_t;

static void *aligned(size_t bytes, void **raw)
{
    *raw = malloc(bytes + 16u);
    if (*raw == NULL) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    return (void *)(((uintptr_t)*raw + 15u) & ~(uintptr_t)15u);
}

/* Best-of-REPS time of the stereo and detect stages on one pair, from the
 * pipeline's stage clock. */
static int measure(int32_t w, int32_t h, int32_t max_disp, int reps,
                   figures_t *fig)
{
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx = malloc(sizeof *ctx);
    negobs_image_u8_t l = {lpx, w, h, w};
    negobs_image_u8_t r = {rpx, w, h, w};
    negobs_pipeline_frame_t fr;
    negobs_pipeline_result_t res;
    size_t bytes = 0;
    void *raw;
    void *ws;
    int i;

    negobs_pipeline_config_default(&cfg, w, h);
    cfg.stereo.max_disp = max_disp;
    cfg.detect.max_disp_q4 = (max_disp + 1) * 16;
    /* every rep matches the whole frame, as the figures always did */
    cfg.stereo_roi = 0;
    if (ctx == NULL ||
        negobs_pipeline_workspace_size(&cfg, &bytes) != NEGOBS_OK) {
        return -1;
    }
    ws = aligned(bytes, &raw);
    if (negobs_pipeline_init(ctx, &cfg, ws, bytes) != NEGOBS_OK) {
        return -1;
    }
    (void)negobs_pipeline_set_clock(ctx, clock_ns, NULL);
    fig->stereo_ms = 1e30;
    fig->detect_ms = 1e30;
    for (i = 0; i < NEGOBS_STEREO_STAGE_COUNT; i++) {
        fig->stage_ms[i] = 1e30;
    }
    for (i = 0; i < reps; i++) {
        int k;
        double ms;
        memset(&fr, 0, sizeof fr);
        fr.left = &l;
        fr.right = &r;
        fr.now_ms = (uint32_t)i * 100u;
        fr.t_left_ms = fr.now_ms;
        fr.t_right_ms = fr.now_ms;
        if (negobs_pipeline_process(ctx, &fr, &res) != NEGOBS_OK ||
            res.stereo_status != NEGOBS_OK) {
            return -1;
        }
        fig->st = res.stereo;
        for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
            ms = (double)fig->st.stage_ticks[k] / 1e6;
            if (ms < fig->stage_ms[k])
                fig->stage_ms[k] = ms;
        }
        ms = (double)res.stage_ticks[NEGOBS_PIPELINE_STAGE_STEREO] / 1e6;
        if (ms < fig->stereo_ms)
            fig->stereo_ms = ms;
        ms = (double)res.stage_ticks[NEGOBS_PIPELINE_STAGE_DETECT] / 1e6;
        if (ms < fig->detect_ms)
            fig->detect_ms = ms;
        fig->state = res.detect.state;
    }
    free(raw);
    free(ctx);
    return 0;
}

typedef enum kind { TYPICAL, STRIPES, NOISE, CHECKER, FLAT_AREA } kind_t;
static const char *const kind_name[] = {
    "typical ground scene", "stripes (period 8)", "pure noise (unrelated L/R)",
    "checkerboard (8 px)", "60 % textureless"};

static void make(kind_t k, int32_t w, int32_t h)
{
    synth_scene_t sc;
    int32_t x;
    int32_t y;
    uint32_t s = 7;
    memset(&sc, 0, sizeof sc);
    sc.w = w;
    sc.h = h;
    sc.d_top_q8 = 4 * 256;
    sc.d_bottom_q8 = 40 * 256;
    sc.drop_q8 = 3 * 256;
    sc.seed = 11;
    synth_render(&sc, lpx, rpx, gt, occ, tex);
    for (y = 0; y < h; y++) {
        for (x = 0; x < w; x++) {
            size_t i = (size_t)(y * w + x);
            switch (k) {
            case STRIPES:
                lpx[i] = (uint8_t)(((x / 4) & 1) ? 200 : 50);
                rpx[i] = (uint8_t)((((x + 3) / 4) & 1) ? 200 : 50);
                break;
            case NOISE:
                lpx[i] = (uint8_t)(test_lcg_next(&s) >> 16);
                rpx[i] = (uint8_t)(test_lcg_next(&s) >> 16);
                break;
            case CHECKER:
                lpx[i] = (uint8_t)((((x / 8) + (y / 8)) & 1) ? 220 : 30);
                rpx[i] = (uint8_t)(((((x + 5) / 8) + (y / 8)) & 1) ? 220 : 30);
                break;
            case FLAT_AREA:
                if (y < (h * 6) / 10) {
                    lpx[i] = 120;
                    rpx[i] = 120;
                }
                break;
            case TYPICAL:
            default: break;
            }
        }
    }
}

/* Binary PPM (P6, maxval 255) to grey, BT.601 weights; 0 on success. */
static int read_ppm_grey(const char *path, uint8_t *out, size_t max_px,
                         int32_t *w, int32_t *h)
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
        mh < 1 || mw > 4096 || mh > 4096 || (size_t)mw * (size_t)mh > max_px ||
        fgetc(f) == EOF) {
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

/* Vertical alignment stage (negobs/valign.h) at 320x240, range 0-63, on
 * the typical scene: the first frame (full two-pass search) and the steady
 * state (residual of the tracked model), and the workspace it adds. */
static void bench_valign(void)
{
    static uint8_t out[QW * QH];
    negobs_valign_config_t vc;
    negobs_valign_t ctx;
    negobs_valign_stats_t st;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    negobs_image_u8_t o;
    size_t bytes = 0;
    void *raw;
    void *ws;
    double t0;
    double first;
    double best = 1e30;
    int i;
    negobs_valign_config_default(&vc, QW, QH);
    vc.max_disp = 63;
    if (negobs_valign_workspace_size(&vc, &bytes) != NEGOBS_OK) {
        printf("\nvertical alignment: size query failed\n");
        return;
    }
    ws = aligned(bytes, &raw);
    l.data = lpx;
    l.width = QW;
    l.height = QH;
    l.stride = QW;
    r = l;
    r.data = rpx;
    o = l;
    o.data = out;
    if (negobs_valign_init(&ctx, &vc, ws, bytes) != NEGOBS_OK) {
        printf("\nvertical alignment: init failed\n");
        free(raw);
        return;
    }
    t0 = now_ms();
    if (negobs_valign_process(&ctx, &l, &r, &o, &st) != NEGOBS_OK) {
        printf("\nvertical alignment: failed\n");
        free(raw);
        return;
    }
    first = now_ms() - t0;
    for (i = 0; i < REPS; i++) {
        t0 = now_ms();
        (void)negobs_valign_process(&ctx, &l, &r, &o, &st);
        if (now_ms() - t0 < best) {
            best = now_ms() - t0;
        }
    }
    printf(
        "\nvertical alignment (valign.enable), 320x240, range 0-63: first "
        "frame %.2f ms, later frames %.2f ms (best of %d); model %.3f px "
        "(scene: rectified, 0); workspace %zu bytes + the %d-byte aligned image\n",
        first, best, REPS, st.model.offset_q16 / 65536.0, bytes, QW * QH);
    free(raw);
}

/* Per-stage lines of one measurement. */
static void print_stages(const char *what, const figures_t *fig)
{
    double sum = 0.0;
    int k;
    for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
        sum += fig->stage_ms[k];
    }
    printf(
        "  per stage on %s (thread CPU ms, best of %d each; sum %.2f ms):\n",
        what, REPS, sum);
    for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
        printf("    %-24s %8.2f ms %5.1f %%\n", stage_name[k],
               fig->stage_ms[k],
               sum > 0.0 ? 100.0 * fig->stage_ms[k] / sum : 0.0);
    }
}

/* Middlebury Cones (450x375, range 0-63) when $NEGOBS_DATA has it. */
static void bench_cones(void)
{
    const char *data = getenv("NEGOBS_DATA");
    char lp[1024];
    char rp[1024];
    int32_t w = 0;
    int32_t h = 0;
    int32_t w2 = 0;
    int32_t h2 = 0;
    figures_t fig;
    if (data == NULL) {
        data = "../shared/data";
    }
    snprintf(lp, sizeof lp, "%s/middlebury/cones/im2.ppm", data);
    snprintf(rp, sizeof rp, "%s/middlebury/cones/im6.ppm", data);
    if (read_ppm_grey(lp, lpx, sizeof lpx, &w, &h) != 0 ||
        read_ppm_grey(rp, rpx, sizeof rpx, &w2, &h2) != 0 || w != w2 ||
        h != h2) {
        printf("\nMiddlebury Cones: not found under %s (set NEGOBS_DATA)\n",
               data);
        return;
    }
    if (measure(w, h, 63, REPS, &fig) != 0) {
        printf("\nMiddlebury Cones: failed\n");
        return;
    }
    printf("\nMiddlebury Cones %dx%d, range 0-63, best of %d: stereo %.2f ms,"
           " visited cells %u, queue peak %u, overflows %u, seeds %u\n",
           (int)w, (int)h, REPS, fig.stereo_ms, (unsigned)fig.st.visited_cells,
           (unsigned)fig.st.queue_peak, (unsigned)fig.st.queue_overflows,
           (unsigned)fig.st.seeds);
    print_stages("Cones", &fig);
}

int main(int argc, char **argv)
{
    negobs_stereo_config_t sc;
    negobs_pipeline_config_t pc;
    size_t sbytes = 0;
    size_t pbytes = 0;
    figures_t typ;
    figures_t fig;
    double worst_ms = 0.0;
    uint32_t worst_cells = 0;
    uint32_t worst_peak = 0;
    int k;
    int once = (argc > 1 && strcmp(argv[1], "--once") == 0);

    negobs_stereo_config_default(&sc, QW, QH);
    sc.max_disp = 63;
    negobs_pipeline_config_default(&pc, QW, QH);
    if (negobs_stereo_workspace_size(&sc, &sbytes) != NEGOBS_OK ||
        negobs_pipeline_workspace_size(&pc, &pbytes) != NEGOBS_OK) {
        fprintf(stderr, "size query failed\n");
        return 1;
    }
    printf("negobs %s disparity + detection benchmark\n", negobs_version());
    printf("workspace at 320x240, 64 disparities: matcher %zu bytes (%.1f KiB,"
           " target <= 512 KiB), whole pipeline %zu bytes; heap in lib/: 0\n",
           sbytes, (double)sbytes / 1024.0, pbytes);
    if (once) {
        make(TYPICAL, QW, QH);
        return measure(QW, QH, 63, 1, &fig) == 0 ? 0 : 1;
    }
    printf(
        "\n320x240, range 0-63, best of %d (thread CPU ms on this machine):\n",
        REPS);
    printf("  %-28s %9s %9s %7s %11s %8s %9s  %s\n", "frame", "stereo",
           "detect", "det/st", "visited", "q.peak", "overflows", "verdict");
    for (k = TYPICAL; k <= FLAT_AREA; k++) {
        make((kind_t)k, QW, QH);
        if (measure(QW, QH, 63, REPS, &fig) != 0) {
            printf("  %-28s failed\n", kind_name[k]);
            return 1;
        }
        if (k == TYPICAL) {
            typ = fig;
        }
        if (fig.stereo_ms > worst_ms)
            worst_ms = fig.stereo_ms;
        if (fig.st.visited_cells > worst_cells)
            worst_cells = fig.st.visited_cells;
        if (fig.st.queue_peak > worst_peak)
            worst_peak = fig.st.queue_peak;
        printf("  %-28s %9.2f %9.2f %6.1f%% %11u %8u %9u  %s\n", kind_name[k],
               fig.stereo_ms, fig.detect_ms,
               100.0 * fig.detect_ms / fig.stereo_ms,
               (unsigned)fig.st.visited_cells, (unsigned)fig.st.queue_peak,
               (unsigned)fig.st.queue_overflows,
               fig.state == NEGOBS_DETECT_NO_INFO  ? "no-info"
               : fig.state == NEGOBS_DETECT_HAZARD ? "hazard"
                                                   : "clear");
    }
    printf("  worst/typical: time x%.2f, visited cells x%.2f, queue peak x%.2f"
           " (queue capacity %d)\n",
           worst_ms / typ.stereo_ms,
           (double)worst_cells /
               (double)(typ.st.visited_cells ? typ.st.visited_cells : 1),
           (double)worst_peak /
               (double)(typ.st.queue_peak ? typ.st.queue_peak : 1),
           (int)sc.queue_capacity);
    printf(
        "  detection / disparity on the typical frame: %.1f %% (target < 15 %%;"
        " this generated scene is not a walking-camera view, so see\n"
        "  negobs_detect_eval for the figure on rendered walks)\n",
        100.0 * typ.detect_ms / typ.stereo_ms);
    print_stages("the typical 320x240 frame", &typ);
    make(TYPICAL, QW, QH);
    bench_valign();
    bench_cones();
    return 0;
}
