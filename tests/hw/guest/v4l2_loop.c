/*
 * v4l2_loop: stereo frame injection and capture check through vivid's
 * video loopback, for the emulated-hardware tests (tests/hw).
 *
 * vivid (modprobe vivid n_devs=2 node_types=0x101,0x101 vid_cap_nr=0,1
 * vid_out_nr=2,3) gives two instances, each with one capture and one output
 * node.  With the HDMI input/output selected, matching DV timings and
 * formats, and the capture control "Loop Video" on, every captured frame is
 * a copy of the output buffer at the head of the output queue.
 *
 * Modes:
 *   v4l2_loop check  [opts] CAP0 CAP1 OUT0 OUT1
 *       Generates a stereo pair per frame (textured gradient, right eye is
 *       the left eye shifted by a fixed disparity, frame counter + eye tag in
 *       the first row), streams it through OUT0/OUT1 and captures on
 *       CAP0/CAP1 with mmap streaming.  Every captured frame must be
 *       byte-identical to the generated frame whose counter it carries, from
 *       the right eye, with counters that advance.  Exit 0 on pass.
 *   v4l2_loop inject [opts] CAP0 CAP1 OUT0 OUT1
 *       Configures both capture nodes for loopback (input, timings, controls,
 *       format) and then keeps streaming frames into OUT0/OUT1 until killed or
 *       until -t seconds passed.  Frames are generated, or read from raw
 *       files (-L left.raw -R right.raw: concatenated frames of the chosen
 *       format, cycled).  This is the injector for running the real firmware
 *       (negobs_run CAP0 CAP1) against known frames.  With -r FILE it
 *       creates FILE once the consumer may start (capture nodes configured,
 *       output streaming).
 *   v4l2_loop capture [opts] [-x] [-O DIR] CAP0 CAP1
 *       Stands in for the program under test while `inject` runs: only
 *       S_FMT + mmap streaming on CAP0/CAP1, as negobs_run would do.  Checks
 *       the captured frames against the generated ones (-x: no check, for
 *       frames injected from files) and with -O saves -n frames of each
 *       eye (distinct ones when checking) as DIR/left_NNN.raw, right_NNN.raw.
 *
 * Options: -W width (640) -H height (480) -f GREY|YUYV|Y10|Y16 (GREY;
 *          Y10/Y16, 2 bytes per pixel, only with -L/-R files)
 *          -n frames to check per capture node (8) -b buffers (4, >= 3)
 *          -T poll timeout ms (5000) -t seconds (inject: 0 = forever)
 *          -L file -R file (inject: raw frames) -q (quiet)
 *          -P ms (inject with -L/-R: paced playback, file frame i from
 *                 i*ms after the start, once through, then the last frame
 *                 is held: a walk at a known speed)
 *          -N FILE (inject with -L/-R: sensor-like noise, the lowest bit of
 *                 about half the pixels flipped at random in every frame
 *                 written, as long as FILE does not exist; while it exists
 *                 the file frames go out unchanged: a frozen stream)
 *   v4l2_loop ctrl DEV NAME VALUE sets one control by name (e.g. vivid's
 *       "Percentage of Dropped Buffers", to stop a camera's frames).
 *
 * C99 + POSIX, built static for aarch64 by tests/hw/run.sh.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <linux/v4l2-dv-timings.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define MAX_BUFS 8
#define DISPARITY 16 /* px: right eye = left eye shifted left by this */
#define MAGIC0 'N'
#define MAGIC1 'G'
#define MAGIC2 'O'
#define MAGIC3 'B'

struct buf {
	void *p;
	size_t len;
};

struct node {
	const char *path;
	int fd;
	int is_out;
	unsigned nbufs;
	struct buf b[MAX_BUFS];
};

static unsigned g_w = 640, g_h = 480, g_nframes = 8, g_nbufs = 4;
static uint32_t g_fourcc = V4L2_PIX_FMT_GREY;
static int g_timeout_ms = 5000, g_quiet;
static int g_hold_ms;	 /* -P: file frame i shown from i*ms after start */
static double g_play_t0; /* start of the -P playback (0: not started) */
static const char *g_noise_off; /* -N: noise unless this file exists */
static uint64_t g_rng = 0x9E3779B97F4A7C15ull;
static size_t g_size; /* bytes per frame */

