/*
 * Cross-target determinism digest.
 *
 * Runs the core kernels on fixed, generated inputs and prints one FNV-1a
 * 64-bit digest of every output byte. tools/negobs runs it natively and on
 * aarch64/armhf under qemu-user and requires identical lines: the library
 * promises bit-identical results on every target.
 *
 *   negobs_digest              print "digest <16 hex digits>"
 *   negobs_digest --perturb    same, with one input pixel changed
 *   negobs_digest --self-test  exit 1 unless the two digests differ
 */
#include <stdio.h>
#include <string.h>

#include "negobs/negobs.h"

#define W 96
#define H 72

static uint8_t pix[H * W];
static uint16_t sum[H * W];
static uint32_t sumsq[H * W];
static uint32_t colbuf[2 * W];
static uint32_t ii[(W + 1) * (H + 1)];
static uint32_t iiq[(W + 1) * (H + 1)];

typedef struct digest {
    uint64_t h;
} digest_t;

static void feed(digest_t *d, const void *p, size_t n)
{
    const uint8_t *b = (const uint8_t *)p;
    size_t i;
    for (i = 0; i < n; i++) {
        d->h ^= b[i];
        d->h *= 1099511628211ull;
    }
}

/* Feed integers byte by byte, little-endian, whatever the host order. */
static void feed_u32(digest_t *d, uint32_t v)
{
    uint8_t b[4];
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    b[2] = (uint8_t)(v >> 16);
    b[3] = (uint8_t)(v >> 24);
    feed(d, b, 4);
}

static uint64_t run(int perturb)
{
    digest_t d;
    uint32_t seed = 12345u;
    negobs_image_u8_t img;
    size_t i;
    int32_t r;
    int32_t x;

    d.h = 14695981039346656037ull;
    for (i = 0; i < sizeof pix; i++) {
        seed = seed * 1664525u + 1013904223u;
        pix[i] = (uint8_t)(seed >> 24);
    }
    if (perturb) {
        pix[(H / 2) * W + W / 2] ^= 1u;
    }
    img.data = pix;
    img.width = W;
    img.height = H;
    img.stride = W;

    for (r = 1; r <= NEGOBS_BOXSUM_MAX_RADIUS; r++) {
        if (negobs_boxsum_u8(&img, r, sum, W, sumsq, W, colbuf) != NEGOBS_OK) {
            return 0;
        }
        for (i = 0; i < (size_t)(W * H); i++) {
            feed_u32(&d, sum[i]);
            feed_u32(&d, sumsq[i]);
        }
    }
    if (negobs_integral_u8(&img, ii, iiq, sizeof ii / sizeof ii[0]) !=
        NEGOBS_OK) {
        return 0;
    }
    for (i = 0; i < sizeof ii / sizeof ii[0]; i++) {
        feed_u32(&d, ii[i]);
        feed_u32(&d, iiq[i]);
    }
    for (x = -3000; x < 3000; x += 7) {
        feed_u32(&d, (uint32_t)negobs_rshift_round_s32(x * 977, 5));
        feed_u32(&d, negobs_isqrt_u32((uint32_t)(x + 3000) * 104729u));
        feed_u32(&d, (uint32_t)negobs_div_round_s64((int64_t)x * 1000003, 97));
    }
    return d.h;
}

int main(int argc, char **argv)
{
    const char *mode = (argc > 1) ? argv[1] : "";
    if (strcmp(mode, "--self-test") == 0) {
        uint64_t a = run(0);
        uint64_t b = run(1);
        if (a == 0 || b == 0 || a == b) {
            fprintf(stderr, "digest does not see a one-pixel change\n");
            return 1;
        }
        printf("digest sees a one-pixel change: %016llx != %016llx\n",
               (unsigned long long)a, (unsigned long long)b);
        return 0;
    }
    if (argc > 1 && strcmp(mode, "--perturb") != 0) {
        fprintf(stderr, "usage: %s [--perturb | --self-test]\n", argv[0]);
        return 2;
    }
    {
        uint64_t h = run(strcmp(mode, "--perturb") == 0);
        if (h == 0) {
            fprintf(stderr, "a kernel refused its input\n");
            return 1;
        }
        printf("digest %016llx\n", (unsigned long long)h);
    }
    return 0;
}
