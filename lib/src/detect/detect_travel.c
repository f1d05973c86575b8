/*
 * Forward travel along the floor between two frames (docs/DETECTION.md
 * 6.2, "Verified by walking").
 *
 * Floor patches of the previous frame are stored with their floor
 * coordinates (forward along the heading, lateral). A forward travel T
 * moves each such point to (forward - T, lateral) in this frame's floor
 * coordinates; projected through this frame's own floor (its height,
 * pitch and roll: bobbing and sway are this frame's pose, not travel) it
 * lands on a pixel whose patch is compared with the stored one. The
 * travel is the T of the smallest sum of mean-removed absolute
 * differences over a grid of candidates.
 *
 * It is counted only when the images show it: the best T must lie inside
 * the grid (a faster motion is not measured), away from standing still,
 * and its cost at most TRAVEL_CLEAR_NUM / TRAVEL_CLEAR_DEN of the cost of
 * standing still. A standing wearer, a bland floor, sensor noise alone or a
 * repeated frame therefore count nothing. Yaw between frames is not
 * modelled: a turning head spoils the match and counts nothing too.
 *
 * Fixed point: the floor's unit vectors are Q30; a camera-frame point
 * (mm, Q30) is at most 2^14 * 2^30 * 3 < 2^46, and the focal length in
 * 1/16 px (< 2^17) times it stays below 2^63.
 */
#include "detect_travel.h"

#include <stddef.h>

#include "negobs/fixed.h"

#include "geom_internal.h"
#include "mount.h"

/* The fastest travel measured: 2 m/s, a brisk walk (a cane user walks at
 * about 1 m/s). Beyond it the best T lies at the grid's end and nothing is
 * counted. */
#define TRAVEL_MAX_MM_PER_S 2000
/* A longer gap between frames (a dropped frame or two at 10 fps is
 * 200-300 ms) measures nothing: the patches may have left the view. */
#define TRAVEL_MAX_GAP_MS 500
/* Candidates of T from 0 to the fastest travel. */
#define TRAVEL_STEPS 24
/* The best T must cost at most 3/4 of standing still: with the same floor
 * in view and noise alone, T = 0 is the best or ties with its neighbours. */
#define TRAVEL_CLEAR_NUM 3
#define TRAVEL_CLEAR_DEN 4
/* Fewer patches in view at every candidate than this: no measurement. */
#define TRAVEL_MIN_PATCHES 16
/* Nearer than this to the camera a point is not projected. */
#define TRAVEL_MIN_DEPTH_MM 200

#define TRAVEL_R (TRAVEL_PATCH / 2 * TRAVEL_STRIDE)
#define TRAVEL_N (TRAVEL_PATCH * TRAVEL_PATCH)
/* patch_cost()'s largest value, 25 x 25 x 255 */
#define TRAVEL_WORST_COST 159375

/* The floor's axes in camera coordinates, Q30: n (down to the floor),
 * fwd (along the floor in the heading), right (along the floor, to the
 * right). With n = (cos p sin r, cos p cos r, sin p):
 * fwd = (-sin p sin r, -sin p cos r, cos p), right = (cos r, -sin r, 0). */
typedef struct floor_axes {
    int64_t n[3];
    int64_t f[3];
    int64_t r[3];
    int64_t h_mm;
} floor_axes_t;

static int axes_of(const negobs_ground_frame_t *fr, floor_axes_t *a)
{
    const int64_t cp = fr->cos_pitch_q30;
    if (cp <= 0 || fr->height_mm <= 0) {
        return 0;
    }
    a->n[0] = fr->nx_q30;
    a->n[1] = fr->ny_q30;
    a->n[2] = fr->nz_q30;
    a->f[0] = -((int64_t)fr->nz_q30 * fr->nx_q30) / cp;
    a->f[1] = -((int64_t)fr->nz_q30 * fr->ny_q30) / cp;
    a->f[2] = cp;
    a->r[0] = ((int64_t)fr->ny_q30 * (1 << 30)) / cp;
    a->r[1] = -((int64_t)fr->nx_q30 * (1 << 30)) / cp;
    a->r[2] = 0;
    a->h_mm = fr->height_mm;
    return 1;
}

/* Pixel (rounded) of the floor point (fwd, lat); 0 when behind or too
 * near the camera. */
