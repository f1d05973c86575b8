/*
 * The V4L2 backend's device path against two fake capture nodes: open,
 * ioctl, poll, mmap, munmap and close are replaced at link time
 * (-Wl,--wrap=...), so format negotiation, buffer handling, timestamp
 * pairing, control handling and device loss/reopen run exactly as on a
 * device, without one. Calls on other descriptors go to the real libc.
 */
#define _DEFAULT_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdbool.h>
#include <string.h>
#include <time.h>
#include <sys/mman.h>
#include <sys/types.h>

#include <linux/videodev2.h>

#include "cmocka_all.h"
#include "negobs_port/camera.h"
#include "negobs_port/camera_v4l2.h"

#ifdef NEGOBS_TEST_MJPEG
#include <turbojpeg.h>
#endif

#define FW 64
#define FH 8
#define NBUF_MAX 4
#define BUFSZ (2 * 128 * FH)
#define FAKE_FD0 900

typedef struct fake_dev {
    const char *path;
    bool is_open;
    int open_errno; /* open() fails with this when non-zero */
    uint32_t fmts[4];
    int nfmts;
    uint32_t bpl_pad;       /* driver pads rows by this many bytes */
    uint32_t reqbufs_count; /* buffers the driver grants */
    bool has_exposure;
    int32_t exposure_set; /* last S_CTRL value, -1 none */
    int exposure_calls;
    /* live state */
    struct v4l2_pix_format fmt;
    uint32_t nbuf;
    bool queued[NBUF_MAX];
    bool streaming;
    uint8_t mem[NBUF_MAX][BUFSZ];
    /* frame script: timestamps in ms; arrive one per poll call */
    uint32_t ts_ms[16];
    int nframes;
    int arrived;
    int next;
    int dqbuf_errno_at; /* frame index at which DQBUF fails, -1 never */
    int dqbuf_errno;
    int frozen_from; /* frames [from, to) repeat frame from-1's */
    int frozen_to;   /* content (a hung ISP); -1 never          */
    /* MJPEG: frame n carries jpeg[n % 2] (jpeg[0] only when jpeg_same) */
    const uint8_t *jpeg[2];
    size_t jpeg_len[2];
    bool jpeg_same;
} fake_dev_t;

static fake_dev_t fk[2];
static int poll_eintr;  /* next polls fail with EINTR */
static int dqbuf_eintr; /* next DQBUFs fail with EINTR */

static fake_dev_t *fake_of(int fd)
{
    if (fd == FAKE_FD0 || fd == FAKE_FD0 + 1) {
        return &fk[fd - FAKE_FD0];
    }
    return NULL;
}

/* Meson builds with _FILE_OFFSET_BITS=64, so glibc's open() and mmap()
 * are the symbols open64 and mmap64 in the objects under test. */
int __real_open64(const char *path, int flags, ...);
int __wrap_open64(const char *path, int flags, ...);
int __real_close(int fd);
int __wrap_close(int fd);
int __real_ioctl(int fd, unsigned long req, ...);
int __wrap_ioctl(int fd, unsigned long req, ...);
int __real_poll(struct pollfd *fds, nfds_t n, int timeout);
int __wrap_poll(struct pollfd *fds, nfds_t n, int timeout);
void *__real_mmap64(void *a, size_t len, int prot, int flags, int fd,
                    off_t off);
void *__wrap_mmap64(void *a, size_t len, int prot, int flags, int fd,
                    off_t off);
int __real_munmap(void *a, size_t len);
int __wrap_munmap(void *a, size_t len);

int __wrap_open64(const char *path, int flags, ...)
{
    int i;
    mode_t mode = 0;
    va_list ap;
    va_start(ap, flags);
    if ((flags & O_CREAT) != 0) {
        mode = (mode_t)va_arg(ap, unsigned int);
    }
    va_end(ap);
    for (i = 0; i < 2; i++) {
        if (fk[i].path != NULL && strcmp(path, fk[i].path) == 0) {
            if (fk[i].open_errno != 0) {
                errno = fk[i].open_errno;
                return -1;
            }
            fk[i].is_open = true;
            fk[i].streaming = false;
            fk[i].nbuf = 0;
            memset(fk[i].queued, 0, sizeof fk[i].queued);
            return FAKE_FD0 + i;
        }
    }
    return __real_open64(path, flags, mode);
}

int __wrap_close(int fd)
{
    fake_dev_t *d = fake_of(fd);
    if (d == NULL) {
        return __real_close(fd);
    }
    d->is_open = false;
    return 0;
}

