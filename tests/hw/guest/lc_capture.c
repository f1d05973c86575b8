/*
 * lc_capture: frames from one camera through negobs' libcamera backend
 * (port/camera/libcamera), for the emulated-hardware section
 * libcamera-vimc. Cross-built by tests/hw/build_libcamera.sh against
 * Debian's arm64 libcamera, dynamically linked.
 *
 * usage: lc_capture [-n FRAMES] [-w W] [-h H] [-T FIRST_TIMEOUT_MS] [-R]
 *                   [-r RIGHT] [-E STATUS] libcamera:N | libcamera:ID
 *
 * Opens the camera alone (single-camera mode: RIGHT empty), captures
 * FRAMES frames and checks each one: the requested size, a stride of at
 * least the width, a capture time and a sequence number later than the
 * previous frame's, and content that is not one flat value. -R stops and
 * starts the camera again after half the frames (the stop must be clean
 * and the stream must resume). Prints one
 * line per frame and a summary; exit 0 when every check passed, 1 when
 * one failed, 2 on bad usage.
 *
 * -r RIGHT opens a stereo pair instead. -E STATUS expects open() to fail
 * with that status (e.g. -8, NEGOBS_ERR_NODEV) and passes when it does.
 * The default config is used, so frozen-stream detection is on (10
 * identical frames): a run of more frames also shows it does not fire on a
 * live stream.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "negobs_port/camera.h"
#include "negobs_port/camera_libcamera.h"
#include "negobs_port/clock.h"

#define MAX_W 1280
#define MAX_H 960

static uint8_t scratch[MAX_W * MAX_H];
static negobs_libcamera_t lc;

static int fail(const char *what, negobs_capture_t *cam)
{
	printf("lc_capture: FAIL: %s%s%s\n", what, cam != NULL ? ": " : "",
	       cam != NULL ? negobs_capture_errmsg(cam) : "");
	return 1;
}

int main(int argc, char **argv)
{
	negobs_capture_t cam;
	negobs_capture_config_t cfg;
	negobs_frame_pair_t pair;
	negobs_capture_stats_t stats;
	long frames = 6;
	long first_timeout_ms = 20000;
	long w = 640;
	long h = 480;
	uint64_t prev_ts = 0;
	uint64_t first_ts = 0;
	uint32_t prev_seq = 0;
	uint64_t t_open;
	uint64_t t_first = 0;
	int bad = 0;
	int restart = 0;
	int expect_open = 0;
	int have_expect_open = 0;
	const char *right = NULL;
	int c;
	long i;
	negobs_status_t s;

	while ((c = getopt(argc, argv, "n:w:h:T:Rr:E:")) != -1) {
		switch (c) {
		case 'n':
			frames = strtol(optarg, NULL, 10);
			break;
		case 'w':
			w = strtol(optarg, NULL, 10);
			break;
		case 'h':
			h = strtol(optarg, NULL, 10);
			break;
		case 'T':
			first_timeout_ms = strtol(optarg, NULL, 10);
			break;
		case 'R':
			restart = 1;
			break;
		case 'r':
			right = optarg;
			break;
		case 'E':
			expect_open = (int)strtol(optarg, NULL, 10);
			have_expect_open = 1;
			break;
		default:
			return 2;
		}
	}
	if (optind != argc - 1 || frames < 2 || w < 16 || h < 16 || w > MAX_W ||
	    h > MAX_H) {
		fprintf(stderr, "usage: lc_capture [-n N>=2] [-w W] [-h H] "
				"[-T MS] libcamera:N|libcamera:ID\n");
		return 2;
	}
	if (negobs_libcamera_init(&lc, scratch, sizeof scratch, &cam) !=
	    NEGOBS_OK) {
		return fail("backend not compiled in", NULL);
	}
	negobs_capture_config_default(&cfg);
	cfg.left = argv[optind];
	cfg.right = right; /* NULL: one camera (vimc gives libcamera one) */
	cfg.width = (int32_t)w;
	cfg.height = (int32_t)h;
	t_open = negobs_clock_now_ms();
	s = negobs_capture_open(&cam, &cfg);
	if (have_expect_open) {
		printf("lc_capture: open %s%s%s: status %d (expected %d): %s\n",
		       cfg.left, right != NULL ? " + " : "",
		       right != NULL ? right : "", (int)s, expect_open,
		       negobs_capture_errmsg(&cam));
		if (s == NEGOBS_OK) {
			negobs_capture_close(&cam);
		}
		return (int)s == expect_open ? 0 : 1;
	}
	if (s != NEGOBS_OK) {
		printf("lc_capture: open status %d\n", (int)s);
		return fail("open", &cam);
	}
	printf("lc_capture: opened %s in %lu ms\n", cfg.left,
	       (unsigned long)(negobs_clock_now_ms() - t_open));
	s = negobs_capture_start(&cam);
	if (s != NEGOBS_OK) {
		negobs_capture_close(&cam);
		return fail("start", &cam);
	}
	for (i = 0; i < frames && bad == 0; i++) {
		const negobs_image_u8_t *y = &pair.left.y;
		int32_t r;
		uint32_t lo = 255;
		uint32_t hi = 0;
		uint64_t sum = 0;
		int rc;
		if (restart && i == frames / 2) {
			negobs_capture_stop(&cam);
			s = negobs_capture_start(&cam);
			printf(
			    "lc_capture: stopped and started again: status %d\n",
			    (int)s);
			if (s != NEGOBS_OK) {
				bad = fail("restart", &cam);
				break;
			}
		}
		rc = negobs_capture_get_pair(
		    &cam, &pair, i == 0 ? (int32_t)first_timeout_ms : 5000);
		if (rc != NEGOBS_OK) {
			printf("lc_capture: frame %ld: get_pair status %d\n", i,
			       rc);
			bad = fail("get_pair", &cam);
			break;
		}
		if (i == 0) {
			t_first = negobs_clock_now_ms();
			first_ts = pair.left.ts_ns;
		}
		for (r = 0; r < y->height; r++) {
			const uint8_t *row =
			    y->data + (size_t)r * (size_t)y->stride;
			int32_t x;
			for (x = 0; x < y->width; x++) {
				lo = row[x] < lo ? row[x] : lo;
				hi = row[x] > hi ? row[x] : hi;
				sum += row[x];
			}
		}
		printf("lc_capture: frame %ld seq %lu ts %lu.%03lu ms %ldx%ld "
		       "stride %ld luma %lu..%lu mean %lu\n",
		       i, (unsigned long)pair.left.sequence,
		       (unsigned long)(pair.left.ts_ns / 1000000u),
		       (unsigned long)(pair.left.ts_ns / 1000u % 1000u),
		       (long)y->width, (long)y->height, (long)y->stride,
		       (unsigned long)lo, (unsigned long)hi,
		       (unsigned long)(sum / ((uint64_t)y->width *
					      (uint64_t)y->height)));
		if (y->width != (int32_t)w || y->height != (int32_t)h) {
			bad = fail("frame size differs from the requested one",
				   NULL);
		} else if (y->stride < y->width) {
			bad = fail("stride below the width", NULL);
		} else if (pair.left.ts_ns == 0 ||
			   (i > 0 && pair.left.ts_ns <= prev_ts)) {
			bad = fail("timestamp did not advance", NULL);
		} else if (i > 0 && pair.left.sequence <= prev_seq &&
			   !(restart && i == frames / 2)) {
			/* a restart begins a new stream: sequences start over */
			bad = fail("sequence did not advance", NULL);
		} else if (lo == hi) {
			bad = fail("flat frame (one value everywhere)", NULL);
		} else if (pair.right.y.data != y->data) {
			bad =
			    fail("single-camera pair does not repeat the frame",
				 NULL);
		}
		prev_ts = pair.left.ts_ns;
		prev_seq = pair.left.sequence;
		negobs_capture_release(&cam, &pair);
	}
	negobs_capture_get_stats(&cam, &stats);
	negobs_capture_stop(&cam);
	negobs_capture_close(&cam);
	if (bad != 0) {
		return 1;
	}
	printf("lc_capture: PASS %ld frames %ldx%ld, first after %lu ms, "
	       "then %.1f frames/s by timestamp; stale %lu short %lu "
	       "timeouts %lu\n",
	       frames, w, h, (unsigned long)(t_first - t_open),
	       prev_ts > first_ts
		   ? (double)(frames - 1) * 1e9 / (double)(prev_ts - first_ts)
		   : 0.0,
	       (unsigned long)stats.stale_frames,
	       (unsigned long)stats.short_frames,
	       (unsigned long)stats.timeouts);
	return 0;
}
