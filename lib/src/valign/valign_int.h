/*
 * Internal helpers of the vertical-alignment stage (lib/src/valign).
 */
#ifndef NEGOBS_VALIGN_INT_H
#define NEGOBS_VALIGN_INT_H

#include <stdint.h>

#include "negobs/valign.h"

/* Largest |offset| a model may carry, Q16 (64 px). */
#define VALIGN_OFFSET_LIMIT_Q16 ((int32_t)64 * 65536)
/* Half side of the matching window (7 x 7). */
#define VALIGN_WIN_R 3
#define VALIGN_WIN_N 49
/* Minimum curvature of a tile's summed score curve, per sample, Q14
 * (0.01): flatter peaks say nothing about the offset. */
#define VALIGN_CURV_MIN_Q14 164

/* Frames in a row whose residual search fails before a full search. */
#define VALIGN_REACQUIRE 4

/**
 * @brief Estimate the misalignment of one pair, without memory of earlier
 *        frames (two passes; `scratch` receives the pair's right image
 *        warped with the first-pass model and is left so).
 * @param[out] model the estimate; the zero model when not accepted
 * @param[out] stats may be NULL
 * @return NEGOBS_OK (also when too little texture: stats->accepted = 0),
 *         NEGOBS_ERR_INVAL (bad or mismatched images, scratch aliasing
 *         right), NEGOBS_ERR_STATE (no init).
 */
negobs_status_t negobs_valign_estimate(negobs_valign_t *ctx,
                                       const negobs_image_u8_t *left,
                                       const negobs_image_u8_t *right,
                                       negobs_image_u8_t *scratch,
                                       negobs_valign_model_t *model,
                                       negobs_valign_stats_t *stats);

/**
 * @brief Resample `right` so that its row y holds what the model says
 *        matches left row y (linear interpolation at 1/16 px, rows
 *        clamped). Stateless.
 * @return NEGOBS_OK, or NEGOBS_ERR_INVAL (bad images, size mismatch,
 *         overlap, |offset| > 64 px or a slope beyond the limit).
 */
negobs_status_t negobs_valign_warp(const negobs_valign_model_t *model,
                                   const negobs_image_u8_t *right,
                                   negobs_image_u8_t *out);

/* 1 if every field is within the limits negobs_valign_warp() accepts. */
int valign_model_ok(const negobs_valign_model_t *m);

#endif /* NEGOBS_VALIGN_INT_H */
