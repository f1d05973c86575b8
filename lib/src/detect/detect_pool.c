/* Frames pooled along the measured travel, or an upper bound of it
 * (docs/DETECTION.md, "Pooled frames"). */
#include "detect_internal.h"

/*
 * Each pixel's value is pooled with the same floor point's value of the
 * last pooled frame, found through the travel between the two (measured
 * by detect_travel.c, or assumed: below). The quantity pooled is the
 * relative residual rho = (d - d_g) / d_g against each frame's own ground
 * model: a drop of h below a floor seen from height H gives
 * rho = -h / (H + h) wherever the ray meets its lower level, the same
 * number in every frame, while the disparity itself grows as the wearer
 * comes nearer. Each frame's own fit (the bob of the head) is taken out
 * the same way.
 *
 * Why: a floor patch's matching error is nearly independent from one
 * frame to the next (docs/journal/2026-12-03-pooling-frames.md measured
 * frame-to-frame correlations of 0.0-0.2 on every texture), so the mean
 * of n frames scatters about 1 / sqrt(n) as much, and on weak textures
 * and narrow baselines one frame's noise is as large as a minimum drop's
 * deficit. The detector measures its noise on the pooled map as on any
 * other: nothing assumes the 1 / sqrt(n).
 *
 * The alignment: the travel measured this tick, or else, when the
 * patches measured nothing this tick but a pace within the last 500 ms
 * (a floor they follow only now and then), an upper bound of the walk
 * since: that pace plus what a walker gains in that time, at most
 * hold_speed_mm_s (the walking speeds' upper end). Aligned along more
 * travel than was walked, a sample of the lower level beyond an edge is
 * pooled onto the floor before it, so the edge errs toward the walker;
 * along less, it would err away from the walker, past the true edge,
 * which is why an unmeasured travel is never taken as 0. Without a recent
 * pace nothing is pooled: the wearer may be standing, and pooling a
 * standing camera's frames along a walk it did not make moved drops more
 * than 10 % nearer and let one noisy strip, the same in every frame, be
 * confirmed as a drop (tests/detect's static scenes).
 *
 * A pixel is pooled only when
 * - the two frames' fits agree within what a walking head moves between
 *   two ticks (POOL_FIT_MM, POOL_FIT_MDEG; without a measured travel
 *   POOL_ASSUME_FIT_MM, POOL_ASSUME_FIT_MDEG), and the last one was not
 *   rejected afterwards (det_pool_distrust): a fit that jumped may have
 *   moved onto a lower level or a blend of two, and each frame's floor is
 *   what places its samples; misplaced, they would smooth away the very
 *   edge that shows the fit to be wrong;
 * - its floor point was in the last pooled frame's view with a value;
 * - the two agree within 3 sigmas of their difference (the fit's
 *   per-pixel sigma times sqrt(2); at least POOL_GATE_MIN_Q4, at most
 *   POOL_GATE_MAX_Q4): anything else is another surface (a moving object,
 *   an occlusion boundary, a wall whose relative residual changes with
 *   the range), kept as measured.
 * The weight of the past is at most pool_frames - 1 frames (a running
 * mean up to pool_frames, an exponential one after).
 *
 * Fixed point: rho is Q14, kept in the history with its count in the two
 * low bits (Q12 precision, 1/4096 of the ground disparity: 0.04 q4 at
 * 10 px); POOL_NONE marks no value. A pixel's pooled disparity is
 * d_g + rho * d_g / 2^14, rounded.
 */

#define POOL_NONE INT16_MIN
/* Node spacing of the floor mapping (columns; prev_at shifts by 3): the
 * mapping is smooth, and linear between nodes 8 px apart it is off by far
 * less than a pixel below the horizon's last rows, which the scan never
 * reads. */
#define POOL_NODE_PX 8
/* A head bobs by 30-50 mm and pitches by a few degrees over a stride of
 * about half a second: between two ticks (100 ms) the rendered gait of
 * the evaluation suite moves by at most 27 mm and 1.1 deg. 50 mm is also
 * the smallest drop to tell apart (ground_verify_mm's default). */
#define POOL_FIT_MM 50
#define POOL_FIT_MDEG 3000
/* 3 sigmas of the difference of two samples (sqrt(2) x the per-pixel
 * sigma, 3 x 1.414 ~= 17/4): two samples of the same floor disagree by
 * more than that 0.3 % of the time. A tighter gate would drop the
 * noisiest samples from the pool and keep exactly those as measured. */
#define POOL_GATE_NUM 17
#define POOL_GATE_DEN 4
/* 0.5 px: on a textured floor (sigma 0.1 px) a sub-pixel misalignment of
 * a sloping surface must not split the pool; 2 px: beyond it the samples
 * are of different surfaces whatever the noise. */