static int xioctl(int fd, unsigned long req, void *arg)
{
	int r;
	do
		r = ioctl(fd, req, arg);
	while (r < 0 && errno == EINTR);
	return r;
}

#define DIE(...)                                                               \
	do {                                                                   \
		fprintf(stderr, "v4l2_loop: " __VA_ARGS__);                    \
		fputc('\n', stderr);                                           \
		exit(2);                                                       \
	} while (0)

static unsigned bpp(void)
{
	return g_fourcc == V4L2_PIX_FMT_GREY ? 1u : 2u;
}

static const char *fourcc_name(void)
{
	switch (g_fourcc) {
	case V4L2_PIX_FMT_YUYV:
		return "YUYV";
	case V4L2_PIX_FMT_Y10:
		return "Y10";
	case V4L2_PIX_FMT_Y16:
		return "Y16";
	default:
		return "GREY";
	}
}

/* Luma of the synthetic scene at (x, y) for frame `n`: a horizontal gradient
 * plus a hashed texture that moves one pixel per frame (so consecutive frames
 * differ everywhere). */
static uint8_t scene(unsigned x, unsigned y, uint32_t n)
{
	uint32_t h = (x + n) * 0x9E3779B1u ^ (y / 2) * 0x85EBCA77u;
	h ^= h >> 15;
	h *= 0x2C1B3C6Du;
	h ^= h >> 12;
	return (uint8_t)(((x + n) * 160u / (g_w + 64u)) + (h & 63u) + 16u);
}

/* Fills `dst` (g_size bytes) with frame `n` of eye `eye` (0 left, 1 right). */
static void gen_frame(uint8_t *dst, uint32_t n, unsigned eye)
{
	unsigned x, y, k = bpp();
	for (y = 0; y < g_h; y++) {
		uint8_t *row = dst + (size_t)y * g_w * k;
		for (x = 0; x < g_w; x++) {
			uint8_t l = scene(x + (eye ? DISPARITY : 0), y, n);
			if (k == 1) {
				row[x] = l;
			} else {
				row[2 * x] = l;
				row[2 * x + 1] =
				    (uint8_t)(128 + (eye ? 20 : -20));
			}
		}
	}
	/* header: magic, counter (LE), eye; in the luma bytes of row 0 */
	{
		uint8_t hdr[9] = {MAGIC0,
				  MAGIC1,
				  MAGIC2,
				  MAGIC3,
				  (uint8_t)n,
				  (uint8_t)(n >> 8),
				  (uint8_t)(n >> 16),
				  (uint8_t)(n >> 24),
				  (uint8_t)eye};
		unsigned i;
		for (i = 0; i < sizeof hdr; i++)
			dst[i * k] = hdr[i];
	}
}

static int parse_hdr(const uint8_t *p, uint32_t *n, unsigned *eye)
{
	unsigned k = bpp();
	if (p[0] != MAGIC0 || p[k] != MAGIC1 || p[2 * k] != MAGIC2 ||
	    p[3 * k] != MAGIC3)
		return -1;
	*n = (uint32_t)p[4 * k] | (uint32_t)p[5 * k] << 8 |
	     (uint32_t)p[6 * k] << 16 | (uint32_t)p[7 * k] << 24;
	*eye = p[8 * k];
	return 0;
}

static int find_ctrl(int fd, const char *name, struct v4l2_queryctrl *out)
{
	struct v4l2_queryctrl q;
	memset(&q, 0, sizeof q);
	q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
	while (xioctl(fd, VIDIOC_QUERYCTRL, &q) == 0) {
		if (strcmp((const char *)q.name, name) == 0) {
			*out = q;
			return 0;
		}
		q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
	}
	return -1;
}

static void set_ctrl(int fd, const char *path, const char *name, int val)
{
	struct v4l2_queryctrl q;
	struct v4l2_control c;
	if (find_ctrl(fd, name, &q) < 0)
		DIE("%s: control '%s' not found (is this vivid?)", path, name);
	c.id = q.id;
	c.value = val;
	if (xioctl(fd, VIDIOC_S_CTRL, &c) < 0)
		DIE("%s: S_CTRL '%s'=%d: %s", path, name, val, strerror(errno));
}

/* HDMI input 3 / output 1 on vivid, 640x480p59.94 timings unless the frame
 * size asks for something else (then the node's default timings are kept
 * and must match the size). */