static int fake_fail(int e)
{
    errno = e;
    return -1;
}

static int fake_ioctl(fake_dev_t *d, unsigned long req, void *arg)
{
    if (!d->is_open) {
        return fake_fail(EBADF);
    }
    if (req == VIDIOC_QUERYCAP) {
        struct v4l2_capability *c = arg;
        memset(c, 0, sizeof *c);
        c->capabilities = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING |
                          V4L2_CAP_DEVICE_CAPS;
        c->device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
        return 0;
    }
    if (req == VIDIOC_ENUM_FMT) {
        struct v4l2_fmtdesc *f = arg;
        if (f->index >= (uint32_t)d->nfmts) {
            return fake_fail(EINVAL);
        }
        f->pixelformat = d->fmts[f->index];
        return 0;
    }
    if (req == VIDIOC_S_FMT) {
        struct v4l2_format *f = arg;
        uint32_t bpp = f->fmt.pix.pixelformat == V4L2_PIX_FMT_YUYV ? 2u : 1u;
        /* The driver clamps the size and pads the rows. */
        f->fmt.pix.width = FW;
        f->fmt.pix.height = FH;
        f->fmt.pix.bytesperline = FW * bpp + d->bpl_pad;
        f->fmt.pix.sizeimage = f->fmt.pix.bytesperline * FH *
                               (bpp == 1u ? 3u : 2u) / 2u;
        if (f->fmt.pix.pixelformat == V4L2_PIX_FMT_MJPEG) {
            f->fmt.pix.bytesperline = 0; /* compressed */
            f->fmt.pix.sizeimage = BUFSZ;
        }
        d->fmt = f->fmt.pix;
        return 0;
    }
    if (req == VIDIOC_G_PARM || req == VIDIOC_S_PARM) {
        struct v4l2_streamparm *p = arg;
        p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
        return 0;
    }
    if (req == VIDIOC_QUERYCTRL) {
        struct v4l2_queryctrl *q = arg;
        return (q->id == V4L2_CID_EXPOSURE_ABSOLUTE && d->has_exposure)
                   ? 0
                   : fake_fail(EINVAL);
    }
    if (req == VIDIOC_S_CTRL) {
        struct v4l2_control *c = arg;
        if (c->id == V4L2_CID_EXPOSURE_ABSOLUTE) {
            d->exposure_set = c->value;
            d->exposure_calls++;
        }
        return 0;
    }
    if (req == VIDIOC_REQBUFS) {
        struct v4l2_requestbuffers *r = arg;
        d->nbuf = r->count == 0 ? 0 : d->reqbufs_count;
        r->count = d->nbuf;
        return 0;
    }
    if (req == VIDIOC_QUERYBUF) {
        struct v4l2_buffer *b = arg;
        if (b->index >= d->nbuf) {
            return fake_fail(EINVAL);
        }
        b->length = BUFSZ;
        b->m.offset = b->index * BUFSZ;
        return 0;
    }
    if (req == VIDIOC_QBUF) {
        struct v4l2_buffer *b = arg;
        if (b->index >= d->nbuf || d->queued[b->index]) {
            return fake_fail(EINVAL);
        }
        d->queued[b->index] = true;
        return 0;
    }
    if (req == VIDIOC_STREAMON) {
        d->streaming = true;
        return 0;
    }
    if (req == VIDIOC_STREAMOFF) {
        d->streaming = false;
        memset(d->queued, 0, sizeof d->queued);
        return 0;
    }
    if (req == VIDIOC_DQBUF) {
        struct v4l2_buffer *b = arg;
        uint32_t i;
        if (dqbuf_eintr > 0) {
            dqbuf_eintr--;
            return fake_fail(EINTR);
        }
        if (d->dqbuf_errno_at >= 0 && d->next >= d->dqbuf_errno_at &&
            d->next < d->arrived) {
            int e = d->dqbuf_errno;
            d->dqbuf_errno_at = -1; /* fails once */
            return fake_fail(e);
        }
        if (!d->streaming || d->next >= d->arrived) {
            return fake_fail(EAGAIN);
        }
        for (i = 0; i < d->nbuf; i++) {
            if (d->queued[i]) {
                break;
            }
        }
        if (i == d->nbuf) {
            return fake_fail(EAGAIN); /* all buffers with the application */
        }
        d->queued[i] = false;
        memset(d->mem[i],
               0x10 + (d->frozen_from > 0 && d->next >= d->frozen_from &&
                               d->next < d->frozen_to
                           ? d->frozen_from - 1
                           : d->next),
               BUFSZ);
        b->index = i;
        b->bytesused = d->fmt.sizeimage;
        if (d->jpeg[0] != NULL) {
            int k = d->jpeg_same ? 0 : d->next % 2;
            memcpy(d->mem[i], d->jpeg[k], d->jpeg_len[k]);
            b->bytesused = (uint32_t)d->jpeg_len[k];
        }
        b->flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
        b->timestamp.tv_sec = (time_t)(d->ts_ms[d->next] / 1000u);
        b->timestamp.tv_usec = (suseconds_t)((d->ts_ms[d->next] % 1000u) *
                                             1000u);
        b->sequence = (uint32_t)d->next;
        d->next++;
        return 0;
    }
    return fake_fail(ENOTTY);
}

