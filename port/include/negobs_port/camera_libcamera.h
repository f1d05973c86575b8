/*
 * libcamera stereo source: two cameras (or one, see below) through
 * libcamera's C++ API, behind the same ops table as the V4L2 source.
 *
 * Sources are "libcamera:N" (index in libcamera's camera list, as `cam -l`
 * prints it minus one) or "libcamera:ID" (the camera id, e.g.
 * "platform/vimc.0 Sensor B"). Each camera gets one stream configured to
 * the requested size and the first pixel format it offers from R8, NV12,
 * NV21, YUV420, YVU420, NV16, NV61, YUYV, UYVY, YVYU, VYUY, RGB888, BGR888,
 * XRGB8888, XBGR8888 (luma in place first: the Y plane is handed out with
 * its stride, without copies; packed YUV and RGB luma is computed into the
 * caller's scratch buffer). Completed requests go through a bounded ring
 * (one slot per request) from libcamera's thread to get_pair(), which keeps
 * the freshest frame per camera and pairs the two by SensorTimestamp with
 * negobs_pair_decide(), exactly as the V4L2 source does. A camera that
 * disconnects or stays silent for 3 timeouts is torn down and looked up
 * again by id with back-off (100 ms .. 2 s), get_pair returning
 * NEGOBS_ERR_NODEV meanwhile.
 *
 * Single camera: with cfg->right NULL or "" only the left camera is opened
 * and every pair carries the same frame on both sides (pair.right ==
 * pair.left). Stereo processing makes no sense on it; it exists for bring-up
 * and for the emulator, where libcamera sees one vimc camera only.
 *
 * Memory: libcamera allocates (its camera manager, requests, buffers); the
 * shim's own state is one C++ object created by open() and freed by
 * close(). One libcamera::CameraManager is shared by every libcamera source
 * in the process (libcamera allows only one). No C++ exception crosses into
 * C: each entry point catches and returns NEGOBS_ERR_IO with a message.
 * Signals do not interrupt get_pair(); it returns within timeout_ms.
 *
 * cfg->exposure is libcamera's ExposureTime (microseconds), cfg->gain its
 * AnalogueGain in hundredths (100 = 1.0x); each is applied only when every
 * opened camera offers the control. cfg->fps sets FrameDurationLimits where
 * offered.
 */
#ifndef NEGOBS_PORT_CAMERA_LIBCAMERA_H
#define NEGOBS_PORT_CAMERA_LIBCAMERA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "negobs_port/motor.h"
#include "negobs_port/camera.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Source prefix accepted (and required) by open(). */
#define NEGOBS_LIBCAMERA_PREFIX "libcamera:"
/** Buffers asked for per camera (the pipeline may give more). */
#define NEGOBS_LIBCAMERA_BUFFERS 4
/** Fewer than this and open() fails, as for V4L2. */
#define NEGOBS_LIBCAMERA_MIN_BUFFERS 3
#define NEGOBS_LIBCAMERA_MAX_BUFFERS 16
#define NEGOBS_LIBCAMERA_TIMEOUTS_BEFORE_REOPEN 3
/** Longest camera id kept for reopening. */
#define NEGOBS_LIBCAMERA_ID_LEN 128

/** Four-character code as DRM (and libcamera's PixelFormat) builds it. */
#define NEGOBS_DRM_FOURCC(a, b, c, d)                                         \
    ((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) |           \
     ((uint32_t)(d) << 24))

/** State of a libcamera source (caller-owned, fields private). */
typedef struct negobs_libcamera {
    void *impl;       /**< C++ state, from open() to close()     */
    uint8_t *scratch; /**< luma of packed formats, 2 * w * h     */
    size_t scratch_bytes;
    negobs_capture_stats_t stats;
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
} negobs_libcamera_t;

/**
 * @brief Bind the state to a scratch buffer and fill a camera handle.
 * @param scratch  2 * width * height bytes, used only when a camera offers
 *                 no format with a Y plane (packed YUV, RGB); may be NULL.
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL (NULL st or cam);
 *         NEGOBS_ERR_UNSUPPORTED when built without libcamera (the handle
 *         is still filled: its errmsg() says why, its ops refuse).
 */
negobs_status_t negobs_libcamera_init(negobs_libcamera_t *st, uint8_t *scratch,
                                      size_t scratch_bytes,
                                      negobs_capture_t *cam);

/** @brief True when this build has the libcamera backend compiled in. */
bool negobs_libcamera_available(void);

/* ---- Pure helpers (no libcamera; unit-tested on their own) ---- */

/**
 * @brief Split a source name: "libcamera:2" gives *index = 2, *id = NULL;
 *        "libcamera:platform/vimc.0 Sensor B" gives *index = -1 and *id
 *        pointing after the prefix.
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL (NULL, no prefix, nothing after it,
 *         an index above 999, or an id of NEGOBS_LIBCAMERA_ID_LEN or more).
 */
negobs_status_t negobs_libcamera_parse_source(const char *src, int32_t *index,
                                              const char **id);

/**
 * @brief Preference of a DRM fourcc: 0 best, -1 unsupported. Formats whose
 *        first plane is luma rank before packed YUV, RGB last.
 */
int negobs_libcamera_format_rank(uint32_t fourcc);

/** @brief True when the luma must be computed into scratch. */
bool negobs_libcamera_format_packed(uint32_t fourcc);

/**
 * @brief Describe (Y plane: in place) or compute (packed: into scratch)
 *        the luma of plane 0 of a completed buffer.
 * @param base, bytesused  plane 0 and how much of it the camera filled
 * @param stride           bytes between rows of plane 0
 * @param scratch          w * h bytes for packed formats (else unused)
 * @return NEGOBS_OK; NEGOBS_ERR_CORRUPT (bytesused short of the rows);
 *         NEGOBS_ERR_NOSPACE (scratch too small); NEGOBS_ERR_INVAL (size or
 *         stride); NEGOBS_ERR_UNSUPPORTED (format).
 */
negobs_status_t negobs_libcamera_luma(uint32_t fourcc, uint8_t *base,
                                      size_t bytesused, int32_t width,
                                      int32_t height, uint32_t stride,
                                      uint8_t *scratch, size_t scratch_bytes,
                                      negobs_image_u8_t *out);

/** What get_pair() does next with the frames waiting on each camera. */
typedef enum negobs_lc_step {
    NEGOBS_LC_WAIT = 0,      /**< wait for more completed requests      */
    NEGOBS_LC_SINGLE = 1,    /**< one camera: its frame is both sides   */
    NEGOBS_LC_PAIR = 2,      /**< the two waiting frames are a pair     */
    NEGOBS_LC_DROP_LEFT = 3, /**< left is older by more than the
                                   tolerance: requeue it                 */
    NEGOBS_LC_DROP_RIGHT = 4
} negobs_lc_step_t;

/**
 * @brief The pairing step of get_pair(): each camera keeps only its newest
 *        completed frame (older ones are requeued as stale); when both
 *        wait, they pair within tol_ns of SensorTimestamp, else the older
 *        one is requeued (negobs_pair_decide()).
 * @param nsides  1 (single camera) or 2
 */
negobs_lc_step_t negobs_libcamera_pair_step(int32_t nsides, bool pend_l,
                                            uint64_t ts_l, bool pend_r,
                                            uint64_t ts_r, uint64_t tol_ns);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CAMERA_LIBCAMERA_H */
