/*
 * Frame conversion between what a camera delivers and the processing size
 * (pure functions, no device access; used by the V4L2 source).
 *
 *  - Side by side: one node carries both eyes in one frame (ELP, Arducam,
 *    ZED-style 2560x720 or 2560x800): the left half is the left eye.
 *  - Crop and bin: an eye larger than the processing size is centre-cropped
 *    to k * out_w x k * out_h and averaged over k x k blocks (integer area
 *    binning). k is the largest integer with k * out <= eye in both
 *    directions, so the aspect ratio of the processing size is kept and no
 *    pixel is interpolated; the crop offsets are multiples of k.
 *  - 16-bit mono (V4L2 Y10 and Y16, little endian): the block sum of the
 *    16-bit samples is averaged and shifted right by `shift` (2 for Y10,
 *    8 for Y16): the top 8 bits of the sensor's range, no gain. Averaging
 *    before the shift keeps the extra precision the binning brings.
 *
 * Intrinsics follow the binning: an output pixel u' covers source columns
 * x0 + k u' .. x0 + k u' + k - 1, whose centre is x0 + k u' + (k - 1) / 2,
 * so f' = f / k and cx' = (cx - x0 - (k - 1) / 2) / k (same for y).
 */
#ifndef NEGOBS_PORT_FRAME_CONVERT_H
#define NEGOBS_PORT_FRAME_CONVERT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "negobs/image.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest bin factor (a 4096-wide eye down to 16 pixels and more). */
#define NEGOBS_BIN_MAX 16

/** How one eye of a frame becomes one processing image. */
typedef struct negobs_bin_plan {
    int32_t eye_w; /**< one eye in the delivered frame           */
    int32_t eye_h;
    int32_t k;  /**< bin factor, 1..NEGOBS_BIN_MAX            */
    int32_t x0; /**< crop offset inside the eye (pixels)      */
    int32_t y0;
    int32_t out_w; /**< processing size                         */
    int32_t out_h;
} negobs_bin_plan_t;

/**
 * @brief Plan the crop and bin of an eye_w x eye_h eye to out_w x out_h.
 *        out_w or out_h 0: the eye's own size (k = 1, no crop).
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL (sizes outside 1..NEGOBS_MAX_DIM,
 *         or an eye smaller than the processing size); NEGOBS_ERR_UNSUPPORTED
 *         (k would exceed NEGOBS_BIN_MAX).
 */
negobs_status_t negobs_bin_plan(int32_t eye_w, int32_t eye_h, int32_t out_w,
                                int32_t out_h, negobs_bin_plan_t *plan);

/** @brief True when the plan is the identity (k = 1, no crop). */
bool negobs_bin_identity(const negobs_bin_plan_t *plan);

/**
 * @brief Eye size of a delivered frame: the frame, or its halves when
 *        side_by_side (the width must then be even).
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_sbs_eye_size(int32_t frame_w, int32_t frame_h,
                                    bool side_by_side, int32_t *eye_w,
                                    int32_t *eye_h);

/**
 * @brief Crop and bin 8-bit samples.
 * @param src     sample (0, 0) of the eye (before the crop)
 * @param stride  bytes between rows of src
 * @param step    bytes between samples of a row (1 grey, 2 YUYV luma)
 * @param dst     plan->out_w x plan->out_h, rows dst_stride bytes apart
 * Each output is the rounded mean of its k x k block (sum < 2^16 * 256:
 * no overflow in 32 bits for k <= NEGOBS_BIN_MAX).
 */
void negobs_bin_u8(const uint8_t *src, size_t stride, size_t step,
                   const negobs_bin_plan_t *plan, uint8_t *dst,
                   size_t dst_stride);

/**
 * @brief Crop and bin 16-bit little-endian samples to 8 bits:
 *        min(255, round(mean of the block) >> shift). Samples above the
 *        format's range (a Y10 driver leaving high bits set) saturate.
 * @param src, stride  sample (0, 0) of the eye; bytes between rows
 * @param shift        2 for Y10, 8 for Y16 (0..8)
 * The block sum is < 2^16 * 256 = 2^24: no overflow in 32 bits.
 */
void negobs_bin_u16le(const uint8_t *src, size_t stride, uint32_t shift,
                      const negobs_bin_plan_t *plan, uint8_t *dst,
                      size_t dst_stride);

/**
 * @brief Intrinsics of the binned image from those of the eye, in 1/16
 *        pixel (q4): f' = f / k, c' = (c - off - (k - 1) / 2) / k, rounded
 *        to nearest. A principal point < 0 ("centre of the image") stays
 *        -1. Any pointer may be NULL.
 */
void negobs_bin_intrinsics_q4(const negobs_bin_plan_t *plan, int32_t *f_q4,
                              int32_t *cx_q4, int32_t *cy_q4);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_FRAME_CONVERT_H */