#define POOL_GATE_MIN_Q4 8
#define POOL_GATE_MAX_Q4 32
/* An assumed travel only across a gap the patches would measure across
 * (detect_travel.c, 500 ms): after a longer one the walk since is
 * unknown. */
#define POOL_ASSUME_GAP_MS 500
/* A measured travel also shows that both fits place the floor alike (the
 * patches matched through them); an assumed one shows nothing, and a fit
 * off by 3 deg (a worn floor at a 40 deg pitch) moves the relative
 * residual of the image's upper half by 10-20 %, more than a 10 cm
 * drop's (6 % under a 1.55 m camera). So the fits must agree within the
 * head's own motion in a tick (the suite's gait: 27 mm and 1.1 deg,
 * rounded up), not the generous bound above. */
#define POOL_ASSUME_FIT_MM 30
#define POOL_ASSUME_FIT_MDEG 1500
/* A pace measured within POOL_PACE_MS bounds the walk: a walker starting
 * off reaches walking speed in about a second (about 1 m/s^2), so in
 * 500 ms gains at most POOL_PACE_MARGIN_MM_S. On the real wearable walk
 * (0.3-0.4 m/s where measured) the bare upper end instead overshot by
 * 100 mm a tick, and its steps were confirmed on no frame instead of 20
 * of 82. */
#define POOL_PACE_MS 500
#define POOL_PACE_MARGIN_MM_S 500

static inline int32_t hist_rho(int16_t h)
{
    return (int32_t)h & ~3;
}

static inline int32_t hist_n(int16_t h)
{
    return ((int32_t)h & 3) + 1;
}

static inline int16_t hist_pack(int32_t rho_q14, int32_t n)
{
    return (int16_t)((rho_q14 & ~3) | (n - 1));
}

int32_t det_pool_nodes(int32_t width)
{
    /* nodes at u = 0, 8, ...: the last one at or beyond the last column,
     * so every column lies in a whole span (shifts, no division) */
    return (width - 1) / POOL_NODE_PX + 2;
}

/* Previous-frame pixel (q4) of each node of row v: INT32_MIN when the
 * node's floor point is not on the floor of both frames (a node past the
 * last column is projected like any other). */
static void map_row(const negobs_rig_t *rig,
                    const negobs_ground_plane_t *plane,
                    const negobs_ground_frame_t *fr, const floor_axes_t *prev,
                    int32_t travel_mm, int32_t v, int32_t *node_uv)
{
    const int32_t nn = det_pool_nodes(rig->width);
    int32_t k;
    for (k = 0; k < nn; k++) {
        int32_t *node = node_uv + (ptrdiff_t)2 * k;
        int32_t fwd = 0;
        int32_t lat = 0;
        if (!mount_floor_point(rig, plane, fr, k * POOL_NODE_PX, v, &fwd,
                               &lat) ||
            !travel_pixel_q4(rig, prev, fwd + travel_mm, lat, &node[0],
                             &node[1])) {
            node[0] = INT32_MIN;
        }
    }
}

/* The last pooled frame's history at the previous-frame pixel of (u, v)
 * (linear between the row's nodes, rounded down to 1/16 px), or
 * POOL_NONE. */
static inline int16_t prev_at(const int16_t *prev_hist,
                              const negobs_rig_t *rig, const int32_t *node_uv,
                              int32_t u)
{
    const int32_t *a = node_uv + (ptrdiff_t)2 * (u / POOL_NODE_PX);
    const int32_t t = u % POOL_NODE_PX;
    int32_t pu;
    int32_t pv;
    if (a[0] == INT32_MIN || a[2] == INT32_MIN) {
        return POOL_NONE;
    }
    pu = (a[0] + (((a[2] - a[0]) * t) >> 3) + 8) >> 4;
    pv = (a[1] + (((a[3] - a[1]) * t) >> 3) + 8) >> 4;
    if (pu < 0 || pv < 0 || pu >= rig->width || pv >= rig->height) {
        return POOL_NONE;
    }
    return prev_hist[(size_t)pv * (size_t)rig->width + (size_t)pu];
}

/* One row: rho of each valid pixel below the horizon, pooled with the
 * previous frame where allowed (node_uv NULL: not at all). Counts the
 * row's valid pixels below the horizon and the pooled ones into cnt. */
