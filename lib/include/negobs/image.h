/*
 * Image descriptors.
 *
 * Images are always described, never assumed: the caller owns the pixels,
 * and rows may be padded (V4L2 hands out bytesperline > width). Strides are
 * counted in elements of the pixel type, so for 8-bit images they equal
 * bytes.
 */
#ifndef NEGOBS_IMAGE_H
#define NEGOBS_IMAGE_H

#include <stdint.h>

#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest width or height any module accepts (pixels). */
#ifndef NEGOBS_MAX_DIM
#define NEGOBS_MAX_DIM 4096
#endif

/** 8-bit grey image; `data` points at pixel (0, 0). */
typedef struct negobs_image_u8 {
    uint8_t *data;  /**< first pixel of the first row            */
    int32_t width;  /**< pixels per row, 1..NEGOBS_MAX_DIM       */
    int32_t height; /**< rows, 1..NEGOBS_MAX_DIM                 */
    int32_t stride; /**< elements from one row to the next, >= width */
} negobs_image_u8_t;

/** Signed 16-bit image (disparity in 1/16 px, costs, ...). */
typedef struct negobs_image_s16 {
    int16_t *data;
    int32_t width;
    int32_t height;
    int32_t stride; /**< elements (not bytes) between rows, >= width */
} negobs_image_s16_t;

/**
 * @brief Check a descriptor: non-NULL data, 1 <= width, height <=
 *        NEGOBS_MAX_DIM, width <= stride <= 4 * NEGOBS_MAX_DIM.
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_image_u8_check(const negobs_image_u8_t *img);

/** @brief Same rules as negobs_image_u8_check() for an int16 image. */
negobs_status_t negobs_image_s16_check(const negobs_image_s16_t *img);

/**
 * @brief Check that an image is valid and at least min_w x min_h pixels,
 *        e.g. no smaller than a matching window.
 * @return NEGOBS_OK, or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_image_u8_check_min(const negobs_image_u8_t *img,
                                          int32_t min_w, int32_t min_h);

/** @brief Pointer to row y (no bounds check; y must be in [0, height)). */
static inline uint8_t *negobs_image_u8_row(const negobs_image_u8_t *img,
                                           int32_t y)
{
    return img->data + (intptr_t)y * img->stride;
}

/** @brief Pointer to row y of an int16 image (no bounds check). */
static inline int16_t *negobs_image_s16_row(const negobs_image_s16_t *img,
                                            int32_t y)
{
    return img->data + (intptr_t)y * img->stride;
}

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_IMAGE_H */
