/*
 * Replay source: stereo pairs from a folder, and the session recorder.
 *
 * Two folder layouts are read (docs/RUNNING.md has the details):
 *  - PGM pairs: left_0000.pgm / right_0000.pgm, left_0001.pgm, ... (binary
 *    P5, maxval <= 255), numbered from 0 without gaps; timestamps are
 *    synthesised as index / fps.
 *  - a recorded session (written by negobs_run --record DIR): session.txt,
 *    frames.txt, left.y, right.y.
 * Truncated or malformed files give NEGOBS_ERR_CORRUPT with a message in
 * errmsg() (a missing session file NEGOBS_ERR_NODEV, an unreadable one
 * NEGOBS_ERR_IO); the reader never trusts sizes from a file beyond the
 * buffer it was given. A recorded session cut short is replayed as far as
 * its files allow: see negobs_replay_damage().
 */
#ifndef NEGOBS_PORT_CAMERA_REPLAY_H
#define NEGOBS_PORT_CAMERA_REPLAY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>

#include "negobs/image.h"
#include "negobs_port/motor.h"
#include "negobs_port/camera.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest path the replay source handles. */
#define NEGOBS_REPLAY_PATH_MAX 512

/** Replay state (caller-owned; fields private). */
typedef struct negobs_replay {
    char dir[NEGOBS_REPLAY_PATH_MAX];
    uint8_t *buf; /**< caller's pixel buffer (2 images)       */
    size_t buf_bytes;
    bool session; /**< recorded-session layout                */
    bool started;
    bool loop;
    int32_t width; /**< 0 until the first frame is read        */
    int32_t height;
    int32_t want_w; /**< size the caller asked for, 0 = any     */
    int32_t want_h;
    int32_t fps;
    uint32_t next;    /**< next pair index                        */
    uint32_t n_index; /**< session: records in frames.txt         */
    uint32_t n_play;  /**< session: complete pairs in left/right.y */
    FILE *frames_txt; /**< session: timestamp list                */
    FILE *left_f;     /**< session: raw left frames               */
    FILE *right_f;
    uint64_t t0_ns;       /**< pacing: clock at start                 */
    uint64_t ts0_ns;      /**< pacing: first frame timestamp          */
    uint64_t last_due_ns; /**< delivery time of the last pair         */
    bool held;            /**< a pair is read but not yet due         */
    int32_t cur_w;        /**< the held pair: size, stamps, sequence  */
    int32_t cur_h;
    uint64_t cur_tl;
    uint64_t cur_tr;
    uint32_t cur_seq;
    negobs_capture_stats_t stats;
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
    char damage[2 * NEGOBS_PORT_ERRMSG_LEN + NEGOBS_REPLAY_PATH_MAX];
} negobs_replay_t;

/**
 * @brief Bind a replay state to a pixel buffer and fill a camera handle.
 * @param buf        pixel memory for one pair: >= 2 * width * height bytes
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 * cfg->left names the folder at open() (a "replay:" prefix is accepted);
 * cfg->right is ignored. cfg->width/height, when non-zero, must match the
 * files (NEGOBS_ERR_INVAL otherwise).
 */
negobs_status_t negobs_replay_init(negobs_replay_t *st, uint8_t *buf,
                                   size_t buf_bytes, negobs_capture_t *cam);

/**
 * @brief What is wrong with the session opened last ("" when nothing).
 *
 * A session cut short (crash, SIGKILL, full disk, power cut) may have
 * fewer frames.txt records than frames in left.y/right.y, a cut last
 * line, or a partial last frame. open() then still succeeds when at least
 * one pair is complete in both pixel files, and says here what it found
 * and how many pairs it replays; pairs past the last usable record get
 * synthesised timestamps (one frame period apart). The end of such a
 * replay is NEGOBS_ERR_CORRUPT with this text, not NEGOBS_CAPTURE_END, so
 * that a damaged session never reads as a clean one. No complete pair:
 * open() fails with NEGOBS_ERR_CORRUPT.
 */
const char *negobs_replay_damage(const negobs_replay_t *st);

/**
 * @brief Read a binary PGM (P5, maxval 1..255) into `dst` (rows packed,
 *        stride = width).
 * @param cap  bytes available at dst
 * @param[out] w,h  image size
 * @param[out] err  message on failure (may be NULL), err_len bytes
 * @return NEGOBS_OK, NEGOBS_ERR_NODEV (file missing), NEGOBS_ERR_IO,
 *         NEGOBS_ERR_CORRUPT (bad header, truncated data),
 *         NEGOBS_ERR_NOSPACE (image larger than cap).
 */
negobs_status_t negobs_pgm_read(const char *path, uint8_t *dst, size_t cap,
                                int32_t *w, int32_t *h, char *err,
                                size_t err_len);

/** @brief Write an image as binary PGM. @return NEGOBS_OK or _ERR_IO. */
negobs_status_t negobs_pgm_write(const char *path,
                                 const negobs_image_u8_t *img);

/** Pairs between two fdatasync() of the session files (about 1 s at
 *  30 fps): what a power cut can lose. See recorder.c. */
#define NEGOBS_RECORDER_SYNC_PAIRS 30u

/** Session recorder state (caller-owned; fields private except
 *  write_fn). */
typedef struct negobs_recorder {
    int frames_fd;
    int left_fd;
    int right_fd;
    bool is_open;
    int32_t width;
    int32_t height;
    uint32_t count;    /**< pairs written                          */
    uint32_t unsynced; /**< pairs since the last fdatasync         */
    /** write(2) by default; set after open() to inject failures. */
    ssize_t (*write_fn)(int fd, const void *buf, size_t n);
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
} negobs_recorder_t;

/**
 * @brief Whether DIR can take a new session: NEGOBS_OK when it does not
 *        exist or is a folder without any session file; else
 *        NEGOBS_ERR_INVAL and a message ("... already holds a session").
 *        Only looks (stat), so it can run before anything starts.
 */
negobs_status_t negobs_recorder_check_dir(const char *dir, char *msg,
                                          size_t msg_len);

/**
 * @brief Create DIR (if needed) and its session files for w x h frames.
 *        The files are created exclusively: an existing session is never
 *        truncated (NEGOBS_ERR_INVAL, "already holds a session").
 * @return NEGOBS_OK, NEGOBS_ERR_IO (see rec->errmsg), NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_recorder_open(negobs_recorder_t *rec, const char *dir,
                                     int32_t width, int32_t height);

/**
 * @brief Append a pair (luma only, rows written without padding): left.y,
 *        right.y, then its frames.txt line, each straight to the kernel.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (size differs from the session),
 *         NEGOBS_ERR_IO (disk full, ...; rec->errmsg says which).
 */
negobs_status_t negobs_recorder_write(negobs_recorder_t *rec,
                                      const negobs_frame_pair_t *pair);

/** @brief fdatasync and close the session files; safe to call twice and
 *         on a recorder that never opened. */
void negobs_recorder_close(negobs_recorder_t *rec);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CAMERA_REPLAY_H */
