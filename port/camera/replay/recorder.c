/*
 * Session recorder (negobs_run --record DIR). Format in docs/RUNNING.md:
 * session.txt (magic, width, height), frames.txt (one line per pair:
 * index, left and right timestamps in ns, sequence), left.y and right.y
 * (raw 8-bit luma frames, width * height bytes each, back to back).
 * Raw frames keep recording cheap (no encoding on the device) and make
 * replay a fixed-offset read.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "negobs_port/camera_replay.h"

static FILE *open_in(negobs_recorder_t *rec, const char *dir,
                     const char *leaf, const char *mode)
{
    char path[NEGOBS_REPLAY_PATH_MAX + 32];
    FILE *f;
    int n = snprintf(path, sizeof path, "%s/%s", dir, leaf);
    if (n < 0 || (size_t)n >= sizeof path) {
        (void)snprintf(rec->errmsg, sizeof rec->errmsg, "path too long");
        return NULL;
    }
    f = fopen(path, mode);
    if (f == NULL) {
        if (snprintf(rec->errmsg, sizeof rec->errmsg, "%s: %s", path,
                     strerror(errno)) < 0) {
            rec->errmsg[0] = '\0';
        }
    }
    return f;
}

negobs_status_t negobs_recorder_open(negobs_recorder_t *rec, const char *dir,
                                     int32_t width, int32_t height)
{
    FILE *hdr;
    int ok;
    if (rec == NULL || dir == NULL || width < 1 || height < 1 ||
        width > NEGOBS_MAX_DIM || height > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    memset(rec, 0, sizeof *rec);
    rec->width = width;
    rec->height = height;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        if (snprintf(rec->errmsg, sizeof rec->errmsg, "mkdir %s: %s", dir,
                     strerror(errno)) < 0) {
            rec->errmsg[0] = '\0';
        }
        return NEGOBS_ERR_IO;
    }
    hdr = open_in(rec, dir, "session.txt", "w");
    if (hdr == NULL) {
        return NEGOBS_ERR_IO;
    }
    ok = fprintf(hdr, "negobs-session 1\nwidth %ld\nheight %ld\n",
                 (long)width, (long)height) > 0;
    if (fclose(hdr) != 0 || !ok) {
        if (snprintf(rec->errmsg, sizeof rec->errmsg,
                     "%s/session.txt: write failed", dir) < 0) {
            rec->errmsg[0] = '\0';
        }
        return NEGOBS_ERR_IO;
    }
    rec->frames_txt = open_in(rec, dir, "frames.txt", "w");
    rec->left_f = open_in(rec, dir, "left.y", "wb");
    rec->right_f = open_in(rec, dir, "right.y", "wb");
    if (rec->frames_txt == NULL || rec->left_f == NULL ||
        rec->right_f == NULL) {
        negobs_recorder_close(rec);
        return NEGOBS_ERR_IO;
    }
    ok = fprintf(rec->frames_txt,
                 "# index left_ts_ns right_ts_ns sequence\n") > 0;
    return ok ? NEGOBS_OK : NEGOBS_ERR_IO;
}

static int write_plane(FILE *f, const negobs_image_u8_t *img)
{
    int32_t y;
    for (y = 0; y < img->height; y++) {
        if (fwrite(negobs_image_u8_row(img, y), 1, (size_t)img->width, f) !=
            (size_t)img->width) {
            return -1;
        }
    }
    return 0;
}

negobs_status_t negobs_recorder_write(negobs_recorder_t *rec,
                                      const negobs_frame_pair_t *pair)
{
    if (rec == NULL || pair == NULL || rec->frames_txt == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (pair->left.y.width != rec->width ||
        pair->left.y.height != rec->height ||
        pair->right.y.width != rec->width ||
        pair->right.y.height != rec->height) {
        (void)snprintf(rec->errmsg, sizeof rec->errmsg,
                       "frame size differs from the session");
        return NEGOBS_ERR_INVAL;
    }
    if (write_plane(rec->left_f, &pair->left.y) != 0 ||
        write_plane(rec->right_f, &pair->right.y) != 0 ||
        fprintf(rec->frames_txt, "%lu %llu %llu %lu\n",
                (unsigned long)rec->count,
                (unsigned long long)pair->left.ts_ns,
                (unsigned long long)pair->right.ts_ns,
                (unsigned long)pair->left.sequence) < 0) {
        (void)snprintf(rec->errmsg, sizeof rec->errmsg,
                       "write failed at pair %lu: %s",
                       (unsigned long)rec->count, strerror(errno));
        return NEGOBS_ERR_IO;
    }
    rec->count++;
    return NEGOBS_OK;
}

void negobs_recorder_close(negobs_recorder_t *rec)
{
    FILE **all[3];
    int i;
    all[0] = &rec->frames_txt;
    all[1] = &rec->left_f;
    all[2] = &rec->right_f;
    for (i = 0; i < 3; i++) {
        if (*all[i] != NULL) {
            (void)fclose(*all[i]);
            *all[i] = NULL;
        }
    }
}
