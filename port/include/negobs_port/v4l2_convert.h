/*
 * From a dequeued V4L2 buffer to the two processing images (pure: no
 * device access; unit-tested on generated buffers).
 *
 * A node delivers one eye, or both side by side (ELP, Arducam, ZED-style
 * 2560x720 / 2560x800 frames: left half = left eye). Its pixel format is
 * brought to 8-bit luma:
 *   GREY, NV12, NV21, YU12, YV12  the Y plane, in place
 *   YUYV, UYVY                    every other byte
 *   Y10, Y16 (16-bit LE mono)     averaged, then >> 2 (Y10) or >> 8 (Y16)
 *   MJPG                          decoded to grey by libjpeg-turbo
 * and each eye is cropped and binned to the processing size
 * (negobs_port/frame_convert.h). When nothing has to change (an 8-bit
 * plane, k = 1, no crop) the eyes are described in place, without a copy,
 * as before; otherwise they are written to the caller's scratch.
 */
#ifndef NEGOBS_PORT_V4L2_CONVERT_H
#define NEGOBS_PORT_V4L2_CONVERT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "negobs/image.h"
#include "negobs/status.h"
#include "negobs_port/frame_convert.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How one node's frames become processing images. */
typedef struct negobs_v4l2_conv {
    uint32_t fourcc;
    int32_t width; /**< frame as delivered (both eyes when sbs) */
    int32_t height;
    uint32_t bytesperline;
    bool side_by_side;
    negobs_bin_plan_t plan; /**< per eye                             */
    bool in_place;          /**< eyes described in the buffer        */
} negobs_v4l2_conv_t;

/**
 * @brief Plan the conversion of a negotiated format.
 * @param out_w, out_h  processing size per eye; 0: the eye's own size
 * @return NEGOBS_OK; NEGOBS_ERR_UNSUPPORTED (format); NEGOBS_ERR_INVAL
 *         (odd side-by-side width, eye smaller than the processing size,
 *         bad sizes).
 */
negobs_status_t negobs_v4l2_conv_setup(negobs_v4l2_conv_t *c, uint32_t fourcc,
                                       int32_t width, int32_t height,
                                       uint32_t bytesperline,
                                       bool side_by_side, int32_t out_w,
                                       int32_t out_h);

/** @brief Scratch bytes a node needs (0 when the eyes stay in place):
 *         the decoded frame for MJPG plus the binned eyes. */
size_t negobs_v4l2_conv_scratch_bytes(const negobs_v4l2_conv_t *c);

/**
 * @brief Convert one buffer.
 * @param base, bytesused  the buffer and how much the driver filled
 * @param right            NULL unless side_by_side
 * @return NEGOBS_OK; NEGOBS_ERR_CORRUPT (short buffer, bad JPEG);
 *         NEGOBS_ERR_NOSPACE (scratch too small); NEGOBS_ERR_INVAL;
 *         NEGOBS_ERR_UNSUPPORTED (MJPG in a build without libturbojpeg).
 */
negobs_status_t negobs_v4l2_conv_frame(const negobs_v4l2_conv_t *c,
                                       uint8_t *base, size_t bytesused,
                                       uint8_t *scratch, size_t scratch_bytes,
                                       negobs_image_u8_t *left,
                                       negobs_image_u8_t *right);

/**
 * @brief The bytes of a buffer that the frozen-stream check signs
 *        (negobs_frame_signature(), every 3rd byte of every 2nd row): the
 *        first plane's rows, bytesperline wide, or for MJPEG (bytesperline
 *        0) the whole compressed frame as one row, so that the
 *        entropy-coded data is sampled and not only the headers, which
 *        are the same in every frame. width 0 when there are no bytes.
 */
void negobs_v4l2_conv_raw_view(const negobs_v4l2_conv_t *c, uint8_t *base,
                               size_t bytesused, negobs_image_u8_t *out);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_V4L2_CONVERT_H */
