/*
 * Internal interface of the detector (lib/src/detect/detect_*.c): the
 * state carved from the workspace, the per-frame scan context and the
 * steps one negobs_detect_process() call runs, one file each:
 *
 *   detect_config.c  config defaults, presets, checks, workspace, init
 *   detect_gate.c    photometric image gate
 *   detect_fill.c    rectification fill: the columns out of view
 *   detect_scan.c    per-strip scan (the rule of docs/DETECTION.md 5)
 *   detect_unit.c    a drop's depth over one pixel of floor (section 5)
 *   detect_noise.c   measured strip-median noise per band (step 6)
 *   detect_vouch.c   the vouched range and the verdict (section 10)
 *   detect_merge.c   strips -> hazards
 *   detect_cue.c     ground-drop cue (section 6.1)
 *   detect_travel.c  travel along the floor: a start verified by walking
 *   detect_sight.c   recent candidates bound the vouched range
 *   detect_near.c    the floor nearer than the view, vouched earlier
 *   detect_pool.c    frames pooled along the measured travel
 *   detect.c         negobs_detect_process: the sequence of the above
 */
#ifndef NEGOBS_DETECT_INTERNAL_H
#define NEGOBS_DETECT_INTERNAL_H

#include <string.h>

#include "negobs/detect.h"
#include "negobs/stereo.h" /* the confidence scale of the disparity map */

#include "arena.h"
#include "disp_canny.h"
#include "geom_internal.h"
#include "ground_fit.h"
#include "mount.h"
#include "temporal.h"
#include "detect_int.h"
#include "detect_travel.h"

#define DETECT_MAGIC 0x4E474454u /* "NGDT" */
#define MAX_STRIP_PX 64

/* Median of n (1..MAX_STRIP_PX) values, times 2 (the two middle values
 * summed for even n), so no precision is lost: a strip row's vote. Sorts
 * x in place (insertion sort: n is small). */
static inline int32_t det_median2_s32(int32_t *x, int32_t n)
{
    int32_t i;
    for (i = 1; i < n; i++) {
        int32_t t = x[i];
        int32_t j = i - 1;
        while (j >= 0 && x[j] > t) {
            x[j + 1] = x[j];
            j--;
        }
        x[j + 1] = t;
    }
    return (n & 1) ? 2 * x[n / 2] : x[n / 2 - 1] + x[n / 2];
}

/* Frames of candidate sightings kept (detect_sight.c): confirm_n is at
 * most 31, and a sighting counts for confirm_n - 1 frames after its own. */
#define SIGHT_FRAMES 32

enum row_class {
    ROW_INVALID = 0,
    ROW_GROUND,
    ROW_DEFICIT,
    ROW_POSITIVE,
    ROW_MIXED
};

typedef struct strip_hit {
    int32_t found;
    negobs_hazard_type_t type;
    int32_t u0;
    int32_t u1;
    int32_t edge_v; /* last ground row (bottom of the box)         */
    int32_t top_v;  /* farthest row examined for this hazard       */
    int32_t range_mm;
    int32_t lateral_mm;
    int32_t depth_mm;
    int32_t drop_mm;
    int32_t h_lower;
    int32_t textured;  /* missing ground: 1 textured band, 0 bland/unknown */
    int32_t margin_q8; /* mean deficit / tau, Q8                     */
    int32_t rho1_q15;  /* relative deficit of the first plateau       */
    /* the drop over one whole pixel of floor disparity past the edge
     * (detect_unit.c, det_unit_drop_mm), mm; -1: not measured (missing
     * ground, or the pixel runs out of the scan) */
    int32_t unit_drop_mm;
    int32_t reported; /* part of a candidate of this frame           */
    /* det_strip_noise: where a wall or up-step closes the strip (the foot of
     * its rise; rows at or above it are not measured), or -1; the run of
     * rows far above the ground so far */
    int32_t blocked_v;
    int32_t pos_run;
    /* 1 when the closure at blocked_v is an obstacle that bars the lane:
     * a face at least BAR_H_MM high standing at its foot
     * (det_closure_bars); the walker meets it before any floor beyond */
    int32_t bars;
    /* vouch: farthest row the strip's support reaches from the bottom
     * (an unseen run or a closure ends it) */
    int32_t sup_v;
    /* det_strip_occluder: rows at or below it are covered by a near
     * occluder (out of view); rig.height when none */
    int32_t occl_v;
} strip_hit_t;