int __wrap_ioctl(int fd, unsigned long req, ...)
{
    va_list ap;
    void *arg;
    fake_dev_t *d;
    va_start(ap, req);
    arg = va_arg(ap, void *);
    va_end(ap);
    d = fake_of(fd);
    if (d == NULL) {
        return __real_ioctl(fd, req, arg);
    }
    return fake_ioctl(d, req, arg);
}

/* Each poll lets one more frame arrive on every polled node. */
int __wrap_poll(struct pollfd *fds, nfds_t n, int timeout)
{
    nfds_t i;
    int ready = 0;
    if (n == 0 || fake_of(fds[0].fd) == NULL) {
        return __real_poll(fds, n, timeout);
    }
    if (poll_eintr > 0) {
        poll_eintr--;
        errno = EINTR;
        return -1;
    }
    for (i = 0; i < n; i++) {
        fake_dev_t *d = fake_of(fds[i].fd);
        fds[i].revents = 0;
        if (d->arrived < d->nframes) {
            d->arrived++;
        }
        if (d->next < d->arrived) {
            fds[i].revents = POLLIN;
            ready++;
        }
    }
    return ready; /* 0 = timeout, returned at once */
}

void *__wrap_mmap64(void *a, size_t len, int prot, int flags, int fd,
                    off_t off)
{
    fake_dev_t *d = fake_of(fd);
    if (d == NULL) {
        return __real_mmap64(a, len, prot, flags, fd, off);
    }
    return d->mem[(size_t)off / BUFSZ];
}

int __wrap_munmap(void *a, size_t len)
{
    int i;
    for (i = 0; i < 2; i++) {
        if ((uint8_t *)a >= &fk[i].mem[0][0] &&
            (uint8_t *)a < &fk[i].mem[0][0] + sizeof fk[i].mem) {
            return 0;
        }
    }
    return __real_munmap(a, len);
}

/* ---- fixtures -------------------------------------------------------- */

static negobs_v4l2_t st;
static negobs_capture_t cam;
static uint8_t scratch[2 * FW * FH];
static int32_t frozen_limit; /* cfg.frozen_frames of open_cam() */
static int32_t pair_tol;     /* cfg.pair_tol_ms of open_cam() */

static int setup(void **state)
{
    int i;
    (void)state;
    memset(fk, 0, sizeof fk);
    poll_eintr = 0;
    dqbuf_eintr = 0;
    fk[0].path = "/fake/video0";
    fk[1].path = "/fake/video1";
    for (i = 0; i < 2; i++) {
        fk[i].fmts[0] = V4L2_PIX_FMT_YUYV;
        fk[i].fmts[1] = V4L2_PIX_FMT_NV12;
        fk[i].nfmts = 2;
        fk[i].bpl_pad = 16;
        fk[i].reqbufs_count = 4;
        fk[i].exposure_set = -1;
        fk[i].dqbuf_errno_at = -1;
        fk[i].frozen_from = -1;
        fk[i].frozen_to = -1;
    }
    frozen_limit = NEGOBS_CAPTURE_FROZEN_FRAMES_DEFAULT;
    pair_tol = NEGOBS_CAPTURE_PAIR_TOL_MS_DEFAULT;
    return 0;
}

static void script(int side, const uint32_t *ts, int n)
{
    memcpy(fk[side].ts_ms, ts, (size_t)n * sizeof ts[0]);
    fk[side].nframes = n;
}

