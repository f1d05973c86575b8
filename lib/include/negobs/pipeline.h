/*
 * The whole per-frame job in one module: stereo pair -> disparity ->
 * detection -> alert schedule. It owns nothing but one caller workspace
 * that holds the stage workspaces and the intermediate disparity and
 * confidence images.
 *
 * A runtime calls negobs_pipeline_process() for every frame pair and
 * negobs_pipeline_tick() whenever no pair arrived in time (its watchdog):
 * the alert logic then falls to the no-information pattern by itself.
 */
#ifndef NEGOBS_PIPELINE_H
#define NEGOBS_PIPELINE_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/alert.h"
#include "negobs/detect.h"
#include "negobs/executor.h"
#include "negobs/image.h"
#include "negobs/status.h"
#include "negobs/stereo.h"
#include "negobs/valign.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Configuration of every stage; keep sizes consistent (see default). */
typedef struct negobs_pipeline_config {
    /** Vertical alignment before the matcher (off by default). With
     *  valign.enable = 1 the right image is resampled to the left one's
     *  rows by the tracked sub-pixel model, and the matcher's own integer
     *  vertical search and offset are not used (init zeroes them). */
    negobs_valign_config_t valign;
    negobs_stereo_config_t stereo;
    negobs_detect_config_t detect;
    negobs_alert_config_t alert;
    /** 1: match only the rows the detector reads. After a frame with a
     *  ground model, the next frame's matcher starts roi_margin_rows
     *  above the highest row where that ground is still nearer than
     *  detect.range_max_mm (negobs_stereo_set_first_row); without a
     *  model it matches every row. Never above the ground fit's rows.
     *  [1] */
    int32_t stereo_roi;
    /** Rows kept above that row, for pitch changes between two frames
     *  (default height / 8: 30 rows at 240, about 6.8 deg at f 250). */
    int32_t roi_margin_rows;
    /** The matcher's vertical offset search (stereo.vertical_search > 0)
     *  runs on the first frame and then on every vertical_every_frames-th
     *  one; the frames between match with the last offset found
     *  (negobs_stereo_hold_vertical_offset). A rig's row misalignment is
     *  mechanical: it moves with a knock or with heat, not from one frame
     *  to the next, and a once-a-second search finds a knock within a
     *  second. 1: search every frame. 1..1000 [10: once a second at
     *  10 fps] */
    int32_t vertical_every_frames;
    /** Half-resolution pass for weak texture (docs/DETECTION.md, "Weak
     *  texture: the half-resolution pass"): when the full-size map leaves
     *  more than coarse_weak_permille of the rows it matched below
     *  detect.min_confidence, the same matcher runs on the 2x2-averaged
     *  pair, and each of those pixels, and each confident one measured in
     *  a window without texture, takes the half-size value (doubled)
     *  where that one reaches detect.min_confidence. 0: off, 1: on. Off,
     *  or a half frame too small for the matcher, leaves the workspace
     *  and every output as without it. [1] */
    int32_t coarse_pass;
    /** The weak share, in permille of the matched rows' pixels right of
     *  the first stereo.max_disp columns (which no disparity can match),
     *  above which the pass runs. 0..1000 [125: see the docs] */
    int32_t coarse_weak_permille;
} negobs_pipeline_config_t;

/** One frame pair with its capture times (ms, caller's monotonic clock). */
typedef struct negobs_pipeline_frame {
    const negobs_image_u8_t *left;  /**< NULL: camera lost (no-info)  */
    const negobs_image_u8_t *right; /**< NULL: camera lost (no-info)  */
    uint32_t t_left_ms;
    uint32_t t_right_ms;
    uint32_t now_ms;     /**< time of this call                       */
    int32_t battery_low; /**< 1 plays the low-battery pattern         */
} negobs_pipeline_frame_t;

/**
 * Stages timed by the optional clock (negobs_pipeline_set_clock). Every
 * tick between the clock reads at the start and the end of
 * negobs_pipeline_process() is attributed to exactly one of them.
 */
