/*
 * libcamera source without a camera: source-name parsing, format choice,
 * luma extraction (pure helpers, every build), and, where the backend is
 * compiled in, what a machine without the asked-for camera must get:
 * clear statuses and messages, no crash, a camera manager that can be
 * started again. Real frames: tests/hw (section libcamera-vimc).
 */
#define _XOPEN_SOURCE 700

#include <string.h>

#include "cmocka_all.h"
#include "negobs_port/camera.h"
#include "negobs_port/camera_libcamera.h"

#define FCC(a, b, c, d) NEGOBS_DRM_FOURCC(a, b, c, d)

static void test_parse_index_and_id(void **state)
{
    int32_t index = 7;
    const char *id = "x";
    (void)state;
    assert_int_equal(negobs_libcamera_parse_source("libcamera:0", &index, &id),
                     NEGOBS_OK);
    assert_int_equal(index, 0);
    assert_null(id);
    assert_int_equal(
        negobs_libcamera_parse_source("libcamera:12", &index, &id), NEGOBS_OK);
    assert_int_equal(index, 12);
    assert_int_equal(negobs_libcamera_parse_source(
                         "libcamera:platform/vimc.0 Sensor B", &index, &id),
                     NEGOBS_OK);
    assert_int_equal(index, -1);
    assert_string_equal(id, "platform/vimc.0 Sensor B");
    /* digits then text is an id, not an index */
    assert_int_equal(
        negobs_libcamera_parse_source("libcamera:1a", &index, &id), NEGOBS_OK);
    assert_int_equal(index, -1);
    assert_string_equal(id, "1a");
}

