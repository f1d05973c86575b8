/*
 * V4L2 backend logic without a device: timestamp pairing, format choice
 * and checks, luma plane description/extraction, reopen back-off.
 */
#define _XOPEN_SOURCE 700

#include <string.h>

#include <linux/videodev2.h>

#include "cmocka_all.h"
#include "negobs_port/camera.h"
#include "negobs_port/camera_v4l2.h"
#include "negobs_port/mjpeg.h"

#define MS 1000000u

static void test_pair_decide_matches_within_tolerance(void **state)
{
    (void)state;
    assert_int_equal(negobs_pair_decide(100 * MS, 100 * MS, 10 * MS),
                     NEGOBS_PAIR_MATCH);
    assert_int_equal(negobs_pair_decide(100 * MS, 110 * MS, 10 * MS),
                     NEGOBS_PAIR_MATCH);
    assert_int_equal(negobs_pair_decide(110 * MS, 100 * MS, 10 * MS),
                     NEGOBS_PAIR_MATCH);
    assert_int_equal(negobs_pair_decide(100 * MS, 110 * MS + 1, 10 * MS),
                     NEGOBS_PAIR_DROP_LEFT);
    assert_int_equal(negobs_pair_decide(133 * MS, 100 * MS, 10 * MS),
                     NEGOBS_PAIR_DROP_RIGHT);
    assert_int_equal(negobs_pair_decide(5, 5, 0), NEGOBS_PAIR_MATCH);
}

/*
 * Simulate the backend's loop on two timestamp streams: one pending frame
 * per side; when both wait, match or drop the older; a side without a
 * pending frame takes its next one. Returns pairs made; *dropped counts.
 */
static uint32_t simulate(const uint64_t *l, uint32_t nl, const uint64_t *r,
                         uint32_t nr, uint64_t tol, uint32_t *dropped,
                         uint64_t *first_pair_l)
{
    uint32_t il = 0;
    uint32_t ir = 0;
    uint32_t pairs = 0;
    *dropped = 0;
    while (il < nl && ir < nr) {
        negobs_pair_action_t a = negobs_pair_decide(l[il], r[ir], tol);
        if (a == NEGOBS_PAIR_MATCH) {
            if (pairs == 0) {
                *first_pair_l = l[il];
            }
            pairs++;
            il++;
            ir++;
        } else if (a == NEGOBS_PAIR_DROP_LEFT) {
            il++;
            (*dropped)++;
        } else {
            ir++;
            (*dropped)++;
        }
    }
    return pairs;
}

static void test_pairing_recovers_from_a_missing_frame(void **state)
{
    /* 30 fps, right 3 ms behind; the right camera loses its 3rd frame. */
    uint64_t l[10];
    uint64_t r[9];
    uint32_t i;
    uint32_t k = 0;
    uint32_t dropped;
    uint64_t first = 0;
    (void)state;
    for (i = 0; i < 10; i++) {
        l[i] = 1000 * MS + i * 33 * MS;
        if (i != 2) {
            r[k++] = l[i] + 3 * MS;
        }
    }
    assert_int_equal(simulate(l, 10, r, 9, 10 * MS, &dropped, &first), 9);
    assert_int_equal(dropped, 1); /* only the orphaned left frame */
    assert_int_equal(first, 1000 * MS);
}

static void test_pairing_drops_out_of_sync_streams(void **state)
{
    /* Phase offset of 16 ms > 10 ms tolerance: nothing may pair. */
    uint64_t l[8];
    uint64_t r[8];
    uint32_t i;
    uint32_t dropped;
    uint64_t first = 0;
    (void)state;
    for (i = 0; i < 8; i++) {
        l[i] = i * 33 * MS;
        r[i] = l[i] + 16 * MS;
    }
    assert_int_equal(simulate(l, 8, r, 8, 10 * MS, &dropped, &first), 0);
    assert_true(dropped >= 8);
    /* A wider tolerance accepts them. */
    assert_int_equal(simulate(l, 8, r, 8, 20 * MS, &dropped, &first), 8);
    assert_int_equal(dropped, 0);
}

