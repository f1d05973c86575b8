/*
 * bench_pipeline DIR N K [--profile compact|fast]
 *
 * Loads the grey pairs DIR/left_NNNN.pgm and DIR/right_NNNN.pgm for
 * NNNN = 0 .. N-1 (binary PGM, 320x240 or any size), then runs
 * negobs_pipeline_process on the first K of them with the camera of the
 * demo walk (f = 250 px at 320 px width, scaled with the width; B = 120
 * mm; the image centre; hint 1.2 m / 20 deg; 10 fps), as negobs_png does
 * with the walk's gt.json. It prints one line per frame (state, reasons,
 * clear_to_mm, hazards, nearest range) and a checksum of them, so runs on
 * two targets can be compared.
 *
 * It exists to count the whole pipeline's instructions where valgrind
 * cannot go: under qemu-user with an instruction-counting plugin the
 * count of K = N minus that of K = 0 is the pipeline alone over N frames,
 * with loading and setup cancelled out (tools/negobs bench --aarch64).
 * No timing, no threads, no OpenCV, plain C.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "negobs/pipeline.h"

#include "bench_common.h"

#define MAX_FRAMES 1000

static int usage(const char *msg)
{
    fprintf(stderr,
            "bench_pipeline: %s\nusage: bench_pipeline DIR N K "
            "[--profile compact|fast]\n",
            msg);
    return 1;
}

/* FNV-1a over a line of text. */
static uint64_t fnv(uint64_t h, const char *s)
{
    while (*s != '\0') {
        h ^= (uint8_t)*s++;
        h *= 1099511628211u;
    }
    return h;
}

int main(int argc, char **argv)
{
    static uint8_t *px[2][MAX_FRAMES];
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t ctx;
    negobs_status_t st;
    int profile = NEGOBS_STEREO_PROFILE_COMPACT;
    int32_t w = 0;
    int32_t h = 0;
    long n;
    long k;
    long i;
    int a;
    int rc = 0;
    size_t bytes = 0;
    void *ws;
    uint64_t sum = 1469598103934665603u;

    if (argc < 4) {
        return usage("DIR, N and K are required");
    }
    n = strtol(argv[2], NULL, 10);
    k = strtol(argv[3], NULL, 10);
    if (n < 1 || n > MAX_FRAMES || k < 0 || k > n) {
        return usage("need 1 <= N <= 1000 and 0 <= K <= N");
    }
    for (a = 4; a < argc; a++) {
        if (strcmp(argv[a], "--profile") == 0 && a + 1 < argc) {
            if (!bench_parse_profile(argv[++a], &profile)) {
                return usage("--profile takes compact or fast");
            }
        } else {
            return usage("unknown argument");
        }
    }
    for (i = 0; i < n; i++) {
        int s;
        for (s = 0; s < 2; s++) {
            char path[4096];
            int32_t fw = 0;
            int32_t fh = 0;
            snprintf(path, sizeof path, "%s/%s_%04ld.pgm", argv[1],
                     s == 0 ? "left" : "right", i);
            px[s][i] = bench_read_pgm(path, &fw, &fh);
            if (px[s][i] == NULL) {
                fprintf(stderr, "bench_pipeline: cannot read %s\n", path);
                return 1;
            }
            if (w == 0) {
                w = fw;
                h = fh;
            } else if (fw != w || fh != h) {
                fprintf(stderr, "bench_pipeline: %s: size differs\n", path);
                return 1;
            }
        }
    }

    negobs_pipeline_config_default(&cfg, w, h);
    /* the demo walk's camera (negobs_synth's defaults, its gt.json) */
    cfg.detect.rig.focal_q4 = 250 * 16 * w / 320;
    cfg.detect.rig.cx_q4 = (w - 1) * 8;
    cfg.detect.rig.cy_q4 = (h - 1) * 8;
    cfg.detect.rig.baseline_um = 120000;
    cfg.detect.cam_height_mm = 1200;
    cfg.detect.cam_pitch_mdeg = 20000;
    cfg.stereo.memory_profile = profile;
    st = negobs_pipeline_workspace_size(&cfg, &bytes);
    if (st != NEGOBS_OK) {
        fprintf(stderr, "bench_pipeline: config: %s\n", negobs_status_str(st));
        return 1;
    }
    ws = malloc(bytes);
    if (ws == NULL) {
        fprintf(stderr, "bench_pipeline: out of memory\n");
        return 1;
    }
    st = negobs_pipeline_init(&ctx, &cfg, ws, bytes);
    if (st != NEGOBS_OK) {
        fprintf(stderr, "bench_pipeline: init: %s\n", negobs_status_str(st));
        free(ws);
        return 1;
    }
    for (i = 0; i < k && rc == 0; i++) {
        negobs_image_u8_t l;
        negobs_image_u8_t r;
        negobs_pipeline_frame_t fr;
        static negobs_pipeline_result_t res;
        const negobs_detect_result_t *d = &res.detect;
        char line[160];
        uint32_t t_ms = 1000u + (uint32_t)(100 * i); /* 10 fps */
        l.data = px[0][i];
        r.data = px[1][i];
        l.width = r.width = w;
        l.height = r.height = h;
        l.stride = r.stride = w;
        memset(&fr, 0, sizeof fr);
        fr.left = &l;
        fr.right = &r;
        fr.t_left_ms = fr.t_right_ms = fr.now_ms = t_ms;
        st = negobs_pipeline_process(&ctx, &fr, &res);
        if (st != NEGOBS_OK) {
            fprintf(stderr, "bench_pipeline: frame %ld: %s\n", i,
                    negobs_status_str(st));
            rc = 1;
            break;
        }
        snprintf(line, sizeof line,
                 "frame %ld state %d reasons %08lx clear_to %ld hazards %lu "
                 "nearest %ld",
                 i, (int)d->state, (unsigned long)d->reasons,
                 (long)d->clear_to_mm, (unsigned long)d->n_hazards,
                 (long)d->nearest_range_mm);
        printf("%s\n", line);
        sum = fnv(sum, line);
    }
    if (rc == 0) {
        printf("frames %ld checksum %016llx\n", k, (unsigned long long)sum);
    }
    for (i = 0; i < n; i++) {
        free(px[0][i]);
        free(px[1][i]);
    }
    free(ws);
    return rc;
}
