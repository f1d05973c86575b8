/*
 * The processing hook of negobs_run: one call per synchronised pair.
 *
 * app_process_pair() runs the library's whole pipeline (negobs/pipeline.h:
 * stereo -> ground model -> drop-off detection with temporal confirmation)
 * and the detector's verdict decides: no-information, clear, caution or
 * imminent. Whether the images can carry information at all (too dark,
 * saturated, textureless) is the detector's photometric gate, on both
 * images, with the thresholds below passed to it; the app adds only the
 * pair check the detector lacks (left and right brightness far apart),
 * on the same statistics.
 */
#ifndef NEGOBS_APP_PIPELINE_H
#define NEGOBS_APP_PIPELINE_H

#include <stdint.h>

#include "negobs/detect.h"
#include "negobs/image.h"
#include "negobs/pipeline.h"
#include "negobs/status.h"
#include "negobs/stereo.h"

/** What the pair says about the path ahead (maps to a motor pattern). */
typedef enum app_verdict {
    APP_VERDICT_NO_INFO = 0, /**< cannot judge: play the no-info pattern */
    APP_VERDICT_CLEAR = 1,   /**< nothing to report (silence)            */
    APP_VERDICT_CAUTION = 2, /**< confirmed drop-off ahead               */
    APP_VERDICT_IMMINENT = 3 /**< confirmed drop-off close               */
} app_verdict_t;

/** Why the last pair gave NO_INFO. */
typedef enum app_reason {
    APP_REASON_NONE = 0,
    APP_REASON_BAD_INPUT,   /**< invalid descriptor or size mismatch      */
    APP_REASON_DARK,        /**< detector: TOO_DARK                       */
    APP_REASON_SATURATED,   /**< detector: SATURATED (pixels >= 250)      */
    APP_REASON_TEXTURELESS, /**< detector: LOW_TEXTURE                    */
    APP_REASON_MISMATCH,    /**< left and right brightness far apart      */
    APP_REASON_DETECTOR,    /**< the detector cannot see (detect_reasons) */
    APP_REASON_LATE         /**< "clear" judged a view older than the
                                 latency budget (app_pipeline_latency_gate) */
} app_reason_t;

/**
 * Thresholds (all integers; defaults in brackets). The three photometric
 * ones are the detector's (negobs_detect_config_t, whose defaults
 * app_pipeline_config_default copies), passed through unchanged.
 */
typedef struct app_pipeline_config {
    int32_t dark_mean_min;    /**< mean grey below: dark [detector's 20] */
    int32_t sat_permille_max; /**< share of pixels >= 250 above:
                                     saturated [detector's 250]            */
    int32_t texture_min_q4;   /**< mean |horizontal gradient| below:
                                     textureless, 1/16 grey [detector's 24] */
    int32_t lr_mean_diff_max; /**< |mean L - mean R| [60]              */
    /* Camera geometry for the detector (rectified pair). */
    int32_t focal_px;       /**< focal length, pixels [250]          */
    int32_t baseline_mm;    /**< stereo baseline [120]               */
    int32_t cam_height_mm;  /**< camera height hint [1200]; 0: none,
                                       the detector measures it          */
    int32_t cam_pitch_mdeg; /**< downward pitch, 1/1000 deg [20000]  */
    int32_t max_disp;       /**< largest disparity searched [63]     */
    int32_t vertical_align; /**< 1: sub-pixel vertical alignment stage
                                       before the matcher, for rigs without
                                       a calibration table [0]             */
    int32_t row_crop;       /**< 1: match only the rows from the top
                                       of the warning range down (the
                                       library's stereo_roi, following the
                                       last ground model) [1]              */
    /* Exact geometry from a calibration table (negobs_run --calib); they
     * take precedence over focal_px / baseline_mm when set. */
    int32_t focal_q4;          /**< focal, 1/16 px; 0 = focal_px [0]    */
    int32_t baseline_um;       /**< baseline, um; 0 = baseline_mm [0]   */
    int32_t cx_q4;             /**< principal point x, 1/16 px;
                                       -1 = image centre [-1]              */
    int32_t cy_q4;             /**< principal point y; -1 = centre [-1] */
    int32_t sync_tol_ms;       /**< L/R capture skew the detector accepts;
                                       negobs_run sets its pairing limit [10] */
    int32_t max_frame_age_ms;  /**< older frames are stale: no-info [150] */
    int32_t latency_budget_ms; /**< capture-to-verdict time above which a
                                       "clear" is not trusted: no-info;
                                       0 = off [250]                       */
    int32_t threads;           /**< threads running the matcher's row
                                       bands (a pthread pool); the output
                                       is the same for every count [1]     */
} app_pipeline_config_t;