static negobs_status_t open_cam(int32_t exposure)
{
    negobs_capture_config_t cfg;
    negobs_status_t s;
    negobs_capture_config_default(&cfg);
    cfg.left = "/fake/video0";
    cfg.right = "v4l2:/fake/video1";
    cfg.exposure = exposure;
    cfg.frozen_frames = frozen_limit;
    cfg.pair_tol_ms = pair_tol;
    assert_int_equal(negobs_v4l2_init(&st, scratch, sizeof scratch, &cam),
                     NEGOBS_OK);
    s = negobs_capture_open(&cam, &cfg);
    if (s == NEGOBS_OK) {
        assert_int_equal(negobs_capture_start(&cam), NEGOBS_OK);
    }
    return s;
}

/* ---- tests ----------------------------------------------------------- */

static void test_v4l2_negotiates_planar_and_hands_out_y_in_place(void **state)
{
    static const uint32_t ts[] = {1000, 1033};
    negobs_frame_pair_t p;
    (void)state;
    script(0, ts, 2);
    script(1, ts, 2);
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    assert_int_equal(st.dev[0].fourcc, V4L2_PIX_FMT_NV12);
    assert_int_equal(st.dev[0].bytesperline, FW + 16);
    assert_true(fk[0].streaming && fk[1].streaming);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.left.y.width, FW);
    assert_int_equal(p.left.y.height, FH);
    assert_int_equal(p.left.y.stride, FW + 16); /* bytesperline, no copy */
    assert_true(p.left.y.data >= &fk[0].mem[0][0] &&
                p.left.y.data < &fk[0].mem[0][0] + sizeof fk[0].mem);
    assert_int_equal(p.left.ts_ns, 1000u * 1000000u);
    assert_int_equal(p.left.y.data[0], 0x10);
    /* Released buffers go back to the driver. */
    negobs_capture_release(&cam, &p);
    assert_true(fk[0].queued[0] && fk[1].queued[0]);
    negobs_capture_stop(&cam);
    negobs_capture_close(&cam);
    assert_false(fk[0].is_open || fk[1].is_open);
}

static void test_v4l2_packed_only_extracts_luma_to_scratch(void **state)
{
    static const uint32_t ts[] = {1000};
    negobs_frame_pair_t p;
    (void)state;
    fk[0].nfmts = 1; /* YUYV only */
    fk[1].nfmts = 1;
    script(0, ts, 1);
    script(1, ts, 1);
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    assert_int_equal(st.dev[1].fourcc, V4L2_PIX_FMT_YUYV);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_ptr_equal(p.left.y.data, scratch);
    assert_ptr_equal(p.right.y.data, scratch + FW * FH);
    assert_int_equal(p.right.y.stride, FW);
    negobs_capture_close(&cam);
}

static void test_v4l2_pairs_by_timestamp_and_counts_drops(void **state)
{
    /* Right loses its 2nd frame: left 1033 has no partner. */
    static const uint32_t l[] = {1000, 1033, 1066, 1100};
    static const uint32_t r[] = {1002, 1068, 1103};
    negobs_frame_pair_t p;
    negobs_capture_stats_t s;
    (void)state;
    script(0, l, 4);
    script(1, r, 3);
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.left.ts_ns / 1000000u, 1000);
    assert_int_equal(p.right.ts_ns / 1000000u, 1002);
    negobs_capture_release(&cam, &p);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.left.ts_ns / 1000000u, 1066);
    assert_int_equal(p.right.ts_ns / 1000000u, 1068);
    assert_int_equal(p.left.sequence, 2);
    /* Not released on purpose: get_pair releases it itself. */
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.left.ts_ns / 1000000u, 1100);
    assert_int_equal(p.index, 2);
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.pairs, 3);
    assert_int_equal(s.dropped_pairs, 1);
    /* Nothing more: a timeout, reported as such. */
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 50),
                     NEGOBS_ERR_TIMEOUT);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "no frames from"));
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.timeouts, 1);
    negobs_capture_close(&cam);
}

