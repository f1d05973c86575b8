/*
 * The processing hook of negobs_run: one call per synchronised pair.
 *
 * Today app_process_pair() only checks whether the images can carry
 * information at all (brightness, saturation, texture, from the library's
 * box sums) and answers NO_INFO when they cannot. The stereo matching and
 * drop-off detection are NOT wired in yet: a usable pair gives
 * APP_VERDICT_CLEAR without any obstacle check. Replacing the body of
 * app_process_pair() with the full pipeline is the only change needed;
 * the verdicts and the rest of negobs_run stay as they are.
 */
#ifndef NEGOBS_APP_PIPELINE_H
#define NEGOBS_APP_PIPELINE_H

#include <stdint.h>

#include "negobs/image.h"
#include "negobs/status.h"

/** What the pair says about the path ahead (maps to a motor pattern). */
typedef enum app_verdict {
    APP_VERDICT_NO_INFO = 0,  /**< cannot judge: play the no-info pattern */
    APP_VERDICT_CLEAR = 1,    /**< nothing to report (silence)            */
    APP_VERDICT_CAUTION = 2,  /**< drop-off ahead (not produced yet)       */
    APP_VERDICT_IMMINENT = 3  /**< drop-off close (not produced yet)       */
} app_verdict_t;

/** Why the last pair gave NO_INFO. */
typedef enum app_reason {
    APP_REASON_NONE = 0,
    APP_REASON_BAD_INPUT,   /**< invalid descriptor or size mismatch      */
    APP_REASON_DARK,        /**< mean grey below dark_mean_min            */
    APP_REASON_SATURATED,   /**< too many pixels at >= 250                */
    APP_REASON_TEXTURELESS, /**< too few windows with local contrast      */
    APP_REASON_MISMATCH     /**< left and right brightness far apart      */
} app_reason_t;

/** Thresholds (all integers; defaults in brackets). */
typedef struct app_pipeline_config {
    int32_t dark_mean_min;        /**< grey level [20]                     */
    int32_t sat_permille_max;     /**< share of pixels >= 250 [300]        */
    int32_t texture_std_min;      /**< 5x5 std dev for "textured" [4]      */
    int32_t texture_permille_min; /**< share of textured windows [20]      */
    int32_t lr_mean_diff_max;     /**< |mean L - mean R| [60]              */
} app_pipeline_config_t;

/** Statistics of the last pair, per image (0 = left, 1 = right). */
typedef struct app_frame_stats {
    int32_t mean[2];
    int32_t sat_permille[2];
    int32_t texture_permille[2];
    app_reason_t reason;
} app_frame_stats_t;

typedef struct app_pipeline {
    app_pipeline_config_t cfg;
    app_frame_stats_t last;
} app_pipeline_t;

void app_pipeline_config_default(app_pipeline_config_t *cfg);

/** @return NEGOBS_OK or NEGOBS_ERR_INVAL (thresholds out of range). */
negobs_status_t app_pipeline_init(app_pipeline_t *p,
                                  const app_pipeline_config_t *cfg);

/**
 * @brief Process one synchronised pair (images are only read).
 * Uses static scratch buffers: not reentrant, one pipeline per process.
 */
app_verdict_t app_process_pair(app_pipeline_t *p,
                               const negobs_image_u8_t *left,
                               const negobs_image_u8_t *right);

const char *app_verdict_name(app_verdict_t v);
const char *app_reason_name(app_reason_t r);

#endif /* NEGOBS_APP_PIPELINE_H */
