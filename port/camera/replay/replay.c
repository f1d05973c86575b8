/*
 * Replay camera source: PGM pair folders and recorded sessions.
 *
 * Both layouts are read sequentially into the caller's buffer (left image
 * in the first half, right in the second, stride = width). Every size that
 * comes from a file is checked against NEGOBS_MAX_DIM and the buffer
 * before use, and every short read is a NEGOBS_ERR_CORRUPT with the file
 * name in errmsg(), so a damaged recording stops a replay cleanly.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "negobs_port/camera_replay.h"
#include "negobs_port/clock.h"
#include "negobs_port/errmsg.h"

/* errmsg, with ": strerror(err)" when err != 0 (negobs_port_verrmsg). */
static void rp_error(negobs_replay_t *st, int err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    /* va_start() is above; clang-tidy 14 reports this false positive
     * only when it analyses several files in one run. */
    /* NOLINTNEXTLINE(clang-analyzer-valist.Uninitialized) */
    negobs_port_verrmsg(st->errmsg, sizeof st->errmsg, err, fmt, ap);
    va_end(ap);
}

static int join(char *buf, size_t len, const char *dir, const char *leaf)
{
    int n = snprintf(buf, len, "%s/%s", dir, leaf);
    return (n < 0 || (size_t)n >= len) ? -1 : 0;
}

/* Parse up to n unsigned decimal fields separated by blanks; the rest of
 * the line may only be blanks. Returns the fields read, -1 on junk. */
static int parse_fields(const char *s, unsigned long long *out, int n)
{
    int k = 0;
    for (;;) {
        char *end = NULL;
        while (*s == ' ' || *s == '\t') {
            s++;
        }
        if (*s == '\0' || *s == '\n' || *s == '\r') {
            return k;
        }
        if (k == n || *s < '0' || *s > '9') {
            return -1;
        }
        errno = 0;
        out[k] = strtoull(s, &end, 10);
        if (errno != 0 || end == s) {
            return -1;
        }
        k++;
        s = end;
        if (*s != ' ' && *s != '\t' && *s != '\0' && *s != '\n' &&
            *s != '\r') {
            return -1;
        }
    }
}

static bool file_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

static void close_files(negobs_replay_t *st)
{
    if (st->frames_txt != NULL) {
        (void)fclose(st->frames_txt);
        st->frames_txt = NULL;
    }
    if (st->left_f != NULL) {
        (void)fclose(st->left_f);
        st->left_f = NULL;
    }
    if (st->right_f != NULL) {
        (void)fclose(st->right_f);
        st->right_f = NULL;
    }
}

/* session.txt: "negobs-session 1", "width W", "height H", any order after
 * the first line; '#' comments. */
static negobs_status_t read_session_header(negobs_replay_t *st)
{
    char path[NEGOBS_REPLAY_PATH_MAX + 32];
    char line[128];
    FILE *f;
    long w = 0;
    long h = 0;
    bool magic = false;
    if (join(path, sizeof path, st->dir, "session.txt") != 0) {
        return NEGOBS_ERR_INVAL;
    }
    f = fopen(path, "r");
    if (f == NULL) {
        rp_error(st, errno, "%s", path);
        return NEGOBS_ERR_IO;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        char *val;
        unsigned long long v;
        if (line[0] == '#' || line[0] == '\n') {
            continue;
        }
        /* "key number": split at the first blank. */
        val = strpbrk(line, " \t");
        if (val == NULL || parse_fields(val, &v, 1) != 1 ||
            v > (unsigned long long)NEGOBS_MAX_DIM * 16u) {
            break;
        }
        *val = '\0';
        if (!magic) {
            magic = strcmp(line, "negobs-session") == 0 && v == 1u;
            if (!magic) {
                break;
            }
        } else if (strcmp(line, "width") == 0) {
            w = (long)v;
        } else if (strcmp(line, "height") == 0) {
            h = (long)v;
        }
    }
    (void)fclose(f);
    if (!magic) {
        rp_error(st, 0, "%s: not a version-1 negobs session", path);
        return NEGOBS_ERR_CORRUPT;
    }
    if (w < 1 || h < 1 || w > NEGOBS_MAX_DIM || h > NEGOBS_MAX_DIM) {
        rp_error(st, 0, "%s: bad or missing width/height", path);
        return NEGOBS_ERR_CORRUPT;
    }
    st->width = (int32_t)w;
    st->height = (int32_t)h;
    return NEGOBS_OK;
}

