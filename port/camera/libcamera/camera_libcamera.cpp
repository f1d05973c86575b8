/*
 * libcamera stereo capture behind the C ops table (camera_libcamera.h).
 *
 * Per camera, after libcamera's `cam` tool: acquire -> generateConfiguration
 * (one VideoRecording stream) -> pick a format we can take luma from ->
 * validate -> configure -> FrameBufferAllocator -> mmap plane 0 of every
 * buffer once -> one Request per buffer -> start -> queue them all.
 *
 * Threads. libcamera completes requests in its own thread; the completion
 * slot only appends the request to the camera's ring (one slot per request,
 * so it can never overflow) under a mutex and wakes get_pair(). Everything
 * else (pairing, requeueing, reopening, stats) happens in the caller's
 * thread, so the C-side state needs no lock. camera->stop() waits for
 * libcamera's thread, so it is never called with the mutex held.
 *
 * Pairing and freshness are the V4L2 source's rules: at most one completed
 * frame waits per camera, a newer one replaces it (the older is requeued
 * and counted stale), and negobs_pair_decide() matches the two or drops the
 * older.
 */
#include <algorithm>
#include <chrono>
#include <cstring>
#include <exception>
#include <mutex>
#include <new>
#include <optional>

#include "lc_internal.hpp"
#include "negobs_port/camera_libcamera.h"
#include "negobs_port/clock.h"

