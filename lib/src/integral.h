/*
 * Integral images (internal: the library and its tests only).
 *
 * Integral images of a whole frame exceed 2^32 (640x480x255^2 ~ 2^34), so
 * they are kept modulo 2^32 in uint32: unsigned wrap-around is defined in C,
 * and a box sum computed as A - B - C + D modulo 2^32 is exact whenever the
 * true box sum is below 2^32, which the window bounds in negobs/boxsum.h
 * guarantee (15x15 window: Q <= 14 630 625).
 */
#ifndef NEGOBS_INTEGRAL_H
#define NEGOBS_INTEGRAL_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/image.h"
#include "negobs/status.h"

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
negobs_status_t negobs_integral_u8(const negobs_image_u8_t *img, uint32_t *sum,
                                   uint32_t *sumsq, size_t elems);

/**
 * @brief Sum over the half-open box [x0, x1) x [y0, y1) from an integral
 *        image with row stride `istride` (= image width + 1).
 *
 * Exact modulo 2^32 (see the overflow note above); no bounds check.
 */
static inline uint32_t negobs_integral_box(const uint32_t *ii, int32_t istride,
                                           int32_t x0, int32_t y0, int32_t x1,
                                           int32_t y1)
{
    const uint32_t *top = ii + (ptrdiff_t)y0 * istride;
    const uint32_t *bot = ii + (ptrdiff_t)y1 * istride;
    return bot[x1] - bot[x0] - top[x1] + top[x0];
}

#endif /* NEGOBS_INTEGRAL_H */
