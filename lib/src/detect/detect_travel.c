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
 * repeated frame therefore count nothing.
 *
 * The head and the trunk turn to and fro at the stride's rate while the
 * walk keeps its heading: a few degrees between frames, which moves the
 * floor by several pixels sideways. Searched for T alone, such a turn
 * spoils the match or, worse, finds a wrong T: a camera turning by 2 deg
 * in place read 83 mm of travel. So the search also turns the camera about
 * the floor's normal (turn_search()), and standing still is taken at the
 * turn that explains it best.
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

int travel_axes_of(const negobs_ground_frame_t *fr, floor_axes_t *a)
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

int travel_pixel_q4(const negobs_rig_t *rig, const floor_axes_t *a,
                    int32_t fwd_mm, int32_t lat_mm, int32_t *u_q4,
                    int32_t *v_q4)
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
    *u_q4 = (int32_t)(rig->cx_q4 +
                      negobs_div_round_s64(rig->focal_q4 * p[0], p[2]));
    *v_q4 = (int32_t)(rig->cy_q4 +
                      negobs_div_round_s64(rig->focal_q4 * p[1], p[2]));
    return 1;
}

/* Pixel (rounded) of the floor point (fwd, lat); 0 when behind or too
 * near the camera. */
static int project(const negobs_rig_t *rig, const floor_axes_t *a,
                   int32_t fwd_mm, int32_t lat_mm, int32_t *u, int32_t *v)
{
    int32_t uq = 0;
    int32_t vq = 0;
    if (!travel_pixel_q4(rig, a, fwd_mm, lat_mm, &uq, &vq)) {
        return 0;
    }
    *u = (uq + 8) >> 4;
    *v = (vq + 8) >> 4;
    return 1;
}

/* A turn of the camera about the floor's normal between frames, as sine
 * and cosine (Q30) of the angle. */
typedef struct travel_turn {
    int64_t sin_q30;
    int64_t cos_q30;
} travel_turn_t;

/* Pixel of the stored floor point (fwd, lat) after a forward travel of
 * t_mm and the turn: the point moves back by t_mm along the old heading,
 * then the floor frame turns about the camera's foot. Products stay below
 * 2^14 * 2^30 * 2. */
