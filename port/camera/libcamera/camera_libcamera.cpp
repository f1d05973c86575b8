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
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include <libcamera/libcamera.h>

#include "negobs_port/camera_libcamera.h"
#include "negobs_port/clock.h"

namespace {

using libcamera::Camera;
using libcamera::CameraConfiguration;
using libcamera::CameraManager;
using libcamera::ControlList;
using libcamera::FrameBuffer;
using libcamera::FrameBufferAllocator;
using libcamera::FrameMetadata;
using libcamera::PixelFormat;
using libcamera::Request;
using libcamera::Size;
using libcamera::Stream;
using libcamera::StreamConfiguration;
using libcamera::StreamRole;

constexpr uint32_t kBackoffMinMs = 100;
constexpr uint32_t kBackoffMaxMs = 2000;

void set_error(negobs_libcamera_t *st, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

void set_error(negobs_libcamera_t *st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)std::vsnprintf(st->errmsg, sizeof st->errmsg, fmt, ap);
    va_end(ap);
}

negobs_status_t errno_status(int e)
{
    return (e == ENODEV || e == ENOENT || e == ENXIO) ? NEGOBS_ERR_NODEV
                                                      : NEGOBS_ERR_IO;
}

/* ---- the process's one CameraManager (libcamera allows one) -------- */

std::mutex g_cm_mu;
CameraManager *g_cm = nullptr;
int g_cm_users = 0;

negobs_status_t cm_get(negobs_libcamera_t *st, CameraManager **out)
{
    std::lock_guard<std::mutex> lk(g_cm_mu);
    if (g_cm == nullptr) {
        /* libcamera logs INFO lines to stderr by default; keep warnings
         * unless the user chose levels. Categories are created lazily,
         * so this takes effect before libcamera's first message. */
        (void)setenv("LIBCAMERA_LOG_LEVELS", "*:WARN", 0);
        std::unique_ptr<CameraManager> cm(new CameraManager());
        int r = cm->start();
        if (r < 0) {
            set_error(st, "libcamera: CameraManager::start: %s",
                      std::strerror(-r));
            return errno_status(-r);
        }
        g_cm = cm.release();
    }
    g_cm_users++;
    *out = g_cm;
    return NEGOBS_OK;
}

void cm_put()
{
    std::lock_guard<std::mutex> lk(g_cm_mu);
    if (g_cm_users > 0 && --g_cm_users == 0) {
        g_cm->stop();
        delete g_cm;
        g_cm = nullptr;
    }
}

/* ---- one camera ------------------------------------------------------ */

struct Impl;

struct Mapping {
    void *addr = nullptr;
    size_t len = 0;
    uint8_t *y = nullptr; /* plane 0 inside the mapping */
};

struct Side {
    Impl *owner = nullptr;
    int index = 0;           /* 0 left, 1 right                        */
    int32_t spec_index = -1; /* "libcamera:N", until resolved to an id */
    std::string id;          /* camera id, kept for reopening          */

    std::shared_ptr<Camera> cam;
    bool acquired = false;
    bool running = false;
    std::unique_ptr<CameraConfiguration> config;
    Stream *stream = nullptr;
    std::unique_ptr<FrameBufferAllocator> alloc;
    std::vector<std::unique_ptr<Request>> requests;
    std::vector<Mapping> maps; /* by request cookie */
    uint32_t fourcc = 0;
    int32_t width = 0;
    int32_t height = 0;
    uint32_t stride = 0;
    bool has_exposure = false;
    bool has_gain = false;
    bool has_frame_duration = false;

    /* written by libcamera's thread, under Impl::mu */
    std::vector<Request *> ring;
    size_t ring_head = 0;
    size_t ring_count = 0;
    bool disconnected = false;

    /* caller's thread only */
    Request *pending = nullptr;
    uint64_t pend_ts = 0;
    uint32_t pend_seq = 0;
    size_t pend_bytes = 0;
    bool pend_frozen = false;
    negobs_frozen_t frozen{};
    Request *held = nullptr;
    bool lost = false;
    uint64_t retry_at_ms = 0;
    uint32_t backoff_ms = 0;
    uint32_t timeouts_in_row = 0;