static void test_format_rank_prefers_in_place_luma(void **state)
{
    (void)state;
    assert_int_equal(negobs_v4l2_format_rank(V4L2_PIX_FMT_GREY), 0);
    assert_true(negobs_v4l2_format_rank(V4L2_PIX_FMT_NV12) <
                negobs_v4l2_format_rank(V4L2_PIX_FMT_YUYV));
    assert_true(negobs_v4l2_format_rank(V4L2_PIX_FMT_YUV420) <
                negobs_v4l2_format_rank(V4L2_PIX_FMT_YUYV));
    assert_true(negobs_v4l2_format_rank(V4L2_PIX_FMT_UYVY) >= 0);
    /* MJPEG: a decode, ranked last, and only where libturbojpeg is in */
    if (negobs_mjpeg_available()) {
        assert_true(negobs_v4l2_format_rank(V4L2_PIX_FMT_MJPEG) >
                    negobs_v4l2_format_rank(V4L2_PIX_FMT_Y10));
    } else {
        assert_int_equal(negobs_v4l2_format_rank(V4L2_PIX_FMT_MJPEG), -1);
    }
    assert_true(negobs_v4l2_format_rank(V4L2_PIX_FMT_Y10) >
                negobs_v4l2_format_rank(V4L2_PIX_FMT_YUYV));
    assert_true(negobs_v4l2_format_rank(V4L2_PIX_FMT_Y16) >= 0);
    assert_int_equal(negobs_v4l2_format_rank(V4L2_PIX_FMT_RGB24), -1);
    assert_int_equal(negobs_v4l2_format_rank(V4L2_PIX_FMT_H264), -1);
    assert_true(negobs_v4l2_format_packed(V4L2_PIX_FMT_YUYV));
    assert_false(negobs_v4l2_format_packed(V4L2_PIX_FMT_NV12));
    /* Our fourcc macro agrees with the kernel's. */
    assert_int_equal(NEGOBS_FOURCC('Y', 'U', '1', '2'), V4L2_PIX_FMT_YUV420);
}

static void test_format_check_catches_bad_driver_answers(void **state)
{
    (void)state;
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_GREY, 640, 480, 640, 307200),
        NEGOBS_OK);
    /* Padded stride is fine, as long as sizeimage covers it. */
    assert_int_equal(negobs_v4l2_check_format(V4L2_PIX_FMT_NV12, 640, 480, 704,
                                              704 * 480 * 3 / 2),
                     NEGOBS_OK);
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_NV12, 640, 480, 704, 704 * 480),
        NEGOBS_ERR_INVAL);
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_YUYV, 640, 480, 640, 614400),
        NEGOBS_ERR_INVAL); /* YUYV needs 2 bytes/pixel */
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_YUYV, 640, 480, 1280, 614400),
        NEGOBS_OK);
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_GREY, 0, 480, 640, 307200),
        NEGOBS_ERR_INVAL);
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_H264, 640, 480, 640, 307200),
        NEGOBS_ERR_UNSUPPORTED);
    /* 16-bit mono: 2 bytes per pixel */
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_Y10, 640, 480, 640, 614400),
        NEGOBS_ERR_INVAL);
    assert_int_equal(
        negobs_v4l2_check_format(V4L2_PIX_FMT_Y16, 640, 480, 1280, 614400),
        NEGOBS_OK);
    if (negobs_mjpeg_available()) {
        /* compressed: bytesperline 0, sizeimage the largest frame */
        assert_int_equal(
            negobs_v4l2_check_format(V4L2_PIX_FMT_MJPEG, 1280, 720, 0, 460800),
            NEGOBS_OK);
        assert_int_equal(
            negobs_v4l2_check_format(V4L2_PIX_FMT_MJPEG, 1280, 720, 0, 0),
            NEGOBS_ERR_INVAL);
    }
    assert_int_equal(negobs_v4l2_frame_bytes(V4L2_PIX_FMT_YUV420, 480, 640),
                     460800);
    assert_int_equal(negobs_v4l2_frame_bytes(V4L2_PIX_FMT_YUYV, 480, 1280),
                     614400);
}

