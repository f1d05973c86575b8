/* Rectification fill: the part of each image that lies outside the
 * camera's field of view (docs/DETECTION.md 10.2, "Out of view"). */
#include "detect_internal.h"

/*
 * A rectified image is resampled from the sensor; where the map leaves the
 * sensor, the remap writes a constant (usually 0) or replicates the sensor's
 * edge pixel along the row. Either way a row of fill is a run of exactly
 * identical grey levels reaching the image border.
 *
 * FILL_MIN_RUN: under sensor noise of at least 1 LSB (shot and read noise
 * of an 8-bit sensor, even on a uniform wall) eight neighbouring pixels are
 * exactly equal with a chance below 1 in 100 per row; only clipped regions
 * (black 0, saturated 255) give such runs in a real scene.
 * FILL_MIN_ROWS_DIV: a side is treated as fill only when a quarter of the
 * rows carry such a run there; the map leaves the sensor along a smooth
 * curve that spans a large part of a border, while a clipped object touches
 * it over a few rows.
 * FILL_MAX_DIV: a run of a quarter of the width or more is not fill: a
 * rectification that loses that much is broken, and such a run is more
 * likely a clipped scene; that row stays in view (unseen, not out of view).
 */
#define FILL_MIN_RUN 8
#define FILL_MIN_ROWS_DIV 4
#define FILL_MAX_DIV 4

/* Length of the run of pixels equal to row[u0] starting at u0 and going in
 * steps of du (+1 or -1), at most max_n. */
static int32_t same_run(const uint8_t *row, int32_t u0, int32_t du,
                        int32_t max_n)
{
    int32_t n = 1;
    while (n < max_n && row[u0 + n * du] == row[u0]) {
        n++;
    }
    return n;
}

negobs_status_t negobs_detect_fill_extent(const negobs_image_u8_t *img,
                                          int16_t *view_u0, int16_t *view_u1)
{
    int32_t max_n;
    int32_t n_l = 0;
    int32_t n_r = 0;
    int32_t v;
    if (view_u0 == NULL || view_u1 == NULL ||
        negobs_image_u8_check(img) != NEGOBS_OK || img->width > INT16_MAX) {
        return NEGOBS_ERR_INVAL;
    }
    max_n = img->width / FILL_MAX_DIV;
    for (v = 0; v < img->height; v++) {
        const uint8_t *row = negobs_image_u8_row(img, v);
        int32_t rl = (max_n > 0) ? same_run(row, 0, 1, max_n) : 0;
        int32_t rr = (max_n > 0) ? same_run(row, img->width - 1, -1, max_n)
                                 : 0;
        rl = (rl >= FILL_MIN_RUN && rl < max_n) ? rl : 0;
        rr = (rr >= FILL_MIN_RUN && rr < max_n) ? rr : 0;
        view_u0[v] = (int16_t)rl;
        view_u1[v] = (int16_t)(img->width - rr);
        n_l += rl > 0;
        n_r += rr > 0;
    }
    for (v = 0; v < img->height; v++) {
        if (n_l * FILL_MIN_ROWS_DIV < img->height) {
            view_u0[v] = 0;
        }
        if (n_r * FILL_MIN_ROWS_DIV < img->height) {
            view_u1[v] = (int16_t)img->width;
        }
    }
    return NEGOBS_OK;
}