static void pool_row(detect_priv_t *p, const negobs_detect_config_t *cfg,
                     const negobs_image_s16_t *disp,
                     const negobs_ground_plane_t *plane, int32_t v,
                     const int32_t *node_uv, int32_t gate_q4, int32_t cnt[2])
{
    const int32_t w = cfg->rig.width;
    const int16_t *in = negobs_image_s16_row(disp, v);
    int16_t *out = p->pool_out + (size_t)v * (size_t)w;
    int16_t *hist = p->pool_hist[p->pool_cur] + (size_t)v * (size_t)w;
    const int16_t *prev_hist = p->pool_hist[p->pool_cur ^ 1];
    int64_t acc = (int64_t)plane->b_q20 * v + plane->c_q20;
    int32_t u;
    for (u = 0; u < w; u++, acc += plane->a_q20) {
        const int32_t d = in[u];
        const int32_t dg = (int32_t)geom_rshift_round_s64(acc, 16);
        int32_t rho;
        int32_t n = 1;
        int16_t h;
        out[u] = (int16_t)d;
        hist[u] = (int16_t)POOL_NONE;
        if (d == NEGOBS_DISP_INVALID || d < 0 || dg <= 0) {
            continue;
        }
        cnt[0]++;
        rho = (int32_t)(((int64_t)(d - dg) << 14) / dg);
        if (rho < -16384 || rho >= 16384) {
            continue; /* nearer than twice the floor's disparity: not
                         pooled, as measured */
        }
        h = (int16_t)POOL_NONE;
        if (node_uv != NULL) {
            h = prev_at(prev_hist, &cfg->rig, node_uv, u);
        }
        if (h != POOL_NONE &&
            negobs_abs_s32((int32_t)(((int64_t)(rho - hist_rho(h)) * dg) >>
                                     14)) <= gate_q4) {
            const int32_t np = geom_min_s32(hist_n(h), cfg->pool_frames - 1);
            /* |sum| <= 4 x 2^14: an int32 division, rounded half away */
            const int32_t sum = rho + np * hist_rho(h);
            rho = (sum >= 0) ? (sum + (np + 1) / 2) / (np + 1)
                             : -((-sum + (np + 1) / 2) / (np + 1));
            n = np + 1;
            cnt[1]++;
            /* 0 <= d_g (1 + rho) < 2 d_g: saturated like the ground
             * disparity itself, for a plane that steep */
            out[u] = (int16_t)negobs_clamp_s32(
                dg + (int32_t)geom_rshift_round_s64((int64_t)rho * dg, 14), 0,
                INT16_MAX);
        }
        hist[u] = hist_pack(rho, n);
    }
}

/* One frame's pass, shared by its row bands. */
typedef struct pool_pass {
    detect_priv_t *p;
    const negobs_detect_config_t *cfg;
    const negobs_image_s16_t *disp;
    const gfit_out_t *g;
    floor_axes_t prev;
    int use_prev;
    int32_t travel_mm;
    int32_t gate_q4;
} pool_pass_t;

/* Band `job` of NEGOBS_DETECT_POOL_BANDS, counted from the bottom (the
 * most floor first: the costliest first, as the executor asks): its rows,
 * its own nodes and counts, so bands may run at once in any order. A band
 * run twice gives the same rows (it reads only the last frame's history);
 * a job index outside the bands is ignored. */
static void pool_band(void *arg, int32_t job, int32_t worker)
{
    const pool_pass_t *pp = (const pool_pass_t *)arg;
    detect_priv_t *p = pp->p;
    const negobs_detect_config_t *cfg = pp->cfg;
    const int32_t hgt = cfg->rig.height;
    int32_t *node;
    int32_t *cnt;
    int32_t v1;
    int32_t v;
    (void)worker;
    if (job < 0 || job >= NEGOBS_DETECT_POOL_BANDS) {
        return;
    }
    v1 = hgt - hgt * job / NEGOBS_DETECT_POOL_BANDS;
    node = p->pool_node + (ptrdiff_t)job * 2 * det_pool_nodes(cfg->rig.width);
    cnt = p->pool_cnt[job];
    cnt[0] = 0;
    cnt[1] = 0;
    for (v = hgt - hgt * (job + 1) / NEGOBS_DETECT_POOL_BANDS; v < v1; v++) {
        /* a row with floor at either end (the plane is linear along it) */
        const int row_prev = pp->use_prev &&
                             (negobs_ground_disp_q4(&pp->g->plane, 0, v) > 0 ||
                              negobs_ground_disp_q4(
                                  &pp->g->plane, cfg->rig.width - 1, v) > 0);
        if (row_prev) {
            map_row(&cfg->rig, &pp->g->plane, &pp->g->frame, &pp->prev,
                    pp->travel_mm, v, node);
        }
        pool_row(p, cfg, pp->disp, &pp->g->plane, v, row_prev ? node : NULL,
                 pp->gate_q4, cnt);
    }
    p->pool_done[job] = 1;
}

