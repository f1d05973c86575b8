/*
 * Session recorder (negobs_run --record DIR). Format in docs/RUNNING.md:
 * session.txt (magic, width, height), frames.txt (one line per pair:
 * index, left and right timestamps in ns, sequence), left.y and right.y
 * (raw 8-bit luma frames, width * height bytes each, back to back).
 * Raw frames keep recording cheap (no encoding on the device) and make
 * replay a fixed-offset read.
 *
 * Durability: every file is written with write(2), no stdio buffer, so
 * what a pair wrote is in the kernel before the next pair starts and
 * survives SIGKILL or a crash of the process. The pixels of a pair go out
 * before its frames.txt line, so an index line never names pixels that
 * were not handed to the kernel. Against power loss the files are
 * fdatasync'ed every NEGOBS_RECORDER_SYNC_PAIRS pairs and at close: at
 * most that many pairs (about one second) are lost, and replay recovers
 * what the files hold (camera_replay.h). Syncing every pair would cost an
 * SD card a flash write per pair for no gain to the wearer.
 *
 * Files are created with O_EXCL: a recorder never truncates or appends
 * to an earlier session.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "negobs_port/camera_replay.h"
#include "negobs_port/errmsg.h"

static const char *const session_files[4] = {"session.txt", "frames.txt",
                                             "left.y", "right.y"};

static void rec_msg(negobs_recorder_t *rec, const char *a, const char *b,
                    int err)
{
    negobs_port_errmsg(rec->errmsg, sizeof rec->errmsg, err, "%s%s", a, b);
}

static int join_path(char *buf, size_t len, const char *dir, const char *leaf)
{
    int n = snprintf(buf, len, "%s/%s", dir, leaf);
    return (n < 0 || (size_t)n >= len) ? -1 : 0;
}

negobs_status_t negobs_recorder_check_dir(const char *dir, char *msg,
                                          size_t msg_len)
{
    char path[NEGOBS_REPLAY_PATH_MAX + 32];
    struct stat sb;
    int i;
    if (dir == NULL || dir[0] == '\0') {
        return NEGOBS_ERR_INVAL;
    }
    if (stat(dir, &sb) == 0 && !S_ISDIR(sb.st_mode)) {
        (void)snprintf(msg, msg_len, "%s exists and is not a folder", dir);
        return NEGOBS_ERR_INVAL;
    }
    for (i = 0; i < 4; i++) {
        if (join_path(path, sizeof path, dir, session_files[i]) != 0) {
            (void)snprintf(msg, msg_len, "path too long");
            return NEGOBS_ERR_INVAL;
        }
        if (lstat(path, &sb) == 0) {
            (void)snprintf(msg, msg_len,
                           "%s already holds a session (%s): refusing to "
                           "record over it; give a new folder",
                           dir, session_files[i]);
            return NEGOBS_ERR_INVAL;
        }
    }
    return NEGOBS_OK;
}

static ssize_t plain_write(int fd, const void *buf, size_t n)
{
    return write(fd, buf, n);
}

/* All of buf, through the hook; -1 with errno set on failure. */
static int write_all(negobs_recorder_t *rec, int fd, const void *buf, size_t n)
{
    const uint8_t *p = buf;
    while (n > 0) {
        ssize_t w = rec->write_fn(fd, p, n);
        if (w < 0 && errno == EINTR) {
            continue;
        }
        if (w <= 0) {
            if (w == 0) {
                errno = ENOSPC;
            }
            return -1;
        }
        p += (size_t)w;
        n -= (size_t)w;
    }
    return 0;
}

static int create_in(negobs_recorder_t *rec, const char *dir, const char *leaf)
{
    char path[NEGOBS_REPLAY_PATH_MAX + 32];
    int fd;
    if (join_path(path, sizeof path, dir, leaf) != 0) {
        (void)snprintf(rec->errmsg, sizeof rec->errmsg, "path too long");
        return -1;
    }
    fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
        int e = errno;
        if (e == EEXIST) {
            (void)snprintf(rec->errmsg, sizeof rec->errmsg,
                           "%s already holds a session (%s): refusing to "
                           "record over it",
                           dir, leaf);
        } else {
            rec_msg(rec, path, "", e);
        }
        errno = e;
    }
    return fd;
}

