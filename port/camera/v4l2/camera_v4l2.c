/*
 * V4L2 stereo capture (two nodes, MMAP streaming), after v4l-utils'
 * capture-example.c, with a handle instead of globals and statuses instead
 * of exit(): QUERYCAP -> S_FMT (re-read: the driver may change it) ->
 * S_PARM -> REQBUFS -> QUERYBUF + mmap -> QBUF all -> STREAMON; then
 * poll + DQBUF, and QBUF again when the application releases the pair.
 *
 * Pairing. Each node keeps at most one dequeued frame waiting for its
 * partner; when both wait, negobs_pair_decide() matches them or drops the
 * older one. When a node has several frames ready, only the newest is
 * kept (older ones are requeued and counted as stale), so the pipeline
 * always works on the freshest pair instead of a growing backlog.
 *
 * Frozen content. A driver or ISP that hangs may keep handing out the same
 * image; every dequeued frame's sampled signature is compared with that
 * node's previous one, and while frozen_frames frames in a row were
 * identical the pair is requeued and get_pair returns NEGOBS_ERR_IO
 * ("frozen: ..."), so the caller plays no-information instead of judging a
 * stale view. The first frame that changes clears it.
 *
 * Drift. Pairs further apart than pair_tol_ms are dropped; when nothing
 * could be paired before the timeout although frames arrived, the timeout
 * says so ("left/right out of sync: ...") rather than "no frames".
 *
 * Device loss. ENODEV/EIO from an ioctl, POLLERR/POLLHUP, or several poll
 * timeouts in a row mark a node lost: it is closed, and get_pair tries to
 * reopen it with exponential back-off, returning NEGOBS_ERR_NODEV (after
 * waiting at most its timeout) until it is back.
 *
 * One node's setup and teardown (open, format, buffers, controls) live in
 * v4l2_dev.c.
 */
#define _DEFAULT_SOURCE

#include <errno.h>
#include <poll.h>
#include <string.h>

#include <linux/videodev2.h>

#include "negobs_port/camera_list.h"
#include "negobs_port/camera_v4l2.h"
#include "negobs_port/clock.h"
#include "v4l2_internal.h"

/* Scratch per node: the larger need of the open nodes. */
static size_t node_scratch_bytes(const negobs_v4l2_t *st)
{
    size_t a = negobs_v4l2_conv_scratch_bytes(&st->dev[0].conv);
    size_t b = st->nodes == 2
                   ? negobs_v4l2_conv_scratch_bytes(&st->dev[1].conv)
                   : 0u;
    return a > b ? a : b;
}

static const char *fourcc_name(uint32_t f, char s[5])
{
    int i;
    for (i = 0; i < 4; i++) {
        s[i] = (char)((f >> (8 * i)) & 0x7Fu);
    }
    s[4] = '\0';
    return s;
}

static const char *strip_prefix(const char *p)
{
    return strncmp(p, "v4l2:", 5) == 0 ? p + 5 : p;
}

