/*
 * libcamera backend, one camera at a time: the shared CameraManager, and
 * the setup, start, teardown and reopen of one Side (lc_internal.hpp).
 * Pairing and the C ops table live in camera_libcamera.cpp.
 */
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "lc_internal.hpp"
#include "negobs_port/errmsg.h"
#include "negobs_port/clock.h"

namespace negobs_lc {

constexpr uint32_t kBackoffMinMs = 100;
constexpr uint32_t kBackoffMaxMs = 2000;

void set_error(negobs_libcamera_t *st, int err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    negobs_port_verrmsg(st->errmsg, sizeof st->errmsg, err, fmt, ap);
    va_end(ap);
}

negobs_status_t errno_status(int e)
{
    return (e == ENODEV || e == ENOENT || e == ENXIO) ? NEGOBS_ERR_NODEV
                                                      : NEGOBS_ERR_IO;
}

/* ---- the process's one CameraManager (libcamera allows one) -------- */

namespace {

std::mutex g_cm_mu;
CameraManager *g_cm = nullptr;
int g_cm_users = 0;

} // namespace

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
            set_error(st, -r, "libcamera: CameraManager::start");
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

static void unmap_all(Side &s)
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
static negobs_status_t map_buffer(negobs_libcamera_t *st, Side &s,
                                  const FrameBuffer &b, Mapping *m)
{
    const std::vector<FrameBuffer::Plane> &pl = b.planes();
    if (pl.empty() || pl[0].fd.get() < 0) {
        set_error(st, 0, "libcamera: %s: buffer without a plane",
                  s.id.c_str());
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
        set_error(st, e, "libcamera: %s: mmap", s.id.c_str());
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

static PixelFormat best_format(const StreamConfiguration &sc)
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

static std::string format_list(const StreamConfiguration &sc)
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
            set_error(st, 0, "libcamera: no camera %ld (%lu found)",
                      static_cast<long>(s.spec_index),
                      static_cast<unsigned long>(ncams));
        } else {
            set_error(st, 0, "libcamera: no camera '%s' (%lu found)",
                      s.id.c_str(), static_cast<unsigned long>(ncams));
        }
        return NEGOBS_ERR_NODEV;
    }
    s.id = s.cam->id(); /* an index resolves once; reopen by id */
    int r = s.cam->acquire();
    if (r < 0) {
        if (r == -EBUSY) {
            set_error(st, 0,
                      "libcamera: %s: acquire: in use by another process",
                      s.id.c_str());
        } else {
            set_error(st, -r, "libcamera: %s: acquire", s.id.c_str());
        }
        s.cam.reset();
        return r == -EBUSY ? NEGOBS_ERR_IO : errno_status(-r);
    }
    s.acquired = true;

    s.config = s.cam->generateConfiguration({StreamRole::VideoRecording});
    if (!s.config || s.config->empty()) {
        set_error(st, 0, "libcamera: %s: no video stream configuration",
                  s.id.c_str());
        return NEGOBS_ERR_UNSUPPORTED;
    }
    StreamConfiguration &sc = s.config->at(0);
    PixelFormat pf = best_format(sc);
    if (!pf.isValid()) {
        set_error(st, 0, "libcamera: %s: no Y/YUV/RGB format (offers %s)",
                  s.id.c_str(), format_list(sc).c_str());
        return NEGOBS_ERR_UNSUPPORTED;
    }
    sc.pixelFormat = pf;
    sc.size = Size(static_cast<unsigned int>(im.cfg.width),
                   static_cast<unsigned int>(im.cfg.height));
    sc.bufferCount = std::max<unsigned int>(sc.bufferCount,
                                            NEGOBS_LIBCAMERA_BUFFERS);
    if (s.config->validate() == CameraConfiguration::Invalid) {
        set_error(st, 0, "libcamera: %s: %s %dx%d not accepted", s.id.c_str(),
                  pf.toString().c_str(), static_cast<int>(im.cfg.width),
                  static_cast<int>(im.cfg.height));
        return NEGOBS_ERR_UNSUPPORTED;
    }
    /* validate() may adjust anything: believe what it left */
    uint32_t fcc = sc.pixelFormat.fourcc();
    if (negobs_libcamera_format_rank(fcc) < 0 || sc.size.width == 0 ||
        sc.size.height == 0 || sc.size.width > NEGOBS_MAX_DIM ||
        sc.size.height > NEGOBS_MAX_DIM) {
        set_error(st, 0, "libcamera: %s: adjusted to unusable %s",
                  s.id.c_str(), sc.toString().c_str());
        return NEGOBS_ERR_UNSUPPORTED;
    }
    r = s.cam->configure(s.config.get());
    if (r < 0) {
        set_error(st, -r, "libcamera: %s: configure %s", s.id.c_str(),
                  sc.toString().c_str());
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
        set_error(st, -r, "libcamera: %s: allocating buffers", s.id.c_str());
        return errno_status(-r);
    }
    const std::vector<std::unique_ptr<FrameBuffer>> &bufs = s.alloc->buffers(
        s.stream);
    if (bufs.size() < NEGOBS_LIBCAMERA_MIN_BUFFERS ||
        bufs.size() > NEGOBS_LIBCAMERA_MAX_BUFFERS) {
        set_error(st, 0, "libcamera: %s: got %lu buffers, need %u..%u",
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
            set_error(st, 0, "libcamera: %s: cannot build request %lu",
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
static ControlList start_controls(Impl &im)
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
        set_error(im.st, -r, "libcamera: %s: start", s.id.c_str());
        return errno_status(-r);
    }
    s.running = true;
    for (std::unique_ptr<Request> &req : s.requests) {
        req->reuse(Request::ReuseBuffers);
        r = s.cam->queueRequest(req.get());
        if (r < 0) {
            set_error(im.st, -r, "libcamera: %s: queueRequest", s.id.c_str());
            return errno_status(-r);
        }
    }
    s.timeouts_in_row = 0;
    return NEGOBS_OK;
}

void mark_lost(Impl &im, Side &s, const char *what)
{
    set_error(im.st, 0, "libcamera: %s: %s, reopening", s.id.c_str(), what);
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
        set_error(im.st, 0, "libcamera: %s: came back with another size",
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

} // namespace negobs_lc
