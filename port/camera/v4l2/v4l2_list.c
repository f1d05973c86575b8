/*
 * V4L2 discovery: modes of a node, the format choice from them, and the
 * --list-cameras listing (see negobs_port/camera_list.h).
 */
#define _DEFAULT_SOURCE

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <linux/videodev2.h>

#include "negobs_port/camera_list.h"
#include "negobs_port/camera_v4l2.h"
#include "negobs_port/mjpeg.h"

static int xioctl(int fd, unsigned long req, void *arg)
{
    int r;
    do {
        r = ioctl(fd, req, arg);
    } while (r < 0 && errno == EINTR);
    return r;
}

uint32_t negobs_v4l2_choose_format(const negobs_v4l2_mode_t *modes, size_t n,
                                   int32_t width, int32_t height, int32_t fps)
{
    const uint32_t want_milli = fps > 0 ? (uint32_t)fps * 1000u : 0u;
    uint32_t best_fast = 0;
    int rank_fast = -1;
    uint32_t best_size = 0;
    int rank_size = -1;
    uint32_t fps_size = 0;
    uint32_t best_any = 0;
    int rank_any = -1;
    size_t i;
    for (i = 0; i < n; i++) {
        const negobs_v4l2_mode_t *m = &modes[i];
        int r = negobs_v4l2_format_rank(m->fourcc);
        bool size_ok = m->width == width && m->height == height;
        if (r < 0) {
            continue;
        }
        if (rank_any < 0 || r < rank_any) {
            rank_any = r;
            best_any = m->fourcc;
        }
        if (!size_ok) {
            continue;
        }
        /* a rate the driver does not state counts as fast enough */
        if ((m->fps_milli == 0u || m->fps_milli >= want_milli) &&
            (rank_fast < 0 || r < rank_fast)) {
            rank_fast = r;
            best_fast = m->fourcc;
        }
        if (rank_size < 0 || m->fps_milli > fps_size ||
            (m->fps_milli == fps_size && r < rank_size)) {
            rank_size = r;
            fps_size = m->fps_milli;
            best_size = m->fourcc;
        }
    }
    return rank_fast >= 0 ? best_fast : rank_size >= 0 ? best_size : best_any;
}

/* Fastest rate of one size (the shortest frame interval). */
static uint32_t max_fps_milli(int fd, uint32_t fourcc, uint32_t w, uint32_t h)
{
    struct v4l2_frmivalenum iv;
    uint32_t best = 0;
    memset(&iv, 0, sizeof iv);
    iv.pixel_format = fourcc;
    iv.width = w;
    iv.height = h;
    while (iv.index < 64u &&
           xioctl(fd, VIDIOC_ENUM_FRAMEINTERVALS, &iv) == 0) {
        const struct v4l2_fract *f = iv.type == V4L2_FRMIVAL_TYPE_DISCRETE
                                         ? &iv.discrete
                                         : &iv.stepwise.min;
        if (f->numerator > 0u) {
            uint64_t milli = (uint64_t)f->denominator * 1000u / f->numerator;
            if (milli > best && milli <= 0xFFFFFFFFu) {
                best = (uint32_t)milli;
            }
        }
        if (iv.type != V4L2_FRMIVAL_TYPE_DISCRETE) {
            break;
        }
        iv.index++;
    }
    return best;
}

static size_t add_mode(int fd, negobs_v4l2_mode_t *modes, size_t n, size_t max,
                       uint32_t fourcc, uint32_t w, uint32_t h)
{
    if (n >= max || w > (uint32_t)NEGOBS_MAX_DIM ||
        h > (uint32_t)NEGOBS_MAX_DIM) {
        return n;
    }
    modes[n].fourcc = fourcc;
    modes[n].width = (int32_t)w;
    modes[n].height = (int32_t)h;
    modes[n].fps_milli = w > 0u ? max_fps_milli(fd, fourcc, w, h) : 0u;
    return n + 1u;
}