/* A strip is closed by a positive obstacle after this many consecutive
 * rows whose strip median is at least BLOCK_MIN_Q5 (1/32 px) and 3 times
 * the row's per-pixel sigma above the ground model. */
#define BLOCK_ROWS 4
#define BLOCK_MIN_Q5 32
/* A closure bars the lane (docs/DETECTION.md 10.2, "Barred lanes") when
 * BLOCK_ROWS strip rows above its foot show points at least BAR_H_MM above
 * the floor within BAR_RUN_MM of the foot's floor distance. 400 mm is twice
 * the highest stair riser or curb (200 mm): an obstacle that high is walked
 * around, not stepped onto, so no floor beyond it is reached through it.
 * 200 mm of run for 400 mm of rise is a face steeper than 63 deg, steeper
 * than any stair (<= 45 deg) or ramp, which are walked onto. */
#define BAR_H_MM 400
#define BAR_RUN_MM 200

/* det_strip_row_e's memo (detect_priv_t.row_e): not asked yet, and asked
 * with no value (outside the corridor or too few voting pixels). A value
 * that does not fit the int16 left beside them (only a wild map's) is
 * not kept: it is worked out again at each ask, so the memo never
 * changes an answer. */
#define ROW_E_UNSET (-32768)
#define ROW_E_NONE (-32767)

/*
 * The minimum drop of the definitions: 5 cm within 1.5 m, 10 cm beyond.
 * Fixed here, not configured: a preset may make the rule more sensitive,
 * but never changes what counts as a false vouch (detect_vouch.c,
 * detect_near.c).
 */
#define VOUCH_H_NEAR_MM 50
#define VOUCH_H_FAR_MM 100
#define VOUCH_NEAR_RANGE_MM 1500

/* The smallest deficit below the ground model (1/16 px) the rule counts
 * and the vouch relies on. The matcher's sub-pixel parabola errs with the
 * fraction of the disparity (pixel locking): a ripple fixed in the image,
 * the same along each row, measured at -0.038 to +0.009 px on the
 * full-size map and +-0.02-0.05 px where the half-size pass's values
 * replace it, plus the 1/32 px of rounding to 1/16. Along a row that is
 * a deficit of one sixteenth passed by every pixel at once, which is
 * what the rule counts: on a 3 cm rig (f = 380 px, 1.7 m) the 40 mm near
 * threshold at 2 m is 1.6/16 px, and flat asphalt read as 2-5 cm holes
 * there, held IMMINENT. Two sixteenths (0.125 px) is 2.5 times the
 * ripple. Where a drop's deficit is below it, the rule's threshold is
 * this deficit's height (a higher one), and the vouch does not claim the
 * drop would show (docs/DETECTION.md 5, "The rig's resolution"). */
#define DEFICIT_MIN_Q4 2

/* One following of the floor nearer than the view (detect_near.c): its
 * state, the vouched floor ahead of the feet (lower bound), the far end of
 * unvouched floor (upper bound) and the floor vouched beyond it (lower
 * bound), in mm ahead of the feet. */
typedef struct near_track {
    int32_t state;
    int32_t ahead_mm;
    int32_t gap_mm;
    int32_t beyond_mm;
} near_track_t;

#define NOISE_BANDS 8
#define NOISE_BINS 64
/* Signed strip-median residuals, 1/32 px bins centred on 0: +-2 px. */
#define STRIP_BINS 128

/* Local noise of one strip in one band of rows (vouch.c's cells): the
 * strip-median residuals e (1/32 px) of its seen rows. */
typedef struct vouch_cell {
    int32_t n;       /* seen strip rows                                 */
    int32_t sum;     /* sum of e                                        */
    int32_t sum_abs; /* sum of |e - the cell's own mean|               */
} vouch_cell_t;

