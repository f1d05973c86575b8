/*
 * Ground model in disparity space.
 *
 * A ground plane seen by a rectified stereo pair is a plane in (u, v, d)
 * space: d(u, v) = a*u + b*v + c. With the unit ground normal n in camera
 * coordinates (x right, y down, z forward; n points from the camera to the
 * ground) and camera height H above it,
 *
 *     d(u, v) = (B/H) * (n_x*(u - cx) + n_y*(v - cy) + n_z*f)
 *
 * and n = (cos(p)*sin(r), cos(p)*cos(r), sin(p)) for pitch p (down > 0) and
 * roll r (> 0: ground disparity grows to the right). With r = 0 this is the
 * v-disparity line d = (B/H)*((v - cy)*cos(p) + f*sin(p)), horizon row
 * v_h = cy - f*tan(p).
 *
 * Fixed point: a, b and c are "disparity in px times 2^20" (`_q20`), which
 * is also disp_q4 times 2^16: d_q4(u, v) = (a*u + b*v + c) / 2^16, with u and
 * v integer pixel coordinates.
 */
#ifndef NEGOBS_GROUND_H
#define NEGOBS_GROUND_H

#include <stdint.h>

#include "negobs/depth.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Ground plane in disparity space (see the file comment). */
typedef struct negobs_ground_plane {
    int32_t a_q20; /**< d change per column (px/px * 2^20)        */
    int32_t b_q20; /**< d change per row (px/px * 2^20)           */
    int32_t c_q20; /**< d at pixel (0, 0) (px * 2^20)             */
} negobs_ground_plane_t;

/** Camera pose relative to the ground. */
typedef struct negobs_ground_pose {
    int32_t height_mm;  /**< camera centre above the ground (mm)      */
    int32_t pitch_mdeg; /**< optical axis below horizontal (mdeg)     */
    int32_t roll_mdeg;  /**< roll (mdeg), > 0: ground nearer on right */
} negobs_ground_pose_t;

/** Unit ground normal in camera coordinates, Q30, plus B/H in Q30. */
typedef struct negobs_ground_frame {
    int32_t nx_q30;
    int32_t ny_q30;
    int32_t nz_q30;        /**< sin(pitch)                         */
    int32_t cos_pitch_q30; /**< sqrt(nx^2 + ny^2)                  */
    int32_t height_mm;
} negobs_ground_frame_t;

/**
 * @brief Plane for a camera pose.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (bad camera, NULL, height outside
 *         100..10000 mm, |pitch| or |roll| >= 80 degrees).
 */
negobs_status_t negobs_ground_plane_from_pose(const negobs_rig_t *rig,
                                              const negobs_ground_pose_t *pose,
                                              negobs_ground_plane_t *plane);

/** @brief Ground disparity at pixel (u, v) in 1/16 px, rounded, saturated
 *         to int16 range. */
int32_t negobs_ground_disp_q4(const negobs_ground_plane_t *plane, int32_t u,
                              int32_t v);

/* The two below are public because the evaluation tools place labelled
 * image rows on the floor with them (negobs_detect_eval --surdis). */

/**
 * @brief Camera pose (and normal) for a plane: B/H = |(a, b, d0/f)| with
 *        d0 the plane's disparity at the principal point.
 * @param[out] frame may be NULL.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (NULL, bad camera) or
 *         NEGOBS_ERR_RANGE (degenerate plane: no ground in front).
 */
negobs_status_t negobs_ground_pose_from_plane(
    const negobs_rig_t *rig, const negobs_ground_plane_t *plane,
    negobs_ground_pose_t *pose, negobs_ground_frame_t *frame);

/**
 * @brief Forward distance along the floor to a ground point at camera depth
 *        z_mm: D = (Z - H*sin(p)) / cos(p); lateral offset along the floor
 *        X = (n_y*x - n_x*y) / cos(p) with x, y the camera coordinates.
 * @param u_q4, v_q4 pixel (1/16 px); z_mm camera depth of the point.
 */
void negobs_ground_floor_point(const negobs_rig_t *rig,
                               const negobs_ground_frame_t *frame,
                               int32_t u_q4, int32_t v_q4, int32_t z_mm,
                               int32_t *forward_mm, int32_t *lateral_mm);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_GROUND_H */
