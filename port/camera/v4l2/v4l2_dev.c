/*
 * One V4L2 capture node: open, QUERYCAP, format negotiation (S_FMT, then
 * believe what the driver returns), frame rate, controls, MMAP buffers,
 * STREAMON and close. camera_v4l2.c pairs two nodes behind the ops table.
 */
#define _DEFAULT_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <linux/videodev2.h>

#include "negobs_port/camera_list.h"
#include "negobs_port/errmsg.h"
#include "v4l2_internal.h"

void v4l2_error(negobs_v4l2_t *st, int err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    /* va_start() is above; clang-tidy 14 reports this false positive
     * only when it analyses several files in one run. */
    /* NOLINTNEXTLINE(clang-analyzer-valist.Uninitialized) */
    negobs_port_verrmsg(st->errmsg, sizeof st->errmsg, err, fmt, ap);
    va_end(ap);
}

int v4l2_xioctl(int fd, unsigned long req, void *arg)
{
    int r;
    do {
        r = ioctl(fd, req, arg);
    } while (r < 0 && errno == EINTR);
    return r;
}

negobs_status_t v4l2_errno_status(int e)
{
    return (e == ENODEV || e == ENOENT || e == ENXIO) ? NEGOBS_ERR_NODEV
                                                      : NEGOBS_ERR_IO;
}

void v4l2_dev_reset(negobs_v4l2_dev_t *d)
{
    d->fd = -1;
    d->nbuf = 0;
    d->streaming = false;
    d->pending = false;
    d->held_idx = -1;
}

void v4l2_dev_close(negobs_v4l2_dev_t *d)
{
    uint32_t i;
    if (d->fd >= 0) {
        if (d->streaming) {
            enum v4l2_buf_type t = V4L2_BUF_TYPE_VIDEO_CAPTURE;
            (void)v4l2_xioctl(d->fd, VIDIOC_STREAMOFF, &t);
        }
        for (i = 0; i < d->nbuf; i++) {
            if (d->buf[i].start != NULL) {
                (void)munmap(d->buf[i].start, d->buf[i].length);
                d->buf[i].start = NULL;
            }
        }
        if (d->nbuf > 0) {
            struct v4l2_requestbuffers rb;
            memset(&rb, 0, sizeof rb);
            rb.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
            rb.memory = V4L2_MEMORY_MMAP;
            (void)v4l2_xioctl(d->fd, VIDIOC_REQBUFS, &rb);
        }
        (void)close(d->fd);
    }
    v4l2_dev_reset(d);
}

/* The format the node lists for the capture size, S_FMT and re-read. */
static negobs_status_t dev_set_format(negobs_v4l2_t *st, negobs_v4l2_dev_t *d)
{
    negobs_v4l2_mode_t modes[NEGOBS_V4L2_MAX_MODES];
    struct v4l2_format f;
    uint32_t best;
    negobs_status_t s;
    int32_t cap_w = st->cfg.capture_width > 0
                        ? st->cfg.capture_width
                        : st->cfg.width * (st->cfg.side_by_side ? 2 : 1);
    int32_t cap_h = st->cfg.capture_height > 0 ? st->cfg.capture_height
                                               : st->cfg.height;
    size_t n = negobs_v4l2_enum_modes(d->fd, cap_w, cap_h, modes,
                                      NEGOBS_V4L2_MAX_MODES);
    best = st->cfg.pixel_format != 0u
               ? st->cfg.pixel_format
               : negobs_v4l2_choose_format(modes, n, cap_w, cap_h,
                                           st->cfg.fps);
    if (negobs_v4l2_format_rank(best) < 0 && st->cfg.pixel_format != 0u) {
        v4l2_error(st, 0,
                   "%s: pixel format %c%c%c%c is not one negobs converts "
                   "(GREY/NV12/NV21/YU12/YV12/YUYV/UYVY/Y10/Y16/MJPG)",
                   d->path, (char)(best & 0x7Fu), (char)((best >> 8) & 0x7Fu),
                   (char)((best >> 16) & 0x7Fu), (char)((best >> 24) & 0x7Fu));
        return NEGOBS_ERR_UNSUPPORTED;
    }
    if (best == 0) {
        v4l2_error(st, 0,
                   "%s: no GREY/NV12/NV21/YU12/YV12/YUYV/UYVY/Y10/Y16/MJPG "
                   "format (negobs_run --list-cameras)",
                   d->path);
        return NEGOBS_ERR_UNSUPPORTED;
    }
    memset(&f, 0, sizeof f);
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    f.fmt.pix.width = (uint32_t)cap_w;
    f.fmt.pix.height = (uint32_t)cap_h;
    f.fmt.pix.pixelformat = best;
    f.fmt.pix.field = V4L2_FIELD_NONE;
    f.fmt.pix.bytesperline = 0; /* let the driver choose its stride */
    if (v4l2_xioctl(d->fd, VIDIOC_S_FMT, &f) != 0) {
        int e = errno;
        v4l2_error(st, e, "%s: VIDIOC_S_FMT", d->path);
        return e == EINVAL ? NEGOBS_ERR_UNSUPPORTED : v4l2_errno_status(e);
    }
    /* S_FMT may change anything: believe what it returns. */
    if (f.fmt.pix.width > (uint32_t)NEGOBS_MAX_DIM ||
        f.fmt.pix.height > (uint32_t)NEGOBS_MAX_DIM) {
        v4l2_error(st, 0, "%s: driver size too large", d->path);
        return NEGOBS_ERR_UNSUPPORTED;
    }
    if (st->cfg.pixel_format != 0u &&
        f.fmt.pix.pixelformat != st->cfg.pixel_format) {
        /* asked for by name: another format is a configuration error,
         * not something to convert silently */
        v4l2_error(st, 0,
                   "%s: the node does not offer the configured pixel "
                   "format (negobs_run --list-cameras)",
                   d->path);
        return NEGOBS_ERR_UNSUPPORTED;
    }
    s = negobs_v4l2_check_format(f.fmt.pix.pixelformat,
                                 (int32_t)f.fmt.pix.width,
                                 (int32_t)f.fmt.pix.height,
                                 f.fmt.pix.bytesperline, f.fmt.pix.sizeimage);
    if (s != NEGOBS_OK) {
        v4l2_error(st, 0, "%s: driver returned an unusable format", d->path);
        return s;
    }
    d->fourcc = f.fmt.pix.pixelformat;
    d->width = (int32_t)f.fmt.pix.width;
    d->height = (int32_t)f.fmt.pix.height;
    d->bytesperline = f.fmt.pix.bytesperline;
    d->sizeimage = f.fmt.pix.sizeimage;
    s = negobs_v4l2_conv_setup(&d->conv, d->fourcc, d->width, d->height,
                               d->bytesperline, st->cfg.side_by_side,
                               st->cfg.capture_width > 0 ? st->cfg.width : 0,
                               st->cfg.capture_width > 0 ? st->cfg.height : 0);
    if (s != NEGOBS_OK) {
        v4l2_error(st, 0, "%s: %ldx%ld frames cannot give %ldx%ld%s", d->path,
                   (long)d->width, (long)d->height, (long)st->cfg.width,
                   (long)st->cfg.height,
                   st->cfg.side_by_side ? " per eye side by side" : "");
    }
    return s;
}

