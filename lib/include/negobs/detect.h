/*
 * Negative-obstacle detection (paper steps 7, 9, 10 and beyond).
 *
 * Per frame: validity gating -> ground model (v-disparity Hough, plane
 * refinement, tracking, noise estimate) -> per-strip signed-residual scan
 * from near to far inside the walking corridor -> hazards (type, range,
 * bearing, drop height, box, confidence) -> temporal confirmation, clearing
 * and hold. A runtime calls
 *
 *     negobs_stereo_process() -> negobs_detect_process() -> negobs_alert_update()
 *
 * All arithmetic is integer; see docs/DETECTION.md for formulas, formats and
 * every parameter.
 */
#ifndef NEGOBS_DETECT_H
#define NEGOBS_DETECT_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/depth.h"
#include "negobs/executor.h"
#include "negobs/fixed.h"
#include "negobs/ground.h"
#include "negobs/image.h"
#include "negobs/status.h"
#include "negobs/verdict.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Hazards reported per frame (bounded; nearest are kept). */
#ifndef NEGOBS_DETECT_MAX_HAZARDS
#define NEGOBS_DETECT_MAX_HAZARDS 8
#endif
/** Hazard tracks kept by the temporal logic. */
#ifndef NEGOBS_DETECT_MAX_TRACKS
#define NEGOBS_DETECT_MAX_TRACKS 8
#endif

/** Row bands of the pooled frames' pass (negobs_detect_set_executor):
 * a fixed layout, bottom band first (the most floor, the costliest). */
#define NEGOBS_DETECT_POOL_BANDS 8

/**
 * Upper bound of negobs_detect_workspace_size() as a constant expression,
 * for static buffers: any valid config with this width, height and
 * max_disp_q4 <= 16 * max_disp_px fits. (Context, tracks and the travel
 * patches < 8 KiB, v-disparity histogram <= h x (2 max_disp + 2) x 2 bytes,
 * Hough 16 KiB,
 * strips <= w/4 x (64 + 112) bytes (scan state, local-noise cells),
 * their row medians' memo <= w/4 x h x 2 bytes, noise bands 2 + 2 KiB,
 * the disparity Canny window 3 x w x 2 + 16 x w bytes, two row profiles
 * h x 8 bytes, pooled frames (pool_frames > 1) w x h x 6 bytes and
 * (w / 8 + 2) x 8 bytes of nodes for each of its
 * NEGOBS_DETECT_POOL_BANDS row bands, plus arena guards.)
 */
#define NEGOBS_DETECT_WORKSPACE_MAX(w, h, max_disp_px)                        \
    ((size_t)8192u +                                                          \
     (size_t)(h) * ((size_t)(max_disp_px)*2u + 2u + 4u) * 2u +                \
     (size_t)16640u + ((size_t)(w) / 4u + 1u) * (176u + (size_t)(h)*2u) +     \
     (size_t)(w)*22u + (size_t)(w) * (size_t)(h)*6u +                         \
     ((size_t)(w) / 8u + 2u) * 8u * (size_t)NEGOBS_DETECT_POOL_BANDS +        \
     (size_t)4608u + (size_t)256u)

/** Why the detector cannot vouch for "no hazard" (bitmask). */
typedef enum negobs_degraded_reason {
    NEGOBS_DEGRADED_TOO_DARK = 1u << 0,        /**< mean/dark share       */
    NEGOBS_DEGRADED_SATURATED = 1u << 1,       /**< blown-out share       */
    NEGOBS_DEGRADED_LOW_TEXTURE = 1u << 2,     /**< mean gradient too low */
    NEGOBS_DEGRADED_FEW_GROUND = 1u << 3,      /**< valid ground pixels, or
                                                 support ends the vouched
                                                 range under near_min_mm */
    NEGOBS_DEGRADED_GROUND_REJECTED = 1u << 4, /**< no planar support,
                                                 not a floor (priors), or
                                                 a fit ground_drop_mm below
                                                 the previous frame's */
    NEGOBS_DEGRADED_STALE = 1u << 5,           /**< frame too old / gap   */
    NEGOBS_DEGRADED_UNSYNCED = 1u << 6,        /**< L/R timestamps apart  */
    NEGOBS_DEGRADED_NOISY = 1u << 7,     /**< local noise ends the vouched
                                                 range under near_min_mm */
    NEGOBS_DEGRADED_BAD_INPUT = 1u << 8, /**< missing/unusable frame */
    /** No reference yet for the ground under the feet, and the camera
     *  height fitted to the ground in view differs from the height hint
     *  by ground_verify_mm or more (or there is no hint): an edge nearer
     *  than the view, or a wrong hint (at most ground_drop_max_ms after
     *  the first ground model) */
    NEGOBS_DEGRADED_GROUND_UNVERIFIED = 1u << 9,
    /** Floor now nearer than the view was never vouched while it was in
     *  view (an unconfirmed drop, a dark or untextured stretch; within
     *  1.5 m of the feet, never vouched for 5 cm drops) and has not been
     *  walked over yet: nothing is vouched from the feet
     *  (docs/DETECTION.md, "The floor under the view") */
    NEGOBS_DEGRADED_NEAR_UNSEEN = 1u << 10
} negobs_degraded_reason_t;

