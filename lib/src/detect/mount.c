/*
 * Camera mounting estimate.
 *
 * The ground fit (ground_fit.c) measures the floor plane on every frame it
 * can; this file says which planes may be a floor and keeps the mounting
 * the frame results report:
 *
 * - Priors, not hints. A worn or hand-held camera sits 0.6-2.0 m over the
 *   floor (a child's chest to a tall adult's head), looks 0-60 degrees
 *   down (level: the floor only reaches the image below the centre row;
 *   steeper than 60: the view ends about a metre ahead) and is rolled by
 *   at most 20 degrees (a head tilt). A fit outside them, or one whose
 *   disparity does not grow down the image (not facing a floor), is no
 *   floor. The configured height and pitch are never compared with it.
 * - Pitch per frame: it moves with every step (head bob), and the plane a
 *   frame's detection uses is that frame's own fit.
 * - Height and roll slowly: a running mean over the first frames after
 *   (re)acquisition, then an exponential track (mount_gain_q15), from
 *   clean frames only; the frame's own plane still carries the bob.
 * - Look-away: after mount_reacquire_ms without a fit the estimate is
 *   HELD, and the next fits start it again from scratch.
 */
#include "mount.h"
#include "detect_int.h"

#include <string.h>

#include "negobs/fixed.h"

/* Frames of running mean before the exponential track: 16 frames make
 * the mean as steady as the track's 1/16 gain. */
#define MOUNT_MEAN_FRAMES 16

void mount_config_default(negobs_detect_config_t *cfg)
{
    /* The generic hint: a chest- or head-worn camera of an adult. */
    cfg->cam_height_mm = 1200;
    cfg->cam_pitch_mdeg = 20000;
    cfg->mount_height_min_mm = 600;
    cfg->mount_height_max_mm = 2000;
    cfg->mount_pitch_min_mdeg = 0;
    cfg->mount_pitch_max_mdeg = 60000;
    cfg->mount_roll_max_mdeg = 20000;
    cfg->mount_gain_q15 = 2048;
    /* Two seconds without a floor is a look-away (at the sky, a wall, the
     * own hand), longer than a stumble's few frames of lost ground. */
    cfg->mount_reacquire_ms = 2000;
    /* About one step: nearer than that the cane has the floor, and a fit
     * that reaches it rests on the ground under the feet. */
    cfg->mount_verify_near_mm = 600;
}

static int mount_in(int32_t x, int32_t lo, int32_t hi)
{
    return x >= lo && x <= hi;
}