namespace negobs_lc {
namespace {

/* Every completed frame counts, not only those paired, as in the V4L2
 * source: the raw bytes of plane 0 (rows of `stride` bytes, whatever the
 * format) change with sensor noise; a repeated buffer does not. */
bool frame_frozen(Impl &im, Side &s, Request *r)
{
    const Mapping &m = s.maps[r->cookie()];
    negobs_image_u8_t raw;
    size_t rows = s.stride > 0 ? s.pend_bytes / s.stride : 0;
    raw.data = m.y;
    raw.width = static_cast<int32_t>(s.stride);
    raw.height = static_cast<int32_t>(
        std::min(rows, static_cast<size_t>(s.height)));
    raw.stride = raw.width;
    return negobs_frozen_update(&s.frozen, negobs_frame_signature(&raw),
                                im.cfg.frozen_frames);
}

/* True when a side about to be delivered is frozen (errmsg set). */
bool frozen_check(Impl &im)
{
    bool frozen = false;
    for (int i = 0; i < im.nsides; i++) {
        Side &s = im.side[i];
        if (s.pend_frozen) {
            set_error(im.st, 0,
                      "frozen: libcamera %s image unchanged for %lu "
                      "frames",
                      s.id.c_str(),
                      static_cast<unsigned long>(s.frozen.repeats) + 1u);
            frozen = true;
        }
    }
    return frozen;
}

/* Take what libcamera completed; keep only the newest good frame. */
void drain(Impl &im, Side &s)
{
    Request *got[NEGOBS_LIBCAMERA_MAX_BUFFERS];
    size_t n = 0;
    {
        std::lock_guard<std::mutex> lk(im.mu);
        while (s.ring_count > 0 && n < NEGOBS_LIBCAMERA_MAX_BUFFERS) {
            got[n++] = s.ring[s.ring_head];
            s.ring_head = (s.ring_head + 1) % s.ring.size();
            s.ring_count--;
        }
    }
    for (size_t i = 0; i < n; i++) {
        Request *r = got[i];
        FrameBuffer *b = r->findBuffer(s.stream);
        if (b == nullptr || r->status() != Request::RequestComplete ||
            b->metadata().status != FrameMetadata::FrameSuccess ||
            b->metadata().planes().empty() || r->cookie() >= s.maps.size()) {
            im.st->stats.short_frames++;
            requeue(s, r);
            continue;
        }
        if (s.pending != nullptr) {
            im.st->stats.stale_frames++;
            requeue(s, s.pending);
        }
        s.pending = r;
        s.pend_bytes = b->metadata().planes()[0].bytesused;
        s.pend_frozen = frame_frozen(im, s, r);
        s.pend_seq = b->metadata().sequence;
        /* SensorTimestamp: start of exposure, CLOCK_MONOTONIC; the
         * buffer's timestamp is the same clock where it is missing. */
        std::optional<int64_t> ts = r->metadata().get(
            libcamera::controls::SensorTimestamp);
        s.pend_ts = (ts && *ts > 0) ? static_cast<uint64_t>(*ts)
                                    : b->metadata().timestamp;
        if (s.pend_ts == 0) {
            s.pend_ts = negobs_clock_now_ns();
        }
        s.timeouts_in_row = 0;
    }
}

negobs_status_t make_frame(Impl &im, Side &s, negobs_frame_t *f)
{
    negobs_libcamera_t *st = im.st;
    size_t plane = static_cast<size_t>(s.width) *
                   static_cast<size_t>(s.height);
    uint8_t *scr = st->scratch != nullptr
                       ? st->scratch + static_cast<size_t>(s.index) * plane
                       : nullptr;
    size_t scr_bytes = st->scratch != nullptr ? plane : 0;
    const Mapping &m = s.maps[s.pending->cookie()];
    f->ts_ns = s.pend_ts;
    f->sequence = s.pend_seq;
    return negobs_libcamera_luma(s.fourcc, m.y, s.pend_bytes, s.width,
                                 s.height, s.stride, scr, scr_bytes, &f->y);
}

/* ---- ops ------------------------------------------------------------- */

void close_impl(negobs_libcamera_t *st)
{
    Impl *im = static_cast<Impl *>(st->impl);
    if (im == nullptr) {
        return;
    }
    for (int i = 0; i < 2; i++) {
        side_teardown(*im, im->side[i]);
    }
    if (im->cm != nullptr) {
        cm_put();
    }
    delete im;
    st->impl = nullptr;
}

negobs_status_t parse_side(negobs_libcamera_t *st, Side &s, const char *src)
{
    int32_t index = -1;
    const char *id = nullptr;
    if (negobs_libcamera_parse_source(src, &index, &id) != NEGOBS_OK) {
        set_error(st, 0,
                  "libcamera: bad source '%s' (want libcamera:N or "
                  "libcamera:ID)",
                  src);
        return NEGOBS_ERR_INVAL;
    }
    s.spec_index = index;
    s.id = id != nullptr ? id : "";
    return NEGOBS_OK;
}

negobs_status_t open_impl(negobs_libcamera_t *st,
                          const negobs_capture_config_t *cfg)
{
    close_impl(st);
    std::memset(&st->stats, 0, sizeof st->stats);
    Impl *im = new Impl();
    st->impl = im;
    im->st = st;
    im->cfg = *cfg;
    if (im->cfg.width <= 0) {
        im->cfg.width = 640;
    }
    if (im->cfg.height <= 0) {
        im->cfg.height = 480;
    }
    if (im->cfg.pair_tol_ms < 0) {
        im->cfg.pair_tol_ms = NEGOBS_CAPTURE_PAIR_TOL_MS_DEFAULT;
    }
    im->nsides = (cfg->right == nullptr || cfg->right[0] == '\0') ? 1 : 2;
    for (int i = 0; i < 2; i++) {
        im->side[i].owner = im;
        im->side[i].index = i;
    }
    negobs_status_t s = parse_side(st, im->side[0], cfg->left);
    if (s == NEGOBS_OK && im->nsides == 2) {
        s = parse_side(st, im->side[1], cfg->right);
    }
    if (s == NEGOBS_OK) {
        s = cm_get(st, &im->cm);
        if (s != NEGOBS_OK) {
            im->cm = nullptr;
        }
    }
    if (s == NEGOBS_OK && im->nsides == 2) {
        /* before acquire(), which would call the second one "in use" */
        size_t n = 0;
        std::shared_ptr<Camera> a = find_camera(*im, im->side[0], &n);
        std::shared_ptr<Camera> b = find_camera(*im, im->side[1], &n);
        if (a && b && a->id() == b->id()) {
            set_error(st, 0,
                      "libcamera: left and right are the same camera "
                      "('%s')",
                      a->id().c_str());
            s = NEGOBS_ERR_INVAL;
        }
    }
    for (int i = 0; i < im->nsides && s == NEGOBS_OK; i++) {
        s = side_setup(*im, im->side[i]);
    }
    if (s == NEGOBS_OK && im->nsides == 2 &&
        (im->side[0].width != im->side[1].width ||
         im->side[0].height != im->side[1].height)) {
        set_error(st, 0,
                  "libcamera: cameras disagree on size: %ldx%ld vs %ldx%ld",
                  static_cast<long>(im->side[0].width),
                  static_cast<long>(im->side[0].height),
                  static_cast<long>(im->side[1].width),
                  static_cast<long>(im->side[1].height));
        s = NEGOBS_ERR_UNSUPPORTED;
    }
    if (s == NEGOBS_OK) {
        bool packed = false;
        for (int i = 0; i < im->nsides; i++) {
            packed = packed ||
                     negobs_libcamera_format_packed(im->side[i].fourcc);
        }
        size_t need = static_cast<size_t>(im->nsides) *
                      static_cast<size_t>(im->side[0].width) *
                      static_cast<size_t>(im->side[0].height);
        if (packed && (st->scratch == nullptr || st->scratch_bytes < need)) {
            set_error(st, 0, "libcamera: %s needs %lu bytes of scratch",
                      fourcc_str(im->side[0].fourcc).c_str(),
                      static_cast<unsigned long>(need));
            s = NEGOBS_ERR_NOSPACE;
        }
    }
    if (s != NEGOBS_OK) {
        char keep[sizeof st->errmsg];
        std::memcpy(keep, st->errmsg, sizeof keep);
        close_impl(st);
        std::memcpy(st->errmsg, keep, sizeof keep);
    }
    return s;
}

int get_pair_impl(Impl &im, negobs_frame_pair_t *pair, int32_t timeout_ms);

void release_impl(Impl &im)
{
    for (int i = 0; i < im.nsides; i++) {
        Side &s = im.side[i];
        if (s.held != nullptr) {
            requeue(s, s.held);
            s.held = nullptr;
        }
    }
}

int get_pair_impl(Impl &im, negobs_frame_pair_t *pair, int32_t timeout_ms)
{
    negobs_libcamera_t *st = im.st;
    release_impl(im); /* a pair not released is released now */
    uint64_t tol_ns = static_cast<uint64_t>(im.cfg.pair_tol_ms) * 1000000u;
    uint64_t deadline = negobs_clock_now_ms() +
                        static_cast<uint64_t>(timeout_ms > 0 ? timeout_ms : 0);
    for (;;) {
        uint64_t now = negobs_clock_now_ms();
        bool any_lost = false;
        for (int i = 0; i < im.nsides; i++) {
            Side &s = im.side[i];
            bool disc;
            {
                std::lock_guard<std::mutex> lk(im.mu);
                disc = s.disconnected;
            }
            if (!s.lost && disc) {
                mark_lost(im, s, "disconnected");
            }
            if (s.lost) {
                try_reopen(im, s, now);
            }
            any_lost = any_lost || s.lost;
        }
        if (any_lost) {
            uint64_t wake = deadline;
            for (int i = 0; i < im.nsides; i++) {
                if (im.side[i].lost && im.side[i].retry_at_ms < wake) {
                    wake = im.side[i].retry_at_ms;
                }
            }
            if (wake > now) {
                negobs_clock_sleep_ms(static_cast<uint32_t>(wake - now));
            }
            return NEGOBS_ERR_NODEV;
        }

        for (int i = 0; i < im.nsides; i++) {
            drain(im, im.side[i]);
        }
        Side &l = im.side[0];
        Side &r = im.side[1];
        negobs_lc_step_t step = negobs_libcamera_pair_step(
            im.nsides, l.pending != nullptr, l.pend_ts, r.pending != nullptr,
            r.pend_ts, tol_ns);
        if (step == NEGOBS_LC_SINGLE) {
            negobs_status_t fs = make_frame(im, l, &pair->left);
            Request *p = l.pending;
            l.pending = nullptr;
            if (fs != NEGOBS_OK) {
                st->stats.short_frames++;
                requeue(l, p);
                continue;
            }
            if (frozen_check(im)) {
                requeue(l, p);
                st->stats.frozen_pairs++;
                return NEGOBS_ERR_IO;
            }
            l.held = p;
            pair->right = pair->left;
            pair->index = st->stats.pairs++;
            return NEGOBS_OK;
        }
        if (step != NEGOBS_LC_WAIT) {
            if (step == NEGOBS_LC_PAIR) {
                negobs_status_t sl = make_frame(im, l, &pair->left);
                negobs_status_t sr = make_frame(im, r, &pair->right);
                Request *pl = l.pending;
                Request *pr = r.pending;
                l.pending = nullptr;
                r.pending = nullptr;
                if (sl != NEGOBS_OK || sr != NEGOBS_OK) {
                    st->stats.short_frames++;
                    requeue(l, pl);
                    requeue(r, pr);
                    continue;
                }
                if (frozen_check(im)) {
                    requeue(l, pl);
                    requeue(r, pr);
                    st->stats.frozen_pairs++;
                    return NEGOBS_ERR_IO;
                }
                l.held = pl;
                r.held = pr;
                pair->index = st->stats.pairs++;
                return NEGOBS_OK;
            }
            Side &old = step == NEGOBS_LC_DROP_LEFT ? l : r;
            Request *p = old.pending;
            old.pending = nullptr;
            requeue(old, p);
            st->stats.dropped_pairs++;
            continue;
        }

        if (now >= deadline) {
            for (int i = 0; i < im.nsides; i++) {
                Side &s = im.side[i];
                if (s.pending == nullptr &&
                    ++s.timeouts_in_row >=
                        NEGOBS_LIBCAMERA_TIMEOUTS_BEFORE_REOPEN) {
                    mark_lost(im, s, "no frames");
                }
            }
            st->stats.timeouts++;
            return NEGOBS_ERR_TIMEOUT;
        }
        std::unique_lock<std::mutex> lk(im.mu);
        (void)im.cv.wait_for(
            lk, std::chrono::milliseconds(deadline - now), [&im] {
                for (int i = 0; i < im.nsides; i++) {
                    const Side &s = im.side[i];
                    if (s.disconnected ||
                        (s.pending == nullptr && s.ring_count > 0)) {
                        return true;
                    }
                }
                return false;
            });
    }
}

/* No exception may unwind into C: each op catches everything. */
template <typename F> int guarded(negobs_libcamera_t *st, F f)
{
    try {
        return f();
    } catch (const std::bad_alloc &) {
        set_error(st, 0, "libcamera: out of memory");
    } catch (const std::exception &e) {
        set_error(st, 0, "libcamera: %s", e.what());
    } catch (...) {
        set_error(st, 0, "libcamera: unknown C++ exception");
    }
    return NEGOBS_ERR_IO;
}

negobs_status_t lc_open(void *ctx, const negobs_capture_config_t *cfg)
{
    negobs_libcamera_t *st = static_cast<negobs_libcamera_t *>(ctx);
    if (cfg == nullptr || cfg->left == nullptr) {
        set_error(st, 0, "libcamera: no left camera given");
        return NEGOBS_ERR_INVAL;
    }
    int r = guarded(st, [&] { return static_cast<int>(open_impl(st, cfg)); });
    if (r != NEGOBS_OK && st->impl != nullptr) {
        /* an exception mid-open: drop what was built, keep the message */
        char keep[sizeof st->errmsg];
        std::memcpy(keep, st->errmsg, sizeof keep);
        (void)guarded(st, [&] {
            close_impl(st);
            return 0;
        });
        std::memcpy(st->errmsg, keep, sizeof keep);
    }
    return static_cast<negobs_status_t>(r);
}

negobs_status_t lc_start(void *ctx)
{
    negobs_libcamera_t *st = static_cast<negobs_libcamera_t *>(ctx);
    Impl *im = static_cast<Impl *>(st->impl);
    if (im == nullptr) {
        set_error(st, 0, "libcamera: start before a successful open");
        return NEGOBS_ERR_STATE;
    }
    if (im->started) {
        return NEGOBS_OK;
    }
    int r = guarded(st, [&] {
        for (int i = 0; i < im->nsides; i++) {
            negobs_status_t s = side_start(*im, im->side[i]);
            if (s != NEGOBS_OK) {
                return static_cast<int>(s);
            }
        }
        return static_cast<int>(NEGOBS_OK);
    });
    im->started = r == NEGOBS_OK;
    return static_cast<negobs_status_t>(r);
}

int lc_get_pair(void *ctx, negobs_frame_pair_t *pair, int32_t timeout_ms)
{
    negobs_libcamera_t *st = static_cast<negobs_libcamera_t *>(ctx);
    Impl *im = static_cast<Impl *>(st->impl);
    if (im == nullptr || !im->started || pair == nullptr) {
        return NEGOBS_ERR_STATE;
    }
    return guarded(st, [&] { return get_pair_impl(*im, pair, timeout_ms); });
}

void lc_release(void *ctx, negobs_frame_pair_t *pair)
{
    negobs_libcamera_t *st = static_cast<negobs_libcamera_t *>(ctx);
    Impl *im = static_cast<Impl *>(st->impl);
    (void)pair;
    if (im != nullptr) {
        (void)guarded(st, [&] {
            release_impl(*im);
            return 0;
        });
    }
}

void lc_stop(void *ctx)
{
    negobs_libcamera_t *st = static_cast<negobs_libcamera_t *>(ctx);
    Impl *im = static_cast<Impl *>(st->impl);
    if (im == nullptr) {
        return;
    }
    (void)guarded(st, [&] {
        for (int i = 0; i < im->nsides; i++) {
            Side &s = im->side[i];
            if (s.cam && s.running) {
                (void)s.cam->stop();
            }
            s.running = false;
            s.pending = nullptr;
            s.held = nullptr;
            std::lock_guard<std::mutex> lk(im->mu);
            s.ring_head = 0;
            s.ring_count = 0;
        }
        return 0;
    });
    im->started = false;
}

void lc_close(void *ctx)
{
    negobs_libcamera_t *st = static_cast<negobs_libcamera_t *>(ctx);
    (void)guarded(st, [&] {
        close_impl(st);
        return 0;
    });
}

void lc_stats(void *ctx, negobs_capture_stats_t *out)
{
    *out = static_cast<negobs_libcamera_t *>(ctx)->stats;
}

const char *lc_errmsg(void *ctx)
{
    return static_cast<negobs_libcamera_t *>(ctx)->errmsg;
}

/* C++17 has no designated initialisers: the table is filled by name. */
negobs_capture_ops_t make_ops()
{
    negobs_capture_ops_t o{};
    o.name = "libcamera";
    o.open = lc_open;
    o.start = lc_start;
    o.get_pair = lc_get_pair;
    o.release = lc_release;
    o.stop = lc_stop;
    o.close = lc_close;
    o.stats = lc_stats;
    o.errmsg = lc_errmsg;
    return o;
}

const negobs_capture_ops_t libcamera_ops = make_ops();

} // namespace
} // namespace negobs_lc

extern "C" negobs_status_t negobs_libcamera_init(negobs_libcamera_t *st,
                                                 uint8_t *scratch,
                                                 size_t scratch_bytes,
                                                 negobs_capture_t *cam)
{
    if (st == nullptr || cam == nullptr) {
        return NEGOBS_ERR_INVAL;
    }
    std::memset(st, 0, sizeof *st);
    st->scratch = scratch;
    st->scratch_bytes = scratch != nullptr ? scratch_bytes : 0;
    cam->ops = &negobs_lc::libcamera_ops;
    cam->ctx = st;
    return NEGOBS_OK;
}

extern "C" bool negobs_libcamera_available(void)
{
    return true;
}