static negobs_status_t open_session_files(negobs_replay_t *st)
{
    char path[NEGOBS_REPLAY_PATH_MAX + 32];
    static const char *const names[3] = {"frames.txt", "left.y", "right.y"};
    FILE **slots[3];
    int i;
    slots[0] = &st->frames_txt;
    slots[1] = &st->left_f;
    slots[2] = &st->right_f;
    for (i = 0; i < 3; i++) {
        if (join(path, sizeof path, st->dir, names[i]) != 0) {
            return NEGOBS_ERR_INVAL;
        }
        *slots[i] = fopen(path, i == 0 ? "r" : "rb");
        if (*slots[i] == NULL) {
            int e = errno;
            rp_error(st, e, "%s", path);
            close_files(st);
            return e == ENOENT ? NEGOBS_ERR_NODEV : NEGOBS_ERR_IO;
        }
    }
    return NEGOBS_OK;
}

/* Records in frames.txt (lines that are not comments or blank); a last
 * line without its newline (cut by a crash or a full disk) is not one. */
static uint32_t count_records(FILE *f, bool *torn)
{
    uint32_t n = 0;
    int c;
    bool start = true;
    bool content = false;
    *torn = false;
    while ((c = getc(f)) != EOF) {
        if (start) {
            content = c != '#' && c != '\n';
            start = false;
        }
        if (c == '\n') {
            n += content ? 1u : 0u;
            start = true;
            content = false;
        }
    }
    *torn = !start && content;
    rewind(f);
    return n;
}

/* Size of a regular file; -1 for anything else (a FIFO or a device
 * streams its frames: its size says nothing, nothing is recovered). */
static int64_t file_bytes(FILE *f)
{
    struct stat sb;
    return (fstat(fileno(f), &sb) == 0 && S_ISREG(sb.st_mode))
               ? (int64_t)sb.st_size
               : -1;
}

/* A session cut short (crash, SIGKILL, full disk, power cut): frames.txt
 * and the two pixel files may disagree. Replay the pairs whose pixels are
 * complete in both files; past the last usable frames.txt record their
 * timestamps are synthesised (one frame period apart). Say what was
 * recovered; nothing at all is an error. */
static negobs_status_t check_session_damage(negobs_replay_t *st)
{
    uint64_t frame = (uint64_t)st->width * (uint64_t)st->height;
    int64_t lb = file_bytes(st->left_f);
    int64_t rb = file_bytes(st->right_f);
    uint64_t n64;
    uint32_t nl;
    uint32_t nr;
    bool torn = false;
    int n;
    st->damage[0] = '\0';
    st->n_index = file_bytes(st->frames_txt) >= 0
                      ? count_records(st->frames_txt, &torn)
                      : UINT32_MAX;
    if (lb < 0 || rb < 0) {
        /* streamed pixels: the index alone says how many pairs */
        st->n_play = st->n_index;
        return NEGOBS_OK;
    }
    /* more frames than a uint32 index counts are not replayed */
    n64 = (uint64_t)lb / frame;
    nl = n64 > UINT32_MAX - 1u ? UINT32_MAX - 1u : (uint32_t)n64;
    n64 = (uint64_t)rb / frame;
    nr = n64 > UINT32_MAX - 1u ? UINT32_MAX - 1u : (uint32_t)n64;
    st->n_play = nl < nr ? nl : nr;
    if (st->n_play == 0) {
        rp_error(st, 0,
                 "%s: damaged session, no complete pair to replay "
                 "(frames.txt lists %lu, left.y %llu bytes, right.y %llu "
                 "bytes, %lu per frame)",
                 st->dir, (unsigned long)st->n_index, (unsigned long long)lb,
                 (unsigned long long)rb, (unsigned long)frame);
        return NEGOBS_ERR_CORRUPT;
    }
    if (st->n_index == st->n_play && nl == nr && !torn &&
        (uint64_t)lb % frame == 0 && (uint64_t)rb % frame == 0) {
        return NEGOBS_OK;
    }
    n = snprintf(st->damage, sizeof st->damage,
                 "damaged session %s: frames.txt lists %lu pairs%s, left.y "
                 "holds %lu and right.y %lu complete frames (+%lu/+%lu "
                 "bytes); replaying %lu pairs",
                 st->dir, (unsigned long)st->n_index,
                 torn ? " and a cut line" : "", (unsigned long)nl,
                 (unsigned long)nr, (unsigned long)((uint64_t)lb % frame),
                 (unsigned long)((uint64_t)rb % frame),
                 (unsigned long)st->n_play);
    if (n > 0 && st->n_index < st->n_play && (size_t)n < sizeof st->damage) {
        (void)snprintf(st->damage + n, sizeof st->damage - (size_t)n,
                       ", %lu with synthesised timestamps",
                       (unsigned long)(st->n_play - st->n_index));
    }
    return NEGOBS_OK;
}