static void select_hdmi(struct node *nd)
{
	int idx = nd->is_out ? 1 : 3;
	struct v4l2_dv_timings t = V4L2_DV_BT_CEA_640X480P59_94;
	if (xioctl(nd->fd, nd->is_out ? VIDIOC_S_OUTPUT : VIDIOC_S_INPUT,
		   &idx) < 0)
		DIE("%s: select HDMI %s %d: %s", nd->path,
		    nd->is_out ? "output" : "input", idx, strerror(errno));
	if (g_w == 640 && g_h == 480) {
		if (xioctl(nd->fd, VIDIOC_S_DV_TIMINGS, &t) < 0)
			DIE("%s: S_DV_TIMINGS 640x480p59.94: %s", nd->path,
			    strerror(errno));
	} else if (g_w == 1280 && g_h == 720) {
		struct v4l2_dv_timings t2 = V4L2_DV_BT_CEA_1280X720P60;
		if (xioctl(nd->fd, VIDIOC_S_DV_TIMINGS, &t2) < 0)
			DIE("%s: S_DV_TIMINGS 1280x720p60: %s", nd->path,
			    strerror(errno));
	}
}

static void set_fmt(struct node *nd)
{
	struct v4l2_format f;
	memset(&f, 0, sizeof f);
	f.type = nd->is_out ? V4L2_BUF_TYPE_VIDEO_OUTPUT
			    : V4L2_BUF_TYPE_VIDEO_CAPTURE;
	f.fmt.pix.width = g_w;
	f.fmt.pix.height = g_h;
	f.fmt.pix.pixelformat = g_fourcc;
	f.fmt.pix.field = V4L2_FIELD_NONE;
	f.fmt.pix.bytesperline = 0; /* else vivid may keep a padded stride */
	if (xioctl(nd->fd, VIDIOC_S_FMT, &f) < 0)
		DIE("%s: S_FMT: %s", nd->path, strerror(errno));
	if (f.fmt.pix.width != g_w || f.fmt.pix.height != g_h ||
	    f.fmt.pix.pixelformat != g_fourcc ||
	    f.fmt.pix.bytesperline != g_w * bpp() ||
	    f.fmt.pix.sizeimage != g_size)
		DIE("%s: S_FMT gave %ux%u fourcc %.4s stride %u size %u, "
		    "wanted %ux%u stride %u size %zu",
		    nd->path, f.fmt.pix.width, f.fmt.pix.height,
		    (const char *)&f.fmt.pix.pixelformat,
		    f.fmt.pix.bytesperline, f.fmt.pix.sizeimage, g_w, g_h,
		    g_w * bpp(), g_size);
}

static void open_node(struct node *nd, const char *path, int is_out)
{
	struct v4l2_capability cap;
	uint32_t caps, want;
	nd->path = path;
	nd->is_out = is_out;
	nd->fd = open(path, O_RDWR | O_NONBLOCK);
	if (nd->fd < 0)
		DIE("open %s: %s", path, strerror(errno));
	if (xioctl(nd->fd, VIDIOC_QUERYCAP, &cap) < 0)
		DIE("%s: QUERYCAP: %s", path, strerror(errno));
	caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps
							 : cap.capabilities;
	want = (is_out ? V4L2_CAP_VIDEO_OUTPUT : V4L2_CAP_VIDEO_CAPTURE) |
	       V4L2_CAP_STREAMING;
	if ((caps & want) != want)
		DIE("%s: not a streaming %s node (caps 0x%08x)", path,
		    is_out ? "output" : "capture", caps);
	if (!g_quiet)
		printf("%s: driver %s card '%s' bus %s %s\n", path,
		       (const char *)cap.driver, (const char *)cap.card,
		       (const char *)cap.bus_info,
		       is_out ? "output" : "capture");
}

