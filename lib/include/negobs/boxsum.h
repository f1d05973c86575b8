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
 * Integral images of a whole frame exceed 2^32 (640x480x255^2 ~ 2^34), so
 * they are kept modulo 2^32 in uint32: unsigned wrap-around is defined in C,
 * and a box sum computed as A - B - C + D modulo 2^32 is exact whenever the
 * true box sum is below 2^32, which the bounds above guarantee.
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

/** @brief Elements of an integral image for a w x h image: (w+1)(h+1). */
static inline size_t negobs_integral_elems(int32_t width, int32_t height)
{
    return (size_t)(width + 1) * (size_t)(height + 1);
}

/**
 * @brief Integral images of grey values and of their squares, modulo 2^32.
 *
 * Layout: (width+1) x (height+1), row stride width+1, first row and column
 * zero; ii[y][x] = sum of img over [0, x) x [0, y).
 * @param[in]  img    source image
 * @param[out] sum    integral of values, negobs_integral_elems() entries
 * @param[out] sumsq  integral of squares, same size; may be NULL
 * @param[in]  elems  entries available in each output buffer
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (bad image, NULL sum) or
 *         NEGOBS_ERR_NOSPACE (elems too small).
 */
negobs_status_t negobs_integral_u8(const negobs_image_u8_t *img,
                                   uint32_t *sum, uint32_t *sumsq,
                                   size_t elems);

/**
 * @brief Sum over the half-open box [x0, x1) x [y0, y1) from an integral
 *        image with row stride `istride` (= image width + 1).
 *
 * Exact modulo 2^32 (see the overflow note above); no bounds check.
 */
static inline uint32_t negobs_integral_box(const uint32_t *ii,
                                           int32_t istride, int32_t x0,
                                           int32_t y0, int32_t x1, int32_t y1)
{
    const uint32_t *top = ii + (ptrdiff_t)y0 * istride;
    const uint32_t *bot = ii + (ptrdiff_t)y1 * istride;
    return bot[x1] - bot[x0] - top[x1] + top[x0];
}

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