typedef enum negobs_hazard_type {
    NEGOBS_HAZARD_UNKNOWN = 0, /**< missing ground only               */
    NEGOBS_HAZARD_DROP = 1,    /**< curb / drop-off: one deficit       */
    NEGOBS_HAZARD_STAIRS = 2,  /**< >= 2 successive deficits           */
    NEGOBS_HAZARD_HOLE = 3     /**< deficit, then ground/far wall again */
} negobs_hazard_type_t;

typedef enum negobs_missing_policy {
    NEGOBS_MISSING_IGNORE = 0,
    NEGOBS_MISSING_CAUTION = 1, /**< default: may raise CAUTION only  */
    NEGOBS_MISSING_DANGER = 2,  /**< treated like a drop              */
    /** A band whose left image is textured (NEGOBS_HAZARD_F_TEXTURED) is
     *  treated like a drop, a bland one (or without a left image) may
     *  raise CAUTION only. */
    NEGOBS_MISSING_TEXTURED = 3
} negobs_missing_policy_t;

typedef enum negobs_sensitivity {
    NEGOBS_SENS_SENSITIVE = 0,
    NEGOBS_SENS_BALANCED = 1,
    NEGOBS_SENS_CONSERVATIVE = 2
} negobs_sensitivity_t;

/** Hazard flags. */
#define NEGOBS_HAZARD_F_CONFIRMED 1u /**< passed k-of-n confirmation      */
#define NEGOBS_HAZARD_F_HELD 2u      /**< below the image: dead-reckoned  */
#define NEGOBS_HAZARD_F_H_LOWER 4u   /**< drop_mm is a lower bound        */
#define NEGOBS_HAZARD_F_CANNY 8u     /**< disparity edges support it      */
/** From the ground model alone: the ground in view lies drop_mm lower
 *  than the ground under the feet, so an edge is nearer than the view's
 *  bottom (range_mm, an upper bound); the edge itself is not seen. */
#define NEGOBS_HAZARD_F_GROUND_DROP 16u
/** Missing ground (type UNKNOWN) over a band whose left image has at least
 *  half the texture of the matched ground before it: the matcher failed
 *  where it should have matched, an occlusion / drop cue. Without it the
 *  band is bland (or no left image was given): "unknown". */
#define NEGOBS_HAZARD_F_TEXTURED 32u
/** A measured drop whose strips' mean depth over one whole pixel of
 *  floor disparity past the edge stays below both the rule's height there
 *  and half of the plateau they read: its plateau may be the matcher's
 *  sub-pixel ripple, which alternates in sign over such a pixel. It cuts
 *  the vouched range as any candidate, but never confirms a track by its
 *  depth (docs/DETECTION.md 5, "One pixel of floor"). */
#define NEGOBS_HAZARD_F_UNIT_SHALLOW 64u

