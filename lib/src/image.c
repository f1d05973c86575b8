#include "negobs/image.h"

#include <stddef.h>

/*
 * The stride cap keeps y * stride inside int32 for every legal row:
 * 4096 * 4 * 4096 = 2^26, so row pointers never overflow on 32-bit ports.
 */
static negobs_status_t check_geometry(const void *data, int32_t width,
                                      int32_t height, int32_t stride)
{
    if (data == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (width < 1 || height < 1 || width > NEGOBS_MAX_DIM ||
        height > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    if (stride < width || stride > 4 * NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

negobs_status_t negobs_image_u8_check(const negobs_image_u8_t *img)
{
    if (img == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    return check_geometry(img->data, img->width, img->height, img->stride);
}

negobs_status_t negobs_image_s16_check(const negobs_image_s16_t *img)
{
    if (img == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    return check_geometry(img->data, img->width, img->height, img->stride);
}

negobs_status_t negobs_image_u8_check_min(const negobs_image_u8_t *img,
                                          int32_t min_w, int32_t min_h)
{
    negobs_status_t st = negobs_image_u8_check(img);
    if (st != NEGOBS_OK) {
        return st;
    }
    if (img->width < min_w || img->height < min_h) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}
