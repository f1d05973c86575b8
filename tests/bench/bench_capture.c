/*
 * Capture conversion benchmark: what each camera format costs per frame
 * before the pipeline sees it (negobs_v4l2_conv_frame(): MJPEG decode,
 * 16-bit mono, packed YUV, side-by-side split, crop and area binning).
 * Frames are generated (textured, like a floor) and, for MJPEG, encoded
 * here with libturbojpeg at quality 85 4:2:2 (what UVC cameras send).
 * Prints thread-CPU ms per frame, best of N; no pass/fail.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <linux/videodev2.h>

#include "negobs_port/mjpeg.h"
#include "negobs_port/v4l2_convert.h"

#ifdef NEGOBS_BENCH_MJPEG
#include <turbojpeg.h>
#endif

#define RUNS 20

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static uint8_t texture(int x, int y)
{
    uint32_t h = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u;
    return (uint8_t)(64u + (uint32_t)((x / 3 + y / 2) % 64) + (h >> 27));
}

typedef struct bcase {
    const char *name;
    uint32_t fourcc;
    int w;
    int h;
    int sbs;
    int out_w;
    int out_h;
} bcase_t;

static void fill(const bcase_t *c, uint8_t *buf, size_t *bytes)
{
    int x;
    int y;
    size_t bpp = (c->fourcc == V4L2_PIX_FMT_GREY) ? 1u : 2u;
    for (y = 0; y < c->h; y++) {
        for (x = 0; x < c->w; x++) {
            uint8_t v = texture(x, y);
            uint8_t *p = buf + ((size_t)y * (size_t)c->w + (size_t)x) * bpp;
            if (c->fourcc == V4L2_PIX_FMT_GREY) {
                p[0] = v;
            } else if (c->fourcc == V4L2_PIX_FMT_YUYV) {
                p[0] = v;
                p[1] = 128;
            } else { /* Y10 little endian */
                p[0] = (uint8_t)((v << 2) & 0xFF);
                p[1] = (uint8_t)(v >> 6);
            }
        }
    }
    *bytes = (size_t)c->w * (size_t)c->h * bpp;
}

static void run(const bcase_t *c, uint8_t *frame, size_t bytes,
                uint8_t *scratch, size_t scratch_bytes)
{
    negobs_v4l2_conv_t conv;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    double best = 1e9;
    int i;
    uint32_t bpl = c->fourcc == V4L2_PIX_FMT_MJPEG  ? 0u
                   : c->fourcc == V4L2_PIX_FMT_GREY ? (uint32_t)c->w
                                                    : 2u * (uint32_t)c->w;
    if (negobs_v4l2_conv_setup(&conv, c->fourcc, c->w, c->h, bpl, c->sbs != 0,
                               c->out_w, c->out_h) != NEGOBS_OK ||
        negobs_v4l2_conv_scratch_bytes(&conv) > scratch_bytes) {
        printf("  %-44s setup failed\n", c->name);
        return;
    }
    for (i = 0; i < RUNS; i++) {
        double t0 = now_ms();
        if (negobs_v4l2_conv_frame(&conv, frame, bytes, scratch, scratch_bytes,
                                   &l, &r) != NEGOBS_OK) {
            printf("  %-44s failed\n", c->name);
            return;
        }
        t0 = now_ms() - t0;
        best = t0 < best ? t0 : best;
    }
    printf("  %-44s %8.2f ms  (k=%d, %dx%d per eye)\n", c->name, best,
           (int)conv.plan.k, (int)conv.plan.out_w, (int)conv.plan.out_h);
}

int main(void)
{
    static const bcase_t cases[] = {
        {"GREY 2560x720 side by side -> 1280x720", V4L2_PIX_FMT_GREY, 2560,
         720, 1, 0, 0},
        {"GREY 2560x720 side by side -> 640x360", V4L2_PIX_FMT_GREY, 2560, 720,
         1, 640, 360},
        {"GREY 2560x720 side by side -> 320x240", V4L2_PIX_FMT_GREY, 2560, 720,
         1, 320, 240},
        {"YUYV 2560x720 side by side -> 640x360", V4L2_PIX_FMT_YUYV, 2560, 720,
         1, 640, 360},
        {"Y10 1280x800 (one eye) -> 640x400", V4L2_PIX_FMT_Y10, 1280, 800, 0,
         640, 400},
        {"MJPG 2560x720 side by side -> 640x360", V4L2_PIX_FMT_MJPEG, 2560,
         720, 1, 640, 360},
        {"MJPG 2560x720 side by side -> 320x240", V4L2_PIX_FMT_MJPEG, 2560,
         720, 1, 320, 240},
        {"MJPG 1280x720 (one eye) -> 640x360", V4L2_PIX_FMT_MJPEG, 1280, 720,
         0, 640, 360},
    };
    size_t cap = 2560u * 800u * 2u;
    uint8_t *frame = malloc(cap);
    uint8_t *scratch = malloc(cap);
    size_t i;
    if (frame == NULL || scratch == NULL) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    printf("capture conversion per frame, best of %d (thread CPU ms on this "
           "machine):\n",
           RUNS);
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bcase_t *c = &cases[i];
        size_t bytes = 0;
        if (c->fourcc == V4L2_PIX_FMT_MJPEG) {
#ifdef NEGOBS_BENCH_MJPEG
            unsigned char *jpeg = NULL;
            unsigned long n = 0;
            tjhandle t = tjInitCompress();
            uint8_t *rgb = malloc((size_t)c->w * (size_t)c->h * 3u);
            int x;
            int y;
            if (rgb == NULL) {
                fprintf(stderr, "out of memory\n");
                return 1;
            }
            for (y = 0; y < c->h; y++) {
                for (x = 0; x < c->w; x++) {
                    uint8_t *p = rgb +
                                 ((size_t)y * (size_t)c->w + (size_t)x) * 3u;
                    uint8_t v = texture(x, y);
                    p[0] = v;
                    p[1] = (uint8_t)(v / 2u + 60u);
                    p[2] = texture(x + 7, y + 3);
                }
            }
            if (t == NULL || tjCompress2(t, rgb, c->w, 0, c->h, TJPF_RGB,
                                         &jpeg, &n, TJSAMP_422, 85, 0) != 0) {
                printf("  %-44s encode failed\n", c->name);
                free(rgb);
                continue;
            }
            free(rgb);
            memcpy(frame, jpeg, n);
            bytes = n;
            tjFree(jpeg);
            (void)tjDestroy(t);
#else
            printf("  %-44s (built without libturbojpeg)\n", c->name);
            continue;
#endif
        } else {
            fill(c, frame, &bytes);
        }
        run(c, frame, bytes, scratch, cap);
    }
    free(frame);
    free(scratch);
    return 0;
}