/** One hazard (a candidate of this frame or a temporal track). */
typedef struct negobs_hazard {
    negobs_hazard_type_t type;
    negobs_alert_level_t level; /**< urgency (tracks only)            */
    uint32_t flags;             /**< NEGOBS_HAZARD_F_*                */
    uint32_t track_id;          /**< 0 for raw candidates             */
    int32_t range_mm;           /**< forward floor distance to the edge (mm) */
    int32_t lateral_mm;         /**< floor offset, right > 0 (mm)          */
    int32_t bearing_mdeg;       /**< atan2(lateral, range), right > 0      */
    int32_t depth_mm;           /**< camera depth Z of the edge point (mm) */
    int32_t drop_mm;            /**< H*(d_ground/d_far - 1) (mm)           */
    int16_t u0, v0, u1, v1;     /**< image box, inclusive (pixels)        */
    int16_t conf_q15;           /**< confidence 0..32767                   */
    int16_t strips;             /**< column strips that agreed             */
    int32_t edge_angle_mdeg;    /**< edge direction against the lateral
                                  axis: 0 = square across the path,
                                  > 0 = nearer on the left (mdeg)      */
} negobs_hazard_t;

/** Photometric statistics of one image (from negobs_detect_photo_stats). */
typedef struct negobs_photo_stats {
    int32_t mean;               /**< mean grey level 0..255            */
    int32_t dark_permille;      /**< share of pixels <= 8              */
    int32_t saturated_permille; /**< share of pixels >= 250            */
    int32_t texture_q4;         /**< mean |horizontal gradient|, 1/16  */
} negobs_photo_stats_t;

/** Where the camera mounting used by a frame came from. */
typedef enum negobs_mount_source {
    NEGOBS_MOUNT_CONFIG = 0,    /**< nothing measured yet: the hint       */
    NEGOBS_MOUNT_ESTIMATED = 1, /**< measured on this frame's floor       */
    NEGOBS_MOUNT_HELD = 2       /**< this frame could not measure: the
                                     last estimate, held                 */
} negobs_mount_source_t;

/** How the ground under the feet (the reference of the ground-drop cue,
 *  docs/DETECTION.md 6.1) was established. Only the first three are
 *  evidence that the floor in view is the floor under the feet; a
 *  mounting remembered across switch-ons must come from one of them. */
typedef enum negobs_ground_ref_by {
    NEGOBS_GROUND_REF_NONE = 0, /**< not yet: the start is unverified   */
    NEGOBS_GROUND_REF_HINT = 1, /**< the fit agreed with cam_height_mm   */
    NEGOBS_GROUND_REF_FEET = 2, /**< the view reached the feet           */
    NEGOBS_GROUND_REF_WALK = 3, /**< verified by walking (6.2)           */
    NEGOBS_GROUND_REF_TIME = 4  /**< taken as it is after
                                      ground_drop_max_ms without proof (or
                                      a raised camera accepted): not
                                      evidence                          */
} negobs_ground_ref_by_t;

/** Camera mounting over the floor, as used by one frame. */
typedef struct negobs_mount {
    int32_t height_mm;  /**< camera centre above the floor (mm)        */
    int32_t pitch_mdeg; /**< optical axis below horizontal (mdeg)      */
    int32_t roll_mdeg;  /**< roll (mdeg), > 0: floor nearer on right   */
    int32_t source;     /**< negobs_mount_source_t                     */
} negobs_mount_t;