    void on_request_completed(Request *r);
    void on_disconnected();
};

struct Impl {
    negobs_libcamera_t *st = nullptr;
    CameraManager *cm = nullptr;
    negobs_camera_config_t cfg{};
    int nsides = 0;
    Side side[2];
    bool started = false;
    std::mutex mu;
    std::condition_variable cv;
};

void Side::on_request_completed(Request *r)
{
    if (r->status() == Request::RequestCancelled) {
        return; /* stop() cancels what is queued; nobody waits for it */
    }
    std::lock_guard<std::mutex> lk(owner->mu);
    if (ring_count < ring.size()) {
        ring[(ring_head + ring_count) % ring.size()] = r;
        ring_count++;
    }
    owner->cv.notify_all();
}

void Side::on_disconnected()
{
    std::lock_guard<std::mutex> lk(owner->mu);
    disconnected = true;
    owner->cv.notify_all();
}

std::string fourcc_str(uint32_t f)
{
    char s[5];
    for (int i = 0; i < 4; i++) {
        char c = static_cast<char>((f >> (8 * i)) & 0xffu);
        s[i] = (c >= 32 && c < 127) ? c : '?';
    }
    s[4] = '\0';
    return s;
}

std::shared_ptr<Camera> find_camera(Impl &im, Side &s, size_t *count)
{
    std::vector<std::shared_ptr<Camera>> cams = im.cm->cameras();
    *count = cams.size();
    if (!s.id.empty()) {
        return im.cm->get(s.id);
    }
    if (s.spec_index >= 0 && static_cast<size_t>(s.spec_index) < cams.size()) {
        return cams[static_cast<size_t>(s.spec_index)];
    }
    return nullptr;
}

void unmap_all(Side &s)
{
    for (Mapping &m : s.maps) {
        if (m.addr != nullptr) {
            (void)munmap(m.addr, m.len);
        }
    }
    s.maps.clear();
}

/* Map plane 0's dmabuf once: from offset 0 to the end of the last plane
 * sharing its fd (mmap offsets must be page-aligned, plane offsets not). */
negobs_status_t map_buffer(negobs_libcamera_t *st, Side &s,
                           const FrameBuffer &b, Mapping *m)
{
    const std::vector<FrameBuffer::Plane> &pl = b.planes();
    if (pl.empty() || pl[0].fd.get() < 0) {
        set_error(st, "libcamera: %s: buffer without a plane", s.id.c_str());
        return NEGOBS_ERR_IO;
    }
    int fd = pl[0].fd.get();
    size_t len = 0;
    for (const FrameBuffer::Plane &p : pl) {
        if (p.fd.get() == fd) {
            len = std::max(len, static_cast<size_t>(p.offset) + p.length);
        }
    }
    void *a = mmap(nullptr, len, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (a == MAP_FAILED) {
        /* some exporters refuse writable maps; the library only reads */
        a = mmap(nullptr, len, PROT_READ, MAP_SHARED, fd, 0);
    }
    if (a == MAP_FAILED) {
        int e = errno;
        set_error(st, "libcamera: %s: mmap: %s", s.id.c_str(),
                  std::strerror(e));
        return NEGOBS_ERR_IO;
    }
    m->addr = a;
    m->len = len;
    m->y = static_cast<uint8_t *>(a) + pl[0].offset;
    return NEGOBS_OK;
}

/* Everything side_setup() built, undone in reverse; safe on a partial
 * setup and on a side never set up. */
void side_teardown(Impl &im, Side &s)
{
    if (s.cam && s.running) {
        (void)s.cam->stop(); /* waits for libcamera's thread */
    }
    s.running = false;
    if (s.cam) {
        s.cam->requestCompleted.disconnect(&s);
        s.cam->disconnected.disconnect(&s);
    }
    {
        std::lock_guard<std::mutex> lk(im.mu);
        s.ring.clear();
        s.ring_head = 0;
        s.ring_count = 0;
        s.disconnected = false;
    }
    s.pending = nullptr;
    s.held = nullptr;
    s.frozen = negobs_frozen_t{};
    s.requests.clear(); /* before the buffers they point to */
    unmap_all(s);
    s.alloc.reset();
    s.stream = nullptr;
    s.config.reset();
    if (s.cam && s.acquired) {
        (void)s.cam->release();
    }
    s.acquired = false;
    s.cam.reset();
}

PixelFormat best_format(const StreamConfiguration &sc)
{
    PixelFormat best;
    int best_rank = -1;
    for (const PixelFormat &f : sc.formats().pixelformats()) {
        int r = negobs_libcamera_format_rank(f.fourcc());
        if (r >= 0 && (best_rank < 0 || r < best_rank)) {
            best_rank = r;
            best = f;
        }
    }
    return best;
}

std::string format_list(const StreamConfiguration &sc)
{
    std::string s;
    for (const PixelFormat &f : sc.formats().pixelformats()) {
        s += (s.empty() ? "" : " ") + f.toString();
    }
    return s.empty() ? "none" : s;
}

negobs_status_t side_setup(Impl &im, Side &s)
{
    negobs_libcamera_t *st = im.st;
    size_t ncams = 0;
    s.cam = find_camera(im, s, &ncams);
    if (!s.cam) {
        if (s.id.empty()) {
            set_error(st, "libcamera: no camera %ld (%lu found)",
                      static_cast<long>(s.spec_index),
                      static_cast<unsigned long>(ncams));
        } else {
            set_error(st, "libcamera: no camera '%s' (%lu found)",
                      s.id.c_str(), static_cast<unsigned long>(ncams));
        }
        return NEGOBS_ERR_NODEV;
    }
    s.id = s.cam->id(); /* an index resolves once; reopen by id */
    int r = s.cam->acquire();
    if (r < 0) {
        set_error(st, "libcamera: %s: acquire: %s", s.id.c_str(),
                  r == -EBUSY ? "in use by another process"
                              : std::strerror(-r));
        s.cam.reset();
        return r == -EBUSY ? NEGOBS_ERR_IO : errno_status(-r);
    }
    s.acquired = true;

    s.config = s.cam->generateConfiguration({StreamRole::VideoRecording});
    if (!s.config || s.config->empty()) {
        set_error(st, "libcamera: %s: no video stream configuration",
                  s.id.c_str());
        return NEGOBS_ERR_UNSUPPORTED;
    }
    StreamConfiguration &sc = s.config->at(0);
    PixelFormat pf = best_format(sc);
    if (!pf.isValid()) {
        set_error(st, "libcamera: %s: no Y/YUV/RGB format (offers %s)",
                  s.id.c_str(), format_list(sc).c_str());
        return NEGOBS_ERR_UNSUPPORTED;
    }
    sc.pixelFormat = pf;
    sc.size = Size(static_cast<unsigned int>(im.cfg.width),
                   static_cast<unsigned int>(im.cfg.height));
    sc.bufferCount = std::max<unsigned int>(sc.bufferCount,
                                            NEGOBS_LIBCAMERA_BUFFERS);
    if (s.config->validate() == CameraConfiguration::Invalid) {
        set_error(st, "libcamera: %s: %s %dx%d not accepted", s.id.c_str(),
                  pf.toString().c_str(), static_cast<int>(im.cfg.width),
                  static_cast<int>(im.cfg.height));
        return NEGOBS_ERR_UNSUPPORTED;
    }
    /* validate() may adjust anything: believe what it left */
    uint32_t fcc = sc.pixelFormat.fourcc();
    if (negobs_libcamera_format_rank(fcc) < 0 || sc.size.width == 0 ||
        sc.size.height == 0 || sc.size.width > NEGOBS_MAX_DIM ||
        sc.size.height > NEGOBS_MAX_DIM) {
        set_error(st, "libcamera: %s: adjusted to unusable %s", s.id.c_str(),
                  sc.toString().c_str());
        return NEGOBS_ERR_UNSUPPORTED;
    }
    r = s.cam->configure(s.config.get());
    if (r < 0) {
        set_error(st, "libcamera: %s: configure %s: %s", s.id.c_str(),
                  sc.toString().c_str(), std::strerror(-r));
        return r == -EINVAL ? NEGOBS_ERR_UNSUPPORTED : errno_status(-r);
    }
    s.fourcc = fcc;
    s.width = static_cast<int32_t>(sc.size.width);
    s.height = static_cast<int32_t>(sc.size.height);
    s.stride = sc.stride;
    s.stream = sc.stream();

    s.alloc = std::make_unique<FrameBufferAllocator>(s.cam);
    r = s.alloc->allocate(s.stream);
    if (r < 0) {
        set_error(st, "libcamera: %s: allocating buffers: %s", s.id.c_str(),
                  std::strerror(-r));
        return errno_status(-r);
    }
    const std::vector<std::unique_ptr<FrameBuffer>> &bufs = s.alloc->buffers(
        s.stream);
    if (bufs.size() < NEGOBS_LIBCAMERA_MIN_BUFFERS ||
        bufs.size() > NEGOBS_LIBCAMERA_MAX_BUFFERS) {
        set_error(st, "libcamera: %s: got %lu buffers, need %u..%u",
                  s.id.c_str(), static_cast<unsigned long>(bufs.size()),
                  static_cast<unsigned>(NEGOBS_LIBCAMERA_MIN_BUFFERS),
                  static_cast<unsigned>(NEGOBS_LIBCAMERA_MAX_BUFFERS));
        return NEGOBS_ERR_NOSPACE;
    }
    s.maps.assign(bufs.size(), Mapping());
    for (size_t i = 0; i < bufs.size(); i++) {
        negobs_status_t ms = map_buffer(st, s, *bufs[i], &s.maps[i]);
        if (ms != NEGOBS_OK) {
            return ms;
        }
        std::unique_ptr<Request> req = s.cam->createRequest(i);
        if (!req || req->addBuffer(s.stream, bufs[i].get()) < 0) {
            set_error(st, "libcamera: %s: cannot build request %lu",
                      s.id.c_str(), static_cast<unsigned long>(i));
            return NEGOBS_ERR_IO;
        }
        s.requests.push_back(std::move(req));
    }
    {
        std::lock_guard<std::mutex> lk(im.mu);
        s.ring.assign(bufs.size(), nullptr);
        s.ring_head = 0;
        s.ring_count = 0;
        s.disconnected = false;
    }
    const libcamera::ControlInfoMap &ci = s.cam->controls();
    s.has_exposure = ci.count(&libcamera::controls::ExposureTime) > 0;
    s.has_gain = ci.count(&libcamera::controls::AnalogueGain) > 0;
    s.has_frame_duration = ci.count(
                               &libcamera::controls::FrameDurationLimits) > 0;
    s.cam->requestCompleted.connect(&s, &Side::on_request_completed);
    s.cam->disconnected.connect(&s, &Side::on_disconnected);
    return NEGOBS_OK;
}

/* Exposure, gain and rate go to every camera alike, or to none. */
ControlList start_controls(Impl &im)
{
    ControlList c(libcamera::controls::controls);
    bool exposure = im.cfg.exposure >= 0;
    bool gain = im.cfg.gain >= 0;
    bool rate = im.cfg.fps > 0;
    for (int i = 0; i < im.nsides; i++) {
        exposure = exposure && im.side[i].has_exposure;
        gain = gain && im.side[i].has_gain;
        rate = rate && im.side[i].has_frame_duration;
    }
    if (exposure) {
        c.set(libcamera::controls::AeEnable, false);
        c.set(libcamera::controls::ExposureTime, im.cfg.exposure);
    }
    if (gain) {
        c.set(libcamera::controls::AnalogueGain,
              static_cast<float>(im.cfg.gain) / 100.0f);
    }
    if (rate) {
        int64_t frame_us = 1000000 / im.cfg.fps;
        c.set(libcamera::controls::FrameDurationLimits, {frame_us, frame_us});
    }
    return c;
}

void requeue(Side &s, Request *r)
{
    if (r == nullptr || !s.running) {
        return;
    }
    r->reuse(Request::ReuseBuffers);
    (void)s.cam->queueRequest(r); /* a failure shows up as a timeout */
}

negobs_status_t side_start(Impl &im, Side &s)
{
    ControlList c = start_controls(im);
    int r = s.cam->start(&c);
    if (r < 0) {
        set_error(im.st, "libcamera: %s: start: %s", s.id.c_str(),
                  std::strerror(-r));
        return errno_status(-r);
    }
    s.running = true;
    for (std::unique_ptr<Request> &req : s.requests) {
        req->reuse(Request::ReuseBuffers);
        r = s.cam->queueRequest(req.get());
        if (r < 0) {
            set_error(im.st, "libcamera: %s: queueRequest: %s", s.id.c_str(),
                      std::strerror(-r));
            return errno_status(-r);
        }
    }
    s.timeouts_in_row = 0;
    return NEGOBS_OK;
}

void mark_lost(Impl &im, Side &s, const char *what)
{
    set_error(im.st, "libcamera: %s: %s, reopening", s.id.c_str(), what);
    side_teardown(im, s);
    s.lost = true;
    s.backoff_ms = kBackoffMinMs;
    s.retry_at_ms = negobs_clock_now_ms() + s.backoff_ms;
    im.st->stats.device_losses++;
}

void try_reopen(Impl &im, Side &s, uint64_t now)
{
    if (now < s.retry_at_ms) {
        return;
    }
    negobs_status_t r = side_setup(im, s);
    const Side &other = im.side[1 - s.index];
    if (r == NEGOBS_OK && im.nsides == 2 && other.cam &&
        (s.width != other.width || s.height != other.height)) {
        set_error(im.st, "libcamera: %s: came back with another size",
                  s.id.c_str());
        r = NEGOBS_ERR_UNSUPPORTED;
    }
    if (r == NEGOBS_OK) {
        r = side_start(im, s);
    }
    if (r == NEGOBS_OK) {
        s.lost = false;
        im.st->stats.reopens++;
        return;
    }
    side_teardown(im, s);
    s.backoff_ms = s.backoff_ms >= kBackoffMaxMs / 2u ? kBackoffMaxMs
                                                      : s.backoff_ms * 2u;
    s.retry_at_ms = now + s.backoff_ms;
}

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
            set_error(im.st,
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
        set_error(st,
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
                          const negobs_camera_config_t *cfg)
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
        im->cfg.pair_tol_ms = NEGOBS_CAMERA_PAIR_TOL_MS_DEFAULT;
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
            set_error(st,
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
        set_error(st,
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
            set_error(st, "libcamera: %s needs %lu bytes of scratch",
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
        set_error(st, "libcamera: out of memory");
    } catch (const std::exception &e) {
        set_error(st, "libcamera: %s", e.what());
    } catch (...) {
        set_error(st, "libcamera: unknown C++ exception");
    }
    return NEGOBS_ERR_IO;
}

negobs_status_t lc_open(void *ctx, const negobs_camera_config_t *cfg)
{
    negobs_libcamera_t *st = static_cast<negobs_libcamera_t *>(ctx);
    if (cfg == nullptr || cfg->left == nullptr) {
        set_error(st, "libcamera: no left camera given");
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
        set_error(st, "libcamera: start before a successful open");
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

void lc_stats(void *ctx, negobs_camera_stats_t *out)
{
    *out = static_cast<negobs_libcamera_t *>(ctx)->stats;
}

const char *lc_errmsg(void *ctx)
{
    return static_cast<negobs_libcamera_t *>(ctx)->errmsg;
}

const negobs_camera_ops_t libcamera_ops = {
    "libcamera", lc_open,  lc_start, lc_get_pair, lc_release,
    lc_stop,     lc_close, lc_stats, lc_errmsg,
};

} // namespace

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
    cam->ops = &libcamera_ops;
    cam->ctx = st;
    return NEGOBS_OK;
}

extern "C" bool negobs_libcamera_available(void)
{
    return true;
}