static void test_v4l2_frozen_camera_withholds_pairs_until_it_changes(
    void **state)
{
    static const uint32_t ts[] = {1000, 1033, 1066, 1100, 1133, 1166, 1200};
    negobs_frame_pair_t p;
    negobs_capture_stats_t s;
    int i;
    (void)state;
    script(0, ts, 7);
    script(1, ts, 7);
    /* Right frames 1..4 repeat frame 0's content; frame 5 is new. */
    fk[1].frozen_from = 1;
    fk[1].frozen_to = 5;
    frozen_limit = 3;
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    /* Frames 0 and 1: two identical, below the limit of 3. */
    for (i = 0; i < 2; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
        negobs_capture_release(&cam, &p);
    }
    /* Frames 2, 3, 4: frozen, withheld with an error that says so, and
     * the buffers go back to the driver. */
    for (i = 2; i < 5; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                         NEGOBS_ERR_IO);
        assert_non_null(strstr(negobs_capture_errmsg(&cam), "frozen"));
        assert_non_null(strstr(negobs_capture_errmsg(&cam), "/fake/video1"));
    }
    assert_true(fk[1].queued[0] || fk[1].queued[1] || fk[1].queued[2] ||
                fk[1].queued[3]);
    /* Frame 5 changed: pairs flow again, without a reopen. */
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.right.ts_ns / 1000000u, 1166);
    assert_int_equal(p.right.y.data[0], 0x15);
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.frozen_pairs, 3);
    assert_int_equal(s.reopens, 0);
    negobs_capture_close(&cam);
}

static void test_v4l2_frame_waiting_too_long_is_dropped(void **state)
{
    /* Right's clock runs 4 s ahead: its frame is always the newer one and
     * would wait for a partner forever, hiding the node from poll. */
    static const uint32_t l[] = {1000};
    static const uint32_t r[] = {5000};
    negobs_frame_pair_t p;
    negobs_capture_stats_t s;
    struct timespec ts = {0, (long)(NEGOBS_V4L2_PENDING_MAX_MS + 100u) *
                                 1000000L};
    (void)state;
    script(0, l, 1);
    script(1, r, 1);
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 50),
                     NEGOBS_ERR_TIMEOUT);
    assert_true(st.dev[1].pending);
    assert_int_equal(st.dev[1].timeouts_in_row, 0);
    (void)nanosleep(&ts, NULL);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 50),
                     NEGOBS_ERR_TIMEOUT);
    assert_false(st.dev[1].pending);
    assert_int_equal(st.dev[1].timeouts_in_row, 1); /* polled again */
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.dropped_pairs, 2);
    negobs_capture_close(&cam);
}

static void test_v4l2_frozen_check_off_delivers_repeats(void **state)
{
    static const uint32_t ts[] = {1000, 1033, 1066, 1100};
    negobs_frame_pair_t p;
    int i;
    (void)state;
    script(0, ts, 4);
    script(1, ts, 4);
    fk[0].frozen_from = 1;
    fk[0].frozen_to = 4;
    frozen_limit = 0;
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    for (i = 0; i < 4; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    }
    negobs_capture_close(&cam);
}

static void test_v4l2_drift_beyond_tolerance_times_out_as_out_of_sync(
    void **state)
{
    /* Right runs 16 ms behind left: nothing within 10 ms. */
    static const uint32_t l[] = {1000, 1033, 1066, 1100, 1133};
    static const uint32_t r[] = {1016, 1049, 1082, 1100, 1133};
    negobs_frame_pair_t p;
    negobs_capture_stats_t s;
    (void)state;
    script(0, l, 5);
    script(1, r, 5);
    fk[0].nframes = 3; /* the first three for now */
    fk[1].nframes = 3;
    pair_tol = 10;
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 50),
                     NEGOBS_ERR_TIMEOUT);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "out of sync"));
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "16 ms"));
    negobs_capture_get_stats(&cam, &s);
    assert_true(s.dropped_pairs >= 4);
    assert_int_equal(s.pairs, 0);
    /* The drift ends (the cameras are back in step): pairs again, no
     * reopen. */
    fk[0].nframes = 5;
    fk[1].nframes = 5;
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.left.ts_ns / 1000000u, 1100);
    assert_int_equal(p.right.ts_ns / 1000000u, 1100);
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.reopens, 0);
    negobs_capture_close(&cam);
}

