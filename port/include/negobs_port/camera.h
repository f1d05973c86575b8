/*
 * Stereo camera sources.
 *
 * A source delivers synchronised left/right pairs of 8-bit grey (luma)
 * images. The images are described (data, width, height, stride), never
 * assumed: a V4L2 source hands out the driver's buffers with stride =
 * bytesperline, without copying, and the pair stays valid until
 * negobs_capture_release() (or the next get_pair, which releases it).
 *
 * Sources are ops tables, so one program can hold several (a live pair and
 * a replay folder, say). State lives in caller-owned structs declared in
 * camera_v4l2.h / camera_replay.h; nothing is allocated on the heap.
 *
 * Call order: open -> start -> { get_pair -> release }* -> stop -> close.
 */
#ifndef NEGOBS_PORT_CAMERA_H
#define NEGOBS_PORT_CAMERA_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "negobs/image.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** get_pair() return value for "no more frames" (end of a replay). */
#define NEGOBS_CAPTURE_END 1

/** Default largest timestamp difference of a pair (ms). */
#define NEGOBS_CAPTURE_PAIR_TOL_MS_DEFAULT 10

/**
 * Default number of identical frames in a row after which a live camera
 * counts as frozen (10: a third of a second at 30 fps). A real sensor never
 * delivers two identical frames: its temporal noise changes some of the
 * sampled pixels every frame. Only a fully clipped image (all 0 or all 255)
 * can repeat, and that is no-information anyway.
 */
#define NEGOBS_CAPTURE_FROZEN_FRAMES_DEFAULT 10

/** Request passed to open(); zero fields mean "backend default". */
typedef struct negobs_capture_config {
    const char *left;      /**< device or path of the left camera     */
    const char *right;     /**< device or path of the right camera    */
    int32_t width;         /**< requested width (default 640)         */
    int32_t height;        /**< requested height (default 480)        */
    int32_t fps;           /**< requested rate (default 30); replay:
                                pacing rate, 0 = as fast as possible   */
    int32_t pair_tol_ms;   /**< max |t_left - t_right| (default 10)   */
    int32_t exposure;      /**< manual exposure (driver units), -1 auto */
    int32_t gain;          /**< manual gain (driver units), -1 = leave */
    bool loop;             /**< replay: start over at the end          */
    int32_t frozen_frames; /**< live cameras: this many identical frames
                                in a row = frozen, pairs withheld
                                (NEGOBS_ERR_IO); 0 = off               */
    int32_t capture_width; /**< V4L2: frame size asked of the camera
                                (both eyes when side by side); each eye
                                is cropped and binned to width x height.
                                0 = no binning: width x height per eye,
                                the driver's nearest size as delivered */
    int32_t capture_height;
    bool side_by_side;     /**< V4L2: one node, left eye in the left
                                half of each frame (right is ignored)  */
    uint32_t pixel_format; /**< V4L2: fourcc to ask for (NEGOBS_FOURCC);
                                0 = the cheapest usable one the node
                                lists (negobs_v4l2_choose_format())    */
} negobs_capture_config_t;

/** @brief Fill a config with the defaults (exposure/gain -1). */
void negobs_capture_config_default(negobs_capture_config_t *cfg);

/** One frame: luma plane and its capture time. */
typedef struct negobs_frame {
    negobs_image_u8_t y; /**< luma plane, stride = bytesperline      */
    uint64_t ts_ns;      /**< capture time, CLOCK_MONOTONIC ns       */
    uint32_t sequence;   /**< driver or file sequence number         */
} negobs_frame_t;

/** A synchronised pair. */
typedef struct negobs_frame_pair {
    negobs_frame_t left;
    negobs_frame_t right;
    uint32_t index; /**< pairs delivered before this one         */
} negobs_frame_pair_t;

/** Counters kept by every source. */
typedef struct negobs_capture_stats {
    uint32_t pairs;         /**< pairs delivered                        */
    uint32_t dropped_pairs; /**< frames dropped because no partner was
                                 within pair_tol_ms                     */
    uint32_t stale_frames;  /**< older queued frames skipped for fresher */
    uint32_t short_frames;  /**< buffers with too few bytes or errors   */
    uint32_t timeouts;      /**< get_pair calls that timed out          */
    uint32_t reopens;       /**< successful device reopens              */
    uint32_t device_losses; /**< times a device was found gone          */
    uint32_t frozen_pairs;  /**< pairs withheld: a camera was frozen     */
} negobs_capture_stats_t;

/**
 * Operations of one source; `ctx` is its state struct. Backends fill the
 * table with designated initialisers. open, get_pair and close are
 * required; start, release, stop, stats and errmsg may be NULL (a source
 * with nothing to do there), and the negobs_capture_*() wrappers below
 * then do nothing, report zero counters or an empty message. Callers use
 * the wrappers, never the table.
 */
