/*
 * Integer window statistics: integral images and box sums.
 *
 * Matching windows need, per pixel, the sum S and the sum of squares Q of
 * the (2r+1)^2 grey values around it (NCC's mean and variance).
 *
 * Scaling and overflow. For 8-bit pixels and radius r <= 7 (15x15):
 *   S <= 225 * 255   = 57 375      fits uint16
 *   Q <= 225 * 255^2 = 14 630 625  fits uint32 (24 bits)
 * For the 5x5 window the matcher uses, S <= 6 375 and Q <= 1 625 625.
 * (The library's integral images, kept modulo 2^32, are internal:
 * lib/src/integral.h.)
 */
#ifndef NEGOBS_BOXSUM_H
#define NEGOBS_BOXSUM_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/image.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest window radius the box sums accept (15x15 window). */
#define NEGOBS_BOXSUM_MAX_RADIUS 7

/**
 * @brief Per-pixel box sum and sum of squares over a (2r+1)^2 window.
 *
 * Runs separably with one column accumulator per image column, so the only
 * scratch memory is 2 * width uint32 (`colbuf`). Pixels whose window leaves
 * the image get 0 in both outputs: callers treat the r-pixel border as
 * unmatched.
 *
 * @param[in]  img        source image
 * @param[in]  radius     1..NEGOBS_BOXSUM_MAX_RADIUS
 * @param[out] sum        width x height, row stride sum_stride (elements)
 * @param[in]  sum_stride >= width
 * @param[out] sumsq      width x height, row stride sq_stride; may be NULL
 * @param[in]  sq_stride  >= width (ignored when sumsq is NULL)
 * @param[in]  colbuf     scratch of 2 * width uint32
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL (bad image, radius, strides, NULLs,
 *         or an image smaller than one window).
 */
negobs_status_t negobs_boxsum_u8(const negobs_image_u8_t *img, int32_t radius,
                                 uint16_t *sum, int32_t sum_stride,
                                 uint32_t *sumsq, int32_t sq_stride,
                                 uint32_t *colbuf);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_BOXSUM_H */