static void test_v4l2_device_loss_reopens_with_backoff(void **state)
{
    static const uint32_t ts[] = {1000, 1033, 1066, 1100};
    negobs_frame_pair_t p;
    negobs_capture_stats_t s;
    (void)state;
    script(0, ts, 4);
    script(1, ts, 4);
    fk[1].dqbuf_errno_at = 1;
    fk[1].dqbuf_errno = ENODEV;
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    negobs_capture_release(&cam, &p);
    /* Right node vanishes; reopen is refused at first. */
    fk[1].open_errno = ENOENT;
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 300), NEGOBS_ERR_NODEV);
    assert_false(fk[1].is_open);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "/fake/video1"));
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.device_losses, 1);
    assert_int_equal(s.reopens, 0);
    /* The node comes back: the next calls reopen it and pairs flow. */
    fk[1].open_errno = 0;
    fk[1].arrived = fk[1].next = 0;
    fk[1].ts_ms[0] = 1066;
    fk[1].ts_ms[1] = 1100;
    fk[1].nframes = 2;
    {
        int rc = NEGOBS_ERR_NODEV;
        int tries = 0;
        while (rc == NEGOBS_ERR_NODEV && tries++ < 10) {
            rc = negobs_capture_get_pair(&cam, &p, 300);
        }
        assert_int_equal(rc, NEGOBS_OK);
    }
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.reopens, 1);
    assert_true(fk[1].is_open && fk[1].streaming);
    assert_int_equal(p.right.ts_ns / 1000000u, p.left.ts_ns / 1000000u);
    negobs_capture_close(&cam);
}

static void test_v4l2_repeated_timeouts_mark_node_lost(void **state)
{
    negobs_frame_pair_t p;
    negobs_capture_stats_t s;
    int i;
    (void)state;
    assert_int_equal(open_cam(-1), NEGOBS_OK); /* no frames scripted */
    for (i = 0; i < NEGOBS_V4L2_TIMEOUTS_BEFORE_REOPEN; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 10),
                         NEGOBS_ERR_TIMEOUT);
    }
    negobs_capture_get_stats(&cam, &s);
    assert_int_equal(s.timeouts, NEGOBS_V4L2_TIMEOUTS_BEFORE_REOPEN);
    assert_int_equal(s.device_losses, 2);
    negobs_capture_close(&cam);
}

static void test_v4l2_signals_give_again_and_ioctls_retry(void **state)
{
    static const uint32_t ts[] = {1000, 1033};
    negobs_frame_pair_t p;
    (void)state;
    script(0, ts, 2);
    script(1, ts, 2);
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    /* A signal during the wait: the caller gets AGAIN to check its flags. */
    poll_eintr = 1;
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_ERR_AGAIN);
    /* EINTR inside DQBUF is retried silently. */
    dqbuf_eintr = 3;
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(dqbuf_eintr, 0);
    assert_int_equal(p.left.ts_ns / 1000000u, 1000);
    negobs_capture_close(&cam);
}

static void test_v4l2_exposure_only_when_both_offer_it(void **state)
{
    (void)state;
    fk[0].has_exposure = true;
    assert_int_equal(open_cam(500), NEGOBS_OK);
    assert_int_equal(fk[0].exposure_calls + fk[1].exposure_calls, 0);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "exposure"));
    negobs_capture_close(&cam);
    fk[1].has_exposure = true;
    assert_int_equal(open_cam(500), NEGOBS_OK);
    assert_int_equal(fk[0].exposure_set, 500);
    assert_int_equal(fk[1].exposure_set, 500);
    negobs_capture_close(&cam);
}

/* One node carrying both eyes side by side (ELP/Arducam/ZED style): each
 * frame is one pair, the halves described in the driver's buffer. */
static void test_v4l2_side_by_side_one_node(void **state)
{
    static const uint32_t ts[] = {1000, 1033, 1066};
    negobs_capture_config_t cfg;
    negobs_frame_pair_t p;
    (void)state;
    fk[0].fmts[0] = V4L2_PIX_FMT_GREY;
    fk[0].nfmts = 1;
    script(0, ts, 3);
    negobs_capture_config_default(&cfg);
    cfg.left = "/fake/video0";
    cfg.right = NULL;
    cfg.side_by_side = true;
    cfg.width = FW / 2;
    cfg.height = FH;
    assert_int_equal(negobs_v4l2_init(&st, NULL, 0, &cam), NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_OK);
    assert_int_equal(negobs_capture_start(&cam), NEGOBS_OK);
    assert_false(fk[1].is_open); /* the second node is never touched */
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.left.y.width, FW / 2);
    assert_int_equal(p.right.y.width, FW / 2);
    assert_ptr_equal(p.right.y.data, p.left.y.data + FW / 2);
    assert_int_equal(p.left.y.stride, FW + 16);
    assert_true(p.left.y.data >= &fk[0].mem[0][0] &&
                p.left.y.data < &fk[0].mem[0][0] + sizeof fk[0].mem);
    assert_int_equal(p.left.ts_ns, p.right.ts_ns);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.index, 1);
    negobs_capture_stop(&cam);
    negobs_capture_close(&cam);
    assert_false(fk[0].is_open || fk[1].is_open);
}