static negobs_status_t v_open(void *ctx, const negobs_capture_config_t *cfg)
{
    negobs_v4l2_t *st = ctx;
    negobs_status_t s;
    int i;
    if (cfg == NULL || cfg->left == NULL ||
        (cfg->right == NULL && !cfg->side_by_side)) {
        return NEGOBS_ERR_INVAL;
    }
    st->cfg = *cfg;
    st->nodes = cfg->side_by_side ? 1 : 2;
    if (st->cfg.width <= 0) {
        st->cfg.width = 640;
    }
    if (st->cfg.height <= 0) {
        st->cfg.height = 480;
    }
    if (st->cfg.pair_tol_ms < 0) {
        st->cfg.pair_tol_ms = NEGOBS_CAPTURE_PAIR_TOL_MS_DEFAULT;
    }
    memset(&st->stats, 0, sizeof st->stats);
    for (i = 0; i < 2; i++) {
        const char *p = strip_prefix(i == 0 || cfg->side_by_side ? cfg->left
                                                                 : cfg->right);
        negobs_v4l2_dev_t *d = &st->dev[i];
        memset(d, 0, sizeof *d);
        v4l2_dev_reset(d);
        if (strlen(p) >= sizeof d->path) {
            return NEGOBS_ERR_INVAL;
        }
        memcpy(d->path, p, strlen(p) + 1u); /* length checked above */
    }
    for (i = 0; i < st->nodes; i++) {
        s = v4l2_dev_open(st, &st->dev[i]);
        if (s != NEGOBS_OK) {
            v4l2_dev_close(&st->dev[0]);
            return s;
        }
    }
    if (st->nodes == 2 && (st->dev[0].width != st->dev[1].width ||
                           st->dev[0].height != st->dev[1].height)) {
        v4l2_error(st, 0, "cameras disagree on size: %ldx%ld vs %ldx%ld",
                   (long)st->dev[0].width, (long)st->dev[0].height,
                   (long)st->dev[1].width, (long)st->dev[1].height);
        v4l2_dev_close(&st->dev[0]);
        v4l2_dev_close(&st->dev[1]);
        return NEGOBS_ERR_UNSUPPORTED;
    }
    {
        char cc[5];
        size_t need = (size_t)st->nodes *
                      node_scratch_bytes(st); /* per node, the larger */
        if (need > 0u && (st->scratch == NULL || st->scratch_bytes < need)) {
            v4l2_error(st, 0, "format %s needs %lu bytes of scratch",
                       fourcc_name(st->dev[0].fourcc, cc),
                       (unsigned long)need);
            v4l2_dev_close(&st->dev[0]);
            v4l2_dev_close(&st->dev[1]);
            return NEGOBS_ERR_NOSPACE;
        }
    }
    v4l2_apply_controls(st);
    return NEGOBS_OK;
}

static negobs_status_t v_start(void *ctx)
{
    negobs_v4l2_t *st = ctx;
    int i;
    for (i = 0; i < st->nodes; i++) {
        negobs_status_t s = v4l2_dev_start(st, &st->dev[i]);
        if (s != NEGOBS_OK) {
            return s;
        }
    }
    st->started = true;
    return NEGOBS_OK;
}

static void mark_lost(negobs_v4l2_t *st, negobs_v4l2_dev_t *d, int err,
                      const char *what)
{
    v4l2_error(st, err, "%s: %s, reopening", d->path, what);
    v4l2_dev_close(d);
    d->lost = true;
    d->backoff_ms = negobs_v4l2_backoff_ms(0);
    d->retry_at_ms = negobs_clock_now_ms() + d->backoff_ms;
    st->stats.device_losses++;
}

static void try_reopen(negobs_v4l2_t *st, negobs_v4l2_dev_t *d, uint64_t now)
{
    negobs_v4l2_dev_t *other = d == &st->dev[0] ? &st->dev[1] : &st->dev[0];
    negobs_status_t s;
    if (now < d->retry_at_ms) {
        return;
    }
    s = v4l2_dev_open(st, d);
    if (s == NEGOBS_OK && other->fd >= 0 &&
        (d->width != other->width || d->height != other->height)) {
        v4l2_error(st, 0, "%s: came back with another size", d->path);
        v4l2_dev_close(d);
        s = NEGOBS_ERR_UNSUPPORTED;
    }
    if (s == NEGOBS_OK) {
        s = v4l2_dev_start(st, d);
        if (s != NEGOBS_OK) {
            v4l2_dev_close(d);
        }
    }
    if (s == NEGOBS_OK) {
        d->lost = false;
        st->stats.reopens++;
        v4l2_apply_controls(st);
        return;
    }
    d->backoff_ms = d->backoff_ms >= NEGOBS_V4L2_BACKOFF_MAX_MS / 2u
                        ? NEGOBS_V4L2_BACKOFF_MAX_MS
                        : d->backoff_ms * 2u;
    d->retry_at_ms = now + d->backoff_ms;
}

/* Every dequeued frame counts, not only those paired: the check then runs
 * at the camera's rate, whatever the pipeline's. The raw bytes of the
 * first plane are sampled (rows of bytesperline; MJPEG: the compressed
 * data, negobs_v4l2_conv_raw_view()): any format's bytes change with
 * sensor noise. */
static bool frame_frozen(negobs_v4l2_t *st, negobs_v4l2_dev_t *d, uint32_t idx,
                         uint32_t bytesused)
{
    negobs_image_u8_t raw;
    negobs_v4l2_conv_raw_view(&d->conv, d->buf[idx].start, bytesused, &raw);
    return negobs_frozen_update(&d->frozen, negobs_frame_signature(&raw),
                                st->cfg.frozen_frames);
}

