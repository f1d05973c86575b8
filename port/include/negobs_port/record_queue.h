/*
 * Recording off the verdict path: a bounded queue of pairs and a writer
 * thread of its own (negobs_run --record).
 *
 * The main loop copies a pair's luma into a free slot and goes on; the
 * writer thread opens the session on the first pair and writes the pairs
 * in order (negobs_recorder_*). A slow or stalled card therefore never
 * delays a verdict: it fills the queue, and then
 *
 *   drop policy: DROP NEWEST. A pair that finds every slot taken is not
 *   recorded (counted in `dropped`). The writer owns the oldest slot while
 *   it writes it, so dropping the oldest would mean taking a slot away
 *   from under it (a lock held across the write, i.e. the main loop
 *   waiting for the card) or throwing away pairs already queued in order;
 *   dropping the newest needs neither. The recording stays a run of
 *   consecutive pairs up to each stall, and frames.txt keeps each pair's
 *   camera sequence and timestamps, so every gap shows in the session and
 *   replay paces across it.
 *
 * A write failure (full disk, folder gone, file size limit, ...) stops
 * the recording for good: the writer closes the files, keeps the message,
 * discards what is queued, and every later push returns at once. Nothing
 * else stops: the recording is optional, the warnings are not.
 */
#ifndef NEGOBS_PORT_RECORD_QUEUE_H
#define NEGOBS_PORT_RECORD_QUEUE_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "negobs_port/camera.h"
#include "negobs_port/camera_replay.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Most slots a queue may have. */
#define NEGOBS_RECQ_SLOTS_MAX 16u

/** Where a recording stands. */
typedef enum negobs_recq_state {
    NEGOBS_RECQ_OFF = 0,     /**< not started                         */
    NEGOBS_RECQ_WAITING = 1, /**< started, no pair yet                */
    NEGOBS_RECQ_RECORDING = 2,
    NEGOBS_RECQ_FAILED = 3 /**< stopped by an error (see errmsg)    */
} negobs_recq_state_t;

typedef struct negobs_recq_slot {
    int32_t width;
    int32_t height;
    uint64_t ts_left_ns;
    uint64_t ts_right_ns;
    uint32_t sequence;
} negobs_recq_slot_t;

/** Queue and writer state (caller-owned; fields private). */
typedef struct negobs_record_queue {
    char dir[NEGOBS_REPLAY_PATH_MAX];
    uint8_t *buf; /**< n_slots * slot_bytes                 */
    size_t slot_bytes;
    uint32_t n_slots;
    negobs_recq_slot_t meta[NEGOBS_RECQ_SLOTS_MAX];
    negobs_recorder_t rec;
    /** write(2) by default; tests inject failing writers. */
    ssize_t (*write_fn)(int fd, const void *buf, size_t n);
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t cond;
    /* under lock */
    uint32_t head;  /**< oldest queued slot                   */
    uint32_t count; /**< queued slots                         */
    bool stop;
    bool busy; /**< the writer holds the head slot       */
    negobs_recq_state_t state;
    uint32_t written;
    uint32_t dropped;   /**< queue full: newest pair not recorded */
    uint32_t discarded; /**< queued when the recording failed     */
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
    bool running;
} negobs_record_queue_t;

/** A consistent copy of the counters. */
typedef struct negobs_recq_stats {
    negobs_recq_state_t state;
    uint32_t written;
    uint32_t dropped;
    uint32_t discarded;
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
} negobs_recq_stats_t;

/**
 * @brief Start the writer thread for a session in `dir` (created on the
 *        first pair, never over an existing session).
 * @param buf        n_slots * slot_bytes bytes for queued pixels
 * @param slot_bytes room for one pair (2 * width * height)
 * @param n_slots    1..NEGOBS_RECQ_SLOTS_MAX
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL, NEGOBS_ERR_IO (no thread).
 */
negobs_status_t negobs_recq_start(negobs_record_queue_t *q, const char *dir,
                                  uint8_t *buf, size_t slot_bytes,
                                  uint32_t n_slots);

/**
 * @brief Queue a copy of a pair; never waits for the writer.
 * @return 1 queued, 0 dropped (queue full: the newest pair, this one),
 *         -1 not recording (failed, stopped or never started), -2 the
 *         pair does not fit a slot (counted as dropped).
 */
int negobs_recq_push(negobs_record_queue_t *q,
                     const negobs_frame_pair_t *pair);

/** @brief Counters and state (thread-safe). */
void negobs_recq_stats(negobs_record_queue_t *q, negobs_recq_stats_t *out);

/** @brief Write what is queued, close the session (fdatasync) and join
 *         the writer. Safe on a queue never started. */
void negobs_recq_stop(negobs_record_queue_t *q);

/** @brief "off", "waiting", "recording", "failed". */
const char *negobs_recq_state_name(negobs_recq_state_t s);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_RECORD_QUEUE_H */
