/*
 * The pipeline's half-resolution pass for weakly textured floors
 * (coarse.c; docs/DETECTION.md, "Weak texture: the half-resolution pass").
 */
#ifndef NEGOBS_PIPELINE_COARSE_H
#define NEGOBS_PIPELINE_COARSE_H

#include <stdint.h>

#include "negobs/image.h"
#include "negobs/pipeline.h"
#include "negobs/stereo.h"

/* The matcher's config for the half-size pair, derived from the full one:
 * every length in pixels halved (range, tile, strip, speckle area, gap),
 * everything else as configured. Returns 1 when cfg->coarse_pass is on and
 * the half frame is one the matcher accepts, else 0 (no pass). */
int pl_coarse_config(const negobs_pipeline_config_t *cfg,
                     negobs_stereo_config_t *out);

/* 2x2 area average of src into dst (dst->width = src->width / 2, the same
 * for the height; an odd last column or row is dropped), rounded to
 * nearest: the mean of four pixels of 0..255 stays in 0..255. */
void pl_bin2_u8(const negobs_image_u8_t *src, const negobs_image_u8_t *dst);

/* Permille of the pixels of rows [y0, height) and columns [x0, width) whose
 * confidence is below min_conf (no value, filled, textureless or weakly
 * matched). 0 when that area is empty. */
int32_t pl_weak_permille(const negobs_image_u8_t *conf, int32_t y0, int32_t x0,
                         int32_t min_conf);

/* For each pixel of rows [y0, height) whose half-resolution pixel
 * (x / 2, y / 2) has a value with confidence >= min_conf: that value
 * doubled (a half-size disparity is half the full-size one) and its
 * confidence, when the doubled value lies in [dmin_q4, dmax_q4] and the
 * pixel's own value is weak (confidence below min_conf) or was measured
 * without texture: the 5x5 window of left centred on the top-left pixel
 * of its 2x2 block fails det_window_textured against left's noise
 * (detect/detect_int.h). left NULL: no texture test. Returns the number
 * of pixels replaced. */
uint32_t pl_coarse_fuse(const negobs_image_u8_t *left,
                        negobs_image_s16_t *disp, negobs_image_u8_t *conf,
                        const negobs_image_s16_t *half_disp,
                        const negobs_image_u8_t *half_conf, int32_t y0,
                        int32_t min_conf, int32_t dmin_q4, int32_t dmax_q4);

#endif /* NEGOBS_PIPELINE_COARSE_H */