/* Dequeue everything ready on a node, keeping only the newest frame. */
static void drain(negobs_v4l2_t *st, negobs_v4l2_dev_t *d)
{
    for (;;) {
        struct v4l2_buffer b;
        memset(&b, 0, sizeof b);
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        if (v4l2_xioctl(d->fd, VIDIOC_DQBUF, &b) != 0) {
            int e = errno;
            if (e != EAGAIN) {
                mark_lost(st, d, e, "VIDIOC_DQBUF");
            }
            return;
        }
        if (b.index >= d->nbuf) {
            continue; /* cannot happen with a sane driver; never index it */
        }
        if ((b.flags & V4L2_BUF_FLAG_ERROR) != 0 ||
            b.bytesused > d->buf[b.index].length ||
            b.bytesused < negobs_v4l2_frame_bytes(d->fourcc, d->height,
                                                  d->bytesperline) /
                              2u) {
            st->stats.short_frames++;
            (void)v4l2_dev_queue(d, b.index);
            continue;
        }
        if (d->pending) {
            st->stats.stale_frames++;
            (void)v4l2_dev_queue(d, d->pend_idx);
        }
        d->pending = true;
        d->pend_at_ms = negobs_clock_now_ms();
        d->pend_frozen = frame_frozen(st, d, b.index, b.bytesused);
        d->pend_idx = b.index;
        d->pend_bytes = b.bytesused;
        d->pend_seq = b.sequence;
        if ((b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) ==
            V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
            d->pend_ts = (uint64_t)b.timestamp.tv_sec * 1000000000u +
                         (uint64_t)b.timestamp.tv_usec * 1000u;
        } else {
            d->pend_ts = negobs_clock_now_ns();
        }
        d->timeouts_in_row = 0;
    }
}

/* Side by side (f2 != NULL): both eyes from node 0's one buffer. */
static negobs_status_t make_frame(negobs_v4l2_t *st, int side,
                                  negobs_frame_t *f, negobs_frame_t *f2)
{
    negobs_v4l2_dev_t *d = &st->dev[side];
    size_t per_node = node_scratch_bytes(st);
    uint8_t *scr = st->scratch != NULL && per_node > 0u
                       ? st->scratch + (size_t)side * per_node
                       : NULL;
    negobs_status_t s = negobs_v4l2_conv_frame(
        &d->conv, d->buf[d->pend_idx].start, d->pend_bytes, scr,
        scr != NULL ? per_node : 0u, &f->y, f2 != NULL ? &f2->y : NULL);
    f->ts_ns = d->pend_ts;
    f->sequence = d->pend_seq;
    if (f2 != NULL) {
        f2->ts_ns = d->pend_ts;
        f2->sequence = d->pend_seq;
    }
    return s;
}

static void v_release(void *ctx, negobs_frame_pair_t *pair)
{
    negobs_v4l2_t *st = ctx;
    int i;
    (void)pair;
    for (i = 0; i < 2; i++) {
        negobs_v4l2_dev_t *d = &st->dev[i];
        if (d->held_idx >= 0 && d->fd >= 0) {
            if (v4l2_dev_queue(d, (uint32_t)d->held_idx) != NEGOBS_OK &&
                errno == ENODEV) {
                mark_lost(st, d, errno, "VIDIOC_QBUF");
            }
        }
        d->held_idx = -1;
    }
}

/* True when either side is frozen (its errmsg set). */
static bool frozen_check(negobs_v4l2_t *st)
{
    bool frozen = false;
    int i;
    for (i = 0; i < 2; i++) {
        negobs_v4l2_dev_t *d = &st->dev[i];
        if (d->pend_frozen) {
            v4l2_error(st, 0, "frozen: %s image unchanged for %lu frames",
                       d->path, (unsigned long)d->frozen.repeats + 1u);
            frozen = true;
        }
    }
    return frozen;
}

/* Why nothing was paired in time: frames came but never matched (drift),
 * or a node stayed silent. */
static void timeout_message(negobs_v4l2_t *st, uint32_t drops,
                            const int *silent, nfds_t n_silent)
{
    if (drops > 0) {
        v4l2_error(st, 0,
                   "left/right out of sync: %lu frames dropped, last |dt| "
                   "%lu ms > pair_tolerance_ms %ld",
                   (unsigned long)drops,
                   (unsigned long)(st->last_drop_dt_ns / 1000000u),
                   (long)st->cfg.pair_tol_ms);
    } else if (n_silent == 1) {
        v4l2_error(st, 0, "no frames from %s", st->dev[silent[0]].path);
    } else {
        v4l2_error(st, 0, "no frames from %s and %s", st->dev[0].path,
                   st->dev[1].path);
    }
}