static void setup_bufs(struct node *nd)
{
	struct v4l2_requestbuffers rb;
	unsigned i;
	enum v4l2_buf_type t = nd->is_out ? V4L2_BUF_TYPE_VIDEO_OUTPUT
					  : V4L2_BUF_TYPE_VIDEO_CAPTURE;
	memset(&rb, 0, sizeof rb);
	rb.count = g_nbufs;
	rb.type = t;
	rb.memory = V4L2_MEMORY_MMAP;
	if (xioctl(nd->fd, VIDIOC_REQBUFS, &rb) < 0)
		DIE("%s: REQBUFS: %s", nd->path, strerror(errno));
	if (rb.count < 3 || rb.count > MAX_BUFS)
		DIE("%s: REQBUFS gave %u buffers", nd->path, rb.count);
	nd->nbufs = rb.count;
	for (i = 0; i < nd->nbufs; i++) {
		struct v4l2_buffer b;
		memset(&b, 0, sizeof b);
		b.type = t;
		b.memory = V4L2_MEMORY_MMAP;
		b.index = i;
		if (xioctl(nd->fd, VIDIOC_QUERYBUF, &b) < 0)
			DIE("%s: QUERYBUF %u: %s", nd->path, i,
			    strerror(errno));
		if (b.length < g_size)
			DIE("%s: buffer %u is %u bytes < %zu", nd->path, i,
			    b.length, g_size);
		nd->b[i].len = b.length;
		nd->b[i].p = mmap(NULL, b.length, PROT_READ | PROT_WRITE,
				  MAP_SHARED, nd->fd, b.m.offset);
		if (nd->b[i].p == MAP_FAILED)
			DIE("%s: mmap %u: %s", nd->path, i, strerror(errno));
	}
}

static void qbuf(struct node *nd, unsigned idx)
{
	struct v4l2_buffer b;
	memset(&b, 0, sizeof b);
	b.type = nd->is_out ? V4L2_BUF_TYPE_VIDEO_OUTPUT
			    : V4L2_BUF_TYPE_VIDEO_CAPTURE;
	b.memory = V4L2_MEMORY_MMAP;
	b.index = idx;
	if (nd->is_out) {
		b.bytesused = (uint32_t)g_size;
		b.field = V4L2_FIELD_NONE;
	}
	if (xioctl(nd->fd, VIDIOC_QBUF, &b) < 0)
		DIE("%s: QBUF %u: %s", nd->path, idx, strerror(errno));
}

/* returns 0 and fills *b, or -1 on EAGAIN */
static int dqbuf(struct node *nd, struct v4l2_buffer *b)
{
	memset(b, 0, sizeof *b);
	b->type = nd->is_out ? V4L2_BUF_TYPE_VIDEO_OUTPUT
			     : V4L2_BUF_TYPE_VIDEO_CAPTURE;
	b->memory = V4L2_MEMORY_MMAP;
	if (xioctl(nd->fd, VIDIOC_DQBUF, b) < 0) {
		if (errno == EAGAIN)
			return -1;
		DIE("%s: DQBUF: %s", nd->path, strerror(errno));
	}
	return 0;
}

static void stream(struct node *nd, int on)
{
	int t = nd->is_out ? V4L2_BUF_TYPE_VIDEO_OUTPUT
			   : V4L2_BUF_TYPE_VIDEO_CAPTURE;
	if (xioctl(nd->fd, on ? VIDIOC_STREAMON : VIDIOC_STREAMOFF, &t) < 0)
		DIE("%s: STREAM%s: %s", nd->path, on ? "ON" : "OFF",
		    strerror(errno));
}

/* ---- frame sources for the output side ---------------------------------- */

struct source {
	FILE *f[2];    /* raw files, or NULL for generated frames */
	long nfile[2]; /* frames per file */
	uint32_t
	    counter; /* next generated frame number (shared by both eyes) */
	uint32_t next[2]; /* next frame number per eye */
};

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec / 1e9;
}

/* A real sensor never delivers two identical frames (temporal noise);
 * a held synthetic frame does.  xorshift64, 8 pixels per step. */
static void add_noise(uint8_t *dst)
{
	size_t i;
	for (i = 0; i + 8 <= g_size; i += 8) {
		uint64_t w;
		g_rng ^= g_rng << 13;
		g_rng ^= g_rng >> 7;
		g_rng ^= g_rng << 17;
		memcpy(&w, dst + i, 8);
		w ^= g_rng & 0x0101010101010101ull;
		memcpy(dst + i, &w, 8);
	}
}

static void fill_out(struct source *s, unsigned eye, uint8_t *dst)
{
	uint32_t n = s->next[eye]++;
	if (s->f[eye]) {
		long idx = (long)(n % (uint32_t)s->nfile[eye]);
		if (g_hold_ms > 0) {
			/* paced playback: the frame for the time since the
			 * start, once through, then the last frame held */
			idx = g_play_t0 > 0 ? (long)((now_s() - g_play_t0) *
						     1000.0 / g_hold_ms)
					    : 0;
			if (idx >= s->nfile[eye])
				idx = s->nfile[eye] - 1;
		}
		if (fseek(s->f[eye], idx * (long)g_size, SEEK_SET) != 0 ||
		    fread(dst, 1, g_size, s->f[eye]) != g_size)
			DIE("reading frame %ld of eye %u: %s", idx, eye,
			    strerror(errno));
		if (g_noise_off != NULL && access(g_noise_off, F_OK) != 0)
			add_noise(dst);
	} else {
		gen_frame(dst, n, eye);
	}
}