static void dev_set_rate(negobs_v4l2_dev_t *d, int32_t fps)
{
    struct v4l2_streamparm p;
    if (fps <= 0) {
        return;
    }
    memset(&p, 0, sizeof p);
    p.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (v4l2_xioctl(d->fd, VIDIOC_G_PARM, &p) != 0 ||
        (p.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) == 0) {
        return; /* the driver has a fixed rate */
    }
    p.parm.capture.timeperframe.numerator = 1;
    p.parm.capture.timeperframe.denominator = (uint32_t)fps;
    (void)v4l2_xioctl(d->fd, VIDIOC_S_PARM, &p);
}

static bool dev_has_ctrl(negobs_v4l2_dev_t *d, uint32_t id)
{
    struct v4l2_queryctrl q;
    memset(&q, 0, sizeof q);
    q.id = id;
    return v4l2_xioctl(d->fd, VIDIOC_QUERYCTRL, &q) == 0 &&
           (q.flags & V4L2_CTRL_FLAG_DISABLED) == 0;
}

static int dev_set_ctrl(negobs_v4l2_dev_t *d, uint32_t id, int32_t value)
{
    struct v4l2_control c;
    memset(&c, 0, sizeof c);
    c.id = id;
    c.value = value;
    return v4l2_xioctl(d->fd, VIDIOC_S_CTRL, &c);
}

static negobs_status_t dev_map_buffers(negobs_v4l2_t *st, negobs_v4l2_dev_t *d)
{
    struct v4l2_requestbuffers rb;
    uint32_t i;
    memset(&rb, 0, sizeof rb);
    rb.count = NEGOBS_V4L2_BUFFERS;
    rb.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    rb.memory = V4L2_MEMORY_MMAP;
    if (v4l2_xioctl(d->fd, VIDIOC_REQBUFS, &rb) != 0) {
        int e = errno;
        v4l2_error(st, e, "%s: VIDIOC_REQBUFS", d->path);
        return e == EINVAL ? NEGOBS_ERR_UNSUPPORTED : v4l2_errno_status(e);
    }
    d->nbuf = rb.count; /* so v4l2_dev_close frees them whatever happens */
    if (rb.count < NEGOBS_V4L2_MIN_BUFFERS ||
        rb.count > NEGOBS_V4L2_MAX_BUFFERS) {
        v4l2_error(st, 0, "%s: driver gave %u buffers, need %u..%u", d->path,
                   (unsigned)rb.count, (unsigned)NEGOBS_V4L2_MIN_BUFFERS,
                   (unsigned)NEGOBS_V4L2_MAX_BUFFERS);
        if (rb.count > NEGOBS_V4L2_MAX_BUFFERS) {
            d->nbuf = 0;
        }
        return NEGOBS_ERR_NOSPACE;
    }
    for (i = 0; i < rb.count; i++) {
        struct v4l2_buffer b;
        void *p;
        memset(&b, 0, sizeof b);
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = i;
        if (v4l2_xioctl(d->fd, VIDIOC_QUERYBUF, &b) != 0) {
            int e = errno;
            v4l2_error(st, e, "%s: VIDIOC_QUERYBUF", d->path);
            return v4l2_errno_status(e);
        }
        p = mmap(NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, d->fd,
                 (off_t)b.m.offset);
        if (p == MAP_FAILED) {
            int e = errno;
            v4l2_error(st, e, "%s: mmap", d->path);
            return v4l2_errno_status(e);
        }
        d->buf[i].start = p;
        d->buf[i].length = b.length;
    }
    return NEGOBS_OK;
}