/* The travel to align with when none was measured since the last pooled
 * frame: an upper bound of the walk from the recent pace (file comment);
 * 0 (no pooling) without one, or after a gap the patches would not
 * measure across either. */
static inline int32_t assumed_travel_mm(const detect_priv_t *p,
                                        const negobs_detect_config_t *cfg,
                                        uint32_t now_ms)
{
    const uint32_t dt_ms = now_ms - p->pool_ms;
    int32_t speed;
    if (dt_ms == 0u || dt_ms > POOL_ASSUME_GAP_MS || p->pool_pace_mm_s <= 0 ||
        now_ms - p->pool_pace_ms > POOL_PACE_MS) {
        return 0;
    }
    speed = geom_min_s32(cfg->hold_speed_mm_s,
                         p->pool_pace_mm_s + POOL_PACE_MARGIN_MM_S);
    return (int32_t)(((int64_t)speed * dt_ms) / 1000);
}

const negobs_image_s16_t *det_pool_frame(detect_priv_t *p,
                                         const negobs_detect_config_t *cfg,
                                         const negobs_image_s16_t *disp,
                                         const gfit_out_t *g, int tick,
                                         int32_t travel_mm, uint32_t now_ms,
                                         int32_t *pooled_permille)
{
    int32_t cnt[2] = {0, 0};
    int32_t fit_mm;
    int32_t fit_mdeg;
    pool_pass_t pp;
    int32_t j;
    *pooled_permille = 0;
    if (p->pool_out == NULL) {
        return disp;
    }
    if (!tick) {
        /* the travel is measured from tick to tick: between ticks the map
         * is used as measured and the history waits for the next tick */
        return disp;
    }
    pp.p = p;
    pp.cfg = cfg;
    pp.disp = disp;
    pp.g = g;
    fit_mm = POOL_FIT_MM;
    fit_mdeg = POOL_FIT_MDEG;
    if (travel_mm > 0 && p->pool_have && now_ms != p->pool_ms) {
        p->pool_pace_mm_s = (int32_t)((int64_t)travel_mm * 1000 /
                                      (int64_t)(now_ms - p->pool_ms));
        p->pool_pace_ms = now_ms;
    }
    if (travel_mm <= 0 && p->pool_have) {
        travel_mm = assumed_travel_mm(p, cfg, now_ms);
        fit_mm = POOL_ASSUME_FIT_MM;
        fit_mdeg = POOL_ASSUME_FIT_MDEG;
    }
    pp.travel_mm = travel_mm;
    pp.use_prev = p->pool_have && travel_mm > 0 &&
                  negobs_abs_s32(g->pose.height_mm - p->pool_pose.height_mm) <=
                      fit_mm &&
                  negobs_abs_s32(g->pose.pitch_mdeg -
                                 p->pool_pose.pitch_mdeg) <= fit_mdeg &&
                  travel_axes_of(&p->pool_frame, &pp.prev);
    pp.gate_q4 = negobs_clamp_s32(POOL_GATE_NUM * g->sigma_q4 / POOL_GATE_DEN,
                                  POOL_GATE_MIN_Q4, POOL_GATE_MAX_Q4);
    p->pool_cur ^= 1;
    memset(p->pool_done, 0, sizeof p->pool_done);
    if (p->exec.run != NULL) {
        p->exec.run(p->exec.user, NEGOBS_DETECT_POOL_BANDS, pool_band, &pp);
    }
    /* without an executor, and any band a faulty executor skipped: here (a
     * skipped band would leave the last frame's rows in the map) */
    for (j = 0; j < NEGOBS_DETECT_POOL_BANDS; j++) {
        if (!p->pool_done[j]) {
            pool_band(&pp, j, 0);
        }
    }
    for (j = 0; j < NEGOBS_DETECT_POOL_BANDS; j++) {
        cnt[0] += p->pool_cnt[j][0];
        cnt[1] += p->pool_cnt[j][1];
    }
    *pooled_permille = (cnt[0] > 0)
                           ? (int32_t)((int64_t)cnt[1] * 1000 / cnt[0])
                           : 0;
    p->pool_frame = g->frame;
    p->pool_pose = g->pose;
    p->pool_have = 1;
    p->pool_ms = now_ms;
    p->pool_img.data = p->pool_out;
    p->pool_img.width = cfg->rig.width;
    p->pool_img.height = cfg->rig.height;
    p->pool_img.stride = cfg->rig.width;
    return &p->pool_img;
}

void det_pool_distrust(detect_priv_t *p)
{
    p->pool_have = 0;
}