static void usage(void)
{
	fprintf(
	    stderr,
	    "usage: v4l2_loop check  [opts] CAP0 CAP1 OUT0 OUT1\n"
	    "       v4l2_loop inject [opts] [-t s] [-L left.raw -R right.raw] "
	    "[-P hold_ms] [-N nonoise_file] [-r readyfile] CAP0 CAP1 OUT0 OUT1\n"
	    "       v4l2_loop capture [opts] [-x] [-O dir] CAP0 CAP1\n"
	    "       v4l2_loop ctrl DEV 'Control Name' VALUE\n"
	    "opts: -W w -H h -f GREY|YUYV|Y10|Y16 -n frames -b bufs -T poll_ms -q\n");
	exit(2);
}

/* Keeps the output queues fed: dequeue every finished output buffer, refill
 * it with the next frame, queue it again. */
static void feed(struct node *out, struct source *src, unsigned e)
{
	struct v4l2_buffer b;
	while (dqbuf(out, &b) == 0) {
		fill_out(src, e, out->b[b.index].p);
		qbuf(out, b.index);
	}
}

static void save_frame(const char *dir, unsigned e, unsigned k,
		       const uint8_t *p)
{
	char fn[512];
	FILE *f;
	snprintf(fn, sizeof fn, "%s/%s_%03u.raw", dir, e ? "right" : "left", k);
	f = fopen(fn, "wb");
	if (!f || fwrite(p, 1, g_size, f) != g_size || fclose(f) != 0)
		DIE("writing %s: %s", fn, strerror(errno));
}