static int project(const negobs_rig_t *rig, const floor_axes_t *a,
                   int32_t fwd_mm, int32_t lat_mm, int32_t *u, int32_t *v)
{
    int64_t p[3];
    int i;
    for (i = 0; i < 3; i++) {
        p[i] = a->h_mm * a->n[i] + (int64_t)fwd_mm * a->f[i] +
               (int64_t)lat_mm * a->r[i];
    }
    if (p[2] < ((int64_t)TRAVEL_MIN_DEPTH_MM << 30)) {
        return 0;
    }
    *u = (int32_t)((rig->cx_q4 +
                    negobs_div_round_s64(rig->focal_q4 * p[0], p[2]) + 8) >>
                   4);
    *v = (int32_t)((rig->cy_q4 +
                    negobs_div_round_s64(rig->focal_q4 * p[1], p[2]) + 8) >>
                   4);
    return 1;
}

static inline int patch_inside(const negobs_image_u8_t *im, int32_t u,
                               int32_t v)
{
    return u >= TRAVEL_R && v >= TRAVEL_R && u < im->width - TRAVEL_R &&
           v < im->height - TRAVEL_R;
}

/* Sum of |25 a - 25 b - (sum a - sum b)|: the absolute difference of the
 * mean-removed patches, times 25 (no rounding). At most 25 * 25 * 510. */
static int32_t patch_cost(const uint8_t *stored, const negobs_image_u8_t *im,
                          int32_t u, int32_t v)
{
    int32_t b[TRAVEL_N];
    int32_t sa = 0;
    int32_t sb = 0;
    int32_t c = 0;
    int32_t i;
    int32_t j;
    for (j = 0; j < TRAVEL_PATCH; j++) {
        const uint8_t *row = negobs_image_u8_row(im, v - TRAVEL_R +
                                                         j * TRAVEL_STRIDE);
        for (i = 0; i < TRAVEL_PATCH; i++) {
            b[j * TRAVEL_PATCH + i] = row[u - TRAVEL_R + i * TRAVEL_STRIDE];
        }
    }
    for (i = 0; i < TRAVEL_N; i++) {
        sa += stored[i];
        sb += b[i];
    }
    for (i = 0; i < TRAVEL_N; i++) {
        c += negobs_abs_s32(TRAVEL_N * ((int32_t)stored[i] - b[i]) -
                            (sa - sb));
    }
    return c;
}

/* The travel the held patches show on this frame, or 0. */
static int32_t measure(const travel_track_t *t, const negobs_rig_t *rig,
                       const floor_axes_t *a, const negobs_image_u8_t *left,
                       int32_t dt_ms)
{
    int64_t cost[TRAVEL_STEPS + 1];
    int32_t use[TRAVEL_SAMPLES];
    const int32_t t_max = TRAVEL_MAX_MM_PER_S * dt_ms / 1000;
    int32_t n_use = 0;
    int32_t k;
    int32_t i;
    int32_t best = 0;
    if (t_max < TRAVEL_STEPS) {
        return 0;
    }
    /* the patches in view at both ends of the grid are in view at every
     * candidate between them (a floor point moves monotonically) */
    for (i = 0; i < t->n; i++) {
        int32_t u;
        int32_t v;
        if (project(rig, a, t->fwd_mm[i], t->lat_mm[i], &u, &v) &&
            patch_inside(left, u, v) &&
            project(rig, a, t->fwd_mm[i] - t_max, t->lat_mm[i], &u, &v) &&
            patch_inside(left, u, v)) {
            use[n_use++] = i;
        }
    }
    if (n_use < TRAVEL_MIN_PATCHES) {
        return 0;
    }
    for (k = 0; k <= TRAVEL_STEPS; k++) {
        const int32_t tk = t_max * k / TRAVEL_STEPS;
        cost[k] = 0;
        for (i = 0; i < n_use; i++) {
            const int32_t s = use[i];
            int32_t u = 0;
            int32_t v = 0;
            (void)project(rig, a, t->fwd_mm[s] - tk, t->lat_mm[s], &u, &v);
            if (!patch_inside(left, u, v)) {
                /* rounding at the border: count the worst difference */
                cost[k] += TRAVEL_WORST_COST;
                continue;
            }
            cost[k] += patch_cost(t->px[s], left, u, v);
        }
        if (cost[k] < cost[best]) {
            best = k;
        }
    }
    if (best < 2 || best >= TRAVEL_STEPS ||
        cost[best] * TRAVEL_CLEAR_DEN > cost[0] * TRAVEL_CLEAR_NUM) {
        return 0;
    }
    return t_max * best / TRAVEL_STEPS;
}

