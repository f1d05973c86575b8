/*
 * Camera mounting estimate (internal): the physical priors that decide
 * whether a fitted plane can be a floor, the search box the ground fit's
 * Hough grid spans, and the slow track of height and roll that every
 * frame result reports (docs/DETECTION.md, "Mounting estimate").
 */
#ifndef NEGOBS_DETECT_MOUNT_H
#define NEGOBS_DETECT_MOUNT_H

#include <stdint.h>

#include "negobs/detect.h"
#include "negobs/ground.h"

/* The poses the ground fit searches: the priors, nothing narrower. */
typedef struct mount_box {
    int32_t h_min_mm;
    int32_t h_max_mm;
    int32_t p_min_mdeg;
    int32_t p_max_mdeg;
} mount_box_t;

typedef struct mount_track {
    int32_t have;       /* an estimate exists                          */
    int32_t n;          /* measuring frames since (re)acquisition      */
    int32_t height_mm;  /* slow                                        */
    int32_t roll_mdeg;  /* slow                                        */
    int32_t pitch_mdeg; /* last measuring frame's                      */
    uint32_t last_ms;   /* time of the last measuring frame            */
} mount_track_t;

/* Defaults of the mounting fields of the detector config. */
void mount_config_default(negobs_detect_config_t *cfg);

/* NEGOBS_OK or NEGOBS_ERR_INVAL for the mounting fields. */
negobs_status_t mount_config_check(const negobs_detect_config_t *cfg);

/* Search box of the ground fit's Hough grid (the priors). */
void mount_search_box(const negobs_detect_config_t *cfg, mount_box_t *box);

/* 1 if a fitted pose can be the floor under a worn camera. */
int mount_pose_physical(const negobs_detect_config_t *cfg,
                        const negobs_ground_pose_t *pose);

/* 1 if the fitted height must be verified before the view may say
 * CLEAR: ground_verify_mm or more away from the hint, or no hint. */
int mount_height_unverified(const negobs_detect_config_t *cfg,
                            int32_t fitted_height_mm);

/*
 * Where pixel (u, v) meets the fitted floor: forward and lateral floor
 * distances (mm) from the camera foot, in *fwd_mm and *lat_mm (may be
 * NULL). Returns 0, with *fwd_mm = 0, for a pixel at or above the plane's
 * horizon, which meets no floor.
 */
int mount_floor_point(const negobs_rig_t *rig,
                      const negobs_ground_plane_t *plane,
                      const negobs_ground_frame_t *frame, int32_t u, int32_t v,
                      int32_t *fwd_mm, int32_t *lat_mm);

/*
 * 1 if the fitted floor reaches within mount_verify_near_mm of the feet at
 * the centre of row v_near: the bottom row, or the nearest row whose floor
 * lies within the matcher's range (gfit_out_t.v_near). Such a fit's near
 * rows are the floor under the feet, so its height needs no hint: a drop
 * farther ahead lies in the
 * upper fit rows, which the fit discounts (section 4), and one nearer is
 * within the cane's reach. Computed with the fitted height: a fit of a
 * lower floor reads the distance long, never short.
 */
int mount_sees_feet(const negobs_detect_config_t *cfg,
                    const negobs_ground_plane_t *plane,
                    const negobs_ground_frame_t *frame, int32_t v_near);

void mount_reset(mount_track_t *m);

/*
 * One frame. pose is the frame's accepted fit or NULL (no measurement);
 * follow = 0 keeps height and roll (the view may show a lower floor than
 * the one under the feet) while the pitch is still taken. Fills *out.
 */
void mount_update(mount_track_t *m, const negobs_detect_config_t *cfg,
                  const negobs_ground_pose_t *pose, int follow,
                  uint32_t now_ms, negobs_mount_t *out);

/* The current mounting without a measurement (bad input): held or
 * configured. */
void mount_report(const mount_track_t *m, const negobs_detect_config_t *cfg,
                  negobs_mount_t *out);

#endif