/* pixel_format names the format: asked for even where a cheaper one is
 * listed (the node offers NV12 and YUYV: YUYV is set), and a fourcc negobs
 * cannot convert is refused before any S_FMT. */
static void test_v4l2_configured_pixel_format_is_asked_for(void **state)
{
    static const uint32_t ts[] = {1000};
    negobs_capture_config_t cfg;
    (void)state;
    script(0, ts, 1);
    script(1, ts, 1);
    negobs_capture_config_default(&cfg);
    cfg.left = "/fake/video0";
    cfg.right = "/fake/video1";
    cfg.width = FW;
    cfg.height = FH;
    assert_int_equal(negobs_v4l2_init(&st, scratch, sizeof scratch, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_OK);
    assert_int_equal(fk[0].fmt.pixelformat, V4L2_PIX_FMT_NV12);
    negobs_capture_close(&cam);
    cfg.pixel_format = V4L2_PIX_FMT_YUYV;
    assert_int_equal(negobs_v4l2_init(&st, scratch, sizeof scratch, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_OK);
    assert_int_equal(fk[0].fmt.pixelformat, V4L2_PIX_FMT_YUYV);
    assert_int_equal(fk[1].fmt.pixelformat, V4L2_PIX_FMT_YUYV);
    negobs_capture_close(&cam);
    memset(&fk[0].fmt, 0, sizeof fk[0].fmt);
    cfg.pixel_format = V4L2_PIX_FMT_RGB24;
    assert_int_equal(negobs_v4l2_init(&st, scratch, sizeof scratch, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_UNSUPPORTED);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "pixel format RGB3"));
    assert_int_equal(fk[0].fmt.pixelformat, 0); /* never set */
    assert_false(fk[0].is_open || fk[1].is_open);
}

/* A capture size larger than the processing size: 2x2 binned into the
 * scratch buffer (YUYV: every other byte, averaged). */
static void test_v4l2_capture_binned_to_processing_size(void **state)
{
    static const uint32_t ts[] = {1000};
    negobs_capture_config_t cfg;
    negobs_frame_pair_t p;
    (void)state;
    fk[0].nfmts = 1; /* YUYV only */
    fk[1].nfmts = 1;
    script(0, ts, 1);
    script(1, ts, 1);
    negobs_capture_config_default(&cfg);
    cfg.left = "/fake/video0";
    cfg.right = "/fake/video1";
    cfg.capture_width = FW;
    cfg.capture_height = FH;
    cfg.width = FW / 2;
    cfg.height = FH / 2;
    assert_int_equal(negobs_v4l2_init(&st, scratch, sizeof scratch, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_OK);
    assert_int_equal(st.dev[0].conv.plan.k, 2);
    assert_int_equal(negobs_capture_start(&cam), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(p.left.y.width, FW / 2);
    assert_int_equal(p.left.y.height, FH / 2);
    assert_int_equal(p.left.y.stride, FW / 2);
    assert_true(p.left.y.data >= scratch &&
                p.left.y.data < scratch + sizeof scratch);
    assert_int_equal(p.left.y.data[0], 0x10);
    negobs_capture_close(&cam);
    /* too little scratch: open refuses and says how much it needs */
    assert_int_equal(negobs_v4l2_init(&st, scratch, 100, &cam), NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_NOSPACE);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "scratch"));
    /* a processing size the frames cannot give: refused */
    cfg.width = FW * 2;
    assert_int_equal(negobs_v4l2_init(&st, scratch, sizeof scratch, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_INVAL);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "cannot give"));
    assert_false(fk[0].is_open || fk[1].is_open);
}

#ifdef NEGOBS_TEST_MJPEG
/* Two MJPEG nodes: frames decoded into the scratch buffer; a node whose
 * compressed frames stop changing is frozen (its frames are signed by
 * their data, bytesperline being 0), and one whose frames change is not. */