typedef struct negobs_capture_ops {
    const char *name;
    negobs_status_t (*open)(void *ctx, const negobs_capture_config_t *cfg);
    negobs_status_t (*start)(void *ctx); /**< optional: NEGOBS_OK */
    /**
     * Wait up to timeout_ms for the next pair.
     * @return NEGOBS_OK, NEGOBS_CAPTURE_END, NEGOBS_ERR_TIMEOUT,
     *         NEGOBS_ERR_NODEV (device lost; later calls try to reopen it
     *         with back-off), NEGOBS_ERR_AGAIN (interrupted by a signal),
     *         NEGOBS_ERR_CORRUPT (bad replay file), NEGOBS_ERR_IO (also: a
     *         live camera is frozen, see frozen_frames). errmsg() says
     *         which: e.g. "frozen: ..." or, with NEGOBS_ERR_TIMEOUT while
     *         frames arrive, "left/right out of sync: ...".
     */
    int (*get_pair)(void *ctx, negobs_frame_pair_t *pair, int32_t timeout_ms);
    void (*release)(void *ctx, negobs_frame_pair_t *pair); /**< optional */
    void (*stop)(void *ctx);                               /**< optional */
    void (*close)(void *ctx);
    void (*stats)(void *ctx, negobs_capture_stats_t *out); /**< optional */
    const char *(*errmsg)(void *ctx); /**< last diagnostic text; optional */
} negobs_capture_ops_t;

/** A source handle. */
typedef struct negobs_capture {
    const negobs_capture_ops_t *ops;
    void *ctx;
} negobs_capture_t;

static inline negobs_status_t negobs_capture_open(
    negobs_capture_t *c, const negobs_capture_config_t *cfg)
{
    return c->ops->open(c->ctx, cfg);
}
static inline negobs_status_t negobs_capture_start(negobs_capture_t *c)
{
    return c->ops->start != NULL ? c->ops->start(c->ctx) : NEGOBS_OK;
}
static inline int negobs_capture_get_pair(negobs_capture_t *c,
                                          negobs_frame_pair_t *pair,
                                          int32_t timeout_ms)
{
    return c->ops->get_pair(c->ctx, pair, timeout_ms);
}
static inline void negobs_capture_release(negobs_capture_t *c,
                                          negobs_frame_pair_t *pair)
{
    if (c->ops->release != NULL) {
        c->ops->release(c->ctx, pair);
    }
}
static inline void negobs_capture_stop(negobs_capture_t *c)
{
    if (c->ops->stop != NULL) {
        c->ops->stop(c->ctx);
    }
}
static inline void negobs_capture_close(negobs_capture_t *c)
{
    c->ops->close(c->ctx);
}
static inline void negobs_capture_get_stats(negobs_capture_t *c,
                                            negobs_capture_stats_t *out)
{
    if (c->ops->stats != NULL) {
        c->ops->stats(c->ctx, out);
    } else {
        memset(out, 0, sizeof *out);
    }
}
static inline const char *negobs_capture_errmsg(negobs_capture_t *c)
{
    const char *m = c->ops->errmsg != NULL ? c->ops->errmsg(c->ctx) : NULL;
    return m != NULL ? m : "";
}

/* ------------------------------------------------------------------ */
/* Timestamp pairing (pure; used by the V4L2 backend, tested alone)    */

/** What to do with the two oldest unpaired frames. */
typedef enum negobs_pair_action {
    NEGOBS_PAIR_MATCH = 0,     /**< |dt| <= tolerance: deliver the pair */
    NEGOBS_PAIR_DROP_LEFT = 1, /**< left is older by more: drop it      */
    NEGOBS_PAIR_DROP_RIGHT = 2 /**< right is older by more: drop it     */
} negobs_pair_action_t;

/**
 * @brief Decide on two pending frames: match when the timestamps differ by
 *        at most tol_ns, else drop the older one (its partner may still
 *        come; the newer one may pair with the other side's next frame).
 */
negobs_pair_action_t negobs_pair_decide(uint64_t left_ns, uint64_t right_ns,
                                        uint64_t tol_ns);

/* ------------------------------------------------------------------ */
/* Frozen-stream detection (pure; used by the V4L2 backend)            */

/** Per-camera state: signature of the last frame and repeats in a row. */
typedef struct negobs_frozen {
    uint32_t last_sig;
    uint32_t repeats; /**< frames equal to the one before, in a row */
    bool have_last;
} negobs_frozen_t;

/**
 * @brief Cheap content signature of a luma plane: FNV-1a over every 3rd
 *        pixel of every 2nd row (a few thousand samples at VGA). Sensor
 *        noise changes it every frame; a repeated buffer does not.
 * @return The signature; 0 for a NULL or empty image.
 */
uint32_t negobs_frame_signature(const negobs_image_u8_t *img);

/**
 * @brief Feed one frame's signature.
 * @param limit  identical frames in a row that mean "frozen"; 0 = never
 *               (values below 2 count as 2: one frame cannot repeat)
 * @return true while the last `limit` frames were all identical; the first
 *         frame that differs clears it.
 */
bool negobs_frozen_update(negobs_frozen_t *f, uint32_t sig, int32_t limit);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CAMERA_H */