/** Configuration. Zero it, call negobs_detect_config_default(). */
typedef struct negobs_detect_config {
    negobs_rig_t rig; /**< intrinsics (see negobs_rig_t)   */
    /* Mounting: measured from the floor every frame (docs/DETECTION.md,
     * "Mounting estimate"). The configured height and pitch are hints,
     * never gates: a fit is rejected only outside the physical priors. */
    int32_t cam_height_mm;         /**< height hint (default 1200 mm; 0 = no
                                    hint: every start is verified by
                                    time, see ground_verify_mm)         */
    int32_t cam_pitch_mdeg;        /**< pitch hint (default 20000 mdeg),
                                    reported until a fit measures it   */
    int32_t mount_height_min_mm;   /**< prior: lowest camera (600 mm)    */
    int32_t mount_height_max_mm;   /**< prior: highest camera (2000 mm)  */
    int32_t mount_pitch_min_mdeg;  /**< prior: least pitch down (0)      */
    int32_t mount_pitch_max_mdeg;  /**< prior: most pitch down (60000)   */
    int32_t mount_roll_max_mdeg;   /**< prior: largest |roll| (20000)    */
    int32_t mount_gain_q15;        /**< slow height/roll track gain per
                                    measuring frame (default 2048 =
                                    1/16, ~1.6 s at 10 fps)             */
    int32_t mount_reacquire_ms;    /**< no measurement for this long: the
                                    next fits re-acquire the mounting
                                    from scratch (default 2000 ms)      */
    int32_t mount_verify_near_mm;  /**< a fit whose bottom row meets the
                                    floor this near the feet saw the
                                    ground under them: it verifies the
                                    start ("look at your feet"; default
                                    600 mm; 0 = off)                    */
    int32_t max_disp_q4;           /**< one past the matcher's last
                                    disparity, (stereo.max_disp + 1) x
                                    16, as the pipeline sets it (default
                                    64*16): floor at max_disp_q4 - 2 px
                                    and up is beyond the matcher's
                                    range (DETECTION.md section 4)     */
    int32_t min_confidence;        /**< deficit test: confidence below is
                                    not a vote (def. 120, i.e. grown
                                    pixels with NCC >= 0.47)           */
    int32_t ground_min_confidence; /**< ground fit and its validity share:
                                    confidence below: unused (def. 64) */

    /* Ground model. */
    int32_t fit_rows_pct;          /**< bottom rows used for the fit (25 %) */
    int32_t fit_step_px;           /**< fit subsampling (default 2 px)      */
    int32_t ground_min_valid_pct;  /**< valid share in fit ROI (25 %)   */
    int32_t ground_min_inlier_pct; /**< inliers among valid (30 %)      */
    int32_t track_gain_q15;        /**< plane smoothing gain (32768 = 1.0:
                                    follow each accepted fit)           */
    int32_t track_gate_q4;         /**< plane jump gate at ref rows (24)   */
    int32_t sigma_min_q4;          /**< noise floor (default 2 = 1/8 px)   */
    int32_t sigma_max_q4;          /**< rows noisier are not vouched (24)  */

    /* Detection rule. */
    int32_t range_max_mm;           /**< scan limit (default 5000 mm)       */
    int32_t range_warn_mm;          /**< CAUTION inside (default 4000 mm)   */
    int32_t range_imminent_mm;      /**< IMMINENT inside (default 1500 mm)  */
    int32_t near_min_mm;            /**< near-zone minimum: a frame that
                                    vouches less (clear_to_mm) is NO_INFO
                                    (default 1500 mm: walking speed x
                                    verdict latency + reaction, beyond
                                    the cane; docs/DETECTION.md)        */
    int32_t ttc_imminent_ms;        /**< IMMINENT if time to edge < (1200)  */
    int32_t corridor_half_width_mm; /**< lateral scan (default 600 mm) */
    int32_t corridor_near_half_mm;  /**< corridor half-width at the feet:
                                    range x tan 20 deg is added, up to
                                    corridor_half_width_mm (default
                                    250 mm; equal to it for a head-worn
                                    camera; docs/DETECTION.md 10.2)     */
    int32_t strip_px;               /**< column strip width (default 16 px) */
    int32_t h_min_far_mm;           /**< smallest drop beyond near (100 mm) */
    int32_t h_min_near_mm;          /**< smallest drop within near (50 mm)  */
    int32_t h_near_range_mm;        /**< near zone limit (default 2000 mm)  */
    int32_t h_thresh_pct;           /**< geometric threshold as % of h_min
                                    (default 80)                        */
    int32_t k_sigma_q4;             /**< noise multiplier (default 48 = 3.0) */
    int32_t min_edge_rows;          /**< deficit rows in a run (default 3)  */
    int32_t min_support_mm;         /**< ground before the edge (250 mm)    */
    int32_t min_gap_mm;             /**< missing-ground band (default 400)  */
    int32_t max_hole_mm;            /**< hole: ground again within (1000)   */
    int32_t merge_range_mm;         /**< strips merge within (default 300)  */
    int32_t min_strips;             /**< strips per hazard (default 2)      */
    int32_t missing_policy;         /**< negobs_missing_policy_t (CAUTION)  */
    int32_t canny_thresh_permille;  /**< Canny high threshold, share of
                                    the largest gradient (default 70)   */
    int32_t canny_low_permille;     /**< Canny low threshold, share of the
                                    high one (default 400: the ratio
                                    MATLAB's edge() takes for a scalar
                                    threshold)                          */

    /* Temporal logic. */
    int32_t confirm_k;          /**< confirm when seen k ... (default 3) */
    int32_t confirm_n;          /**< ... of the last n frames (5, <= 31),
                                     once one sighting's drop reached
                                     h_t (docs/DETECTION.md section 6) */
    int32_t clear_m;            /**< clean ticks to clear (default 5)   */
    int32_t frame_interval_ms;  /**< a tick is a frame at least 3/4 of
                                     this after the last tick (100 ms:
                                     the 10 fps the counts were set at;
                                     0: every frame). clear_m, the slow
                                     tracks' gains and the travel count
                                     ticks; confirm_k/n count frames
                                     (docs/DETECTION.md section 6)      */
    int32_t pool_frames;        /**< frames whose values of the same
                                     floor point are pooled, along the
                                     measured travel, before the scan
                                     (1: off, 2..4; docs/DETECTION.md,
                                     "Pooled frames"; the workspace
                                     grows by 6 bytes a pixel)          */
    int32_t hold_ms;            /**< latch after leaving image (3000);
                                     sooner once walked 500 mm past it  */
    int32_t hold_speed_mm_s;    /**< dead-reckoning speed (1400 mm/s)   */
    int32_t max_speed_mm_s;     /**< association speed (2000 mm/s)      */
    int32_t assoc_range_mm;     /**< association tolerance (400 mm; a
                                     sighting farther than its track: also
                                     at most 20 % of the range)          */
    int32_t assoc_lateral_mm;   /**< association tolerance (600 mm)     */
    int32_t hold_bottom_rows;   /**< edge this close to the bottom row
                                    is held when lost (default 24 rows) */
    int32_t ground_drop_mm;     /**< rise of the estimated camera height
                                    over the height under the feet that
                                    means the ground in view is lower:
                                    a drop nearer than the view's bottom
                                    (default 100 mm; 0 = off)           */
    int32_t ground_drop_max_ms; /**< after this long the lower ground is
                                    taken as the new reference (the
                                    camera was moved), and an unverified
                                    start (GROUND_UNVERIFIED) is
                                    accepted (default 5000 ms)          */
    int32_t ground_drop_corroborated_mm; /**< the rise that suffices
                                    for hold_ms after a clean frame whose
                                    rule found a drop within
                                    h_near_range_mm (default 70 mm;
                                    0 = off)                            */
    int32_t ground_verify_mm; /**< before the first reference: a fitted
                                    camera height this much or more away
                                    from cam_height_mm (any height when
                                    cam_height_mm is 0) is GROUND_UNVERIFIED,
                                    never CLEAR (a drop of about this
                                    height within ~1.4 m at switch-on;
                                    default 50 mm, 1..2000; used while
                                    ground_drop_mm > 0)                 */

    /* Gating. */
    int32_t sync_tol_ms;            /**< L/R timestamp skew (default 5 ms)  */
    int32_t max_frame_age_ms;       /**< capture-to-now (default 150 ms)    */
    int32_t dark_mean_min;          /**< mean below: too dark (default 20)  */
    int32_t dark_max_permille;      /**< dark share above (default 700)     */
    int32_t saturated_max_permille; /**< saturated share (default 250) */
    int32_t texture_min_q4;         /**< mean gradient below (default 24)   */
} negobs_detect_config_t;

