/*
 * Disparity engine: elementary low-res range -> Canny seeds -> Growing
 * Correspondence Seeds (integer 5x5 NCC, bounded queue) -> banded two-stage
 * DP -> sub-pixel refinement and denoising.
 *
 * API CONTRACT (tools/stereo and tools/detect code against these names; add
 * fields freely, do not rename or remove these):
 *   negobs_stereo_config_t: width, height, min_disp, max_disp (pixels)
 *   negobs_stereo_config_default(cfg, width, height)
 *   negobs_stereo_workspace_size(cfg, &bytes)
 *   negobs_stereo_init(ctx, cfg, workspace, bytes)
 *   negobs_stereo_process(ctx, left, right, disp_q4, confidence, stats)
 *   disp_q4 values: disparity * 16, NEGOBS_DISP_INVALID (INT16_MIN) = none
 *   stats: seeds, queue_peak, queue_overflows, visited_cells, band
 */
#ifndef NEGOBS_STEREO_H
#define NEGOBS_STEREO_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/fixed.h"
#include "negobs/image.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Configuration; zero it, then call negobs_stereo_config_default(). */
typedef struct negobs_stereo_config {
    int32_t width;    /**< frame width (pixels)                    */
    int32_t height;   /**< frame height (pixels)                   */
    int32_t min_disp; /**< smallest disparity searched (pixels)    */
    int32_t max_disp; /**< largest disparity searched (pixels)     */
} negobs_stereo_config_t;

/** Per-frame statistics. */
typedef struct negobs_stereo_stats {
    uint32_t seeds;           /**< seeds accepted                  */
    uint32_t queue_peak;      /**< largest queue fill              */
    uint32_t queue_overflows; /**< pushes dropped by the bound     */
    uint32_t visited_cells;   /**< disparity-space cells scored    */
    int32_t band;             /**< DP band half-width used (px)    */
} negobs_stereo_stats_t;

/** Context; place it anywhere (static is fine). Fields are private. */
typedef struct negobs_stereo {
    negobs_stereo_config_t cfg;
    void *priv;
} negobs_stereo_t;

void negobs_stereo_config_default(negobs_stereo_config_t *cfg, int32_t width,
                                  int32_t height);
negobs_status_t negobs_stereo_workspace_size(const negobs_stereo_config_t *cfg,
                                             size_t *bytes_out);
negobs_status_t negobs_stereo_init(negobs_stereo_t *ctx,
                                   const negobs_stereo_config_t *cfg,
                                   void *workspace, size_t workspace_bytes);
/**
 * @param[out] disp_q4    width x height, disparity * 16 or
 *                        NEGOBS_DISP_INVALID
 * @param[out] confidence width x height, 0 (none) .. 255; may be NULL
 * @param[out] stats      may be NULL
 */
negobs_status_t negobs_stereo_process(negobs_stereo_t *ctx,
                                      const negobs_image_u8_t *left,
                                      const negobs_image_u8_t *right,
                                      negobs_image_s16_t *disp_q4,
                                      negobs_image_u8_t *confidence,
                                      negobs_stereo_stats_t *stats);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_STEREO_H */
