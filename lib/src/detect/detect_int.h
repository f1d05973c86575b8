/*
 * The detect stage's geometry and statistics functions that only the
 * library and its tests call (internal; the public surface is
 * negobs/depth.h, negobs/ground.h and negobs/detect.h).
 */
#ifndef NEGOBS_DETECT_INT_H
#define NEGOBS_DETECT_INT_H

#include <stdint.h>

#include "fixed_int.h"
#include "negobs/depth.h"
#include "negobs/detect.h"
#include "negobs/ground.h"

/**
 * @brief atan2(y, x) in millidegrees, in (-180000, 180000].
 *
 * CORDIC in vectoring mode, 24 iterations, angle table in 1/256 mdeg;
 * error below 2 mdeg. atan2(0, 0) is 0.
 */
int32_t negobs_atan2_mdeg(int64_t y, int64_t x);

/**
 * @brief Sine and cosine of an angle in millidegrees, Q30 (1.0 = 2^30).
 *
 * CORDIC in rotation mode, 24 iterations; absolute error below 2^-22.
 * Any angle is accepted (reduced to (-180, 180] degrees first).
 */
void negobs_sincos_q30(int32_t angle_mdeg, int32_t *sin_q30, int32_t *cos_q30);

/** @brief Bearing of a point (lateral X, forward D) in mdeg, right > 0. */
static inline int32_t negobs_bearing_mdeg(int32_t lateral_mm,
                                          int32_t forward_mm)
{
    return negobs_atan2_mdeg(lateral_mm, forward_mm);
}

/**
 * @brief Sensor noise of an image: the median of |3x3 second difference|
 * over every second pixel and row, in grey levels (4.05 x the noise's
 * sigma), at most 24; 0 for an image too small to measure
 * (detect_texture.c).
 */
int32_t det_noise_median(const negobs_image_u8_t *img);

/**
 * @brief 1 when the 5x5 window centred at (x, y) holds texture: a variance
 * of at least four times the noise's (noise_med from det_noise_median)
 * and horizontal structure a row-wise matcher can lock onto
 * (detect_texture.c). The window must lie inside the image.
 */
int det_window_textured(const negobs_image_u8_t *img, int32_t noise_med,
                        int32_t x, int32_t y);

/**
 * @brief Photometric statistics of an image, sampling every 2nd pixel of
 *        every 2nd row.
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_detect_photo_stats(const negobs_image_u8_t *img,
                                          negobs_photo_stats_t *out);

/**
 * @brief Columns of each row of a rectified image that lie in the field of
 *        view: the rectification fill (a run of at least 8 exactly equal
 *        pixels reaching the left or right border, on at least a quarter of
 *        the rows of that side, shorter than a quarter of the width) is
 *        left out (docs/DETECTION.md 10.2, "Out of view").
 * @param view_u0 per row (img->height entries): first column in view
 * @param view_u1 per row: one past the last column in view
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_detect_fill_extent(const negobs_image_u8_t *img,
                                          int16_t *view_u0, int16_t *view_u1);

/* Half-width (mm) of the walking corridor at floor distance range_mm:
 * corridor_near_half_mm + range x tan 20 deg, capped at
 * corridor_half_width_mm (detect_scan.c; docs/DETECTION.md 10.2). */
int32_t negobs_detect_corridor_half_mm(const negobs_detect_config_t *cfg,
                                       int32_t range_mm);

/* h_t at a floor distance (mm): h_thresh_pct of the minimum drop the rule
 * looks for there, h_min_near_mm within h_near_range_mm, else
 * h_min_far_mm (detect_scan.c; docs/DETECTION.md section 5). */
int32_t det_h_t_at(const negobs_detect_config_t *cfg, int32_t range_mm);

#endif /* NEGOBS_DETECT_INT_H */