typedef struct detect_priv {
    uint32_t magic;
    gfit_t gfit;
    temporal_t temporal;
    strip_hit_t *hits;
    int32_t n_strips;
    uint32_t *band_hist;    /* NOISE_BANDS x NOISE_BINS |horizontal diff| */
    uint16_t *strip_hist;   /* NOISE_BANDS x STRIP_BINS strip medians    */
    dcanny_scratch_t canny; /* disparity Canny around a hazard's edge  */
    vouch_cell_t *cells;    /* n_strips x NOISE_BANDS local-noise cells   */
    int32_t *reach_v;       /* per strip: farthest row vouched from the
                             bottom without a break (height: none)      */
    /* det_strip_row_e's answers this frame, height x n_strips (row v,
     * strip si at v * n_strips + si; ROW_E_UNSET: not asked yet). The
     * noise and the vouch read each corridor row of each strip two to
     * four times, and its median is the detector's costliest sum. */
    int16_t *row_e;
    /* ground-drop cue: the camera height and pitch over the ground under
     * the feet, followed on clean frames only */
    int32_t ref_ok;
    int32_t ref_by;    /* negobs_ground_ref_by_t of the reference      */
    int32_t verify_by; /* how ground_unverified() last verified a frame */
    int32_t ref_height_mm;
    int32_t ref_pitch_mdeg;
    uint32_t drop_since_ms; /* first frame of the current cue           */
    int32_t drop_on;
    /* before the reference: first frame whose ground lay
     * ground_verify_mm or more below the configured height */
    uint32_t unverified_since_ms;
    int32_t unverified_on;
    /* before the reference: the travel along the floor since the first
     * frame (detect_travel.c), and the travel that verifies the start:
     * the nearest floor in view on that frame plus WALK_MARGIN_MM
     * (detect_cue.c) */
    travel_track_t *travel; /* TRAVEL_TRACKS; carved: 4 KiB, and the carve
                               measures on a descriptor on the stack */
    /* this frame's measured travel, 0: none; since the frame up to which
     * it was last measured (travel_step) */
    int32_t travel_mm;
    /* since the last frame alone, the pooling's, also measured for it */
    int32_t pool_travel_mm;
    int32_t walk_on;
    int32_t walk_verified; /* this frame was verified by the walk */
    int32_t walk_fits;     /* fits of the walk, and their sums          */
    int64_t walk_height_sum;
    int64_t walk_pitch_sum;
    int32_t walked_mm;
    int32_t walk_need_mm;
    /* before the reference: the lowest fit height of the last
     * ground_drop_max_ms, and the last frame whose fit stood
     * ground_drop_mm or more above it (detect_cue.c, ground_risen) */
    int32_t low_on;
    int32_t low_height_mm;
    uint32_t low_ms;
    int32_t risen_on;
    uint32_t risen_ms;
    /* this frame's ground awaits the start check with a fit that rose
     * (ground_risen): its candidates are not trusted (detect.c) */
    int32_t fit_risen;
    /* last clean frame with a rule candidate within h_near_range_mm: it
     * corroborates a smaller ground-drop rise for hold_ms */
    uint32_t near_cand_ms;
    int32_t near_cand_on;
    mount_track_t mount; /* the mounting the results report (mount.c) */
    /* slow track of the fitted camera height, 0: no fit yet (det_fit_fell):
     * follows a rise within a few frames, a fall over about 1.5 s */
    int32_t slow_fit_height_mm;
    int32_t slow_fit_pitch_mdeg; /* the same track of the fitted pitch */
    /* row profiles of the left image (det_fit_fell): the last frame with a
     * fit and its pitch, and this frame's scratch; height entries each */
    int32_t *row_prof;
    int32_t *row_prof_cur;
    int32_t row_prof_ok;
    int32_t row_prof_pitch_mdeg;
    /* per row: the columns of the left / right image in the field of view
     * [u0, u1) (detect_fill.c); height entries each */
    int16_t *view_l_u0;
    int16_t *view_l_u1;
    int16_t *view_r_u0;
    int16_t *view_r_u1;
    int32_t view_l_held; /* the left view arrays hold an earlier frame's */
    int32_t view_r_held;
    int16_t *fill_u0; /* scratch: this frame's fill of one image       */
    int16_t *fill_u1;
    /* the nearest candidate of each of the last frames, newest at
     * sight_head - 1 (detect_sight.c); INT32_MAX: none that frame */
    int32_t sight_range_mm[SIGHT_FRAMES];
    uint32_t sight_ms[SIGHT_FRAMES];
    int32_t sight_head;
    int32_t sight_n;
    /* the floor nearer than the view (detect_near.c): whether it is
     * followed, the last frame's time, and its two followings */
    int32_t near_on;
    uint32_t near_ms;
    /* followed twice: the floor vouched for the minimum drop of its range
     * (near_any), and the floor vouched for 5 cm (near_5cm), which is
     * what the floor within VOUCH_NEAR_RANGE_MM of the feet needs */
    near_track_t near_any;
    near_track_t near_5cm;
    /* the same two followings over the frames whose ground awaits the
     * start check, with what each would vouch once it passes; the two
     * above take them over on the frame they start (detect_near.c) */
    near_track_t pend_any;
    near_track_t pend_5cm;
    /* frames pooled along the travel (detect_pool.c); pool_out NULL when
     * pool_frames is 1. Two histories, width x height each (rho Q14 with
     * the count in its low bits; pool_cur: this frame's), the pooled
     * map's pixels, per row the nodes' previous-frame pixels (q4, u and
     * v), the last pooled frame's floor and whether there is one. */
    int16_t *pool_hist[2];
    int16_t *pool_out;
    int32_t *pool_node; /* NEGOBS_DETECT_POOL_BANDS rows of nodes */
    int32_t pool_cnt[NEGOBS_DETECT_POOL_BANDS][2]; /* valid, pooled */
    uint8_t pool_done[NEGOBS_DETECT_POOL_BANDS];   /* this frame's */
    negobs_executor_t exec; /* run NULL: the bands in order, here */
    negobs_image_s16_t pool_img;
    int32_t pool_cur;
    int32_t pool_have;
    uint32_t pool_ms;       /* the last pooled frame's time */
    int32_t pool_pace_mm_s; /* the last measured travel's speed, 0: none */
    uint32_t pool_pace_ms;  /* when it was measured */
    negobs_ground_frame_t pool_frame;
    negobs_ground_pose_t pool_pose;
} detect_priv_t;

