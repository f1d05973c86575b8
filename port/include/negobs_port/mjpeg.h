/*
 * Motion-JPEG frames to grey, through libjpeg-turbo's TurboJPEG API (the
 * decoder is libjpeg-turbo's; negobs only asks it for the luma).
 *
 * Most UVC cameras deliver 720p and larger only as MJPEG. The luma is all
 * the pipeline uses, so the frame is decoded straight to grey
 * (TJPF_GRAY): the chroma is never upsampled or converted. UVC frames
 * often leave out the Huffman tables (Motion-JPEG uses the standard ones);
 * libjpeg-turbo fills them in. A frame the decoder warns about (truncated
 * by a USB error, corrupt data) is refused: half a picture must not be
 * judged.
 *
 * Built without libturbojpeg (meson summary: "MJPEG (libturbojpeg)"),
 * negobs_mjpeg_available() is false and decoding returns
 * NEGOBS_ERR_UNSUPPORTED; the V4L2 source then never picks MJPEG.
 */
#ifndef NEGOBS_PORT_MJPEG_H
#define NEGOBS_PORT_MJPEG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief True when this build decodes MJPEG. */
bool negobs_mjpeg_available(void);

/**
 * @brief Read the picture size from a JPEG header.
 * @return NEGOBS_OK; NEGOBS_ERR_CORRUPT (not a JPEG, or cut before its
 *         frame header); NEGOBS_ERR_UNSUPPORTED (built without it);
 *         NEGOBS_ERR_INVAL (NULL).
 */
negobs_status_t negobs_mjpeg_size(const uint8_t *jpeg, size_t bytes,
                                  int32_t *width, int32_t *height);

/**
 * @brief Decode a JPEG to 8-bit grey (its luma; a grey JPEG as is).
 * @param width, height  size the caller expects: a picture of another size
 *                       is NEGOBS_ERR_CORRUPT (never written past dst)
 * @param dst, stride    width x height bytes, rows stride bytes apart
 * @return NEGOBS_OK; NEGOBS_ERR_CORRUPT (bad or truncated data, a decoder
 *         warning, another size); NEGOBS_ERR_IO (no decoder state);
 *         NEGOBS_ERR_INVAL; NEGOBS_ERR_UNSUPPORTED (built without it).
 * The decoder state is made and freed per frame (libjpeg-turbo allocates
 * it, a few kB: microseconds against the milliseconds of a decode), so
 * the caller keeps no handle.
 */
negobs_status_t negobs_mjpeg_decode_grey(const uint8_t *jpeg, size_t bytes,
                                         int32_t width, int32_t height,
                                         uint8_t *dst, size_t stride);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_MJPEG_H */
