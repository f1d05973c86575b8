/*
 * What the plain-C benchmarks that run under qemu-user (bench_frames,
 * bench_pipeline) share: reading a binary PGM (no OpenCV there) and the
 * memory profile's name.
 */
#ifndef NEGOBS_BENCH_COMMON_H
#define NEGOBS_BENCH_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "negobs/stereo.h"

/* Binary PGM (P5, maxval 255, at most 4096 x 4096) into a new buffer the
 * caller frees; NULL on any error. */
static inline uint8_t *bench_read_pgm(const char *path, int32_t *w, int32_t *h)
{
    FILE *f = fopen(path, "rb");
    uint8_t *px = NULL;
    int maxv = 0;
    if (f == NULL) {
        return NULL;
    }
    if (fscanf(f, "P5 %d %d %d", w, h, &maxv) == 3 && maxv == 255 && *w > 0 &&
        *h > 0 && *w <= 4096 && *h <= 4096 && fgetc(f) != EOF) {
        size_t n = (size_t)*w * (size_t)*h;
        px = malloc(n);
        if (px != NULL && fread(px, 1, n, f) != n) {
            free(px);
            px = NULL;
        }
    }
    fclose(f);
    return px;
}

/* "compact" or "fast" into *profile (NEGOBS_STEREO_PROFILE_*); 0 for any
 * other name. */
static inline int bench_parse_profile(const char *name, int *profile)
{
    if (strcmp(name, "compact") == 0) {
        *profile = NEGOBS_STEREO_PROFILE_COMPACT;
        return 1;
    }
    if (strcmp(name, "fast") == 0) {
        *profile = NEGOBS_STEREO_PROFILE_FAST;
        return 1;
    }
    return 0;
}

#endif