size_t negobs_v4l2_enum_modes(int fd, int32_t width, int32_t height,
                              negobs_v4l2_mode_t *modes, size_t max)
{
    struct v4l2_fmtdesc fd_desc;
    size_t n = 0;
    memset(&fd_desc, 0, sizeof fd_desc);
    fd_desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    while (fd_desc.index < 64u && xioctl(fd, VIDIOC_ENUM_FMT, &fd_desc) == 0) {
        struct v4l2_frmsizeenum fs;
        size_t before = n;
        memset(&fs, 0, sizeof fs);
        fs.pixel_format = fd_desc.pixelformat;
        while (fs.index < 128u &&
               xioctl(fd, VIDIOC_ENUM_FRAMESIZES, &fs) == 0) {
            if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
                n = add_mode(fd, modes, n, max, fs.pixel_format,
                             fs.discrete.width, fs.discrete.height);
                fs.index++;
                continue;
            }
            /* a range: its largest size, and the one asked for in it */
            n = add_mode(fd, modes, n, max, fs.pixel_format,
                         fs.stepwise.max_width, fs.stepwise.max_height);
            if (width > 0 && height > 0 &&
                (uint32_t)width >= fs.stepwise.min_width &&
                (uint32_t)width <= fs.stepwise.max_width &&
                (uint32_t)height >= fs.stepwise.min_height &&
                (uint32_t)height <= fs.stepwise.max_height) {
                n = add_mode(fd, modes, n, max, fs.pixel_format,
                             (uint32_t)width, (uint32_t)height);
            }
            break;
        }
        if (n == before) {
            n = add_mode(fd, modes, n, max, fd_desc.pixelformat, 0u, 0u);
        }
        fd_desc.index++;
    }
    return n;
}

static void fourcc_str(uint32_t f, char s[5])
{
    int i;
    for (i = 0; i < 4; i++) {
        char c = (char)((f >> (8 * i)) & 0x7Fu);
        if (c < 32 || c == 127) {
            c = '.';
        }
        s[i] = c;
    }
    s[4] = '\0';
}

static const char *why_unusable(uint32_t fourcc)
{
    if (fourcc == NEGOBS_FOURCC('M', 'J', 'P', 'G') &&
        !negobs_mjpeg_available()) {
        return "not usable: built without libturbojpeg";
    }
    return negobs_v4l2_format_rank(fourcc) >= 0 ? "usable" : "not usable";
}

/* Print the formats of an open capture node; returns usable formats. */
static int list_formats(int fd, FILE *out)
{
    struct v4l2_fmtdesc d;
    int usable = 0;
    memset(&d, 0, sizeof d);
    d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    while (d.index < 64u && xioctl(fd, VIDIOC_ENUM_FMT, &d) == 0) {
        struct v4l2_frmsizeenum fs;
        char cc[5];
        fourcc_str(d.pixelformat, cc);
        fprintf(out, "    [%u]: '%s' (%.32s%s) %s\n", (unsigned)d.index, cc,
                (const char *)d.description,
                (d.flags & V4L2_FMT_FLAG_COMPRESSED) != 0 ? ", compressed"
                                                          : "",
                why_unusable(d.pixelformat));
        if (negobs_v4l2_format_rank(d.pixelformat) >= 0) {
            usable++;
        }
        memset(&fs, 0, sizeof fs);
        fs.pixel_format = d.pixelformat;
        while (fs.index < 128u &&
               xioctl(fd, VIDIOC_ENUM_FRAMESIZES, &fs) == 0) {
            if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
                uint32_t milli = max_fps_milli(
                    fd, d.pixelformat, fs.discrete.width, fs.discrete.height);
                fprintf(out, "        Size: Discrete %ux%u",
                        (unsigned)fs.discrete.width,
                        (unsigned)fs.discrete.height);
                if (milli > 0u) {
                    fprintf(out, " up to %u.%03u fps",
                            (unsigned)(milli / 1000u),
                            (unsigned)(milli % 1000u));
                }
                fputc('\n', out);
                fs.index++;
                continue;
            }
            fprintf(out, "        Size: %s %ux%u - %ux%u (step %ux%u)\n",
                    fs.type == V4L2_FRMSIZE_TYPE_CONTINUOUS ? "Continuous"
                                                            : "Stepwise",
                    (unsigned)fs.stepwise.min_width,
                    (unsigned)fs.stepwise.min_height,
                    (unsigned)fs.stepwise.max_width,
                    (unsigned)fs.stepwise.max_height,
                    (unsigned)fs.stepwise.step_width,
                    (unsigned)fs.stepwise.step_height);
            break;
        }
        d.index++;
    }
    return usable;
}

