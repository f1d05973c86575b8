/*
 * bench_frames LEFT.pgm RIGHT.pgm N [--profile compact|fast] [--max-disp D]
 *
 * Runs negobs_stereo_process N times on one grey pair (binary PGM, as
 * negobs_speed --write-pgm writes it) and prints the map's checksum. It
 * exists to count instructions where valgrind cannot go: under qemu-user
 * with an instruction-counting plugin, the count of N = 2 minus that of
 * N = 1 is one frame, with loading and setup cancelled out
 * (tools/negobs bench --aarch64). No timing, no OpenCV, plain C.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "negobs/stereo.h"

#include "bench_common.h"

static int usage(const char *msg)
{
    fprintf(stderr,
            "bench_frames: %s\nusage: bench_frames LEFT.pgm RIGHT.pgm "
            "N [--profile compact|fast] [--max-disp D]\n",
            msg);
    return 1;
}

int main(int argc, char **argv)
{
    int32_t w = 0;
    int32_t h = 0;
    int32_t w2 = 0;
    int32_t h2 = 0;
    int32_t max_disp = 63;
    int profile = NEGOBS_STEREO_PROFILE_FAST;
    long n;
    long i;
    int a;
    uint8_t *l;
    uint8_t *r;
    int16_t *d;
    void *ws;
    size_t bytes = 0;
    uint32_t sum = 2166136261u;
    negobs_stereo_config_t cfg;
    negobs_stereo_t ctx;
    negobs_image_u8_t li;
    negobs_image_u8_t ri;
    negobs_image_s16_t di;

    if (argc < 4) {
        return usage("need LEFT RIGHT N");
    }
    n = strtol(argv[3], NULL, 10);
    if (n < 0 || n > 1000) {
        return usage("N must be 0 .. 1000");
    }
    for (a = 4; a < argc; a++) {
        if (strcmp(argv[a], "--profile") == 0 && a + 1 < argc) {
            if (!bench_parse_profile(argv[++a], &profile)) {
                return usage("--profile takes compact or fast");
            }
        } else if (strcmp(argv[a], "--max-disp") == 0 && a + 1 < argc) {
            max_disp = (int32_t)strtol(argv[++a], NULL, 10);
        } else {
            return usage("unknown option");
        }
    }
    l = bench_read_pgm(argv[1], &w, &h);
    r = bench_read_pgm(argv[2], &w2, &h2);
    if (l == NULL || r == NULL || w != w2 || h != h2) {
        return usage("cannot read the pair (binary 8-bit PGM, same size)");
    }
    memset(&cfg, 0, sizeof cfg);
    memset(&ctx, 0, sizeof ctx);
    negobs_stereo_config_default(&cfg, w, h);
    cfg.max_disp = max_disp;
    cfg.memory_profile = profile;
    d = malloc((size_t)w * (size_t)h * sizeof *d);
    if (d == NULL || negobs_stereo_workspace_size(&cfg, &bytes) != NEGOBS_OK ||
        (ws = malloc(bytes)) == NULL ||
        negobs_stereo_init(&ctx, &cfg, ws, bytes) != NEGOBS_OK) {
        return usage("bad configuration for this pair");
    }
    li.data = l;
    li.width = w;
    li.height = h;
    li.stride = w;
    ri = li;
    ri.data = r;
    di.data = d;
    di.width = w;
    di.height = h;
    di.stride = w;
    for (i = 0; i < n; i++) {
        if (negobs_stereo_process(&ctx, &li, &ri, &di, NULL, NULL) !=
            NEGOBS_OK) {
            fprintf(stderr, "bench_frames: negobs_stereo_process failed\n");
            return 3;
        }
    }
    for (i = 0; n > 0 && i < (long)w * h; i++) {
        sum = (sum ^ (uint32_t)(uint16_t)d[i]) * 16777619u;
    }
    printf("%dx%d D=%d frames %ld map checksum %08x\n", (int)w, (int)h,
           (int)max_disp + 1, n, (unsigned)sum);
    free(ws);
    free(d);
    free(l);
    free(r);
    return 0;
}