/* Scan context shared by the strips of one frame. */
typedef struct scan_ctx {
    const negobs_detect_config_t *cfg;
    const negobs_image_s16_t *disp;
    const negobs_image_u8_t *conf;
    const negobs_image_u8_t *left; /* NULL: no texture check */
    /* per row: columns in the field of view of the left and the right image
     * [u0, u1) (detect_priv_t) */
    const int16_t *view_l_u0;
    const int16_t *view_l_u1;
    const int16_t *view_r_u0;
    const int16_t *view_r_u1;
    const negobs_ground_plane_t *plane;
    const negobs_ground_frame_t *frame;
    int32_t sigma_q4;
    int32_t d_min_q4;  /* ground disparity at range_max */
    int32_t d_top_q4;  /* largest disparity measured: max_disp - 1 px */
    int32_t band_v0;   /* first row of the noise bands    */
    int32_t band_rows; /* rows per band (>= 1)            */
    int32_t band_sigma_q4[NOISE_BANDS];
    /* Measured spread and offset of the strip median (1/256 px), per
     * band pooled with the next nearer one; spread 0: too few strip rows
     * (det_strip_noise). */
    int32_t band_strip_q8[NOISE_BANDS];
    int32_t band_bias_q8[NOISE_BANDS];
    /* 1: the vouched walk looks for 5 cm drops at every range and ends
     * where the rule cannot see one (det_vouch_walk_5cm) */
    int32_t vouch_5cm;
} scan_ctx_t;

/* detect_texture.c: whether a box holds texture above the image's noise
 * (det_noise_median, det_window_textured in detect_int.h). */
int det_box_textured(const negobs_image_u8_t *img, int32_t noise_med,
                     int32_t u0, int32_t v0, int32_t u1, int32_t v1);
/* 1 when at least half of the box's windows hold one and a half times
 * the noise variance (and horizontal structure): grain below
 * det_box_textured's signal-to-noise of 3, but grain, not a bland box. */
int det_box_weak_textured(const negobs_image_u8_t *img, int32_t noise_med,
                          int32_t u0, int32_t v0, int32_t u1, int32_t v1);