static void test_luma_planar_is_described_in_place(void **state)
{
    static uint8_t buf[72 * 8 * 3 / 2];
    negobs_image_u8_t y;
    (void)state;
    memset(buf, 0, sizeof buf);
    buf[72 * 3 + 5] = 77;
    assert_int_equal(negobs_v4l2_luma(V4L2_PIX_FMT_NV12, buf, sizeof buf, 64,
                                      8, 72, NULL, 0, &y),
                     NEGOBS_OK);
    assert_ptr_equal(y.data, buf); /* no copy */
    assert_int_equal(y.stride, 72);
    assert_int_equal(y.width, 64);
    assert_int_equal(y.height, 8);
    assert_int_equal(negobs_image_u8_row(&y, 3)[5], 77);
    assert_int_equal(negobs_image_u8_check(&y), NEGOBS_OK);
    /* A short buffer (driver filled less than the Y plane) is corrupt. */
    assert_int_equal(negobs_v4l2_luma(V4L2_PIX_FMT_GREY, buf, 72 * 7 + 63, 64,
                                      8, 72, NULL, 0, &y),
                     NEGOBS_ERR_CORRUPT);
    assert_int_equal(negobs_v4l2_luma(V4L2_PIX_FMT_GREY, buf, 72 * 7 + 64, 64,
                                      8, 72, NULL, 0, &y),
                     NEGOBS_OK);
}

static void test_luma_packed_is_extracted(void **state)
{
    /* 4x2 YUYV with a padded stride of 12 bytes. */
    static uint8_t yuyv[12 * 2];
    uint8_t scratch[8];
    negobs_image_u8_t y;
    int i;
    (void)state;
    for (i = 0; i < 24; i++) {
        yuyv[i] = (uint8_t)(100 + i);
    }
    assert_int_equal(negobs_v4l2_luma(V4L2_PIX_FMT_YUYV, yuyv, sizeof yuyv, 4,
                                      2, 12, scratch, sizeof scratch, &y),
                     NEGOBS_OK);
    assert_ptr_equal(y.data, scratch);
    assert_int_equal(y.stride, 4);
    assert_int_equal(scratch[0], 100);
    assert_int_equal(scratch[1], 102);
    assert_int_equal(scratch[3], 106);
    assert_int_equal(scratch[4], 112); /* row 1 starts at byte 12 */
    assert_int_equal(negobs_v4l2_luma(V4L2_PIX_FMT_UYVY, yuyv, sizeof yuyv, 4,
                                      2, 12, scratch, sizeof scratch, &y),
                     NEGOBS_OK);
    assert_int_equal(scratch[0], 101);
    assert_int_equal(scratch[7], 119);
    assert_int_equal(negobs_v4l2_luma(V4L2_PIX_FMT_YUYV, yuyv, sizeof yuyv, 4,
                                      2, 12, scratch, 7, &y),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(negobs_v4l2_luma(V4L2_PIX_FMT_RGB24, yuyv, sizeof yuyv, 4,
                                      2, 12, scratch, 8, &y),
                     NEGOBS_ERR_UNSUPPORTED);
}

static void test_backoff_doubles_and_caps(void **state)
{
    (void)state;
    assert_int_equal(negobs_v4l2_backoff_ms(0), NEGOBS_V4L2_BACKOFF_MIN_MS);
    assert_int_equal(negobs_v4l2_backoff_ms(1),
                     2 * NEGOBS_V4L2_BACKOFF_MIN_MS);
    assert_int_equal(negobs_v4l2_backoff_ms(40), NEGOBS_V4L2_BACKOFF_MAX_MS);
}

static void test_open_missing_device_is_nodev(void **state)
{
    negobs_v4l2_t st;
    negobs_capture_t cam;
    negobs_capture_config_t cfg;
    (void)state;
    negobs_capture_config_default(&cfg);
    cfg.left = "/nonexistent/video0";
    cfg.right = "v4l2:/nonexistent/video1";
    assert_int_equal(negobs_v4l2_init(&st, NULL, 0, &cam), NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_NODEV);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "video0"));
    /* A file that is not a V4L2 node. */
    cfg.left = "/dev/null";
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_UNSUPPORTED);
    negobs_capture_close(&cam);
}