/* One side-by-side node: its pending frame is the pair. NEGOBS_ERR_AGAIN:
 * the frame was unusable (requeued), look for the next. */
static int sbs_pair(negobs_v4l2_t *st, negobs_frame_pair_t *pair)
{
    negobs_v4l2_dev_t *d = &st->dev[0];
    negobs_status_t s = make_frame(st, 0, &pair->left, &pair->right);
    d->pending = false;
    if (s != NEGOBS_OK) {
        st->stats.short_frames++;
        (void)v4l2_dev_queue(d, d->pend_idx);
        return NEGOBS_ERR_AGAIN;
    }
    if (frozen_check(st)) {
        (void)v4l2_dev_queue(d, d->pend_idx);
        st->stats.frozen_pairs++;
        return NEGOBS_ERR_IO;
    }
    d->held_idx = (int32_t)d->pend_idx;
    pair->index = st->stats.pairs++;
    return NEGOBS_OK;
}

static int v_get_pair(void *ctx, negobs_frame_pair_t *pair, int32_t timeout_ms)
{
    negobs_v4l2_t *st = ctx;
    uint64_t deadline;
    uint64_t tol_ns;
    uint32_t drops = 0;
    if (!st->started || pair == NULL) {
        return NEGOBS_ERR_STATE;
    }
    v_release(st, pair); /* a pair not released is released now */
    tol_ns = (uint64_t)st->cfg.pair_tol_ms * 1000000u;
    deadline = negobs_clock_now_ms() +
               (uint64_t)(timeout_ms > 0 ? timeout_ms : 0);
    for (;;) {
        struct pollfd pfd[2];
        int map[2];
        nfds_t n = 0;
        uint64_t now = negobs_clock_now_ms();
        int i;
        int rc;

        for (i = 0; i < st->nodes; i++) {
            if (st->dev[i].lost) {
                try_reopen(st, &st->dev[i], now);
            }
        }
        if (st->dev[0].lost || st->dev[1].lost) {
            uint64_t wake = deadline;
            for (i = 0; i < 2; i++) {
                if (st->dev[i].lost && st->dev[i].retry_at_ms < wake) {
                    wake = st->dev[i].retry_at_ms;
                }
            }
            if (wake > now) {
                negobs_clock_sleep_ms((uint32_t)(wake - now));
            }
            return NEGOBS_ERR_NODEV;
        }

        if (st->nodes == 1 && st->dev[0].pending) {
            int got = sbs_pair(st, pair);
            if (got != NEGOBS_ERR_AGAIN) {
                return got;
            }
            continue;
        }
        for (i = 0; i < st->nodes; i++) {
            negobs_v4l2_dev_t *d = &st->dev[i];
            /* A frame newer than anything the other side delivers waits
             * for a partner; one that waited this long is too old to be
             * judged, and keeping it would stop this node being polled
             * (so its silence would never be noticed). */
            if (d->pending && !st->dev[1 - i].pending &&
                now - d->pend_at_ms > NEGOBS_V4L2_PENDING_MAX_MS) {
                d->pending = false;
                (void)v4l2_dev_queue(d, d->pend_idx);
                st->stats.dropped_pairs++;
                drops++;
            }
        }

        if (st->dev[0].pending && st->dev[1].pending) {
            negobs_v4l2_dev_t *l = &st->dev[0];
            negobs_v4l2_dev_t *r = &st->dev[1];
            negobs_pair_action_t a = negobs_pair_decide(l->pend_ts, r->pend_ts,
                                                        tol_ns);
            if (a == NEGOBS_PAIR_MATCH) {
                negobs_status_t sl = make_frame(st, 0, &pair->left, NULL);
                negobs_status_t sr = make_frame(st, 1, &pair->right, NULL);
                l->pending = false;
                r->pending = false;
                if (sl != NEGOBS_OK || sr != NEGOBS_OK) {
                    st->stats.short_frames++;
                    (void)v4l2_dev_queue(l, l->pend_idx);
                    (void)v4l2_dev_queue(r, r->pend_idx);
                    continue;
                }
                if (frozen_check(st)) {
                    (void)v4l2_dev_queue(l, l->pend_idx);
                    (void)v4l2_dev_queue(r, r->pend_idx);
                    st->stats.frozen_pairs++;
                    return NEGOBS_ERR_IO;
                }
                l->held_idx = (int32_t)l->pend_idx;
                r->held_idx = (int32_t)r->pend_idx;
                pair->index = st->stats.pairs++;
                return NEGOBS_OK;
            }
            {
                negobs_v4l2_dev_t *old = a == NEGOBS_PAIR_DROP_LEFT ? l : r;
                old->pending = false;
                (void)v4l2_dev_queue(old, old->pend_idx);
                st->stats.dropped_pairs++;
                drops++;
                st->last_drop_dt_ns = l->pend_ts > r->pend_ts
                                          ? l->pend_ts - r->pend_ts
                                          : r->pend_ts - l->pend_ts;
            }
            continue;
        }

        for (i = 0; i < st->nodes; i++) {
            if (!st->dev[i].pending) {
                pfd[n].fd = st->dev[i].fd;
                pfd[n].events = POLLIN;
                pfd[n].revents = 0;
                map[n] = i;
                n++;
            }
        }
        if (now >= deadline) {
            rc = 0;
        } else {
            rc = poll(pfd, n, (int)(deadline - now));
        }
        if (rc < 0) {
            if (errno == EINTR) {
                return NEGOBS_ERR_AGAIN;
            }
            v4l2_error(st, errno, "poll");
            return NEGOBS_ERR_IO;
        }
        if (rc == 0) {
            nfds_t k;
            for (k = 0; k < n; k++) {
                negobs_v4l2_dev_t *d = &st->dev[map[k]];
                if (++d->timeouts_in_row >=
                    NEGOBS_V4L2_TIMEOUTS_BEFORE_REOPEN) {
                    mark_lost(st, d, 0, "no frames");
                }
            }
            st->stats.timeouts++;
            timeout_message(st, drops, map, n);
            return NEGOBS_ERR_TIMEOUT;
        }
        for (i = 0; i < (int)n; i++) {
            negobs_v4l2_dev_t *d = &st->dev[map[i]];
            if ((pfd[i].revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
                mark_lost(st, d, ENODEV, "poll error");
            } else if ((pfd[i].revents & POLLIN) != 0) {
                drain(st, d);
            }
        }
    }
}

static void v_stop(void *ctx)
{
    negobs_v4l2_t *st = ctx;
    int i;
    for (i = 0; i < 2; i++) {
        negobs_v4l2_dev_t *d = &st->dev[i];
        if (d->fd >= 0 && d->streaming) {
            enum v4l2_buf_type t = V4L2_BUF_TYPE_VIDEO_CAPTURE;
            (void)v4l2_xioctl(d->fd, VIDIOC_STREAMOFF, &t);
            d->streaming = false;
        }
        d->pending = false;
        d->held_idx = -1;
    }
    st->started = false;
}

static void v_close(void *ctx)
{
    negobs_v4l2_t *st = ctx;
    v4l2_dev_close(&st->dev[0]);
    v4l2_dev_close(&st->dev[1]);
}

static void v_stats(void *ctx, negobs_capture_stats_t *out)
{
    *out = ((negobs_v4l2_t *)ctx)->stats;
}

static const char *v_errmsg(void *ctx)
{
    return ((negobs_v4l2_t *)ctx)->errmsg;
}

static const negobs_capture_ops_t v4l2_ops = {
    .name = "v4l2",
    .open = v_open,
    .start = v_start,
    .get_pair = v_get_pair,
    .release = v_release,
    .stop = v_stop,
    .close = v_close,
    .stats = v_stats,
    .errmsg = v_errmsg,
};

negobs_status_t negobs_v4l2_init(negobs_v4l2_t *st, uint8_t *scratch,
                                 size_t scratch_bytes, negobs_capture_t *cam)
{
    if (st == NULL || cam == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(st, 0, sizeof *st);
    v4l2_dev_reset(&st->dev[0]);
    v4l2_dev_reset(&st->dev[1]);
    st->scratch = scratch;
    st->scratch_bytes = scratch != NULL ? scratch_bytes : 0;
    cam->ops = &v4l2_ops;
    cam->ctx = st;
    return NEGOBS_OK;
}