static void test_v4l2_mjpeg_decodes_and_detects_frozen(void **state)
{
    static const uint32_t ts[] = {1000, 1033, 1066, 1100, 1133, 1166};
    static uint8_t px[2][FH][FW];
    static uint8_t jpeg[2][BUFSZ];
    unsigned long n[2];
    negobs_frame_pair_t p;
    uint32_t seed = 5;
    int i;
    int k;
    (void)state;
    for (k = 0; k < 2; k++) {
        tjhandle t = tjInitCompress();
        unsigned char *out = jpeg[k];
        int x;
        int y;
        for (y = 0; y < FH; y++) {
            for (x = 0; x < FW; x++) {
                px[k][y][x] = (uint8_t)(100 + (test_lcg_next(&seed) & 7u));
            }
        }
        n[k] = BUFSZ;
        assert_int_equal(tjCompress2(t, &px[k][0][0], FW, 0, FH, TJPF_GRAY,
                                     &out, &n[k], TJSAMP_GRAY, 95,
                                     TJFLAG_NOREALLOC),
                         0);
        (void)tjDestroy(t);
    }
    for (i = 0; i < 2; i++) {
        fk[i].fmts[0] = V4L2_PIX_FMT_MJPEG;
        fk[i].nfmts = 1;
        fk[i].jpeg[0] = jpeg[0];
        fk[i].jpeg[1] = jpeg[1];
        fk[i].jpeg_len[0] = n[0];
        fk[i].jpeg_len[1] = n[1];
        script(i, ts, 6);
    }
    frozen_limit = 3;
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    assert_int_equal(st.dev[0].fourcc, V4L2_PIX_FMT_MJPEG);
    for (i = 0; i < 6; i++) { /* changing frames: never frozen */
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
        assert_true(p.left.y.data >= scratch &&
                    p.left.y.data < scratch + sizeof scratch);
        assert_in_range(p.left.y.data[0], 96, 112); /* decoded texture */
        negobs_capture_release(&cam, &p);
    }
    negobs_capture_close(&cam);

    setup(NULL);
    for (i = 0; i < 2; i++) {
        fk[i].fmts[0] = V4L2_PIX_FMT_MJPEG;
        fk[i].nfmts = 1;
        fk[i].jpeg[0] = jpeg[0];
        fk[i].jpeg_len[0] = n[0];
        fk[i].jpeg_same = i == 1; /* the right camera hangs */
        fk[i].jpeg[1] = jpeg[1];
        fk[i].jpeg_len[1] = n[1];
        script(i, ts, 6);
    }
    frozen_limit = 3;
    assert_int_equal(open_cam(-1), NEGOBS_OK);
    for (i = 0; i < 2; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
        negobs_capture_release(&cam, &p);
    }
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_ERR_IO);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "frozen"));
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "/fake/video1"));
    negobs_capture_close(&cam);
}
#endif

static void test_v4l2_too_few_buffers_or_formats_fail_open(void **state)
{
    (void)state;
    fk[1].reqbufs_count = 2;
    assert_int_equal(open_cam(-1), NEGOBS_ERR_NOSPACE);
    assert_false(fk[0].is_open || fk[1].is_open);
    fk[1].reqbufs_count = 4;
    fk[0].fmts[0] = V4L2_PIX_FMT_H264;
    fk[0].nfmts = 1;
    assert_int_equal(open_cam(-1), NEGOBS_ERR_UNSUPPORTED);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "format"));
    assert_false(fk[0].is_open || fk[1].is_open);
}

int main(void)
{
#define T(f) cmocka_unit_test_setup(f, setup)
    const struct CMUnitTest tests[] = {
        T(test_v4l2_negotiates_planar_and_hands_out_y_in_place),
        T(test_v4l2_packed_only_extracts_luma_to_scratch),
        T(test_v4l2_side_by_side_one_node),
#ifdef NEGOBS_TEST_MJPEG
        T(test_v4l2_mjpeg_decodes_and_detects_frozen),
#endif
        T(test_v4l2_configured_pixel_format_is_asked_for),
        T(test_v4l2_capture_binned_to_processing_size),
        T(test_v4l2_pairs_by_timestamp_and_counts_drops),
        T(test_v4l2_frozen_camera_withholds_pairs_until_it_changes),
        T(test_v4l2_frozen_check_off_delivers_repeats),
        T(test_v4l2_frame_waiting_too_long_is_dropped),
        T(test_v4l2_drift_beyond_tolerance_times_out_as_out_of_sync),
        T(test_v4l2_device_loss_reopens_with_backoff),
        T(test_v4l2_repeated_timeouts_mark_node_lost),
        T(test_v4l2_signals_give_again_and_ioctls_retry),
        T(test_v4l2_exposure_only_when_both_offer_it),
        T(test_v4l2_too_few_buffers_or_formats_fail_open),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
