/*
 * V4L2 stereo source: two capture nodes, MMAP streaming, timestamp pairing.
 *
 * Each node is negotiated to the same size with a pixel format from GREY,
 * NV12, NV21, YU12, YV12, YUYV, UYVY, Y10, Y16, MJPG (planar formats
 * first: their Y plane is handed out in place with stride = bytesperline;
 * the others are converted into the caller's scratch buffer), or one node
 * carries both eyes side by side; frames larger than the processing size
 * are cropped and binned (negobs_port/v4l2_convert.h).
 * Frames are dequeued with poll() and a timeout, the freshest queued frame
 * is kept, and the two sides are paired by timestamp (negobs_pair_decide):
 * pairs further apart than pair_tol_ms are dropped and counted. A node
 * that fails (ENODEV, EIO, POLLERR, or 3 timeouts in a row) is closed and
 * reopened with exponential back-off (100 ms .. 2 s).
 * A node whose content stops changing (frozen_frames identical frames in a
 * row as dequeued, negobs_frozen_update) has its pairs withheld with NEGOBS_ERR_IO and
 * "frozen: ..." until the content changes again.
 */
#ifndef NEGOBS_PORT_CAMERA_V4L2_H
#define NEGOBS_PORT_CAMERA_V4L2_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "negobs_port/motor.h"
#include "negobs_port/camera.h"
#include "negobs_port/v4l2_convert.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Buffers requested per node (the driver may give more, up to MAX). */
#define NEGOBS_V4L2_BUFFERS 4
#define NEGOBS_V4L2_MAX_BUFFERS 8
/** Fewer than this and open() fails: one being filled, one queued, one
 *  held by the application. */
#define NEGOBS_V4L2_MIN_BUFFERS 3
/** Consecutive poll timeouts after which a node is reopened. */
#define NEGOBS_V4L2_TIMEOUTS_BEFORE_REOPEN 3
#define NEGOBS_V4L2_BACKOFF_MIN_MS 100u
#define NEGOBS_V4L2_BACKOFF_MAX_MS 2000u
/** A frame that waited this long for a partner is dropped (ms). */
#define NEGOBS_V4L2_PENDING_MAX_MS 500u

/** Smallest MJPEG frame taken (SOI + EOI markers). */
#define NEGOBS_V4L2_MJPEG_MIN_BYTES 4u

/** Four-character code as V4L2 builds it. */
#define NEGOBS_FOURCC(a, b, c, d)                                             \
    ((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) |           \
     ((uint32_t)(d) << 24))

/** One node (fields private). */
typedef struct negobs_v4l2_dev {
    char path[64];
    int fd;
    uint32_t fourcc;
    int32_t width;
    int32_t height;
    uint32_t bytesperline;
    uint32_t sizeimage;
    struct {
        void *start;
        size_t length;
    } buf[NEGOBS_V4L2_MAX_BUFFERS];
    uint32_t nbuf;
    bool streaming;
    bool pending; /**< a dequeued frame waits for a partner   */
    uint32_t pend_idx;
    uint32_t pend_bytes;
    uint32_t pend_seq;
    uint64_t pend_ts;
    uint64_t pend_at_ms; /**< when the pending frame was dequeued    */
    int32_t held_idx;    /**< buffer lent to the app, -1 if none     */
    bool lost;
    uint64_t retry_at_ms;
    uint32_t backoff_ms;
    uint32_t timeouts_in_row;
    bool has_exposure;
    bool has_gain;
    negobs_frozen_t frozen;
    bool pend_frozen;        /**< the pending frame ends a frozen run    */
    negobs_v4l2_conv_t conv; /**< buffer -> processing images            */
} negobs_v4l2_dev_t;

/** State of a stereo V4L2 source (caller-owned, fields private). */
typedef struct negobs_v4l2 {
    negobs_v4l2_dev_t dev[2];
    int32_t nodes; /**< 2, or 1 for a side-by-side node         */
    negobs_capture_config_t cfg;
    uint8_t *scratch; /**< luma of packed formats, 2 * w * h      */
    size_t scratch_bytes;
    bool started;
    negobs_capture_stats_t stats;
    uint64_t last_drop_dt_ns; /**< |dt| of the last pair dropped          */
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
} negobs_v4l2_t;

/**
 * @brief Bind the state to a scratch buffer and fill a camera handle.
 * @param scratch  per node negobs_v4l2_conv_scratch_bytes() (2 * width *
 *                 height for YUYV/UYVY without binning; the decoded frame
 *                 plus the binned eyes for MJPEG); may be NULL when the
 *                 nodes offer a planar or GREY format at the processing
 *                 size. open() says how much it needs when short.
 * cfg->left / cfg->right of open() are device paths ("/dev/video0"; a
 * "v4l2:" prefix is accepted). cfg->side_by_side: one node (left) carries
 * both eyes; cfg->capture_width/height: the frame asked of the camera,
 * cropped and binned to cfg->width x height (negobs_port/v4l2_convert.h).
 * The format is chosen from what the node lists
 * (negobs_v4l2_choose_format()).
 */
negobs_status_t negobs_v4l2_init(negobs_v4l2_t *st, uint8_t *scratch,
                                 size_t scratch_bytes, negobs_capture_t *cam);

/* ---- Pure helpers (no device access; unit-tested on their own) ---- */

/**
 * @brief Preference of a pixel format: 0 best, larger worse, -1 when not
 *        supported. Formats with a contiguous Y plane rank before packed.
 */
int negobs_v4l2_format_rank(uint32_t fourcc);

/** @brief True for formats whose luma must be copied out (YUYV, UYVY). */
bool negobs_v4l2_format_packed(uint32_t fourcc);

/**
 * @brief Bytes a complete frame needs: bytesperline * height for GREY and
 *        packed formats, bytesperline * height * 3 / 2 for 4:2:0.
 *        0 for unsupported formats.
 */
size_t negobs_v4l2_frame_bytes(uint32_t fourcc, int32_t height,
                               uint32_t bytesperline);

/**
 * @brief Check what the driver returned from S_FMT/G_FMT.
 * @return NEGOBS_OK; NEGOBS_ERR_UNSUPPORTED (format); NEGOBS_ERR_INVAL
 *         (size 0 or above NEGOBS_MAX_DIM, bytesperline too small for the
 *         width, sizeimage smaller than the frame).
 */
negobs_status_t negobs_v4l2_check_format(uint32_t fourcc, int32_t width,
                                         int32_t height, uint32_t bytesperline,
                                         uint32_t sizeimage);

/**
 * @brief Describe (planar, GREY: in place) or extract (packed) the luma
 *        plane of a dequeued buffer.
 * @param base, bytesused  the buffer and how much the driver filled
 * @param scratch          w * h bytes for packed formats (else unused)
 * @return NEGOBS_OK; NEGOBS_ERR_CORRUPT (bytesused short of a frame);
 *         NEGOBS_ERR_NOSPACE (scratch too small); NEGOBS_ERR_UNSUPPORTED.
 */
negobs_status_t negobs_v4l2_luma(uint32_t fourcc, uint8_t *base,
                                 size_t bytesused, int32_t width,
                                 int32_t height, uint32_t bytesperline,
                                 uint8_t *scratch, size_t scratch_bytes,
                                 negobs_image_u8_t *out);

/** @brief Back-off after `failures` consecutive failed reopens (ms). */
uint32_t negobs_v4l2_backoff_ms(uint32_t failures);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CAMERA_V4L2_H */
