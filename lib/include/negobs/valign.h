/*
 * Vertical alignment: estimate and remove the vertical misalignment of an
 * uncalibrated (or badly rectified) stereo pair, to a fraction of a pixel
 * and varying across the image.
 *
 * Why a model and not one offset: the real SurDis wearable pair is off by
 * 2.2 rows at the top of the frame but only 1.0 at the middle and 0.2 at
 * the bottom (a vertical scale difference between the two cameras). A
 * single integer shift leaves the ground, where a negative obstacle is
 * searched, mismatched by up to 1.8 rows; horizontal texture (paving
 * joints, kerb lines) then matches at the wrong column and the disparity
 * of the ground shows bands. docs/DISPARITY.md section 6 has the figures.
 *
 * Model. Left row y of column x matches right row y + off(x, y) with
 *   off(x, y) = offset + slope_y * (y - h/2) + slope_x * (x - w/2)
 * (all in pixels; the fields are Q16: px * 65536, slopes px per px).
 * slope_x is a roll between the cameras, slope_y a scale difference.
 *
 * Estimate. The frame is cut into tiles_x x tiles_y tiles. In each tile a
 * few textured sample points are matched with a 7x7 Moravec NCC over the
 * horizontal range [min_disp, max_disp] for every integer vertical offset
 * in [-max_offset, max_offset]; the best score over the horizontal range
 * is summed per tile and offset. A tile whose summed curve peaks inside
 * the range with a clear curvature gives a sub-pixel offset (parabola
 * vertex, 1/16 px). A least-squares fit of the model over the tiles, then
 * a second fit without the tiles more than 3 MADs (at least 4/16 px) off,
 * gives the model. A second pass on the pair warped with that model
 * measures what is left over +-2 rows and adds it: the parabola is
 * unbiased near zero offset, so the second pass removes its pull towards
 * whole rows.
 *
 * Warp. The right image is resampled row-wise with linear interpolation at
 * 1/16 px: out = (r[y+k] * (16 - f) + r[y+k+1] * f + 8) >> 4, rows
 * clamped to the image. Exact integer arithmetic, the same bytes on every
 * target. A zero model copies the image.
 *
 * Typical use (the pipeline does this when valign.enable is set):
 *   negobs_valign_config_default(&cfg, w, h);
 *   negobs_valign_workspace_size(&cfg, &n);  init on n bytes;
 *   per frame: negobs_valign_process(&ctx, &left, &right, &right_aligned,
 *                                    &stats);
 *   then match left against right_aligned with no vertical search.
 */
#ifndef NEGOBS_VALIGN_H
#define NEGOBS_VALIGN_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/image.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest |offset| searched (rows). */
#define NEGOBS_VALIGN_MAX_OFFSET 4
/** Largest tiles_x or tiles_y. */
#define NEGOBS_VALIGN_MAX_TILES 16
/** Largest samples (per tile side). */
#define NEGOBS_VALIGN_MAX_SAMPLES 8
/** Largest |slope_y| or |slope_x| the fit may report, Q16 (1/64 px/px). */
#define NEGOBS_VALIGN_SLOPE_LIMIT_Q16 1024

/** What the fit may vary. */
typedef enum negobs_valign_kind {
    NEGOBS_VALIGN_CONST = 0, /**< one offset for the frame               */
    NEGOBS_VALIGN_ROWS = 1,  /**< offset + slope_y (scale difference)    */
    NEGOBS_VALIGN_AFFINE = 2 /**< offset + slope_y + slope_x (and roll)  */
} negobs_valign_kind_t;

/** Configuration; zero it, then call negobs_valign_config_default(). */
typedef struct negobs_valign_config {
    int32_t enable;        /**< used by the pipeline only: 1 runs this stage
                              before the matcher (0)                     */
    int32_t width;         /**< frame width (pixels)                       */
    int32_t height;        /**< frame height (pixels)                      */
    int32_t min_disp;      /**< horizontal search while estimating (px, 0)  */
    int32_t max_disp;      /**< (px, 63)                                    */
    int32_t max_offset;    /**< |vertical offset| searched, rows 1..4 (4)   */
    int32_t kind;          /**< negobs_valign_kind_t (AFFINE)               */
    int32_t tiles_x;       /**< estimate grid, 1..16 (8)                    */
    int32_t tiles_y;       /**< 1..16 (6)                                   */
    int32_t samples;       /**< sample points per tile side, 1..8 (3)      */
    int32_t texture_min;   /**< 7x7 window: 49 * sum(g^2) - sum(g)^2 floor
                              (49^2 * 9, a grey-level deviation of 3)    */
    int32_t match_min_q14; /**< a sample counts when its best MNCC over
                              offsets and disparities is >= this (0.5)   */
    int32_t min_tiles;     /**< fewer usable tiles: keep the old model (4)  */
    int32_t smooth_q15;    /**< weight of a new frame's estimate in the
                              tracked model, 1..32768 (8192 = 1/4);
                              32768 forgets the past                     */
} negobs_valign_config_t;