typedef enum negobs_pipeline_stage {
    NEGOBS_PIPELINE_STAGE_VALIGN = 0, /**< vertical alignment (valign)  */
    NEGOBS_PIPELINE_STAGE_STEREO,     /**< matcher, incl. ROI choice    */
    NEGOBS_PIPELINE_STAGE_DETECT,     /**< detector or no-info verdict  */
    NEGOBS_PIPELINE_STAGE_ALERT,      /**< alert schedule               */
    NEGOBS_PIPELINE_STAGE_COUNT
} negobs_pipeline_stage_t;

/**
 * Caller's clock for per-stage timings: any continuously running 32-bit counter
 * (microseconds, nanoseconds, cycles). Differences are taken modulo 2^32,
 * so one stage of one frame must stay below one period (4.29 s for a
 * nanosecond counter). The same clock is handed to the matcher for its
 * own stages (negobs_stereo_set_clock, stereo.stage_ticks).
 */
typedef uint32_t (*negobs_pipeline_clock_fn)(void *user);

/** What one frame produced. */
typedef struct negobs_pipeline_result {
    negobs_status_t stereo_status; /**< NEGOBS_OK or why no disparity */
    negobs_valign_stats_t valign;  /**< alignment (valign.enable)     */
    negobs_stereo_stats_t stereo;  /**< matcher statistics            */
    negobs_detect_result_t detect; /**< state, reasons, hazards; its
                                        stats are the left image's     */
    /** The right image's photometric statistics, judged by the same gate
     *  as the left's (detect.stats); zero when the matcher did not run. */
    negobs_photo_stats_t right_stats;
    negobs_motor_cmd_t motor; /**< what the motor does now/next  */
    /** Half-resolution pass (coarse_pass): the full-size map's weak share
     *  (permille, as coarse_weak_permille; 0 when the matcher did not
     *  run), 1 when the pass ran, and the pixels that took its value. */
    int32_t weak_permille;
    int32_t coarse_ran;
    uint32_t coarse_replaced;
    /** clock ticks per stage (negobs_pipeline_set_clock); all 0 without
     *  a clock. Not part of the output: timings differ between runs. */
    uint64_t stage_ticks[NEGOBS_PIPELINE_STAGE_COUNT];
} negobs_pipeline_result_t;

/**
 * Context storage; place it anywhere (static is fine). Its layout is
 * private to the library (lib/src/pipeline/pipeline_private.h): the
 * members below only give the storage the size and alignment of that
 * layout on every target. Never read or write them; use the functions.
 */
typedef struct negobs_pipeline {
    union {
        struct {
            negobs_pipeline_config_t a;
            negobs_valign_t b;
            negobs_image_u8_t c;
            negobs_stereo_t d;
            negobs_detect_t e;
            negobs_alert_t f;
            negobs_image_s16_t g;
            negobs_image_u8_t h;
            negobs_pipeline_clock_fn i;
            void *j;
            uint32_t k;
            uint32_t l;
            int32_t m;
            int32_t n;
            negobs_stereo_t o;
            negobs_image_u8_t p;
            negobs_image_u8_t q;
            negobs_image_s16_t r;
            negobs_image_u8_t s;
        } layout_;
        uint64_t align_;
    } opaque_;
} negobs_pipeline_t;

/**
 * @brief The first row the matcher needs for the next frame (stereo_roi):
 * roi_margin_rows above the highest row where this frame's ground model
 * is nearer than detect.range_max_mm, never below the ground fit's rows.
 * 0 (every row) when stereo_roi is off or det has no ground model.
 * negobs_pipeline_process applies it itself.
 */
int32_t negobs_pipeline_roi_first_row(const negobs_pipeline_config_t *cfg,
                                      const negobs_detect_result_t *det);

