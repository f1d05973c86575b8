/*
 * Stereo geometry in integers: depth from disparity, lateral offset,
 * bearing, and the angle helpers (CORDIC) the ground model needs.
 *
 * Units: focal length and principal point in 1/16 px (`_q4`), baseline in
 * micrometres (`_um`), depths and offsets in millimetres (`_mm`), angles in
 * millidegrees (`_mdeg`), unit-less ratios in Q30 (`_q30`, 1.0 = 2^30).
 */
#ifndef NEGOBS_DEPTH_H
#define NEGOBS_DEPTH_H

#include <stdint.h>

#include "negobs/fixed.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Returned by the depth conversions for "no depth" (d <= 0 or invalid). */
#define NEGOBS_DEPTH_NONE_MM (-1)
/** Largest depth reported (mm); farther points saturate here. */
#define NEGOBS_DEPTH_MAX_MM 1000000

/** Rectified pinhole stereo camera (left camera is the reference). */
typedef struct negobs_rig {
    int32_t width;       /**< image width (pixels, default 320)          */
    int32_t height;      /**< image height (pixels, default 240)         */
    int32_t focal_q4;    /**< focal length (1/16 px, default 250*16)     */
    int32_t cx_q4;       /**< principal point column (1/16 px)           */
    int32_t cy_q4;       /**< principal point row (1/16 px)              */
    int32_t baseline_um; /**< baseline (micrometres, default 120000)     */
} negobs_rig_t;

/**
 * @brief Defaults for a width x height image: f = 250 px scaled with the
 *        width from 320 px, principal point at the image centre
 *        ((w-1)/2, (h-1)/2), B = 120 mm.
 */
void negobs_rig_default(negobs_rig_t *rig, int32_t width, int32_t height);

/**
 * @brief Check a camera: 16 <= w, h <= NEGOBS_MAX_DIM, 1 px <= f <= 8192
 *        px, principal point inside the image, 1 mm <= B <= 1 m.
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_rig_check(const negobs_rig_t *rig);

/**
 * @brief Depth Z = f*B/d in millimetres.
 *
 * Scaling and overflow: Z_mm = (focal_q4 * baseline_um) / (disp_q4 * 1000);
 * the 1/16 scales of f and d cancel. The numerator is at most
 * 2^17 * 2^20 = 2^37 and is formed in int64; the quotient is rounded to
 * nearest (ties up). d <= 0 or NEGOBS_DISP_INVALID gives
 * NEGOBS_DEPTH_NONE_MM; depths above NEGOBS_DEPTH_MAX_MM saturate.
 */
int32_t negobs_depth_mm_from_disp_q4(const negobs_rig_t *rig, int32_t disp_q4);

/**
 * @brief Inverse: d_q4 = f*B/Z, rounded to nearest; Z <= 0 gives 0; the
 *        result saturates at INT16_MAX.
 */
int32_t negobs_disp_q4_from_depth_mm(const negobs_rig_t *rig,
                                     int32_t depth_mm);

/**
 * @brief Lateral camera coordinate X = (u - cx) * Z / f in millimetres
 *        (positive to the right) for a column u given in 1/16 px.
 *        Rounded to nearest, formed in int64.
 */
int32_t negobs_lateral_mm(const negobs_rig_t *rig, int32_t u_q4,
                          int32_t depth_mm);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_DEPTH_H */