negobs_status_t mount_config_check(const negobs_detect_config_t *c)
{
    /* The hint is 0 (none) or a height the priors could hold; the priors
     * stay inside what the plane <-> pose conversion represents. */
    if (!(c->cam_height_mm == 0 || mount_in(c->cam_height_mm, 200, 5000)) ||
        !mount_in(c->cam_pitch_mdeg, -10000, 70000) ||
        !mount_in(c->mount_height_min_mm, 200, 5000) ||
        !mount_in(c->mount_height_max_mm, c->mount_height_min_mm, 5000) ||
        !mount_in(c->mount_pitch_min_mdeg, -10000, 70000) ||
        !mount_in(c->mount_pitch_max_mdeg, c->mount_pitch_min_mdeg, 70000) ||
        !mount_in(c->mount_roll_max_mdeg, 0, 45000) ||
        !mount_in(c->mount_gain_q15, 1, 32768) ||
        !mount_in(c->mount_reacquire_ms, 0, 600000) ||
        !mount_in(c->mount_verify_near_mm, 0, 5000)) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

void mount_search_box(const negobs_detect_config_t *cfg, mount_box_t *box)
{
    box->h_min_mm = cfg->mount_height_min_mm;
    box->h_max_mm = cfg->mount_height_max_mm;
    box->p_min_mdeg = cfg->mount_pitch_min_mdeg;
    box->p_max_mdeg = cfg->mount_pitch_max_mdeg;
}

int mount_pose_physical(const negobs_detect_config_t *cfg,
                        const negobs_ground_pose_t *pose)
{
    return pose->height_mm >= cfg->mount_height_min_mm &&
           pose->height_mm <= cfg->mount_height_max_mm &&
           pose->pitch_mdeg >= cfg->mount_pitch_min_mdeg &&
           pose->pitch_mdeg <= cfg->mount_pitch_max_mdeg &&
           negobs_abs_s32(pose->roll_mdeg) <= cfg->mount_roll_max_mdeg;
}

int mount_floor_point(const negobs_rig_t *rig,
                      const negobs_ground_plane_t *plane,
                      const negobs_ground_frame_t *frame, int32_t u, int32_t v,
                      int32_t *fwd_mm, int32_t *lat_mm)
{
    const int32_t z = negobs_depth_mm_from_disp_q4(
        rig, negobs_ground_disp_q4(plane, u, v));
    *fwd_mm = 0;
    if (z <= 0) {
        return 0; /* at or above the plane's horizon */
    }
    negobs_ground_floor_point(rig, frame, u * 16, v * 16, z, fwd_mm, lat_mm);
    return 1;
}

int mount_sees_feet(const negobs_detect_config_t *cfg,
                    const negobs_ground_plane_t *plane,
                    const negobs_ground_frame_t *frame, int32_t v_near)
{
    const negobs_rig_t *rig = &cfg->rig;
    int32_t fwd = 0;
    if (cfg->mount_verify_near_mm <= 0 ||
        !mount_floor_point(rig, plane, frame, rig->width / 2, v_near, &fwd,
                           NULL)) {
        return 0;
    }
    return fwd <= cfg->mount_verify_near_mm;
}

int mount_height_unverified(const negobs_detect_config_t *cfg,
                            int32_t fitted_height_mm)
{
    if (cfg->cam_height_mm <= 0) {
        return 1;
    }
    /* Both ways: a hint set too high would otherwise vouch for the
     * view of a lower floor beyond an edge at switch-on (a camera 1.2 m
     * over the feet, hinted 1.5 m, sees 1.35 m in front of a 15 cm drop). */
    return negobs_abs_s32(fitted_height_mm - cfg->cam_height_mm) >=
           cfg->ground_verify_mm;
}

void mount_reset(mount_track_t *m)
{
    memset(m, 0, sizeof *m);
}

/* old + (now - old) * gain, gain in Q15, rounded. |now - old| < 2^32 and
 * gain <= 2^15, so the product stays below 2^47. */
static int32_t mount_blend(int32_t old, int32_t now, int32_t gain_q15)
{
    int64_t d = ((int64_t)now - old) * gain_q15;
    return (int32_t)(old + negobs_div_round_s64(d, 32768));
}

void mount_report(const mount_track_t *m, const negobs_detect_config_t *cfg,
                  negobs_mount_t *out)
{
    if (m->have) {
        out->height_mm = m->height_mm;
        out->pitch_mdeg = m->pitch_mdeg;
        out->roll_mdeg = m->roll_mdeg;
        out->source = NEGOBS_MOUNT_HELD;
    } else {
        out->height_mm = cfg->cam_height_mm;
        out->pitch_mdeg = cfg->cam_pitch_mdeg;
        out->roll_mdeg = 0;
        out->source = NEGOBS_MOUNT_CONFIG;
    }
}

void mount_update(mount_track_t *m, const negobs_detect_config_t *cfg,
                  const negobs_ground_pose_t *pose, int follow,
                  uint32_t now_ms, negobs_mount_t *out)
{
    if (pose == NULL) {
        mount_report(m, cfg, out);
        return;
    }
    if (m->have && (int32_t)(now_ms - m->last_ms) > cfg->mount_reacquire_ms) {
        m->n = 0; /* looked away: start again */
    }
    m->pitch_mdeg = pose->pitch_mdeg;
    m->last_ms = now_ms;
    if (!m->have || m->n == 0) {
        /* nothing followed yet: the estimate is the view's */
        m->have = 1;
        m->n = follow ? 1 : 0;
        m->height_mm = pose->height_mm;
        m->roll_mdeg = pose->roll_mdeg;
    } else if (follow) {
        int32_t gain = cfg->mount_gain_q15;
        if (m->n < MOUNT_MEAN_FRAMES) {
            m->n++;
            /* running mean: the n-th frame weighs 1/n */
            if (32768 / m->n > gain) {
                gain = 32768 / m->n;
            }
        }
        m->height_mm = mount_blend(m->height_mm, pose->height_mm, gain);
        m->roll_mdeg = mount_blend(m->roll_mdeg, pose->roll_mdeg, gain);
    }
    out->height_mm = m->height_mm;
    out->pitch_mdeg = m->pitch_mdeg;
    out->roll_mdeg = m->roll_mdeg;
    out->source = NEGOBS_MOUNT_ESTIMATED;
}
