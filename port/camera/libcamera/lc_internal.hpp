/*
 * Internal to the libcamera backend (camera_libcamera.cpp, lc_side.cpp):
 * the per-camera state and the functions that set one camera up, start it,
 * tear it down and reopen it. Not installed; nothing outside
 * port/camera/libcamera includes it.
 */
#ifndef NEGOBS_PORT_LC_INTERNAL_HPP
#define NEGOBS_PORT_LC_INTERNAL_HPP

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <libcamera/libcamera.h>

#include "negobs_port/camera_libcamera.h"

namespace negobs_lc {

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

/* Formats st->errmsg (printf-style), with ": strerror(err)" when
 * err != 0 (negobs_port_verrmsg). */
void set_error(negobs_libcamera_t *st, int err, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* ENODEV/ENOENT/ENXIO: the camera is gone; anything else: I/O. */
negobs_status_t errno_status(int e);

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
    negobs_capture_config_t cfg{};
    int nsides = 0;
    Side side[2];
    bool started = false;
    std::mutex mu;
    std::condition_variable cv;
};

/* The process's one CameraManager (libcamera allows one), counted. */
negobs_status_t cm_get(negobs_libcamera_t *st, CameraManager **out);
void cm_put();

std::string fourcc_str(uint32_t f);
std::shared_ptr<Camera> find_camera(Impl &im, Side &s, size_t *count);

/* Acquire, configure, allocate, map and build the requests of one camera;
 * on failure errmsg says why and side_teardown() undoes the partial work. */
negobs_status_t side_setup(Impl &im, Side &s);
/* Everything side_setup() built, undone in reverse; safe on a partial
 * setup and on a side never set up. */
void side_teardown(Impl &im, Side &s);
/* Start one camera with the shared controls and queue every request. */
negobs_status_t side_start(Impl &im, Side &s);
/* Give a request back to its (running) camera. */
void requeue(Side &s, Request *r);
/* Tear a camera down and schedule its reopen with back-off. */
void mark_lost(Impl &im, Side &s, const char *what);
/* Reopen a lost camera when its back-off has passed. */
void try_reopen(Impl &im, Side &s, uint64_t now);

} // namespace negobs_lc

#endif /* NEGOBS_PORT_LC_INTERNAL_HPP */