/* Floor distance (forward, mm) of pixel (u, v) on the plane; -1: none. */
static int32_t floor_fwd(const negobs_rig_t *rig,
                         const negobs_ground_plane_t *plane,
                         const negobs_ground_frame_t *fr, int32_t u, int32_t v,
                         int32_t *lat_mm)
{
    int32_t fwd = 0;
    if (!mount_floor_point(rig, plane, fr, u, v, &fwd, lat_mm)) {
        return -1;
    }
    return fwd;
}

/* This frame's patches: 8 rows x 8 columns over the middle 60 % of the
 * columns, on the floor of the fitted plane. The rows lie TRAVEL_ROW0_MM
 * to TRAVEL_ROW0_MM + 7 x TRAVEL_ROW_STEP_MM beyond the nearest floor in
 * view: the nearest stay in view after the fastest travel, and the
 * farthest still move by a pixel or more per 10 mm... at 2.5 m at f = 250
 * and 1.2 m high (the floor's row moves by f H / D^2 per mm). */
#define TRAVEL_ROW0_MM 400
#define TRAVEL_ROW_STEP_MM 300

static void sample(travel_track_t *t, const negobs_rig_t *rig,
                   const negobs_ground_plane_t *plane,
                   const negobs_ground_frame_t *fr,
                   const negobs_image_u8_t *left)
{
    const int32_t w = rig->width;
    const int32_t uc = w / 2;
    int32_t v = rig->height - 1 - TRAVEL_R;
    int32_t j = 0;
    int32_t near_mm = floor_fwd(rig, plane, fr, uc, v, NULL);
    t->n = 0;
    if (near_mm < 0) {
        return;
    }
    for (; v >= TRAVEL_R && j < 8; v--) {
        const int32_t target = near_mm + TRAVEL_ROW0_MM +
                               j * TRAVEL_ROW_STEP_MM;
        const int32_t f = floor_fwd(rig, plane, fr, uc, v, NULL);
        int32_t i;
        if (f < 0) {
            break; /* the horizon */
        }
        if (f < target) {
            continue;
        }
        j++;
        for (i = 0; i < 8; i++) {
            const int32_t u = w / 5 + (w * 3 / 5) * i / 7;
            int32_t lat = 0;
            const int32_t fwd = floor_fwd(rig, plane, fr, u, v, &lat);
            int32_t a;
            int32_t b;
            if (fwd < 0 || !patch_inside(left, u, v)) {
                continue;
            }
            t->fwd_mm[t->n] = fwd;
            t->lat_mm[t->n] = lat;
            for (b = 0; b < TRAVEL_PATCH; b++) {
                const uint8_t *row = negobs_image_u8_row(
                    left, v - TRAVEL_R + b * TRAVEL_STRIDE);
                for (a = 0; a < TRAVEL_PATCH; a++) {
                    t->px[t->n][b * TRAVEL_PATCH + a] =
                        row[u - TRAVEL_R + a * TRAVEL_STRIDE];
                }
            }
            t->n++;
        }
    }
}

int32_t travel_step(travel_track_t *t, const negobs_rig_t *rig,
                    const negobs_ground_plane_t *plane,
                    const negobs_ground_frame_t *frame,
                    const negobs_image_u8_t *left, uint32_t now_ms)
{
    floor_axes_t a;
    int32_t walked = 0;
    int32_t dt;
    if (left == NULL || left->width != rig->width ||
        left->height != rig->height || !axes_of(frame, &a)) {
        travel_reset(t);
        return 0;
    }
    dt = (int32_t)(now_ms - t->t_ms);
    if (t->n > 0 && dt > 0 && dt <= TRAVEL_MAX_GAP_MS) {
        walked = measure(t, rig, &a, left, dt);
    }
    sample(t, rig, plane, frame, left);
    t->t_ms = now_ms;
    return walked;
}