negobs_status_t v4l2_dev_open(negobs_v4l2_t *st, negobs_v4l2_dev_t *d)
{
    struct v4l2_capability cap;
    uint32_t caps;
    negobs_status_t s;
    d->fd = open(d->path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (d->fd < 0) {
        int e = errno;
        v4l2_error(st, e, "open %s", d->path);
        d->fd = -1;
        return v4l2_errno_status(e);
    }
    memset(&cap, 0, sizeof cap);
    if (v4l2_xioctl(d->fd, VIDIOC_QUERYCAP, &cap) != 0) {
        int e = errno;
        v4l2_error(st, e, "%s: VIDIOC_QUERYCAP (not a V4L2 device?)", d->path);
        v4l2_dev_close(d);
        return (e == ENOTTY || e == ENOSYS || e == EINVAL)
                   ? NEGOBS_ERR_UNSUPPORTED
                   : v4l2_errno_status(e);
    }
    caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps
                                                          : cap.capabilities;
    if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 ||
        (caps & V4L2_CAP_STREAMING) == 0) {
        v4l2_error(st, 0, "%s: no single-planar streaming capture", d->path);
        v4l2_dev_close(d);
        return NEGOBS_ERR_UNSUPPORTED;
    }
    s = dev_set_format(st, d);
    if (s == NEGOBS_OK) {
        dev_set_rate(d, st->cfg.fps);
        d->has_exposure = dev_has_ctrl(d, V4L2_CID_EXPOSURE_ABSOLUTE);
        d->has_gain = dev_has_ctrl(d, V4L2_CID_GAIN);
        s = dev_map_buffers(st, d);
    }
    if (s != NEGOBS_OK) {
        v4l2_dev_close(d);
    }
    return s;
}

negobs_status_t v4l2_dev_queue(negobs_v4l2_dev_t *d, uint32_t idx)
{
    struct v4l2_buffer b;
    memset(&b, 0, sizeof b);
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = idx;
    return v4l2_xioctl(d->fd, VIDIOC_QBUF, &b) == 0 ? NEGOBS_OK
                                                    : v4l2_errno_status(errno);
}

negobs_status_t v4l2_dev_start(negobs_v4l2_t *st, negobs_v4l2_dev_t *d)
{
    enum v4l2_buf_type t = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    uint32_t i;
    for (i = 0; i < d->nbuf; i++) {
        if (v4l2_dev_queue(d, i) != NEGOBS_OK) {
            int e = errno;
            v4l2_error(st, e, "%s: VIDIOC_QBUF", d->path);
            return v4l2_errno_status(e);
        }
    }
    if (v4l2_xioctl(d->fd, VIDIOC_STREAMON, &t) != 0) {
        int e = errno;
        v4l2_error(st, e, "%s: VIDIOC_STREAMON", d->path);
        return v4l2_errno_status(e);
    }
    d->streaming = true;
    d->timeouts_in_row = 0;
    return NEGOBS_OK;
}

/* Exposure and gain: set on both nodes alike, or on neither. */
void v4l2_apply_controls(negobs_v4l2_t *st)
{
    negobs_v4l2_dev_t *l = &st->dev[0];
    negobs_v4l2_dev_t *r = &st->dev[1];
    if (st->cfg.exposure >= 0) {
        if (l->has_exposure && r->has_exposure) {
            (void)dev_set_ctrl(l, V4L2_CID_EXPOSURE_AUTO,
                               V4L2_EXPOSURE_MANUAL);
            (void)dev_set_ctrl(r, V4L2_CID_EXPOSURE_AUTO,
                               V4L2_EXPOSURE_MANUAL);
            (void)dev_set_ctrl(l, V4L2_CID_EXPOSURE_ABSOLUTE,
                               st->cfg.exposure);
            (void)dev_set_ctrl(r, V4L2_CID_EXPOSURE_ABSOLUTE,
                               st->cfg.exposure);
        } else {
            v4l2_error(st, 0,
                       "exposure not offered by both cameras: left as is");
        }
    }
    if (st->cfg.gain >= 0) {
        if (l->has_gain && r->has_gain) {
            (void)dev_set_ctrl(l, V4L2_CID_GAIN, st->cfg.gain);
            (void)dev_set_ctrl(r, V4L2_CID_GAIN, st->cfg.gain);
        } else {
            v4l2_error(st, 0, "gain not offered by both cameras: left as is");
        }
    }
}
