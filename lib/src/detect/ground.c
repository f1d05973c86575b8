/*
 * Ground plane geometry: pose <-> disparity-space plane conversions.
 * The formulas are in negobs/ground.h and docs/DETECTION.md.
 */
#include "negobs/ground.h"

#include <stddef.h>

#include "negobs/fixed.h"
#include "detect_int.h"
#include "geom_internal.h"

negobs_status_t negobs_ground_plane_from_pose(const negobs_rig_t *rig,
                                              const negobs_ground_pose_t *pose,
                                              negobs_ground_plane_t *plane)
{
    int32_t sp;
    int32_t cp;
    int32_t sr;
    int32_t cr;
    int64_t nx;
    int64_t ny;
    int64_t nz;
    int64_t k_q24;
    int64_t t_q34;
    int64_t t_q20;

    if (rig == NULL || pose == NULL || plane == NULL ||
        negobs_rig_check(rig) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    if (pose->height_mm < 100 || pose->height_mm > 10000 ||
        negobs_abs_s32(pose->pitch_mdeg) >= 80000 ||
        negobs_abs_s32(pose->roll_mdeg) >= 80000) {
        return NEGOBS_ERR_INVAL;
    }
    negobs_sincos_q30(pose->pitch_mdeg, &sp, &cp);
    negobs_sincos_q30(pose->roll_mdeg, &sr, &cr);
    nx = geom_rshift_round_s64((int64_t)cp * sr, 30);
    ny = geom_rshift_round_s64((int64_t)cp * cr, 30);
    nz = sp;
    /* k = B/H, Q24: B_um < 2^20, so the shifted numerator is < 2^44. */
    k_q24 = ((int64_t)rig->baseline_um << 24) /
            ((int64_t)pose->height_mm * 1000);
    /* a = k*nx: Q24 * Q30 = Q54 -> Q20. k < 10, so the product < 2^58. */
    plane->a_q20 = (int32_t)geom_rshift_round_s64(k_q24 * nx, 34);
    plane->b_q20 = (int32_t)geom_rshift_round_s64(k_q24 * ny, 34);
    /* T = nz*f - nx*cx - ny*cy, Q30 * Q4 = Q34; |T| < 3 * 2^47. */
    t_q34 = nz * rig->focal_q4 - nx * rig->cx_q4 - ny * rig->cy_q4;
    t_q20 = geom_rshift_round_s64(t_q34, 14);
    /* c = k*T: Q24 * Q20 >> 24 -> Q20; |T_q20| < 2^35, k_q24 < 2^28. */
    plane->c_q20 = (int32_t)geom_clamp_s64(
        geom_rshift_round_s64(k_q24 * t_q20, 24), -INT32_MAX, INT32_MAX);
    return NEGOBS_OK;
}

negobs_status_t negobs_ground_pose_from_plane(
    const negobs_rig_t *rig, const negobs_ground_plane_t *plane,
    negobs_ground_pose_t *pose, negobs_ground_frame_t *frame)
{
    int64_t a;
    int64_t b;
    int64_t d0;
    int64_t e;
    int64_t norm;
    int64_t h;
    int64_t nx;
    int64_t ny;
    int64_t nz;
    const int64_t lim = (int64_t)1 << 28;

    if (rig == NULL || plane == NULL || pose == NULL ||
        negobs_rig_check(rig) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    a = plane->a_q20;
    b = plane->b_q20;
    /* Disparity at the principal point, px * 2^20. */
    d0 = (int64_t)plane->c_q20 +
         geom_rshift_round_s64(a * rig->cx_q4 + b * rig->cy_q4, 4);
    e = (d0 * 16) / rig->focal_q4;
    if (a >= lim || a <= -lim || b >= lim || b <= -lim || e >= lim ||
        e <= -lim) {
        return NEGOBS_ERR_RANGE;
    }
    /* Ground ahead and below: disparity grows down the image. */
    if (b <= 0) {
        return NEGOBS_ERR_RANGE;
    }
    norm = (int64_t)negobs_isqrt_u64((uint64_t)(a * a + b * b + e * e));
    /* |n| in Q20 is B/H; B/H < 1/10000 means no usable ground. */
    if (norm * 10000 < ((int64_t)1 << 20)) {
        return NEGOBS_ERR_RANGE;
    }
    h = (((int64_t)rig->baseline_um << 20) + norm * 500) / (norm * 1000);
    if (h > INT32_MAX) {
        return NEGOBS_ERR_RANGE;
    }
    pose->height_mm = (int32_t)h;
    pose->pitch_mdeg = negobs_atan2_mdeg(
        e, (int64_t)negobs_isqrt_u64((uint64_t)(a * a + b * b)));
    pose->roll_mdeg = negobs_atan2_mdeg(a, b);
    if (frame != NULL) {
        nx = (a * ((int64_t)1 << 30)) / norm;
        ny = (b * ((int64_t)1 << 30)) / norm;
        nz = (e * ((int64_t)1 << 30)) / norm;
        frame->nx_q30 = (int32_t)nx;
        frame->ny_q30 = (int32_t)ny;
        frame->nz_q30 = (int32_t)nz;
        frame->cos_pitch_q30 = (int32_t)negobs_isqrt_u64(
            (uint64_t)(nx * nx + ny * ny));
        frame->height_mm = pose->height_mm;
    }
    return NEGOBS_OK;
}

int32_t negobs_ground_disp_q4(const negobs_ground_plane_t *plane, int32_t u,
                              int32_t v)
{
    int64_t d = (int64_t)plane->a_q20 * u + (int64_t)plane->b_q20 * v +
                plane->c_q20;
    return (int32_t)geom_clamp_s64(geom_rshift_round_s64(d, 16), INT16_MIN + 1,
                                   INT16_MAX);
}

void negobs_ground_floor_point(const negobs_rig_t *rig,
                               const negobs_ground_frame_t *frame,
                               int32_t u_q4, int32_t v_q4, int32_t z_mm,
                               int32_t *forward_mm, int32_t *lateral_mm)
{
    int64_t x = negobs_div_round_s64(((int64_t)u_q4 - rig->cx_q4) * z_mm,
                                     rig->focal_q4);
    int64_t y = negobs_div_round_s64(((int64_t)v_q4 - rig->cy_q4) * z_mm,
                                     rig->focal_q4);
    int64_t cosp = frame->cos_pitch_q30;
    /* Height of the point below the camera along the normal, mm. */
    int64_t np = geom_rshift_round_s64(frame->nx_q30 * x + frame->ny_q30 * y +
                                           (int64_t)frame->nz_q30 * z_mm,
                                       30);
    int64_t fwd;
    int64_t lat;

    if (cosp <= 0) {
        cosp = 1;
    }
    fwd = negobs_div_round_s64(
        (int64_t)z_mm * ((int64_t)1 << 30) - np * frame->nz_q30, cosp);
    lat = negobs_div_round_s64(frame->ny_q30 * x - frame->nx_q30 * y, cosp);
    if (forward_mm != NULL) {
        *forward_mm = (int32_t)geom_clamp_s64(fwd, -INT32_MAX, INT32_MAX);
    }
    if (lateral_mm != NULL) {
        *lateral_mm = (int32_t)geom_clamp_s64(lat, -INT32_MAX, INT32_MAX);
    }
}