negobs_status_t negobs_recorder_open(negobs_recorder_t *rec, const char *dir,
                                     int32_t width, int32_t height)
{
    char hdr[96];
    int fd;
    int n;
    if (rec == NULL || dir == NULL || width < 1 || height < 1 ||
        width > NEGOBS_MAX_DIM || height > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    memset(rec, 0, sizeof *rec);
    rec->frames_fd = rec->left_fd = rec->right_fd = -1;
    rec->width = width;
    rec->height = height;
    rec->write_fn = plain_write;
    rec->is_open = true;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        rec_msg(rec, "mkdir ", dir, errno);
        return NEGOBS_ERR_IO;
    }
    /* session.txt first: it is what marks the folder as taken. */
    fd = create_in(rec, dir, "session.txt");
    if (fd < 0) {
        return errno == EEXIST ? NEGOBS_ERR_INVAL : NEGOBS_ERR_IO;
    }
    n = snprintf(hdr, sizeof hdr, "negobs-session 1\nwidth %ld\nheight %ld\n",
                 (long)width, (long)height);
    if (write_all(rec, fd, hdr, (size_t)n) != 0) {
        rec_msg(rec, dir, "/session.txt", errno);
        (void)close(fd);
        return NEGOBS_ERR_IO;
    }
    (void)close(fd);
    rec->frames_fd = create_in(rec, dir, "frames.txt");
    if (rec->frames_fd >= 0) {
        rec->left_fd = create_in(rec, dir, "left.y");
    }
    if (rec->left_fd >= 0) {
        rec->right_fd = create_in(rec, dir, "right.y");
    }
    if (rec->right_fd < 0) {
        int e = errno;
        negobs_recorder_close(rec);
        return e == EEXIST ? NEGOBS_ERR_INVAL : NEGOBS_ERR_IO;
    }
    (void)snprintf(hdr, sizeof hdr,
                   "# index left_ts_ns right_ts_ns sequence\n");
    if (write_all(rec, rec->frames_fd, hdr, strlen(hdr)) != 0) {
        rec_msg(rec, dir, "/frames.txt", errno);
        negobs_recorder_close(rec);
        return NEGOBS_ERR_IO;
    }
    return NEGOBS_OK;
}

static int write_plane(negobs_recorder_t *rec, int fd,
                       const negobs_image_u8_t *img)
{
    int32_t y;
    if (img->stride == img->width) {
        return write_all(rec, fd, img->data,
                         (size_t)img->width * (size_t)img->height);
    }
    for (y = 0; y < img->height; y++) {
        if (write_all(rec, fd, negobs_image_u8_row(img, y),
                      (size_t)img->width) != 0) {
            return -1;
        }
    }
    return 0;
}

negobs_status_t negobs_recorder_write(negobs_recorder_t *rec,
                                      const negobs_frame_pair_t *pair)
{
    char line[96];
    int n;
    if (rec == NULL || pair == NULL || rec->frames_fd < 0) {
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
    n = snprintf(line, sizeof line, "%lu %llu %llu %lu\n",
                 (unsigned long)rec->count,
                 (unsigned long long)pair->left.ts_ns,
                 (unsigned long long)pair->right.ts_ns,
                 (unsigned long)pair->left.sequence);
    if (write_plane(rec, rec->left_fd, &pair->left.y) != 0 ||
        write_plane(rec, rec->right_fd, &pair->right.y) != 0 ||
        write_all(rec, rec->frames_fd, line, (size_t)n) != 0) {
        int e = errno;
        negobs_port_errmsg(rec->errmsg, sizeof rec->errmsg, e,
                           "write failed at pair %lu",
                           (unsigned long)rec->count);
        return NEGOBS_ERR_IO;
    }
    rec->count++;
    if (++rec->unsynced >= NEGOBS_RECORDER_SYNC_PAIRS) {
        rec->unsynced = 0;
        (void)fdatasync(rec->left_fd);
        (void)fdatasync(rec->right_fd);
        (void)fdatasync(rec->frames_fd);
    }
    return NEGOBS_OK;
}

void negobs_recorder_close(negobs_recorder_t *rec)
{
    int *all[3];
    int i;
    if (rec == NULL || !rec->is_open) {
        return;
    }
    rec->is_open = false;
    all[0] = &rec->left_fd;
    all[1] = &rec->right_fd;
    all[2] = &rec->frames_fd;
    for (i = 0; i < 3; i++) {
        if (*all[i] >= 0) {
            (void)fdatasync(*all[i]);
            (void)close(*all[i]);
            *all[i] = -1;
        }
    }
}