/** Statistics of the last pair, per image (0 = left, 1 = right). */
typedef struct app_frame_stats {
    int32_t mean[2];         /**< mean grey (the detector's statistics) */
    int32_t sat_permille[2]; /**< share of pixels >= 250                */
    int32_t texture_q4[2];   /**< mean |horizontal gradient|, 1/16 grey */
    app_reason_t reason;
    uint32_t detect_reasons;  /**< NEGOBS_DEGRADED_* of the detector     */
    int32_t nearest_range_mm; /**< nearest confirmed hazard, -1 if none  */
    int32_t clear_to_mm;      /**< vouched free of a minimum drop (mm)   */
    int32_t short_sight;      /**< CLEAR, vouched short of range_warn    */
    uint32_t hazards;         /**< confirmed or held hazards             */
    negobs_mount_t mount;     /**< camera mounting the detector used
                                   (measured, held or the hint)          */
    int32_t valid_permille;   /**< share of pixels with a disparity      */
    int32_t first_row;        /**< first image row the matcher read (0:
                                   the whole frame; row_crop)            */
    int32_t matcher_threads;  /**< threads the matcher ran on: `threads`,
                                   or fewer where the workspace holds
                                   fewer (0: the library did not run)    */
    int32_t memory_profile;   /**< NEGOBS_STEREO_PROFILE_* the matcher
                                   ran with: fast where its memo fits   */
    int32_t latency_ms;       /**< capture to verdict (latency gate), or
                                   -1 when not measured                  */
    uint32_t stereo_us;       /**< matcher time of this pair, the sum of
                                   stage_us; 0 without app_pipeline_set_clock */
    uint32_t stage_us[NEGOBS_STEREO_STAGE_COUNT]; /**< per matcher stage
                                   (negobs_stereo_stage_t), microseconds */
    /* The ground under the feet as the detector holds it: how it was
     * established (negobs_ground_ref_by_t) and the camera over it (0
     * before); what mount_file keeps (app_mount.h). */
    int32_t ground_ref_by;
    int32_t ground_ref_height_mm;
    int32_t ground_ref_pitch_mdeg;
} app_frame_stats_t;

typedef struct app_pipeline {
    app_pipeline_config_t cfg;
    app_frame_stats_t last;
    negobs_stereo_clock_fn clock_ns; /**< app_pipeline_set_clock      */
    void *clock_user;
    /** The library's whole result for the last pair (negobs_run's JSON
     *  log); valid only when res_valid (the library ran on it). */
    negobs_pipeline_result_t res;
    int32_t res_valid;
} app_pipeline_t;

void app_pipeline_config_default(app_pipeline_config_t *cfg);

/** @return NEGOBS_OK or NEGOBS_ERR_INVAL (thresholds out of range). */
negobs_status_t app_pipeline_init(app_pipeline_t *p,
                                  const app_pipeline_config_t *cfg);

/**
 * @brief Time the matcher's stages of the following pairs with `now_ns`,
 * a free-running nanosecond counter (modulo 2^32), into last.stage_us and
 * last.stereo_us; NULL turns it off (then both stay 0). The verdicts do not
 * depend on it. Call after app_pipeline_init(), which clears it.
 */
void app_pipeline_set_clock(app_pipeline_t *p, negobs_stereo_clock_fn now_ns,
                            void *user);

/**
 * @brief Process one synchronised pair (images are only read).
 * Uses one static library pipeline (set up on
 * the first pair and again when the frame size changes): not reentrant,
 * one pipeline per process. Times are the caller's monotonic ms.
 */
app_verdict_t app_process_pair_at(app_pipeline_t *p,
                                  const negobs_image_u8_t *left,
                                  const negobs_image_u8_t *right,
                                  uint32_t t_left_ms, uint32_t t_right_ms,
                                  uint32_t now_ms);

/** @brief app_process_pair_at() with all times 0 (tests, replays). */
app_verdict_t app_process_pair(app_pipeline_t *p,
                               const negobs_image_u8_t *left,
                               const negobs_image_u8_t *right);

/**
 * @brief Real-time guard (docs/REQUIREMENTS.md: latency), applied once the
 * verdict of a pair is known. A "clear" says the path was clear when the
 * pair was captured; if that was more than cfg.latency_budget_ms ago (a
 * processor that cannot keep up: slow part, thermal throttling, an
 * overloaded system) it is not trusted and becomes NO_INFO with reason
 * APP_REASON_LATE. Hazard verdicts pass unchanged: a late warning is still
 * a warning. latency_ms < 0 (clock went backwards) counts as 0.
 * Records latency_ms in p->last. Budget 0 turns the guard off.
 */
app_verdict_t app_pipeline_latency_gate(app_pipeline_t *p, app_verdict_t v,
                                        int32_t latency_ms);

const char *app_verdict_name(app_verdict_t v);
const char *app_reason_name(app_reason_t r);

#endif /* NEGOBS_APP_PIPELINE_H */
