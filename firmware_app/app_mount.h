/*
 * negobs_run's remembered mounting: the camera height and pitch over the
 * ground under the feet that the detector established with evidence
 * (negobs_ground_ref_by_t HINT, FEET or WALK), kept in a small file so
 * that the next switch-on starts with them as its hints (docs/RUNNING.md,
 * "Remembered mounting"; docs/DETECTION.md 6.1).
 *
 * Why: with a hint 50 mm or more off (or none) every switch-on is
 * NO_INFO until the wearer has walked past the floor the first view
 * could not see, 1-3 m (DETECTION.md 6.2). A mounting measured on an
 * earlier walk is a better hint than a configured guess, and it is only
 * a hint: a start that disagrees with it by ground_verify_mm is still
 * unverified. A reference accepted by time alone (TIME) is never kept:
 * it may be the view of a lower floor stood before for
 * ground_drop_max_ms, and remembered it would verify the next start in
 * front of the same drop.
 *
 * The file is written in the config file's syntax (cam_height_mm = N,
 * cam_pitch_mdeg = N), to a temporary name and renamed over the old one,
 * so a reader sees the old file or the new one, never half of one.
 * Failures are reported to the caller and change nothing else: the
 * warnings never depend on this file.
 */
#ifndef NEGOBS_APP_MOUNT_H
#define NEGOBS_APP_MOUNT_H

#include <stddef.h>
#include <stdint.h>

/** A remembered height must lie in the detector's default physical
 *  prior (negobs_detect_config_t mount_height_min_mm / _max_mm), the
 *  pitch in 0-60 deg; a file outside them is refused. */
#define APP_MOUNT_HEIGHT_MIN_MM 600
#define APP_MOUNT_HEIGHT_MAX_MM 2000
#define APP_MOUNT_PITCH_MAX_MDEG 60000

/** Save again only when the reference moved this far from the file's
 *  value: 20 mm keeps the remembered hint well inside the start check's
 *  50 mm (ground_verify_mm) of the true height, and 2 deg is the walking
 *  pitch sway; both keep the writes rare. */
#define APP_MOUNT_SAVE_DH_MM 20
#define APP_MOUNT_SAVE_DP_MDEG 2000
/** ... and at most this often after the first save (flash wear). */
#define APP_MOUNT_SAVE_EVERY_MS 30000u

typedef struct app_mount_keep {
    int32_t have;      /**< height_mm / pitch_mdeg hold the file's value */
    int32_t height_mm; /**< last value loaded or saved                   */
    int32_t pitch_mdeg;
    int32_t tried;     /**< a save tried (done or failed) by this run    */
    uint32_t tried_ms; /**< when the last one was                        */
} app_mount_keep_t;

/**
 * @brief Read a remembered mounting.
 * @return 1 read (outputs set), 0 no such file, -1 unreadable or
 *         malformed or outside the priors (msg says which).
 */
int app_mount_load(const char *path, int32_t *height_mm, int32_t *pitch_mdeg,
                   char *msg, size_t msg_len);

/**
 * @brief Write a remembered mounting (temporary file, then rename).
 * @return 0, or -1 with msg set; the old file is then unchanged.
 */
int app_mount_save(const char *path, int32_t height_mm, int32_t pitch_mdeg,
                   char *msg, size_t msg_len);

/**
 * @brief Should this frame's reference be saved? 1 when it is evidence
 *        (by HINT, FEET or WALK), inside the priors, and either nothing is
 *        remembered yet or it moved APP_MOUNT_SAVE_DH_MM / _DP_MDEG from
 *        it, and APP_MOUNT_SAVE_EVERY_MS passed since this run's last
 *        try. The caller saves, then calls app_mount_saved() or
 *        app_mount_failed().
 */
int app_mount_due(const app_mount_keep_t *k, int32_t ref_by, int32_t height_mm,
                  int32_t pitch_mdeg, uint32_t now_ms);

/** @brief Note a successful save: it is what is remembered now. */
void app_mount_saved(app_mount_keep_t *k, int32_t height_mm,
                     int32_t pitch_mdeg, uint32_t now_ms);

/**
 * @brief Note a failed save: what is remembered is unchanged, and the
 *        next try waits APP_MOUNT_SAVE_EVERY_MS like the next save would
 *        (a full or read-only card is not written every frame).
 */
void app_mount_failed(app_mount_keep_t *k, uint32_t now_ms);

/** @brief negobs_ground_ref_by_t as logs write it. */
const char *app_ground_ref_name(int32_t ref_by);

#endif
