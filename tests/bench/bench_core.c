/*
 * Core kernel benchmark (a Meson benchmark(), not a timed test): prints
 * best-of-N wall times for the window statistics at QVGA and VGA.
 * Later stages add their own benchmark programs beside this one.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <time.h>

#include "integral.h"
#include "negobs/negobs.h"

#include "../support/test_rng.h"

static uint8_t img_buf[480 * 640];
static uint16_t sum[480 * 640];
static uint32_t sumsq[480 * 640];
static uint32_t colbuf[2 * 640];
static uint32_t ii[481 * 641];
static uint32_t iiq[481 * 641];

static long long now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void bench(int32_t w, int32_t h)
{
    negobs_image_u8_t img;
    long long best_box = -1;
    long long best_int = -1;
    int rep;
    img.data = img_buf;
    img.width = w;
    img.height = h;
    img.stride = w;
    for (rep = 0; rep < 20; rep++) {
        long long t0 = now_ns();
        long long t1;
        long long t2;
        if (negobs_boxsum_u8(&img, 2, sum, w, sumsq, w, colbuf) != NEGOBS_OK) {
            printf("boxsum failed\n");
            return;
        }
        t1 = now_ns();
        if (negobs_integral_u8(&img, ii, iiq, sizeof ii / sizeof ii[0]) !=
            NEGOBS_OK) {
            printf("integral failed\n");
            return;
        }
        t2 = now_ns();
        if (best_box < 0 || t1 - t0 < best_box)
            best_box = t1 - t0;
        if (best_int < 0 || t2 - t1 < best_int)
            best_int = t2 - t1;
    }
    printf("%4dx%-4d boxsum5 (sum+sumsq) %8.3f ms   integral (sum+sumsq) "
           "%8.3f ms   best of 20\n",
           (int)w, (int)h, (double)best_box / 1e6, (double)best_int / 1e6);
}

int main(void)
{
    uint32_t s = 1;
    size_t i;
    for (i = 0; i < sizeof img_buf; i++) {
        img_buf[i] = (uint8_t)(test_lcg_next(&s) >> 16);
    }
    printf("negobs %s core kernels\n", negobs_version());
    bench(320, 240);
    bench(640, 480);
    return 0;
}