/** One frame's input. Images must match cfg->rig width and height. */
typedef struct negobs_detect_frame {
    const negobs_image_s16_t *disp_q4;      /**< required                    */
    const negobs_image_u8_t *confidence;    /**< may be NULL                 */
    const negobs_image_u8_t *left;          /**< may be NULL; without it no
                                        texture test under a candidate, no
                                        start verified by walking and no
                                        pitch-fall judgement
                                        (DETECTION.md 6.2, 10.3)        */
    const negobs_photo_stats_t *left_stats; /**< may be NULL: from left  */
    const negobs_photo_stats_t *right_stats; /**< may be NULL             */
    uint32_t t_left_ms;  /**< capture time of the left image (ms)     */
    uint32_t t_right_ms; /**< capture time of the right image (ms)    */
    uint32_t now_ms;     /**< time of this call (ms, same clock)      */
    int32_t first_row;   /**< rows above it were not matched
                              (negobs_stereo_set_first_row); a frame
                              whose warning-range row lies there cannot
                              vouch for it: FEW_GROUND. 0 = all rows  */
    /** May be NULL: its rectification fill is then not known; with left,
     *  the fill of both images is out of view (DETECTION.md 10.2). */
    const negobs_image_u8_t *right;
    /** May be NULL: the 2x2 average of left that a half-resolution pass
     *  matched (width / 2 x height / 2; the pipeline's coarse_pass). */
    const negobs_image_u8_t *left_half;
    /** May be NULL: that pass's map (same size). With both, a candidate
     *  whose box holds mostly its values is tested for texture at that
     *  scale (DETECTION.md, "Texture under a candidate"). */
    const negobs_image_s16_t *disp_half_q4;
} negobs_detect_frame_t;

