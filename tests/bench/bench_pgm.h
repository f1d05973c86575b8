/*
 * Reading a binary PGM for the plain-C benchmarks that run under
 * qemu-user (bench_frames, bench_pipeline): no OpenCV there.
 */
#ifndef NEGOBS_BENCH_PGM_H
#define NEGOBS_BENCH_PGM_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* Binary PGM (P5, maxval 255, at most 4096 x 4096) into a new buffer the
 * caller frees; NULL on any error. */
static inline uint8_t *bench_read_pgm(const char *path, int32_t *w,
                                      int32_t *h)
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

#endif
