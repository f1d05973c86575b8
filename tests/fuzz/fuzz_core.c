/*
 * Fuzz target: image validation and window statistics with arbitrary
 * geometry (including invalid descriptors), checking that the separable box
 * sums agree with the integral-image box sums wherever both are defined.
 */
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "integral.h"
#include "negobs/negobs.h"

#define MAXW 96
#define MAXH 64

static uint8_t pix[MAXH * 2 * MAXW];
static uint16_t sum[MAXH * MAXW];
static uint32_t sumsq[MAXH * MAXW];
static uint32_t colbuf[2 * MAXW];
static uint32_t ii[(MAXW + 1) * (MAXH + 1)];
static uint32_t iiq[(MAXW + 1) * (MAXH + 1)];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input_t in = {data, size, 0};
    negobs_image_u8_t img;
    int32_t r;
    int32_t x;
    int32_t y;
    negobs_status_t st;

    img.width = fuzz_range(&in, -2, MAXW);
    img.height = fuzz_range(&in, -2, MAXH);
    img.stride = fuzz_range(&in, -2, 2 * MAXW);
    r = fuzz_range(&in, -1, 8);
    img.data = (fuzz_u8(&in) == 0xffu) ? NULL : pix;
    if (img.height > 0 && img.stride > 0) {
        size_t n = (size_t)img.height * (size_t)img.stride;
        fuzz_fill(&in, pix, n < sizeof pix ? n : sizeof pix);
    }

    /* Descriptors that pass the check must fit the backing buffer. */
    st = negobs_image_u8_check(&img);
    if (st == NEGOBS_OK &&
        (size_t)(img.height - 1) * (size_t)img.stride + (size_t)img.width >
            sizeof pix) {
        return 0; /* legal descriptor, but larger than our test buffer */
    }
    if (st == NEGOBS_OK && img.stride < img.width) {
        abort(); /* the check let an impossible stride through */
    }
    st = negobs_boxsum_u8(&img, r, sum, MAXW, sumsq, MAXW, colbuf);
    if (st != NEGOBS_OK) {
        return 0;
    }
    if (negobs_integral_u8(&img, ii, iiq, sizeof ii / sizeof ii[0]) !=
        NEGOBS_OK) {
        abort(); /* boxsum accepted the image, integral must too */
    }
    for (y = r; y < img.height - r; y++) {
        for (x = r; x < img.width - r; x++) {
            uint32_t s = negobs_integral_box(ii, img.width + 1, x - r, y - r,
                                             x + r + 1, y + r + 1);
            uint32_t q = negobs_integral_box(iiq, img.width + 1, x - r, y - r,
                                             x + r + 1, y + r + 1);
            if (s != sum[y * MAXW + x] || q != sumsq[y * MAXW + x]) {
                abort();
            }
        }
    }
    return 0;
}