int main(int argc, char **argv)
{
	struct node cap[2], out[2];
	struct source src;
	const char *mode, *lf = NULL, *rf = NULL, *savedir = NULL;
	const char *readyfile = NULL;
	double seconds = 0, t0;
	int opt, inject = 0, capture_only = 0, verify = 1;
	unsigned i, e;
	uint8_t *expect;
	unsigned got[2] = {0, 0}, bad = 0, distinct[2] = {0, 0};
	unsigned saved[2] = {0, 0};
	uint32_t last[2] = {UINT32_MAX, UINT32_MAX};

	if (argc < 2)
		usage();
	mode = argv[1];
	if (strcmp(mode, "ctrl") == 0) {
		/* v4l2_loop ctrl DEV NAME VALUE: set one control by name */
		int fd;
		if (argc != 5)
			usage();
		fd = open(argv[2], O_RDWR | O_NONBLOCK);
		if (fd < 0)
			DIE("open %s: %s", argv[2], strerror(errno));
		set_ctrl(fd, argv[2], argv[3], atoi(argv[4]));
		close(fd);
		return 0;
	}
	if (strcmp(mode, "inject") == 0)
		inject = 1;
	else if (strcmp(mode, "capture") == 0)
		capture_only = 1;
	else if (strcmp(mode, "check") != 0)
		usage();
	optind = 2;
	while ((opt = getopt(argc, argv, "W:H:f:n:b:T:t:L:R:O:r:P:N:xq")) !=
	       -1) {
		switch (opt) {
		case 'W':
			g_w = (unsigned)atoi(optarg);
			break;
		case 'H':
			g_h = (unsigned)atoi(optarg);
			break;
		case 'f':
			if (strcmp(optarg, "GREY") == 0)
				g_fourcc = V4L2_PIX_FMT_GREY;
			else if (strcmp(optarg, "YUYV") == 0)
				g_fourcc = V4L2_PIX_FMT_YUYV;
			else if (strcmp(optarg, "Y10") == 0)
				g_fourcc = V4L2_PIX_FMT_Y10;
			else if (strcmp(optarg, "Y16") == 0)
				g_fourcc = V4L2_PIX_FMT_Y16;
			else
				usage();
			break;
		case 'n':
			g_nframes = (unsigned)atoi(optarg);
			break;
		case 'b':
			g_nbufs = (unsigned)atoi(optarg);
			break;
		case 'T':
			g_timeout_ms = atoi(optarg);
			break;
		case 't':
			seconds = atof(optarg);
			break;
		case 'L':
			lf = optarg;
			break;
		case 'R':
			rf = optarg;
			break;
		case 'O':
			savedir = optarg;
			break;
		case 'r':
			readyfile = optarg;
			break;
		case 'P':
			g_hold_ms = atoi(optarg);
			break;
		case 'N':
			g_noise_off = optarg;
			break;
		case 'x':
			verify = 0;
			break;
		case 'q':
			g_quiet = 1;
			break;
		default:
			usage();
		}
	}
	if (argc - optind != (capture_only ? 2 : 4) || g_w < 64 || g_h < 16 ||
	    g_nbufs < 3 || g_nbufs > MAX_BUFS || g_nframes < 1)
		usage();
	g_size = (size_t)g_w * g_h * bpp();
	setvbuf(stdout, NULL, _IOLBF, 0);

	if ((g_fourcc == V4L2_PIX_FMT_Y10 || g_fourcc == V4L2_PIX_FMT_Y16) &&
	    (!inject || !lf))
		DIE("-f %s: only for injecting -L/-R files", fourcc_name());
	memset(&src, 0, sizeof src);
	if (lf || rf) {
		const char *fn[2] = {lf, rf};
		if (!inject || !lf || !rf)
			DIE("-L and -R go together, in inject mode");
		for (e = 0; e < 2; e++) {
			struct stat st;
			src.f[e] = fopen(fn[e], "rb");
			if (!src.f[e] || fstat(fileno(src.f[e]), &st) < 0)
				DIE("open %s: %s", fn[e], strerror(errno));
			src.nfile[e] = (long)(st.st_size / (off_t)g_size);
			if (src.nfile[e] < 1 || st.st_size % (off_t)g_size != 0)
				DIE("%s: size %lld is not a multiple of the "
				    "frame size %zu",
				    fn[e], (long long)st.st_size, g_size);
		}
	}

	for (e = 0; e < 2; e++) {
		open_node(&cap[e], argv[optind + e], 0);
		if (capture_only) {
			/* what the program under test does: just the format */
			set_fmt(&cap[e]);
			continue;
		}
		open_node(&out[e], argv[optind + 2 + e], 1);
		/* capture side: HDMI input, loop on, no OSD text */
		select_hdmi(&cap[e]);
		select_hdmi(&out[e]);
		set_ctrl(cap[e].fd, cap[e].path, "Loop Video", 1);
		set_ctrl(cap[e].fd, cap[e].path, "OSD Text Mode", 2);
		set_fmt(&out[e]);
		set_fmt(&cap[e]);
	}

	/* output side: fill every buffer, queue, STREAMON (the loop is decided
	 * when the capture side starts, and needs frames waiting) */
	for (e = 0; e < 2 && !capture_only; e++) {
		setup_bufs(&out[e]);
		for (i = 0; i < out[e].nbufs; i++) {
			fill_out(&src, e, out[e].b[i].p);
			qbuf(&out[e], i);
		}
		stream(&out[e], 1);
	}

	if (inject) {
		/* capture nodes stay configured for the program under test */
		for (e = 0; e < 2; e++)
			close(cap[e].fd);
		printf(
		    "v4l2_loop: injecting %ux%u %s frames (%s) into %s, %s\n",
		    g_w, g_h, fourcc_name(), lf ? "from files" : "generated",
		    out[0].path, out[1].path);
		/* capture nodes configured and frames waiting: a consumer
		 * may start now */
		if (readyfile) {
			FILE *rfp = fopen(readyfile, "w");
			if (!rfp || fclose(rfp) != 0)
				DIE("creating %s: %s", readyfile,
				    strerror(errno));
		}
		t0 = now_s();
		g_play_t0 = t0;
		for (;;) {
			struct pollfd pf[2];
			int r;
			for (e = 0; e < 2; e++) {
				pf[e].fd = out[e].fd;
				pf[e].events = POLLOUT;
				pf[e].revents = 0;
			}
			r = poll(pf, 2, g_timeout_ms);
			if (r < 0 && errno != EINTR)
				DIE("poll: %s", strerror(errno));
			if (r == 0)
				DIE("inject: no output buffer came back in %d ms",
				    g_timeout_ms);
			for (e = 0; e < 2; e++)
				if (pf[e].revents & POLLOUT)
					feed(&out[e], &src, e);
			if (seconds > 0 && now_s() - t0 >= seconds)
				break;
		}
		printf("v4l2_loop: injected %u + %u frames\n", src.next[0],
		       src.next[1]);
		return 0;
	}

	expect = malloc(g_size);
	if (!expect)
		DIE("out of memory");
	for (e = 0; e < 2; e++) {
		setup_bufs(&cap[e]);
		for (i = 0; i < cap[e].nbufs; i++)
			qbuf(&cap[e], i);
		stream(&cap[e], 1);
	}
	t0 = now_s();
	/* -n frames per eye; then, within 50 x -n frames, go on until the
	 * stream has shown it is live (2 distinct frames per eye) and, with -O,
	 * -n distinct frames per eye are saved: when TCG falls behind (busy
	 * host), vivid catches up in bursts that repeat one injected frame */
	while (got[0] < g_nframes || got[1] < g_nframes ||
	       (((verify && (distinct[0] < 2 || distinct[1] < 2)) ||
		 (savedir && (saved[0] < g_nframes || saved[1] < g_nframes))) &&
		got[0] < 50 * g_nframes && got[1] < 50 * g_nframes)) {
		struct pollfd pf[4];
		unsigned nfd = capture_only ? 2 : 4;
		int r;
		for (e = 0; e < 2; e++) {
			pf[e].fd = cap[e].fd;
			pf[e].events = POLLIN;
			pf[e].revents = 0;
			if (!capture_only) {
				pf[2 + e].fd = out[e].fd;
				pf[2 + e].events = POLLOUT;
				pf[2 + e].revents = 0;
			}
		}
		r = poll(pf, nfd, g_timeout_ms);
		if (r < 0 && errno != EINTR)
			DIE("poll: %s", strerror(errno));
		if (r == 0) {
			printf("v4l2_loop: FAIL poll timeout (%d ms) after "
			       "%u/%u frames\n",
			       g_timeout_ms, got[0], got[1]);
			return 1;
		}
		for (e = 0; e < 2; e++) {
			struct v4l2_buffer b;
			if (!capture_only && (pf[2 + e].revents & POLLOUT))
				feed(&out[e], &src, e);
			if (!(pf[e].revents & POLLIN))
				continue;
			while (dqbuf(&cap[e], &b) == 0) {
				const uint8_t *p = cap[e].b[b.index].p;
				uint32_t n = 0;
				unsigned eye = 9;
				const char *why = NULL;
				if (b.flags & V4L2_BUF_FLAG_ERROR)
					why = "V4L2_BUF_FLAG_ERROR";
				else if (b.bytesused != g_size)
					why = "short frame";
				else if (!verify)
					;
				else if (parse_hdr(p, &n, &eye) < 0)
					why = "no frame header (test pattern, "
					      "loop not active?)";
				else if (eye != e)
					why = "frame of the other eye";
				else {
					gen_frame(expect, n, eye);
					if (memcmp(expect, p, g_size) != 0)
						why = "bytes differ from the "
						      "injected frame";
				}
				if (!g_quiet || why)
					printf("%s seq %u bytes %u frame %u "
					       "eye %u: %s\n",
					       cap[e].path, b.sequence,
					       b.bytesused, n, eye,
					       why ? why : "ok");
				if (savedir && !why && saved[e] < g_nframes &&
				    (!verify || n != last[e]))
					save_frame(savedir, e, saved[e]++, p);
				if (why)
					bad++;
				else if (verify && n != last[e]) {
					distinct[e]++;
					last[e] = n;
				}
				got[e]++;
				qbuf(&cap[e], b.index);
			}
		}
	}
	for (e = 0; e < 2; e++) {
		stream(&cap[e], 0);
		if (!capture_only)
			stream(&out[e], 0);
	}
	printf("v4l2_loop: %u+%u frames captured in %.2f s, %u bad, "
	       "%u+%u distinct frames, %u buffers per node, %zu bytes/frame\n",
	       got[0], got[1], now_s() - t0, bad, distinct[0], distinct[1],
	       cap[0].nbufs, g_size);
	if (bad || (verify && (distinct[0] < 2 || distinct[1] < 2))) {
		printf("v4l2_loop: FAIL\n");
		return 1;
	}
	printf("v4l2_loop: OK\n");
	return 0;
}
