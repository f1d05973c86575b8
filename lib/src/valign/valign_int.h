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

/* 1 if every field is within the limits negobs_valign_warp() accepts. */
int valign_model_ok(const negobs_valign_model_t *m);

#endif /* NEGOBS_VALIGN_INT_H */