negobs_status_t negobs_v4l2_list_node(const char *path, FILE *out)
{
    struct v4l2_capability cap;
    uint32_t caps;
    int fd;
    int usable;
    fd = open(path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        fprintf(out, "%s: cannot open: %s\n", path, strerror(errno));
        return NEGOBS_ERR_NODEV;
    }
    memset(&cap, 0, sizeof cap);
    if (xioctl(fd, VIDIOC_QUERYCAP, &cap) != 0) {
        fprintf(out, "%s: not a V4L2 device (VIDIOC_QUERYCAP: %s)\n", path,
                strerror(errno));
        (void)close(fd);
        return NEGOBS_ERR_UNSUPPORTED;
    }
    caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps
                                                          : cap.capabilities;
    fprintf(out, "%s: %.32s (driver %.16s, %.32s)\n", path,
            (const char *)cap.card, (const char *)cap.driver,
            (const char *)cap.bus_info);
    if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 ||
        (caps & V4L2_CAP_STREAMING) == 0) {
        fprintf(out, "    nothing usable: not a single-planar streaming "
                     "capture node (metadata, output or multi-planar)\n");
        (void)close(fd);
        return NEGOBS_ERR_UNSUPPORTED;
    }
    usable = list_formats(fd, out);
    (void)close(fd);
    if (usable == 0) {
        fprintf(out,
                "    nothing usable: negobs reads GREY, NV12, NV21, "
                "YU12, YV12, YUYV, UYVY, Y10, Y16%s\n",
                negobs_mjpeg_available() ? ", MJPG"
                                         : " (MJPG: built without "
                                           "libturbojpeg)");
        return NEGOBS_ERR_UNSUPPORTED;
    }
    return NEGOBS_OK;
}

static int cmp_name(const void *a, const void *b)
{
    const char *x = *(const char *const *)a;
    const char *y = *(const char *const *)b;
    size_t lx = strlen(x);
    size_t ly = strlen(y);
    /* video2 before video10 */
    return lx != ly ? (lx < ly ? -1 : 1) : strcmp(x, y);
}

int negobs_v4l2_list_all(FILE *out)
{
    enum { MAX_NODES = 64 };
    char names[MAX_NODES][32];
    const char *sorted[MAX_NODES];
    size_t n = 0;
    size_t i;
    int usable = 0;
    DIR *d = opendir("/dev");
    struct dirent *e;
    if (d == NULL) {
        fprintf(out, "V4L2: cannot read /dev: %s\n", strerror(errno));
        return 0;
    }
    while ((e = readdir(d)) != NULL && n < MAX_NODES) {
        if (strncmp(e->d_name, "video", 5) == 0 &&
            strlen(e->d_name) < sizeof names[0] - 5u) {
            (void)snprintf(names[n], sizeof names[n], "/dev/%s", e->d_name);
            sorted[n] = names[n];
            n++;
        }
    }
    (void)closedir(d);
    if (n == 0) {
        fprintf(out, "V4L2: no /dev/video* nodes\n");
        return 0;
    }
    qsort(sorted, n, sizeof sorted[0], cmp_name);
    for (i = 0; i < n; i++) {
        if (negobs_v4l2_list_node(sorted[i], out) == NEGOBS_OK) {
            usable++;
        }
    }
    return usable;
}