/* ---- frozen-stream detection --------------------------------------- */

static void test_signature_sees_sampled_pixels_and_ignores_stride(void **state)
{
    static uint8_t a[40 * 30];
    static uint8_t b[48 * 30];
    negobs_image_u8_t ia = {a, 40, 30, 40};
    negobs_image_u8_t ib = {b, 40, 30, 48};
    uint32_t s0;
    int y;
    (void)state;
    for (y = 0; y < 30; y++) {
        int x;
        for (x = 0; x < 40; x++) {
            a[y * 40 + x] = (uint8_t)(x * 7 + y * 3);
            b[y * 48 + x] = (uint8_t)(x * 7 + y * 3);
        }
        memset(&b[y * 48 + 40], 0xAA, 8); /* padding is never read */
    }
    s0 = negobs_frame_signature(&ia);
    assert_int_equal(negobs_frame_signature(&ib), s0);
    /* One sampled pixel (row 2, column 3) flipped by one grey level: a
     * noise-sized change is seen. */
    a[2 * 40 + 3] ^= 1u;
    assert_int_not_equal(negobs_frame_signature(&ia), s0);
    a[2 * 40 + 3] ^= 1u;
    assert_int_equal(negobs_frame_signature(&ia), s0);
    /* Sampling is sparse on purpose: an odd row is not read. */
    a[1 * 40 + 3] ^= 1u;
    assert_int_equal(negobs_frame_signature(&ia), s0);
    assert_int_equal(negobs_frame_signature(NULL), 0);
}

static void test_frozen_needs_limit_identical_frames_and_clears(void **state)
{
    negobs_frozen_t f;
    (void)state;
    memset(&f, 0, sizeof f);
    /* Changing content never freezes. */
    assert_false(negobs_frozen_update(&f, 1, 3));
    assert_false(negobs_frozen_update(&f, 2, 3));
    /* 3 identical frames in a row (the first plus 2 repeats). */
    assert_false(negobs_frozen_update(&f, 7, 3));
    assert_false(negobs_frozen_update(&f, 7, 3));
    assert_true(negobs_frozen_update(&f, 7, 3));
    assert_true(negobs_frozen_update(&f, 7, 3));
    assert_int_equal(f.repeats, 3);
    /* The first changed frame clears it. */
    assert_false(negobs_frozen_update(&f, 8, 3));
    assert_int_equal(f.repeats, 0);
    /* 0 = off, whatever repeats. */
    assert_false(negobs_frozen_update(&f, 8, 0));
    assert_false(negobs_frozen_update(&f, 8, 0));
    /* A limit of 1 means 2: a single frame cannot repeat. */
    memset(&f, 0, sizeof f);
    assert_false(negobs_frozen_update(&f, 5, 1));
    assert_true(negobs_frozen_update(&f, 5, 1));
}

static void test_camera_config_default_turns_frozen_check_on(void **state)
{
    negobs_capture_config_t cfg;
    (void)state;
    negobs_capture_config_default(&cfg);
    assert_int_equal(cfg.frozen_frames, NEGOBS_CAPTURE_FROZEN_FRAMES_DEFAULT);
    assert_true(cfg.frozen_frames >= 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(
            test_signature_sees_sampled_pixels_and_ignores_stride),
        cmocka_unit_test(test_frozen_needs_limit_identical_frames_and_clears),
        cmocka_unit_test(test_camera_config_default_turns_frozen_check_on),
        cmocka_unit_test(test_pair_decide_matches_within_tolerance),
        cmocka_unit_test(test_pairing_recovers_from_a_missing_frame),
        cmocka_unit_test(test_pairing_drops_out_of_sync_streams),
        cmocka_unit_test(test_format_rank_prefers_in_place_luma),
        cmocka_unit_test(test_format_check_catches_bad_driver_answers),
        cmocka_unit_test(test_luma_planar_is_described_in_place),
        cmocka_unit_test(test_luma_packed_is_extracted),
        cmocka_unit_test(test_backoff_doubles_and_caps),
        cmocka_unit_test(test_open_missing_device_is_nodev),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