/** Misalignment model: right row = left row + off(x, y) (see top). */
typedef struct negobs_valign_model {
    int32_t offset_q16;  /**< at the image centre, px * 65536           */
    int32_t slope_y_q16; /**< offset change per row, px/px * 65536      */
    int32_t slope_x_q16; /**< offset change per column, px/px * 65536   */
} negobs_valign_model_t;

/** What one estimate saw. */
typedef struct negobs_valign_stats {
    int32_t samples_used; /**< sample points that matched (first pass)  */
    int32_t tiles_used;   /**< tiles in the final fit (first pass)      */
    int32_t resid_q4;     /**< MAD of those tiles about the fit, 1/16 px */
    int32_t accepted;     /**< 1: the frame's estimate updated the model;
                               0: too little texture, old model kept    */
    negobs_valign_model_t frame; /**< this frame's own estimate          */
    negobs_valign_model_t model; /**< the tracked model that was applied */
} negobs_valign_stats_t;

/** Context; place it anywhere (static is fine). Fields are private. */
typedef struct negobs_valign {
    negobs_valign_config_t cfg;
    negobs_valign_model_t model; /* tracked model                       */
    int32_t have_model;          /* 0 until a frame was accepted        */
    int32_t misses;              /* residual searches failed in a row   */
    int32_t dmin, dmax;          /* horizontal search of the estimate   */
    int32_t *tile_sum;           /* tiles * (2 * max_offset + 1) scores */
    int32_t *tile_n;             /* samples per tile                    */
    int32_t *tile_off_q4;        /* per-tile offset, or INT32_MIN       */
    uint32_t ready;
} negobs_valign_t;

/** @brief Defaults for a width x height frame (see the field comments). */
void negobs_valign_config_default(negobs_valign_config_t *cfg, int32_t width,
                                  int32_t height);

/**
 * @brief Exact workspace bytes for cfg.
 * @return NEGOBS_OK, or NEGOBS_ERR_INVAL for a bad config.
 */
negobs_status_t negobs_valign_workspace_size(const negobs_valign_config_t *cfg,
                                             size_t *bytes_out);

/**
 * @brief Validate cfg (copied) and carve the workspace.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL, NEGOBS_ERR_ALIGN, NEGOBS_ERR_NOSPACE.
 */
negobs_status_t negobs_valign_init(negobs_valign_t *ctx,
                                   const negobs_valign_config_t *cfg,
                                   void *workspace, size_t workspace_bytes);

/**
 * @brief Estimate, blend into the tracked model (smooth_q15), and write
 *        the right image aligned to the left one into `out`.
 *
 * The first frame (and one after 4 frames in a row that gave nothing) gets
 * the full two-pass estimate; later frames only measure what the tracked
 * model leaves, over +-2 rows on the pair warped by it, which costs about a
 * third. A frame with too little texture keeps the tracked model (zero
 * before the first accepted frame). `out` must not overlap `right`.
 * @return NEGOBS_OK (also when too little texture: stats->accepted = 0),
 *         NEGOBS_ERR_INVAL (bad or mismatched images, `out` overlapping
 *         `right`), NEGOBS_ERR_STATE (no init).
 */
negobs_status_t negobs_valign_process(negobs_valign_t *ctx,
                                      const negobs_image_u8_t *left,
                                      const negobs_image_u8_t *right,
                                      negobs_image_u8_t *out,
                                      negobs_valign_stats_t *stats);

/**
 * @brief Narrow the horizontal search of later estimates to [min_disp,
 *        max_disp], clamped into the configured range (the pipeline
 *        passes the matcher's range of the previous frame: the estimate's
 *        cost is proportional to it, and chance matches grow with it).
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (min > max), NEGOBS_ERR_STATE.
 */
negobs_status_t negobs_valign_set_disp_range(negobs_valign_t *ctx,
                                             int32_t min_disp,
                                             int32_t max_disp);

/** @brief The tracked model (zero before the first accepted frame). */
negobs_valign_model_t negobs_valign_model(const negobs_valign_t *ctx);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_VALIGN_H */
