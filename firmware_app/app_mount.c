/* negobs_run's remembered mounting (app_mount.h). */
#include "app_mount.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "negobs/detect.h"

static int in_priors(int32_t height_mm, int32_t pitch_mdeg)
{
    return height_mm >= APP_MOUNT_HEIGHT_MIN_MM &&
           height_mm <= APP_MOUNT_HEIGHT_MAX_MM && pitch_mdeg >= 0 &&
           pitch_mdeg <= APP_MOUNT_PITCH_MAX_MDEG;
}

int app_mount_load(const char *path, int32_t *height_mm, int32_t *pitch_mdeg,
                   char *msg, size_t msg_len)
{
    FILE *f = fopen(path, "r");
    char line[128];
    long h = -1;
    long p = -1;
    int lineno = 0;
    if (f == NULL) {
        if (errno == ENOENT) {
            return 0;
        }
        snprintf(msg, msg_len, "%s: %s", path, strerror(errno));
        return -1;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        long v;
        char key[32];
        char extra;
        lineno++;
        if (line[0] == '#' || line[0] == '\n') {
            continue;
        }
        if (sscanf(line, " %31[a-z_] = %ld %c", key, &v, &extra) != 2) {
            snprintf(msg, msg_len, "%s: line %d is not 'key = number'", path,
                     lineno);
            fclose(f);
            return -1;
        }
        if (strcmp(key, "cam_height_mm") == 0) {
            h = v;
        } else if (strcmp(key, "cam_pitch_mdeg") == 0) {
            p = v;
        } else {
            snprintf(msg, msg_len, "%s: line %d: unknown key '%s'", path,
                     lineno, key);
            fclose(f);
            return -1;
        }
    }
    fclose(f);
    if (h < 0 || p < 0) {
        snprintf(msg, msg_len, "%s: cam_height_mm or cam_pitch_mdeg missing",
                 path);
        return -1;
    }
    if (!in_priors((int32_t)(h > 100000 ? 100000 : h),
                   (int32_t)(p > 1000000 ? 1000000 : p))) {
        snprintf(msg, msg_len,
                 "%s: %ld mm / %ld mdeg is outside %d-%d mm / 0-%d mdeg", path,
                 h, p, APP_MOUNT_HEIGHT_MIN_MM, APP_MOUNT_HEIGHT_MAX_MM,
                 APP_MOUNT_PITCH_MAX_MDEG);
        return -1;
    }
    *height_mm = (int32_t)h;
    *pitch_mdeg = (int32_t)p;
    return 1;
}

int app_mount_save(const char *path, int32_t height_mm, int32_t pitch_mdeg,
                   char *msg, size_t msg_len)
{
    char tmp[512];
    FILE *f;
    int bad;
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp) {
        snprintf(msg, msg_len, "%s: path too long", path);
        return -1;
    }
    f = fopen(tmp, "w");
    if (f == NULL) {
        snprintf(msg, msg_len, "%s: %s", tmp, strerror(errno));
        return -1;
    }
    bad = fprintf(f,
                  "# negobs_run: the mounting measured on the floor (ground "
                  "under the feet)\ncam_height_mm = %ld\ncam_pitch_mdeg = "
                  "%ld\n",
                  (long)height_mm, (long)pitch_mdeg) < 0;
    bad |= fclose(f) != 0;
    if (bad) {
        snprintf(msg, msg_len, "%s: write failed", tmp);
        remove(tmp);
        return -1;
    }
    if (rename(tmp, path) != 0) {
        snprintf(msg, msg_len, "%s: %s", path, strerror(errno));
        remove(tmp);
        return -1;
    }
    return 0;
}

int app_mount_due(const app_mount_keep_t *k, int32_t ref_by, int32_t height_mm,
                  int32_t pitch_mdeg, uint32_t now_ms)
{
    int32_t dh;
    int32_t dp;
    if (ref_by != NEGOBS_GROUND_REF_HINT && ref_by != NEGOBS_GROUND_REF_FEET &&
        ref_by != NEGOBS_GROUND_REF_WALK) {
        return 0;
    }
    if (!in_priors(height_mm, pitch_mdeg)) {
        return 0;
    }
    if (k->tried &&
        (uint32_t)(now_ms - k->tried_ms) < APP_MOUNT_SAVE_EVERY_MS) {
        return 0;
    }
    if (!k->have) {
        return 1;
    }
    dh = height_mm - k->height_mm;
    dp = pitch_mdeg - k->pitch_mdeg;
    return dh >= APP_MOUNT_SAVE_DH_MM || -dh >= APP_MOUNT_SAVE_DH_MM ||
           dp >= APP_MOUNT_SAVE_DP_MDEG || -dp >= APP_MOUNT_SAVE_DP_MDEG;
}

void app_mount_saved(app_mount_keep_t *k, int32_t height_mm,
                     int32_t pitch_mdeg, uint32_t now_ms)
{
    k->have = 1;
    k->height_mm = height_mm;
    k->pitch_mdeg = pitch_mdeg;
    k->tried = 1;
    k->tried_ms = now_ms;
}

void app_mount_failed(app_mount_keep_t *k, uint32_t now_ms)
{
    k->tried = 1;
    k->tried_ms = now_ms;
}

const char *app_ground_ref_name(int32_t ref_by)
{
    static const char *const names[] = {"none", "hint", "feet", "walk",
                                        "time"};
    return (ref_by >= 0 && ref_by < 5) ? names[ref_by] : "?";
}