/** Frame result. */
typedef struct negobs_detect_result {
    negobs_detect_state_t state;
    uint32_t reasons;           /**< NEGOBS_DEGRADED_* bitmask       */
    negobs_alert_level_t level; /**< most urgent confirmed hazard    */
    int32_t nearest_range_mm;   /**< of that hazard, -1 if none      */
    uint32_t n_hazards;         /**< confirmed or held tracks        */
    negobs_hazard_t hazards[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t n_candidates; /**< raw detections of this frame    */
    negobs_hazard_t candidates[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t candidates_dropped;   /**< beyond the bound (farthest)     */
    int32_t ground_valid;          /**< 1 if a ground model was used    */
    negobs_ground_plane_t plane;   /**< ground model used               */
    negobs_ground_pose_t pose;     /**< its camera pose                 */
    int32_t sigma_q4;              /**< disparity noise, ground (q4)    */
    int32_t sigma_warn_q4;         /**< noise at the warning range (q4) */
    int32_t sigma_strip_warn_q8;   /**< measured noise of a strip's median
                                        residual there (1/256 px): what the
                                        self-check compares (step 6)    */
    int32_t offset_strip_warn_q8;  /**< median of that residual there: the
                                        ground model's offset (1/256 px);
                                        > 0 hides drops                 */
    int32_t ground_valid_permille; /**< valid share in the fit ROI      */
    int32_t ground_inliers;        /**< plane-fit inliers               */
    negobs_photo_stats_t stats;    /**< left stats used (or zero)       */
    /** Farthest forward floor distance (mm) up to which the walking
     *  corridor is vouched clear of a minimum drop (5 cm within 1.5 m,
     *  10 cm beyond) by this frame's measured noise. The vouched stretch
     *  starts at the nearest ground row in view; the floor nearer than
     *  that must have been vouched by earlier frames (for 5 cm drops
     *  within 1.5 m of the feet), else it is 0
     *  (NEGOBS_DEGRADED_NEAR_UNSEEN). In HAZARD it is at most the nearest
     *  hazard's range; in NO_INFO it is still reported: 0 after a gating
     *  or ground reason (unverified ground included), else what the noise
     *  vouched for. See docs/DETECTION.md, "Verdicts". */
    int32_t clear_to_mm;
    /** The distance this frame's measured noise, ground support and
     *  texture alone vouch for (mm), before this frame's candidates and
     *  the reported hazards cut it to clear_to_mm; 0 without a ground
     *  model. A diagnostic: the verdict uses clear_to_mm. */
    int32_t noise_vouch_mm;
    /** 1 when the state is CLEAR but clear_to_mm is below range_warn_mm
     *  (short sight): the wearer gets the gentle short-sight pattern. */
    int32_t short_sight;
    /** Floor distance (mm) of the foot of an obstacle that bars every
     *  lane of the corridor (a face at least 400 mm high, steeper than
     *  any stair) where the vouched walk ended; 0 when it did not end so.
     *  The floor up to it is vouched and no floor beyond it is reached
     *  without meeting it: with no hazard the state is CLEAR with
     *  short_sight even when clear_to_mm (= blocked_at_mm) is below the
     *  near-zone minimum. See docs/DETECTION.md 10.2, "Barred lanes". */
    int32_t blocked_at_mm;
    /** Forward floor distance (mm) of the nearest floor the matcher can
     *  measure, when the floor nearer than that lies beyond its disparity
     *  range (a ground disparity of max_disp_q4 - 2 px or more, within
     *  1 px of the matcher's last, at the centre column); 0 when the
     *  bottom row is within the range. That floor is out of view, like
     *  floor below the image. Reported on every frame, it says
     *  stereo.max_disp is too small for this camera and mounting. See
     *  docs/DETECTION.md section 4, "Beyond the matcher's range". */
    int32_t range_near_mm;
    /** Share (per mille) of this frame's valid disparities below the
     *  horizon that were pooled with earlier frames (pool_frames > 1; 0
     *  when off, between ticks, or without a measured travel). See
     *  docs/DETECTION.md, "Pooled frames". */
    int32_t pooled_permille;
    negobs_mount_t mount; /**< camera mounting used this frame */
    /** The ground under the feet as the detector holds it after this
     *  frame: how it was established (negobs_ground_ref_by_t) and the
     *  camera's height and pitch over it, followed slowly on clean frames
     *  (0 while ground_ref_by is NEGOBS_GROUND_REF_NONE). What a device
     *  may remember as its next cam_height_mm / cam_pitch_mdeg hint when
     *  ground_ref_by is HINT, FEET or WALK. */
    int32_t ground_ref_by;
    int32_t ground_ref_height_mm;
    int32_t ground_ref_pitch_mdeg;
} negobs_detect_result_t;

/** Context; place it anywhere. Fields are private. */
typedef struct negobs_detect {
    negobs_detect_config_t cfg;
    void *priv;
} negobs_detect_t;

/** @brief Defaults for a width x height frame (see field comments). */
void negobs_detect_config_default(negobs_detect_config_t *cfg, int32_t width,
                                  int32_t height);

/**
 * @brief Apply a sensitivity preset on top of a config: SENSITIVE
 *        (h_min 80/40 mm, k 2.5, 2 of 4), BALANCED (the defaults),
 *        CONSERVATIVE (h_min 120/60 mm, k 3.5, 4 of 6).
 */
negobs_status_t negobs_detect_config_preset(negobs_detect_config_t *cfg,
                                            negobs_sensitivity_t preset);

/**
 * @brief Exact workspace size for a config.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (NULL or invalid config).
 */
negobs_status_t negobs_detect_workspace_size(const negobs_detect_config_t *cfg,
                                             size_t *bytes_out);

/**
 * @brief Validate cfg, carve the workspace (16-byte aligned, must outlive
 *        ctx) and reset the ground track and hazard tracks.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL, NEGOBS_ERR_ALIGN,
 *         NEGOBS_ERR_NOSPACE (workspace_bytes too small).
 */
negobs_status_t negobs_detect_init(negobs_detect_t *ctx,
                                   const negobs_detect_config_t *cfg,
                                   void *workspace, size_t workspace_bytes);

/**
 * @brief Run the detector's row bands on the caller's executor from the
 * next frame on: the pooled frames' pass (pool_frames > 1,
 * docs/DETECTION.md 6.4), in NEGOBS_DETECT_POOL_BANDS bands of rows. Each
 * band keeps its own scratch and the layout is fixed, so the result does
 * not depend on the executor, its order or its number of workers. NULL
 * runs them in order on the calling thread (the default).
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (run NULL or workers < 1),
 *         NEGOBS_ERR_STATE (not initialised).
 */
negobs_status_t negobs_detect_set_executor(negobs_detect_t *ctx,
                                           const negobs_executor_t *exec);

/**
 * @brief Process one frame.
 *
 * Unusable input that is still well-formed (all-invalid disparity, dark
 * images, skewed timestamps) is not an error: it returns NEGOBS_OK with
 * state NEGOBS_DETECT_NO_INFO and the reasons set. Malformed input (NULL
 * disparity, wrong size) returns NEGOBS_ERR_INVAL *and* fills the result
 * with NO_INFO / NEGOBS_DEGRADED_BAD_INPUT so a caller that ignores the
 * status still does not report "clear".
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL, NEGOBS_ERR_STATE (not initialised).
 */
negobs_status_t negobs_detect_process(negobs_detect_t *ctx,
                                      const negobs_detect_frame_t *frame,
                                      negobs_detect_result_t *result);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_DETECT_H */