/* 1 when some run of `run` adjacent strips among hits[k0..k1-1] holds
 * texture by det_box_textured's test, each strip over its own rows: a
 * hazard merged from strips at several ranges spans the rows of all of
 * them, and its box may be bland where a part of it that alone would be
 * a hazard is not. */
int det_run_textured(const negobs_image_u8_t *img, int32_t noise_med,
                     const strip_hit_t *hits, int32_t k0, int32_t k1,
                     int32_t run);
/* 1 when at least half of the box's pixels with a value carry the value of
 * the half-size map (doubled): the map there is the half-resolution
 * pass's measurement, so its texture is judged at that scale. */
int det_box_from_half(const negobs_image_s16_t *disp,
                      const negobs_image_s16_t *disp_half, int32_t u0,
                      int32_t v0, int32_t u1, int32_t v1);
uint32_t det_photo_reasons(const negobs_detect_config_t *cfg,
                           const negobs_photo_stats_t *s);

int32_t det_sigma_at(const scan_ctx_t *s, int32_t v);

/* Rows v_top.. v_end - 1 are read (v_end: below them the floor lies
 * beyond the matcher's range); the bands span v_top to the bottom row. */
void det_band_noise(scan_ctx_t *s, uint32_t *hist, int32_t v_top,
                    int32_t v_end);

void det_model_point(const scan_ctx_t *s, int32_t u, int32_t v, int32_t dg_q4,
                     int32_t *range_mm, int32_t *lat_mm, int32_t *depth_mm);

int det_in_corridor(const scan_ctx_t *s, int32_t uc, int32_t dg_q4);

int det_in_view(const scan_ctx_t *s, int32_t uc, int32_t v, int32_t dg_q4);
int32_t det_range_row(const scan_ctx_t *s, int32_t uc);

int32_t det_strip_u0(const negobs_detect_config_t *cfg, int32_t n_strips,
                     int32_t si);

int det_strip_in_corridor(const scan_ctx_t *s, int32_t n_strips, int32_t si,
                          int32_t v);

int det_strip_in_walk(const scan_ctx_t *s, int32_t n_strips, int32_t si,
                      int32_t v);

void det_scan_strip(const scan_ctx_t *s, int32_t u0, int32_t u1,
                    strip_hit_t *hit);

/* The drop (mm) past edge_v over the rows where the ground disparity falls
 * by one whole pixel, from the strip's row medians (detect_unit.c); -1 when
 * that pixel runs out of the scan or too few of its rows vote. */
int32_t det_unit_drop_mm(const scan_ctx_t *s, int32_t u0, int32_t u1,
                         int32_t edge_v);

int32_t det_strip_occluder(const scan_ctx_t *s, int32_t u0, int32_t u1);

/* The strip-median residual of strip si on row v inside the corridor
 * (detect_noise.c, strip_row_e), memoised in p->row_e: valid from
 * det_strip_noise, which clears the memo, to the end of the vouch, while
 * the strips' candidates (reported, edge_v, rho1_q15) stay fixed. */
int det_strip_row_e(const scan_ctx_t *s, const detect_priv_t *p, int32_t v,
                    int32_t si, int32_t *rr, int32_t *e_out);

void det_strip_noise(scan_ctx_t *s, detect_priv_t *p, uint16_t *hist);

int32_t det_strip_sigma_at(const scan_ctx_t *s, int32_t v, int32_t *offset_q8);

void det_vouch_collect(const scan_ctx_t *s, detect_priv_t *p);

int32_t det_vouch_walk(const scan_ctx_t *s, detect_priv_t *p,
                       int32_t first_row, int candidates, uint32_t *cause,
                       int32_t *barred);

/* The vouched walk for 5 cm drops beyond VOUCH_NEAR_RANGE_MM too, as far
 * as the rule can see one (h_near_range_mm): the floor distance it
 * reaches, at most walk_to (det_vouch_walk's result, which it equals when
 * that lies within VOUCH_NEAR_RANGE_MM). Leaves p->reach_v alone. */
int32_t det_vouch_walk_5cm(const scan_ctx_t *s, detect_priv_t *p,
                           int32_t first_row, int candidates, int32_t walk_to);

int det_vouch_candidate(const scan_ctx_t *s, const detect_priv_t *p,
                        const negobs_hazard_t *hz);