static void test_parse_rejects_bad_names(void **state)
{
    char long_id[NEGOBS_LIBCAMERA_ID_LEN + 16];
    int32_t index;
    const char *id;
    (void)state;
    assert_int_equal(negobs_libcamera_parse_source("libcamera:", &index, &id),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_libcamera_parse_source("/dev/video0", &index, &id),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(
        negobs_libcamera_parse_source("libcamera:1000", &index, &id),
        NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_libcamera_parse_source(NULL, &index, &id),
                     NEGOBS_ERR_INVAL);
    memcpy(long_id, "libcamera:", 10);
    memset(long_id + 10, 'a', NEGOBS_LIBCAMERA_ID_LEN);
    long_id[10 + NEGOBS_LIBCAMERA_ID_LEN] = '\0';
    assert_int_equal(negobs_libcamera_parse_source(long_id, &index, &id),
                     NEGOBS_ERR_INVAL);
}

static void test_format_preference(void **state)
{
    (void)state;
    assert_int_equal(negobs_libcamera_format_rank(FCC('R', '8', ' ', ' ')), 0);
    assert_true(negobs_libcamera_format_rank(FCC('N', 'V', '1', '2')) <
                negobs_libcamera_format_rank(FCC('Y', 'U', 'Y', 'V')));
    assert_true(negobs_libcamera_format_rank(FCC('Y', 'U', 'Y', 'V')) <
                negobs_libcamera_format_rank(FCC('R', 'G', '2', '4')));
    assert_int_equal(negobs_libcamera_format_rank(FCC('S', 'R', 'G', 'B')),
                     -1); /* Bayer: no luma without an ISP */
    assert_false(negobs_libcamera_format_packed(FCC('N', 'V', '1', '2')));
    assert_true(negobs_libcamera_format_packed(FCC('U', 'Y', 'V', 'Y')));
    assert_true(negobs_libcamera_format_packed(FCC('B', 'G', '2', '4')));
}

static void test_luma_plane_in_place_with_stride(void **state)
{
    uint8_t buf[6 * 4 + 6 * 2]; /* NV12 4x4 with stride 6 */
    negobs_image_u8_t y;
    (void)state;
    memset(buf, 0, sizeof buf);
    assert_int_equal(negobs_libcamera_luma(FCC('N', 'V', '1', '2'), buf,
                                           sizeof buf, 4, 4, 6, NULL, 0, &y),
                     NEGOBS_OK);
    assert_ptr_equal(y.data, buf);
    assert_int_equal(y.width, 4);
    assert_int_equal(y.height, 4);
    assert_int_equal(y.stride, 6);
    /* the last row needs no padding: 6 * 3 + 4 bytes are enough */
    assert_int_equal(negobs_libcamera_luma(FCC('R', '8', ' ', ' '), buf, 22, 4,
                                           4, 6, NULL, 0, &y),
                     NEGOBS_OK);
    assert_int_equal(negobs_libcamera_luma(FCC('R', '8', ' ', ' '), buf, 21, 4,
                                           4, 6, NULL, 0, &y),
                     NEGOBS_ERR_CORRUPT);
    assert_int_equal(negobs_libcamera_luma(FCC('R', '8', ' ', ' '), buf,
                                           sizeof buf, 4, 4, 3, NULL, 0, &y),
                     NEGOBS_ERR_INVAL);
}

static void test_luma_packed_yuv(void **state)
{
    /* 2x2 YUYV (stride 4) and UYVY: luma bytes 10,20 / 30,40 */
    uint8_t yuyv[8] = {10, 128, 20, 128, 30, 128, 40, 128};
    uint8_t uyvy[8] = {128, 10, 128, 20, 128, 30, 128, 40};
    uint8_t scratch[4];
    negobs_image_u8_t y;
    (void)state;
    assert_int_equal(negobs_libcamera_luma(FCC('Y', 'U', 'Y', 'V'), yuyv, 8, 2,
                                           2, 4, scratch, 4, &y),
                     NEGOBS_OK);
    assert_ptr_equal(y.data, scratch);
    assert_int_equal(y.stride, 2);
    assert_memory_equal(scratch, ((uint8_t[]){10, 20, 30, 40}), 4);
    memset(scratch, 0, sizeof scratch);
    assert_int_equal(negobs_libcamera_luma(FCC('U', 'Y', 'V', 'Y'), uyvy, 8, 2,
                                           2, 4, scratch, 4, &y),
                     NEGOBS_OK);
    assert_memory_equal(scratch, ((uint8_t[]){10, 20, 30, 40}), 4);
    assert_int_equal(negobs_libcamera_luma(FCC('Y', 'U', 'Y', 'V'), yuyv, 8, 2,
                                           2, 4, scratch, 3, &y),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(negobs_libcamera_luma(FCC('Y', 'U', 'Y', 'V'), yuyv, 8, 2,
                                           2, 4, NULL, 0, &y),
                     NEGOBS_ERR_NOSPACE);
}

static void test_luma_rgb_byte_orders(void **state)
{
    /* one pure red, green, blue and white pixel; DRM RGB888 ('RG24') is
     * B, G, R in memory, BGR888 ('BG24') R, G, B */
    uint8_t rg24[12] = {0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255};
    uint8_t bg24[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    uint8_t xr24[16] = {0,   0, 255, 9, 0,   255, 0,   9,
                        255, 0, 0,   9, 255, 255, 255, 9};
    /* BT.601 in 1/256, rounded: 255 * 150 / 256 = 149.4 */
    const uint8_t want[4] = {77, 149, 29, 255};
    uint8_t scratch[4];
    negobs_image_u8_t y;
    (void)state;
    assert_int_equal(negobs_libcamera_luma(FCC('R', 'G', '2', '4'), rg24, 12,
                                           4, 1, 12, scratch, 4, &y),
                     NEGOBS_OK);
    assert_memory_equal(scratch, want, 4);
    memset(scratch, 0, sizeof scratch);
    assert_int_equal(negobs_libcamera_luma(FCC('B', 'G', '2', '4'), bg24, 12,
                                           4, 1, 12, scratch, 4, &y),
                     NEGOBS_OK);
    assert_memory_equal(scratch, want, 4);
    memset(scratch, 0, sizeof scratch);
    assert_int_equal(negobs_libcamera_luma(FCC('X', 'R', '2', '4'), xr24, 16,
                                           4, 1, 16, scratch, 4, &y),
                     NEGOBS_OK);
    assert_memory_equal(scratch, want, 4);
    assert_int_equal(negobs_libcamera_luma(FCC('S', 'R', 'G', 'B'), rg24, 12,
                                           4, 1, 12, scratch, 4, &y),
                     NEGOBS_ERR_UNSUPPORTED);
}

/* ---- the backend on a machine without the camera asked for ---- */

#ifndef NEGOBS_TEST_NO_LC_BACKEND
static void test_init_rejects_null(void **state)
{
    negobs_libcamera_t st;
    negobs_capture_t cam;
    (void)state;
    assert_int_equal(negobs_libcamera_init(NULL, NULL, 0, &cam),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_libcamera_init(&st, NULL, 0, NULL),
                     NEGOBS_ERR_INVAL);
}
#endif

#if defined(NEGOBS_TEST_THREADS) && !defined(NEGOBS_TEST_NO_LC_BACKEND)
static void test_absent_cameras_fail_cleanly(void **state)
{
    static negobs_libcamera_t st;
    negobs_capture_t cam;
    negobs_capture_config_t cfg;
    negobs_frame_pair_t pair;
    negobs_capture_stats_t stats;
    int round;
    (void)state;
    if (!negobs_libcamera_available()) {
        /* the handle still says why and refuses, never a NULL ops */
        assert_int_equal(negobs_libcamera_init(&st, NULL, 0, &cam),
                         NEGOBS_ERR_UNSUPPORTED);
        assert_non_null(strstr(negobs_capture_errmsg(&cam), "not built"));
        negobs_capture_config_default(&cfg);
        cfg.left = "libcamera:0";
        assert_int_equal(negobs_capture_open(&cam, &cfg),
                         NEGOBS_ERR_UNSUPPORTED);
        skip();
    }
    assert_int_equal(negobs_libcamera_init(&st, NULL, 0, &cam), NEGOBS_OK);
    assert_string_equal(cam.ops->name, "libcamera");
    negobs_capture_config_default(&cfg);

    /* before open: start and get_pair are out of order, not crashes */
    assert_int_equal(negobs_capture_start(&cam), NEGOBS_ERR_STATE);
    assert_int_equal(negobs_capture_get_pair(&cam, &pair, 10),
                     NEGOBS_ERR_STATE);
    negobs_capture_release(&cam, &pair);
    negobs_capture_stop(&cam);

    assert_int_equal(negobs_capture_open(&cam, NULL), NEGOBS_ERR_INVAL);
    cfg.left = "libcamera:";
    cfg.right = NULL;
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_INVAL);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "bad source"));

    /* the camera manager is started and stopped each round: it must come
     * back, whatever number of cameras this machine has */
    for (round = 0; round < 2; round++) {
        cfg.left = "libcamera:999";
        cfg.right = NULL;
        assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_NODEV);
        assert_non_null(strstr(negobs_capture_errmsg(&cam), "no camera 999"));
        cfg.left = "libcamera:no such camera";
        cfg.right = "libcamera:998";
        assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_ERR_NODEV);
        assert_non_null(
            strstr(negobs_capture_errmsg(&cam), "'no such camera'"));
        assert_int_equal(negobs_capture_start(&cam), NEGOBS_ERR_STATE);
        assert_int_equal(negobs_capture_get_pair(&cam, &pair, 10),
                         NEGOBS_ERR_STATE);
    }
    negobs_capture_get_stats(&cam, &stats);
    assert_int_equal(stats.pairs, 0);
    negobs_capture_close(&cam);
    negobs_capture_close(&cam); /* twice is harmless */
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_index_and_id),
        cmocka_unit_test(test_parse_rejects_bad_names),
        cmocka_unit_test(test_format_preference),
        cmocka_unit_test(test_luma_plane_in_place_with_stride),
        cmocka_unit_test(test_luma_packed_yuv),
        cmocka_unit_test(test_luma_rgb_byte_orders),
#ifndef NEGOBS_TEST_NO_LC_BACKEND
        cmocka_unit_test(test_init_rejects_null),
#endif
#if defined(NEGOBS_TEST_THREADS) && !defined(NEGOBS_TEST_NO_LC_BACKEND)
        cmocka_unit_test(test_absent_cameras_fail_cleanly),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
