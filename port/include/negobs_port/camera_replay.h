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
 * errmsg(); the reader never trusts sizes from a file beyond the buffer it
 * was given.
 */
#ifndef NEGOBS_PORT_CAMERA_REPLAY_H
#define NEGOBS_PORT_CAMERA_REPLAY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "negobs/image.h"
#include "negobs_port/alert.h"
#include "negobs_port/camera.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest path the replay source handles. */
#define NEGOBS_REPLAY_PATH_MAX 512

/** Replay state (caller-owned; fields private). */
typedef struct negobs_replay {
    char dir[NEGOBS_REPLAY_PATH_MAX];
    uint8_t *buf;          /**< caller's pixel buffer (2 images)       */
    size_t buf_bytes;
    bool session;          /**< recorded-session layout                */
    bool started;
    bool loop;
    int32_t width;         /**< 0 until the first frame is read        */
    int32_t height;
    int32_t want_w;        /**< size the caller asked for, 0 = any     */
    int32_t want_h;
    int32_t fps;
    uint32_t next;         /**< next pair index                        */
    uint32_t nframes;      /**< session: pairs listed in frames.txt    */
    FILE *frames_txt;      /**< session: timestamp list                */
    FILE *left_f;          /**< session: raw left frames               */
    FILE *right_f;
    uint64_t t0_ns;        /**< pacing: clock at start                 */
    uint64_t ts0_ns;       /**< pacing: first frame timestamp          */
    uint64_t last_due_ns;  /**< delivery time of the last pair         */
    bool held;             /**< a pair is read but not yet due         */
    int32_t cur_w;         /**< the held pair: size, stamps, sequence  */
    int32_t cur_h;
    uint64_t cur_tl;
    uint64_t cur_tr;
    uint32_t cur_seq;
    negobs_camera_stats_t stats;
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
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

/** Session recorder state (caller-owned). */
typedef struct negobs_recorder {
    FILE *frames_txt;
    FILE *left_f;
    FILE *right_f;
    int32_t width;
    int32_t height;
    uint32_t count;
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
} negobs_recorder_t;

/**
 * @brief Create DIR (if needed) and its session files for w x h frames.
 * @return NEGOBS_OK, NEGOBS_ERR_IO (see rec->errmsg), NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_recorder_open(negobs_recorder_t *rec, const char *dir,
                                     int32_t width, int32_t height);

/**
 * @brief Append a pair (luma only, rows written without padding).
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (size differs from the session),
 *         NEGOBS_ERR_IO (disk full, ...).
 */
negobs_status_t negobs_recorder_write(negobs_recorder_t *rec,
                                      const negobs_frame_pair_t *pair);

/** @brief Flush and close the session files. */
void negobs_recorder_close(negobs_recorder_t *rec);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CAMERA_REPLAY_H */