void det_verdict(const negobs_detect_config_t *cfg,
                 negobs_detect_result_t *res, uint32_t reasons,
                 int32_t walk_to, uint32_t walk_cause, int32_t sight_mm);

/* The range det_verdict vouches on a frame without a degraded reason:
 * the vouched walk cut at sight_mm, this frame's candidates and its
 * reported hazards. */
int32_t det_vouch_cut(const negobs_detect_result_t *res, int32_t walk_to,
                      int32_t sight_mm);

void det_merge_strips(const scan_ctx_t *s, detect_priv_t *p,
                      negobs_detect_result_t *res);

int32_t det_sight_bound(const detect_priv_t *p,
                        const negobs_detect_config_t *cfg, uint32_t now_ms);

void det_sight_note(detect_priv_t *p, const negobs_detect_result_t *res,
                    uint32_t now_ms);

/* Follow the floor nearer than the view (detect_near.c) with this
 * frame's nearest floor in view (seen_mm, 0: no ground model), its
 * vouched range, the part of it vouched for 5 cm drops (vouched_5cm_mm),
 * its measured travel, and whether its ground passed the start check
 * (start_ok: a model, verified, the image usable); 0 when some of that
 * floor was never vouched while in view for the minimum drop it will
 * have to be clear of (5 cm within VOUCH_NEAR_RANGE_MM of the feet) and
 * has not been walked over. pending_mm: on a frame whose usable ground
 * only awaits the start check, the range it would vouch once the check
 * passes (0: nothing); -1 on any other frame. */
int det_near_follow(detect_priv_t *p, const negobs_detect_config_t *cfg,
                    int32_t seen_mm, int32_t vouched_mm,
                    int32_t vouched_5cm_mm, int32_t pending_mm,
                    int32_t travel_mm, int start_ok, uint32_t now_ms);

/* The start check begins again (a fit that rose: the floor under the
 * feet may have changed): the frames awaiting it are followed anew from
 * the next one's view. */
void det_near_pending_restart(detect_priv_t *p);

/* 1 while det_near_follow holds unvouched floor ahead: the travel is
 * measured to know when it has been walked over. */
int det_near_gap(const detect_priv_t *p);

void det_near_candidate_note(detect_priv_t *p,
                             const negobs_detect_config_t *cfg,
                             const negobs_detect_result_t *res,
                             uint32_t now_ms);

/* This frame's travel along the floor (detect_travel.c) into
 * p->travel_mm, and into the tracks' odometer, while a start is to be
 * verified or a track is confirmed. Only a fit of the bottom band is
 * walked on: a wide fit's plane is extrapolated under the view. */
void det_travel_follow(detect_priv_t *p, const negobs_detect_config_t *cfg,
                       const gfit_out_t *g, const negobs_image_u8_t *left,
                       uint32_t now_ms);

/* Nodes per row of the pooling's floor mapping (detect_pool.c). */
int32_t det_pool_nodes(int32_t width);

/* This frame's map pooled with the last pooled frame's (detect_pool.c)
 * on ticks with a measured travel, the map itself otherwise (and when
 * pool_frames is 1), and the share of its values pooled. The result is
 * valid until the next call. */
const negobs_image_s16_t *det_pool_frame(detect_priv_t *p,
                                         const negobs_detect_config_t *cfg,
                                         const negobs_image_s16_t *disp,
                                         const gfit_out_t *g, int tick,
                                         int32_t travel_mm, uint32_t now_ms,
                                         int32_t *pooled_permille);

/* This frame's fit was found wrong after the scan (no fit, or one that
 * fell onto a lower level): the next frame pools nothing with it. */
void det_pool_distrust(detect_priv_t *p);

int det_ground_drop(detect_priv_t *p, const negobs_detect_config_t *cfg,
                    const scan_ctx_t *s, const gfit_out_t *g, uint32_t now_ms,
                    negobs_hazard_t *hz, int *unverified);

void det_ground_ref_follow(detect_priv_t *p, const negobs_detect_config_t *cfg,
                           const gfit_out_t *g, int unverified);

int det_fit_fell(detect_priv_t *p, const negobs_detect_config_t *cfg,
                 const gfit_out_t *g, const negobs_image_u8_t *left);

#endif /* NEGOBS_DETECT_INTERNAL_H */