static int project_turned(const negobs_rig_t *rig, const floor_axes_t *a,
                          int32_t fwd_mm, int32_t lat_mm, int32_t t_mm,
                          const travel_turn_t *turn, int32_t *u, int32_t *v)
{
    const int64_t f = (int64_t)fwd_mm - t_mm;
    const int64_t half = (int64_t)1 << 29;
    const int32_t f2 = (int32_t)((f * turn->cos_q30 +
                                  (int64_t)lat_mm * turn->sin_q30 + half) >>
                                 30);
    const int32_t l2 = (int32_t)((-f * turn->sin_q30 +
                                  (int64_t)lat_mm * turn->cos_q30 + half) >>
                                 30);
    return project(rig, a, f2, l2, u, v);
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

/* The largest turn searched between two frames: 3 deg. The trunk and the
 * head sway by a few degrees at the stride's rate (about 0.9 Hz), which
 * turns a camera by up to about 2.3 deg in 100 ms at 4 deg of sway; a
 * faster turn (looking aside) is not measured and counts nothing. Q30
 * radians. */
#define TRAVEL_TURN_MAX_Q30 56220990 /* 3 deg = 0.0523599 rad */
/* The turn's grid: 1.5 px at the image centre (1.5 / f rad). The match
 * holds within about a pixel either way (5 x 5 samples 2 px apart). */
#define TRAVEL_TURN_STEP_NUM 3
#define TRAVEL_TURN_STEP_DEN 2
/* The whole grid is scored on every TRAVEL_TURN_COARSE-th patch first
 * (the cost of a search over turns), the best turn and its neighbours
 * then on all of them. */
#define TRAVEL_TURN_COARSE 4
/* A bound on the grid's cost: 40 steps of 1.5 px reach 3 deg up to
 * f = 1146 px; a longer lens searches a smaller turn. */
#define TRAVEL_TURN_MAX_STEPS 40
/* T steps either side of the coarse best scored on every patch: the coarse
 * and the fine minimum differ by a step now and then. */
#define TRAVEL_FINE_K 2
/* The coarse stage's turns as this many executor jobs of consecutive
 * turns when the executor has workers to run them on (one pass over all
 * turns otherwise). Each job keeps its own pruning bound, so four jobs
 * prune less than one pass (the travel costs 3.45 instead of 2.98 M
 * instructions a frame on the demo walk); the result is the same. */
#define TRAVEL_TURN_JOBS 4

/* Sine and cosine (Q30) of j turn steps of step_q30 rad: third and second
 * order terms, exact to 1e-6 within 3 deg. */
static travel_turn_t turn_of(int32_t j, int64_t step_q30)
{
    travel_turn_t t;
    const int64_t x = (int64_t)j * step_q30;
    const int64_t x2 = (x * x) >> 30;
    t.sin_q30 = x - ((x2 * x) >> 30) / 6;
    t.cos_q30 = ((int64_t)1 << 30) - x2 / 2;
    return t;
}

/* Cost of travel t_mm and turn over the patches idx[0 .. n-1]; the sum
 * stops once it reaches bound (a candidate that costs that much already
 * cannot be the best: the search keeps the first strict minimum). */
static int64_t turned_cost(const travel_track_t *t, const negobs_rig_t *rig,
                           const floor_axes_t *a,
                           const negobs_image_u8_t *left, const int32_t *idx,
                           int32_t n, int32_t t_mm, const travel_turn_t *turn,
                           int64_t bound)
{
    int64_t c = 0;
    int32_t i;
    for (i = 0; i < n && c < bound; i++) {
        const int32_t s = idx[i];
        int32_t u = 0;
        int32_t v = 0;
        if (!project_turned(rig, a, t->fwd_mm[s], t->lat_mm[s], t_mm, turn, &u,
                            &v) ||
            !patch_inside(left, u, v)) {
            c += TRAVEL_WORST_COST; /* left the view at this candidate */
            continue;
        }
        c += patch_cost(t->px[s], left, u, v);
    }
    return c;
}

/* Best travel step within [k_lo, k_hi] of the T grid at one turn; cost[0]
 * (standing still) is exact, cost[k_lo .. k_hi] exact for the best and at
 * least min(cost[best], beat) for the others: beat is the best cost of the
 * turns scanned before (-1: none), which a candidate must undercut to
 * matter. */
static int32_t best_travel(const travel_track_t *t, const negobs_rig_t *rig,
                           const floor_axes_t *a,
                           const negobs_image_u8_t *left, const int32_t *idx,
                           int32_t n, int32_t t_max, const travel_turn_t *turn,
                           int32_t k_lo, int32_t k_hi, int64_t beat,
                           int64_t *cost)
{
    int32_t k;
    int32_t best = 0;
    cost[0] = turned_cost(t, rig, a, left, idx, n, 0, turn, INT64_MAX);
    for (k = (k_lo > 1) ? k_lo : 1; k <= k_hi; k++) {
        const int64_t bound = (beat >= 0 && beat < cost[best]) ? beat
                                                               : cost[best];
        cost[k] = turned_cost(t, rig, a, left, idx, n,
                              t_max * k / TRAVEL_STEPS, turn, bound);
        if (cost[k] < cost[best]) {
            best = k;
        }
    }
    return best;
}

/* The best (turn, T) of one stage of the search, and standing still's
 * least cost over the same turns. */
typedef struct turn_best {
    int64_t cost;
    int64_t still;
    int32_t j; /* turn steps */
    int32_t k; /* T steps    */
} turn_best_t;

/* No candidate scanned yet: no best, no standing still. */
static const turn_best_t TURN_BEST_NONE = {-1, -1, 0, 0};

/* The better of two stages' bests over consecutive turn ranges, a's
 * turns before b's: the first strict minimum in turn order, as one scan
 * over both ranges finds it (a range's best is exact, and its pruned
 * candidates cost at least that range's best: none of them can be a
 * strict minimum over both); standing still's least cost over both. */
static turn_best_t turn_best_merge(turn_best_t a, const turn_best_t *b)
{
    if (b->cost >= 0 && (a.cost < 0 || b->cost < a.cost)) {
        a.cost = b->cost;
        a.j = b->j;
        a.k = b->k;
    }
    if (b->still >= 0 && (a.still < 0 || b->still < a.still)) {
        a.still = b->still;
    }
    return a;
}

/* Turns j_lo .. j_hi, T steps k_lo .. k_hi (and 0), on the patches idx. */
static turn_best_t scan_turns(const travel_track_t *t, const negobs_rig_t *rig,
                              const floor_axes_t *a,
                              const negobs_image_u8_t *left,
                              const int32_t *idx, int32_t n, int32_t t_max,
                              int64_t step_q30, int32_t j_lo, int32_t j_hi,
                              int32_t k_lo, int32_t k_hi)
{
    int64_t cost[TRAVEL_STEPS + 1];
    turn_best_t b = TURN_BEST_NONE;
    int32_t j;
    for (j = j_lo; j <= j_hi; j++) {
        const travel_turn_t turn = turn_of(j, step_q30);
        const int32_t k = best_travel(t, rig, a, left, idx, n, t_max, &turn,
                                      k_lo, k_hi, b.cost, cost);
        const turn_best_t one = {cost[k], cost[0], j, k};
        b = turn_best_merge(b, &one);
    }
    return b;
}

/* measure()'s conditions: the best T inside the grid and away from
 * standing still, at most TRAVEL_CLEAR_NUM / TRAVEL_CLEAR_DEN of standing
 * still's cost. */
static int travel_clear(const turn_best_t *b)
{
    return b->k >= 2 && b->k < TRAVEL_STEPS &&
           b->cost * TRAVEL_CLEAR_DEN <= b->still * TRAVEL_CLEAR_NUM;
}

/* The coarse stage of one frame's search, as executor jobs: job i of
 * n_jobs scans its share of the turns [j_lo, j_hi] (consecutive turns,
 * in order) over every T and writes only res[i]. */
typedef struct turn_pass {
    const travel_track_t *t;
    const negobs_rig_t *rig;
    const floor_axes_t *a;
    const negobs_image_u8_t *left;
    const int32_t *idx;
    int32_t n;
    int32_t t_max;
    int64_t step_q30;
    int32_t j_lo;
    int32_t j_hi;
    int32_t n_jobs; /* 1 .. TRAVEL_TURN_JOBS */
    turn_best_t res[TRAVEL_TURN_JOBS];
    uint8_t done[TRAVEL_TURN_JOBS];
} turn_pass_t;

static void turn_job(void *arg, int32_t job, int32_t worker)
{
    turn_pass_t *tp = (turn_pass_t *)arg;
    const int32_t span = tp->j_hi - tp->j_lo + 1;
    int32_t lo;
    int32_t hi;
    (void)worker;
    if (job < 0 || job >= tp->n_jobs) {
        return;
    }
    lo = tp->j_lo + span * job / tp->n_jobs;
    hi = tp->j_lo + span * (job + 1) / tp->n_jobs - 1;
    if (lo <= hi) {
        tp->res[job] = scan_turns(tp->t, tp->rig, tp->a, tp->left, tp->idx,
                                  tp->n, tp->t_max, tp->step_q30, lo, hi, 1,
                                  TRAVEL_STEPS);
    } else {
        tp->res[job] = TURN_BEST_NONE;
    }
    tp->done[job] = 1;
}

/* Out of line: the call through the caller's executor stays here, where
 * the stack bound's check (tools/negobs, stack_bound) allows it. */
static __attribute__((noinline)) turn_best_t coarse_turns(
    turn_pass_t *tp, const negobs_executor_t *exec)
{
    turn_best_t b = TURN_BEST_NONE;
    const int parallel = exec != NULL && exec->run != NULL &&
                         exec->workers > 1;
    int32_t i;
    tp->n_jobs = parallel ? TRAVEL_TURN_JOBS : 1;
    for (i = 0; i < tp->n_jobs; i++) {
        tp->done[i] = 0;
    }
    if (parallel) {
        exec->run(exec->user, tp->n_jobs, turn_job, tp);
    }
    /* without workers, and any job a faulty executor skipped */
    for (i = 0; i < tp->n_jobs; i++) {
        if (!tp->done[i]) {
            turn_job(tp, i, 0);
        }
        b = turn_best_merge(b, &tp->res[i]);
    }
    return b;
}

/* The travel over the (T, turn) grid: the whole grid on every
 * TRAVEL_TURN_COARSE-th patch, then the best turn and its two neighbours
 * on every patch, within TRAVEL_FINE_K steps of the coarse best T.
 * Counted only when the images show it, on both stages (travel_clear(),
 * standing still taken at the turn that explains it best, so a head
 * turning while the wearer stands still counts nothing), and with the
 * coarse best turn away from the grid's ends (a faster turn is not
 * measured). 0 otherwise. */
static int32_t turn_search(const travel_track_t *t, const negobs_rig_t *rig,
                           const floor_axes_t *a,
                           const negobs_image_u8_t *left, const int32_t *use,
                           int32_t n_use, int32_t t_max,
                           const negobs_executor_t *exec)
{
    int32_t coarse[TRAVEL_SAMPLES];
    /* positive: focal_q4 < 2^31 */
    const int64_t step_q30 = ((int64_t)TRAVEL_TURN_STEP_NUM * 16 << 30) /
                             ((int64_t)TRAVEL_TURN_STEP_DEN *
                              (rig->focal_q4 > 0 ? rig->focal_q4 : 1));
    int32_t n_steps = (int32_t)((TRAVEL_TURN_MAX_Q30 + step_q30 - 1) /
                                step_q30);
    int32_t n_coarse = 0;
    int32_t i;
    turn_pass_t tp;
    turn_best_t b;
    if (n_steps > TRAVEL_TURN_MAX_STEPS) {
        n_steps = TRAVEL_TURN_MAX_STEPS;
    }
    for (i = 0; i < n_use; i += TRAVEL_TURN_COARSE) {
        coarse[n_coarse++] = use[i];
    }
    tp.t = t;
    tp.rig = rig;
    tp.a = a;
    tp.left = left;
    tp.idx = coarse;
    tp.n = n_coarse;
    tp.t_max = t_max;
    tp.step_q30 = step_q30;
    tp.j_lo = -n_steps;
    tp.j_hi = n_steps;
    b = coarse_turns(&tp, exec);
    if (!travel_clear(&b) || b.j <= -n_steps || b.j >= n_steps) {
        return 0;
    }
    b = scan_turns(t, rig, a, left, use, n_use, t_max, step_q30, b.j - 1,
                   b.j + 1, b.k - TRAVEL_FINE_K,
                   (b.k + TRAVEL_FINE_K < TRAVEL_STEPS) ? b.k + TRAVEL_FINE_K
                                                        : TRAVEL_STEPS);
    return travel_clear(&b) ? t_max * b.k / TRAVEL_STEPS : 0;
}

/* The travel the held patches show on this frame, or 0. */
static int32_t measure(const travel_track_t *t, const negobs_rig_t *rig,
                       const floor_axes_t *a, const negobs_image_u8_t *left,
                       int32_t dt_ms, const negobs_executor_t *exec)
{
    int32_t use[TRAVEL_SAMPLES];
    const int32_t t_max = TRAVEL_MAX_MM_PER_S * dt_ms / 1000;
    int32_t n_use = 0;
    int32_t i;
    if (t_max < TRAVEL_STEPS) {
        return 0;
    }
    /* the patches in view at both ends of the grid are in view at every
     * candidate between them (a floor point moves monotonically); a turn
     * moves them by at most a few pixels more */
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
    return turn_search(t, rig, a, left, use, n_use, t_max, exec);
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

/* The travel since the frame whose patches t holds, or 0. */
static int32_t measure_since(const travel_track_t *t, const negobs_rig_t *rig,
                             const floor_axes_t *a,
                             const negobs_image_u8_t *left, uint32_t now_ms,
                             const negobs_executor_t *exec)
{
    const int32_t dt = (int32_t)(now_ms - t->t_ms);
    if (t->n <= 0 || dt <= 0 || dt > TRAVEL_MAX_GAP_MS) {
        return 0;
    }
    return measure(t, rig, a, left, dt, exec);
}

int32_t travel_step(travel_track_t *t, const negobs_rig_t *rig,
                    const negobs_ground_plane_t *plane,
                    const negobs_ground_frame_t *frame,
                    const negobs_image_u8_t *left, uint32_t now_ms,
                    const negobs_executor_t *exec, int32_t *pair_mm)
{
    floor_axes_t a;
    int32_t walked;
    *pair_mm = 0;
    if (left == NULL || left->width != rig->width ||
        left->height != rig->height || !travel_axes_of(frame, &a)) {
        travel_reset(t);
        return 0;
    }
    *pair_mm = measure_since(&t[0], rig, &a, left, now_ms, exec);
    walked = *pair_mm;
    if (t[1].n > 0) {
        /* the last frame's travel was not measured: from the frame before
         * it, the travel of both intervals, or of neither */
        const int32_t held = measure_since(&t[1], rig, &a, left, now_ms, exec);
        walked = (held > 0) ? held : walked;
    }
    if (walked > 0) {
        t[1].n = 0; /* measured up to this frame */
    } else if (t[0].n > 0 && (t[1].n == 0 || (int32_t)(now_ms - t[1].t_ms) >=
                                                 TRAVEL_MAX_GAP_MS)) {
        /* measured up to the last frame at best: hold its patches (a held
         * frame too old to measure from is given up, and its travel with
         * it, as a frame that measures nothing always was) */
        t[1] = t[0];
    }
    sample(&t[0], rig, plane, frame, left);
    t[0].t_ms = now_ms;
    return walked;
}