/**
 * @brief The product profile: every stage's default for a width x height
 *        frame, then these overrides (the only place they are made):
 *  - stereo.texture_min 100 -> 2500 and stereo.ncc_tau_q14 0.5 -> 0.6
 *    (9830): for drop detection a missing match is safer than a carried
 *    one; the matcher's own defaults suit dense maps
 *    (docs/decisions/0001-pipeline-strict-matcher.md);
 *  - valign.min_disp / max_disp = the matcher's range, and
 *    detect.max_disp_q4 = (stereo.max_disp + 1) px: one disparity range;
 *  - stereo_roi = 1, roi_margin_rows = height / 8;
 *  - vertical_every_frames = 10;
 *  - coarse_pass = 1, coarse_weak_permille = 125.
 * Defaults have one order: the stage's *_config_default(), then this
 * profile, then the application (firmware_app's app_pipeline and
 * negobs_run's settings, which change only what the user set).
 * The photometric gate (too dark, saturated, low texture) is the
 * detector's (detect.dark_mean_min ...), applied to both images.
 */
void negobs_pipeline_config_default(negobs_pipeline_config_t *cfg,
                                    int32_t width, int32_t height);

/**
 * @brief Exact workspace bytes for cfg (stage workspaces + disparity and
 *        confidence images).
 * @return NEGOBS_OK, or the first stage's NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_pipeline_workspace_size(
    const negobs_pipeline_config_t *cfg, size_t *bytes_out);

/**
 * @brief Initialise every stage on one 16-byte aligned workspace. The
 *        config is copied.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (inconsistent sizes or a stage
 *         config), NEGOBS_ERR_ALIGN, NEGOBS_ERR_NOSPACE.
 */
negobs_status_t negobs_pipeline_init(negobs_pipeline_t *ctx,
                                     const negobs_pipeline_config_t *cfg,
                                     void *workspace, size_t workspace_bytes);

/**
 * @brief Run one frame pair. A frame the matcher refuses (NULL image,
 *        wrong size) is not an error of this call: it becomes a
 *        no-information verdict (NEGOBS_DEGRADED_BAD_INPUT) so the user
 *        is told, and stereo_status says why.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (NULL ctx/frame/result),
 *         NEGOBS_ERR_STATE (not initialised).
 */
negobs_status_t negobs_pipeline_process(negobs_pipeline_t *ctx,
                                        const negobs_pipeline_frame_t *frame,
                                        negobs_pipeline_result_t *result);

/**
 * @brief Time every stage of the following frames with the caller's clock
 * (result.stage_ticks, and the matcher's stereo.stage_ticks). NULL (the
 * state after init) turns it off. The clock is only read: every output
 * is the same with and without it.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (NULL ctx), NEGOBS_ERR_STATE (not
 *         initialised).
 */
negobs_status_t negobs_pipeline_set_clock(negobs_pipeline_t *ctx,
                                          negobs_pipeline_clock_fn clock,
                                          void *user);

/**
 * @brief Run the matcher's row bands and the detector's
 * (negobs_detect_set_executor) on the caller's executor from the next
 * frame on (negobs_stereo_set_executor: stereo.bands shapes the output,
 * the executor only the time; exec->workers <= stereo.band_workers).
 * NULL (the state after init) runs them on the calling thread.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (NULL ctx, bad executor),
 *         NEGOBS_ERR_STATE (not initialised).
 */
negobs_status_t negobs_pipeline_set_executor(negobs_pipeline_t *ctx,
                                             const negobs_executor_t *exec);

/**
 * @brief Advance the alert logic without a frame (timer or watchdog).
 * @return as negobs_alert_update().
 */
negobs_status_t negobs_pipeline_tick(negobs_pipeline_t *ctx, uint32_t now_ms,
                                     negobs_motor_cmd_t *motor);

/** @brief The last disparity image (disp_q4), for overlays and logs. */
const negobs_image_s16_t *negobs_pipeline_disparity(
    const negobs_pipeline_t *ctx);

/** @brief The last confidence image (0..255). */
const negobs_image_u8_t *negobs_pipeline_confidence(
    const negobs_pipeline_t *ctx);

/** @brief The last right image as the matcher saw it after vertical
 *  alignment; NULL unless valign.enable. */
const negobs_image_u8_t *negobs_pipeline_aligned_right(
    const negobs_pipeline_t *ctx);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PIPELINE_H */