static negobs_status_t rp_open(void *ctx, const negobs_capture_config_t *cfg)
{
    negobs_replay_t *st = ctx;
    char path[NEGOBS_REPLAY_PATH_MAX + 32];
    const char *dir;
    negobs_status_t s;
    if (cfg == NULL || cfg->left == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    dir = cfg->left;
    if (strncmp(dir, "replay:", 7) == 0) {
        dir += 7;
    }
    if (strlen(dir) >= sizeof st->dir) {
        rp_error(st, 0, "replay folder name too long");
        return NEGOBS_ERR_INVAL;
    }
    close_files(st);
    memcpy(st->dir, dir, strlen(dir) + 1u); /* length checked above */
    st->fps = cfg->fps > 0 ? cfg->fps : 0;
    st->loop = cfg->loop;
    st->next = 0;
    st->held = false;
    st->width = 0;
    st->height = 0;
    st->started = false;
    st->damage[0] = '\0';
    memset(&st->stats, 0, sizeof st->stats);

    if (join(path, sizeof path, st->dir, "left_0000.pgm") != 0) {
        return NEGOBS_ERR_INVAL;
    }
    if (file_exists(path)) {
        st->session = false;
    } else {
        if (join(path, sizeof path, st->dir, "session.txt") != 0) {
            return NEGOBS_ERR_INVAL;
        }
        if (!file_exists(path)) {
            rp_error(st, 0, "%s: no left_0000.pgm and no session.txt",
                     st->dir);
            return NEGOBS_ERR_NODEV;
        }
        st->session = true;
        s = read_session_header(st);
        if (s != NEGOBS_OK) {
            return s;
        }
        if (2u * (size_t)st->width * (size_t)st->height > st->buf_bytes) {
            rp_error(st, 0, "%s: %ldx%ld frames exceed the replay buffer",
                     st->dir, (long)st->width, (long)st->height);
            return NEGOBS_ERR_NOSPACE;
        }
        if (cfg->width > 0 && cfg->height > 0 &&
            (cfg->width != st->width || cfg->height != st->height)) {
            rp_error(st, 0, "%s: session is %ldx%ld, %ldx%ld requested",
                     st->dir, (long)st->width, (long)st->height,
                     (long)cfg->width, (long)cfg->height);
            return NEGOBS_ERR_INVAL;
        }
        s = open_session_files(st);
        if (s == NEGOBS_OK) {
            s = check_session_damage(st);
        }
        if (s != NEGOBS_OK) {
            close_files(st);
            return s;
        }
    }
    /* For PGM folders the requested size is checked on the first frame. */
    st->want_w = cfg->width > 0 && cfg->height > 0 ? cfg->width : 0;
    st->want_h = cfg->width > 0 && cfg->height > 0 ? cfg->height : 0;
    return NEGOBS_OK;
}

static negobs_status_t rp_start(void *ctx)
{
    negobs_replay_t *st = ctx;
    st->started = true;
    st->t0_ns = negobs_clock_now_ns();
    st->ts0_ns = 0;
    return NEGOBS_OK;
}

static void fill_frame(negobs_frame_t *f, uint8_t *data, int32_t w, int32_t h,
                       uint64_t ts, uint32_t seq)
{
    f->y.data = data;
    f->y.width = w;
    f->y.height = h;
    f->y.stride = w;
    f->ts_ns = ts;
    f->sequence = seq;
}

/* Read pair `idx` of a PGM folder. NEGOBS_CAPTURE_END when left is gone. */
static int read_pgm_pair(negobs_replay_t *st, uint32_t idx, int32_t *w,
                         int32_t *h)
{
    char leaf[32];
    char path[NEGOBS_REPLAY_PATH_MAX + 32];
    size_t half = st->buf_bytes / 2;
    int32_t rw;
    int32_t rh;
    negobs_status_t s;
    char err[NEGOBS_PORT_ERRMSG_LEN];
    (void)snprintf(leaf, sizeof leaf, "left_%04u.pgm", (unsigned)idx);
    if (join(path, sizeof path, st->dir, leaf) != 0) {
        return NEGOBS_ERR_INVAL;
    }
    s = negobs_pgm_read(path, st->buf, half, w, h, err, sizeof err);
    if (s == NEGOBS_ERR_NODEV) {
        return NEGOBS_CAPTURE_END;
    }
    if (s != NEGOBS_OK) {
        rp_error(st, 0, "%s", err);
        return s;
    }
    (void)snprintf(leaf, sizeof leaf, "right_%04u.pgm", (unsigned)idx);
    if (join(path, sizeof path, st->dir, leaf) != 0) {
        return NEGOBS_ERR_INVAL;
    }
    /* Right image right after the left one, so frames stay packed. */
    s = negobs_pgm_read(path, st->buf + (size_t)*w * (size_t)*h,
                        st->buf_bytes - (size_t)*w * (size_t)*h, &rw, &rh, err,
                        sizeof err);
    if (s != NEGOBS_OK) {
        rp_error(st, 0, "%s", err);
        return s == NEGOBS_ERR_NODEV ? NEGOBS_ERR_CORRUPT : s;
    }
    if (rw != *w || rh != *h) {
        rp_error(st, 0, "%s: right image size differs from left", path);
        return NEGOBS_ERR_CORRUPT;
    }
    return NEGOBS_OK;
}

/* Timestamps for pairs past the last usable frames.txt record: one frame
 * period after the previous pair (the recording's mean interval, else the
 * replay fps, else 30 fps). */
static void synth_stamp(negobs_replay_t *st, uint64_t *tl, uint64_t *tr,
                        uint32_t *seq)
{
    uint64_t period = 33333333u;
    if (st->next > 1 && st->cur_tl > st->ts0_ns) {
        period = (st->cur_tl - st->ts0_ns) / (st->next - 1u);
    } else if (st->fps > 0) {
        period = 1000000000u / (uint64_t)st->fps;
    }
    *tl = st->next > 0 ? st->cur_tl + period : 0;
    *tr = *tl + (st->next > 0 ? st->cur_tr - st->cur_tl : 0);
    *seq = st->next > 0 ? st->cur_seq + 1u : 0;
}

/* Read the next session record. */
static int read_session_pair(negobs_replay_t *st, uint64_t *tl, uint64_t *tr,
                             uint32_t *seq)
{
    char line[160];
    size_t frame = (size_t)st->width * (size_t)st->height;
    unsigned long long fld[4];
    if (st->next >= st->n_play) {
        return NEGOBS_CAPTURE_END;
    }
    if (st->next < st->n_index) {
        for (;;) {
            if (fgets(line, sizeof line, st->frames_txt) == NULL) {
                if (st->n_index == UINT32_MAX) {
                    return NEGOBS_CAPTURE_END; /* a streamed index ended */
                }
                rp_error(st, 0, "%s/frames.txt: changed while replaying",
                         st->dir);
                return NEGOBS_ERR_CORRUPT;
            }
            if (line[0] != '#' && line[0] != '\n') {
                break;
            }
        }
        if (strchr(line, '\n') == NULL) {
            rp_error(st, 0, "%s/frames.txt: line too long", st->dir);
            return NEGOBS_ERR_CORRUPT;
        }
        if (parse_fields(line, fld, 4) != 4 || fld[0] != st->next) {
            rp_error(st, 0, "%s/frames.txt: bad record for pair %u", st->dir,
                     (unsigned)st->next);
            return NEGOBS_ERR_CORRUPT;
        }
        *tl = (uint64_t)fld[1];
        *tr = (uint64_t)fld[2];
        *seq = (uint32_t)fld[3];
    } else {
        synth_stamp(st, tl, tr, seq);
    }
    if (fread(st->buf, 1, frame, st->left_f) != frame) {
        rp_error(st, 0, "%s/left.y: truncated at pair %u", st->dir,
                 (unsigned)st->next);
        return NEGOBS_ERR_CORRUPT;
    }
    if (fread(st->buf + frame, 1, frame, st->right_f) != frame) {
        rp_error(st, 0, "%s/right.y: truncated at pair %u", st->dir,
                 (unsigned)st->next);
        return NEGOBS_ERR_CORRUPT;
    }
    return NEGOBS_OK;
}

static int rp_rewind(negobs_replay_t *st)
{
    /* The first pair of the next round is due one frame period after the
     * last one, so a looped replay keeps its rate. For sessions the period
     * is the recording's mean frame interval. */
    uint64_t period = 0;
    if (st->session && st->next > 1 && st->cur_tl > st->ts0_ns) {
        period = (st->cur_tl - st->ts0_ns) / (st->next - 1u);
    } else if (st->fps > 0) {
        period = 1000000000u / (uint64_t)st->fps;
    }
    st->t0_ns = st->last_due_ns + period;
    st->next = 0;
    st->ts0_ns = 0;
    if (st->session) {
        rewind(st->frames_txt);
        rewind(st->left_f);
        rewind(st->right_f);
    }
    return NEGOBS_OK;
}

/* Read the next pair into the buffer and the cur_* fields. */
static int rp_read_next(negobs_replay_t *st)
{
    int32_t w = 0;
    int32_t h = 0;
    uint64_t tl = 0;
    uint64_t tr = 0;
    uint32_t seq = 0;
    int rc;
    bool rewound = false;
    for (;;) {
        if (st->session) {
            rc = read_session_pair(st, &tl, &tr, &seq);
            w = st->width;
            h = st->height;
        } else {
            rc = read_pgm_pair(st, st->next, &w, &h);
            seq = st->next;
        }
        if (rc == NEGOBS_CAPTURE_END && st->loop && !rewound && st->next > 0) {
            rewound = true;
            (void)rp_rewind(st);
            continue;
        }
        break;
    }
    if (rc == NEGOBS_CAPTURE_END && st->session && st->damage[0] != '\0') {
        /* the end of a damaged session is not a clean end */
        rp_error(st, 0,
                 "damaged session: all %lu recoverable pairs replayed "
                 "(%lu of them without a frames.txt record)",
                 (unsigned long)st->n_play,
                 (unsigned long)(st->n_play > st->n_index
                                     ? st->n_play - st->n_index
                                     : 0u));
        return NEGOBS_ERR_CORRUPT;
    }
    if (rc != NEGOBS_OK) {
        return rc;
    }
    if (!st->session) {
        if (st->want_w > 0 && (w != st->want_w || h != st->want_h)) {
            rp_error(st, 0, "%s: images are %ldx%ld, %ldx%ld requested",
                     st->dir, (long)w, (long)h, (long)st->want_w,
                     (long)st->want_h);
            return NEGOBS_ERR_INVAL;
        }
        if (st->width > 0 && (w != st->width || h != st->height)) {
            rp_error(st, 0, "%s: pair %u changes the image size", st->dir,
                     (unsigned)st->next);
            return NEGOBS_ERR_CORRUPT;
        }
        st->width = w;
        st->height = h;
        tl = st->fps > 0 ? (uint64_t)st->next * 1000000000u / (uint64_t)st->fps
                         : 0;
        tr = tl;
    }
    if (st->next == 0) {
        st->ts0_ns = tl;
    }
    st->cur_w = w;
    st->cur_h = h;
    st->cur_tl = tl;
    st->cur_tr = tr;
    st->cur_seq = seq;
    st->held = true;
    return NEGOBS_OK;
}

static int rp_get_pair(void *ctx, negobs_frame_pair_t *pair,
                       int32_t timeout_ms)
{
    negobs_replay_t *st = ctx;
    uint64_t due;
    uint64_t now;
    int rc;
    if (!st->started || pair == NULL) {
        return NEGOBS_ERR_STATE;
    }
    if (!st->held) {
        rc = rp_read_next(st);
        if (rc != NEGOBS_OK) {
            return rc;
        }
    }
    /* Pacing: pair i is due at start + (its timestamp - the first one).
     * A pair not due within the timeout is held for the next call. */
    now = negobs_clock_now_ns();
    due = now;
    if (st->fps > 0 && st->cur_tl >= st->ts0_ns) {
        due = st->t0_ns + (st->cur_tl - st->ts0_ns);
        if (due > now && timeout_ms >= 0 &&
            due - now > (uint64_t)timeout_ms * 1000000u) {
            negobs_clock_sleep_until_ns(now + (uint64_t)timeout_ms * 1000000u,
                                        NULL);
            st->stats.timeouts++;
            return NEGOBS_ERR_TIMEOUT;
        }
        if (due > now) {
            negobs_clock_sleep_until_ns(due, NULL);
        } else {
            due = now; /* late (slow consumer): stamp with delivery time */
        }
    }
    st->held = false;
    st->last_due_ns = due;
    fill_frame(&pair->left, st->buf, st->cur_w, st->cur_h, due, st->cur_seq);
    fill_frame(&pair->right, st->buf + (size_t)st->cur_w * (size_t)st->cur_h,
               st->cur_w, st->cur_h, due + (st->cur_tr - st->cur_tl),
               st->cur_seq);
    pair->index = st->stats.pairs;
    st->stats.pairs++;
    st->next++;
    return NEGOBS_OK;
}

static void rp_release(void *ctx, negobs_frame_pair_t *pair)
{
    (void)ctx;
    (void)pair;
}

static void rp_stop(void *ctx)
{
    negobs_replay_t *st = ctx;
    st->started = false;
}

static void rp_close(void *ctx)
{
    close_files((negobs_replay_t *)ctx);
}

static void rp_stats(void *ctx, negobs_capture_stats_t *out)
{
    *out = ((negobs_replay_t *)ctx)->stats;
}

static const char *rp_errmsg(void *ctx)
{
    return ((negobs_replay_t *)ctx)->errmsg;
}

const char *negobs_replay_damage(const negobs_replay_t *st)
{
    return st != NULL ? st->damage : "";
}

static const negobs_capture_ops_t replay_ops = {
    .name = "replay",
    .open = rp_open,
    .start = rp_start,
    .get_pair = rp_get_pair,
    .release = rp_release,
    .stop = rp_stop,
    .close = rp_close,
    .stats = rp_stats,
    .errmsg = rp_errmsg,
};

negobs_status_t negobs_replay_init(negobs_replay_t *st, uint8_t *buf,
                                   size_t buf_bytes, negobs_capture_t *cam)
{
    if (st == NULL || buf == NULL || buf_bytes < 2 || cam == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(st, 0, sizeof *st);
    st->buf = buf;
    st->buf_bytes = buf_bytes;
    cam->ops = &replay_ops;
    cam->ctx = st;
    return NEGOBS_OK;
}
