/*
 * Camera frames to processing images without a device: side-by-side
 * split, crop and integer area binning (and the intrinsics that follow
 * it), 16-bit mono to 8 bit, MJPEG through libjpeg-turbo (frames encoded
 * here with libturbojpeg, then decoded through the capture path), and the
 * V4L2 format choice from listed modes.
 */
#define _XOPEN_SOURCE 700

#include <string.h>

#include <linux/videodev2.h>

#include "cmocka_all.h"
#include "negobs_port/camera.h"
#include "negobs_port/camera_list.h"
#include "negobs_port/camera_v4l2.h"
#include "negobs_port/frame_convert.h"
#include "negobs_port/mjpeg.h"
#include "negobs_port/v4l2_convert.h"

#ifdef NEGOBS_TEST_MJPEG
#include <turbojpeg.h>
#endif

static void test_plan_sizes_of_common_cameras(void **state)
{
    negobs_bin_plan_t p;
    int32_t ew;
    int32_t eh;
    (void)state;
    /* ZED-style 2560x720 side by side: two 1280x720 eyes */
    assert_int_equal(negobs_sbs_eye_size(2560, 720, true, &ew, &eh),
                     NEGOBS_OK);
    assert_int_equal(ew, 1280);
    assert_int_equal(eh, 720);
    /* 1280x720 -> 640x360: 2x2 bins, no crop */
    assert_int_equal(negobs_bin_plan(1280, 720, 640, 360, &p), NEGOBS_OK);
    assert_int_equal(p.k, 2);
    assert_int_equal(p.x0, 0);
    assert_int_equal(p.y0, 0);
    /* 1280x720 -> 320x240: 3x3 bins of a centred 960x720 crop; the offset
     * is a multiple of k (159 = 53 * 3, not 160) */
    assert_int_equal(negobs_bin_plan(1280, 720, 320, 240, &p), NEGOBS_OK);
    assert_int_equal(p.k, 3);
    assert_int_equal(p.x0, 159);
    assert_int_equal(p.y0, 0);
    /* 2560x800 side by side (1280x800 eyes) -> 640x400: k = 2 */
    assert_int_equal(negobs_sbs_eye_size(2560, 800, true, &ew, &eh),
                     NEGOBS_OK);
    assert_int_equal(negobs_bin_plan(ew, eh, 640, 400, &p), NEGOBS_OK);
    assert_int_equal(p.k, 2);
    /* 0: the eye's own size */
    assert_int_equal(negobs_bin_plan(1280, 720, 0, 0, &p), NEGOBS_OK);
    assert_true(negobs_bin_identity(&p));
    /* refused: an eye smaller than the processing size, odd SBS width */
    assert_int_equal(negobs_bin_plan(320, 240, 640, 360, &p),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_sbs_eye_size(2561, 720, true, &ew, &eh),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_bin_plan(4096, 4096, 16, 16, &p),
                     NEGOBS_ERR_UNSUPPORTED); /* k = 256 */
}

static void test_bin_u8_is_the_block_mean(void **state)
{
    enum { W = 12, H = 6 };
    uint8_t src[H][W];
    uint8_t dst[2][4];
    negobs_bin_plan_t p;
    uint32_t seed = 7;
    int x;
    int y;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            src[y][x] = (uint8_t)(test_lcg_next(&seed) & 0xFFu);
        }
    }
    /* 12x6 -> 4x2: k = 3, no crop */
    assert_int_equal(negobs_bin_plan(W, H, 4, 2, &p), NEGOBS_OK);
    assert_int_equal(p.k, 3);
    negobs_bin_u8(&src[0][0], W, 1, &p, &dst[0][0], 4);
    for (y = 0; y < 2; y++) {
        for (x = 0; x < 4; x++) {
            uint32_t sum = 0;
            int by;
            int bx;
            for (by = 0; by < 3; by++) {
                for (bx = 0; bx < 3; bx++) {
                    sum += src[3 * y + by][3 * x + bx];
                }
            }
            assert_int_equal(dst[y][x], (sum + 4u) / 9u);
        }
    }
}

static void test_bin_u8_reads_packed_luma_with_a_step(void **state)
{
    /* YUYV 4x2: Y at even bytes; chroma bytes must not leak in */
    uint8_t yuyv[2][8] = {{10, 200, 20, 201, 30, 202, 40, 203},
                          {50, 204, 60, 205, 70, 206, 80, 207}};
    uint8_t dst[2];
    negobs_bin_plan_t p;
    (void)state;
    assert_int_equal(negobs_bin_plan(4, 2, 2, 1, &p), NEGOBS_OK);
    negobs_bin_u8(&yuyv[0][0], 8, 2, &p, dst, 2);
    assert_int_equal(dst[0], (10 + 20 + 50 + 60 + 2) / 4);
    assert_int_equal(dst[1], (30 + 40 + 70 + 80 + 2) / 4);
}

static void put16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

static void test_y10_and_y16_become_the_top_8_bits(void **state)
{
    uint8_t buf[2][8] = {{0}}; /* 4x2 samples, 16-bit LE */
    uint8_t dst[8];            /* 4x2 out */
    negobs_bin_plan_t p;
    (void)state;
    assert_int_equal(negobs_bin_plan(4, 2, 0, 0, &p), NEGOBS_OK);
    /* Y10: 0, 1023, 512, 3 -> >> 2 */
    put16(&buf[0][0], 0);
    put16(&buf[0][2], 1023);
    put16(&buf[0][4], 512);
    put16(&buf[0][6], 3);
    negobs_bin_u16le(&buf[0][0], 8, 2, &p, dst, 4);
    assert_int_equal(dst[0], 0);
    assert_int_equal(dst[1], 255);
    assert_int_equal(dst[2], 128);
    assert_int_equal(dst[3], 0);
    /* Y16: >> 8 */
    put16(&buf[0][0], 0xFFFF);
    put16(&buf[0][2], 0x8000);
    negobs_bin_u16le(&buf[0][0], 8, 8, &p, dst, 4);
    assert_int_equal(dst[0], 255);
    assert_int_equal(dst[1], 128);
    /* a Y10 driver leaving high bits set saturates, never wraps */
    put16(&buf[0][0], 0xFFFF);
    negobs_bin_u16le(&buf[0][0], 8, 2, &p, dst, 4);
    assert_int_equal(dst[0], 255);
    /* binning before the shift keeps precision: 2x2 of 1,2,1,2 (Y10)
     * is 1.5 -> rounds to 2 -> 0 after >> 2; of 4 x 6 -> 6 >> 2 = 1 */
    assert_int_equal(negobs_bin_plan(4, 2, 2, 1, &p), NEGOBS_OK);
    put16(&buf[0][0], 6);
    put16(&buf[0][2], 6);
    put16(&buf[1][0], 6);
    put16(&buf[1][2], 6);
    negobs_bin_u16le(&buf[0][0], 8, 2, &p, dst, 2);
    assert_int_equal(dst[0], 1);
}

/* A line k pixels wide centred on source column c lands, after binning,
 * where the scaled principal-point formula puts a point at c: its block
 * sums are the overlaps of two k-wide boxes, linear in the offset, so the
 * centroid of the binned line is exact. */
static void test_intrinsics_follow_the_binning(void **state)
{
    enum { W = 96, H = 24 };
    static uint8_t src[H][W];
    uint8_t dst[8][32];
    negobs_bin_plan_t p;
    int32_t f_q4 = 1000 * 16;
    int32_t cx_q4;
    int32_t cy_q4 = -1;
    int32_t c;
    int32_t diff;
    (void)state;
    /* 96x24 -> 20x8: k = 3, crop x0 = (96 - 60) / 2 = 18 */
    assert_int_equal(negobs_bin_plan(W, H, 20, 8, &p), NEGOBS_OK);
    assert_int_equal(p.k, 3);
    assert_int_equal(p.x0, 18);
    for (c = 19; c < 76; c++) {
        uint32_t num = 0;
        uint32_t den = 0;
        int x;
        int y;
        memset(src, 0, sizeof src);
        for (y = 0; y < H; y++) {
            src[y][c - 1] = 240;
            src[y][c] = 240;
            src[y][c + 1] = 240;
        }
        negobs_bin_u8(&src[0][0], W, 1, &p, &dst[0][0], 32);
        for (x = 0; x < 20; x++) {
            num += (uint32_t)x * 16u * dst[3][x];
            den += dst[3][x];
        }
        cx_q4 = c * 16;
        negobs_bin_intrinsics_q4(&p, NULL, &cx_q4, NULL);
        assert_true(den > 0u);
        /* both sides rounded to 1/16 px: equal within one step */
        diff = (int32_t)((num + den / 2u) / den) - cx_q4;
        assert_true(diff >= -1 && diff <= 1);
    }
    cx_q4 = 48 * 16;
    negobs_bin_intrinsics_q4(&p, &f_q4, &cx_q4, &cy_q4);
    assert_int_equal(f_q4, (1000 * 16 + 1) / 3); /* f / k */
    assert_int_equal(cx_q4, 155); /* (48 - 18 - 1) / 3 = 9.67 px */
    assert_int_equal(cy_q4, -1);  /* "centre" stays "centre" */
}

static void test_conv_side_by_side_grey_in_place(void **state)
{
    static uint8_t frame[8 * 80]; /* 64x8 GREY, bytesperline 80 */
    negobs_v4l2_conv_t c;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    (void)state;
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_GREY, 64, 8, 80, true, 0, 0),
        NEGOBS_OK);
    assert_true(c.in_place);
    assert_int_equal(negobs_v4l2_conv_scratch_bytes(&c), 0);
    assert_int_equal(
        negobs_v4l2_conv_frame(&c, frame, sizeof frame, NULL, 0, &l, &r),
        NEGOBS_OK);
    assert_ptr_equal(l.data, frame);
    assert_ptr_equal(r.data, frame + 32);
    assert_int_equal(l.width, 32);
    assert_int_equal(r.width, 32);
    assert_int_equal(l.stride, 80);
    /* short buffer: refused */
    assert_int_equal(
        negobs_v4l2_conv_frame(&c, frame, 80 * 7 + 63, NULL, 0, &l, &r),
        NEGOBS_ERR_CORRUPT);
    /* side by side needs somewhere for the right eye */
    assert_int_equal(
        negobs_v4l2_conv_frame(&c, frame, sizeof frame, NULL, 0, &l, NULL),
        NEGOBS_ERR_INVAL);
}

static void test_conv_side_by_side_yuyv_binned(void **state)
{
    /* 2 eyes of 8x4 YUYV side by side (16x4 frame), each -> 4x2 */
    static uint8_t frame[4][32];
    uint8_t scratch[2 * 4 * 2];
    negobs_v4l2_conv_t c;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    int x;
    int y;
    (void)state;
    for (y = 0; y < 4; y++) {
        for (x = 0; x < 16; x++) {
            frame[y][2 * x] = (uint8_t)(x < 8 ? 40 : 200); /* Y */
            frame[y][2 * x + 1] = 128;                     /* U/V */
        }
    }
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_YUYV, 16, 4, 32, true, 4, 2),
        NEGOBS_OK);
    assert_int_equal(c.plan.k, 2);
    assert_false(c.in_place);
    assert_int_equal(negobs_v4l2_conv_scratch_bytes(&c), sizeof scratch);
    assert_int_equal(negobs_v4l2_conv_frame(&c, &frame[0][0], sizeof frame,
                                            scratch, sizeof scratch - 1u, &l,
                                            &r),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(negobs_v4l2_conv_frame(&c, &frame[0][0], sizeof frame,
                                            scratch, sizeof scratch, &l, &r),
                     NEGOBS_OK);
    assert_int_equal(l.width, 4);
    assert_int_equal(l.height, 2);
    for (y = 0; y < 2; y++) {
        for (x = 0; x < 4; x++) {
            assert_int_equal(l.data[y * l.stride + x], 40);
            assert_int_equal(r.data[y * r.stride + x], 200);
        }
    }
    /* an eye smaller than the processing size is refused at setup */
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_YUYV, 16, 4, 32, true, 16, 4),
        NEGOBS_ERR_INVAL);
}

static void test_conv_y16_two_nodes(void **state)
{
    static uint8_t frame[4 * 16]; /* 8x4 Y16 */
    uint8_t scratch[4 * 2];
    negobs_v4l2_conv_t c;
    negobs_image_u8_t l;
    int i;
    (void)state;
    for (i = 0; i < 32; i++) {
        put16(frame + 2 * i, 0x4000); /* 64 after >> 8 */
    }
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_Y16, 8, 4, 16, false, 4, 2),
        NEGOBS_OK);
    assert_int_equal(negobs_v4l2_conv_frame(&c, frame, sizeof frame, scratch,
                                            sizeof scratch, &l, NULL),
                     NEGOBS_OK);
    assert_int_equal(l.data[0], 64);
    assert_int_equal(l.data[7], 64);
    /* Y10 needs 2 bytes per pixel of stride */
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_Y10, 8, 4, 8, false, 0, 0),
        NEGOBS_ERR_INVAL);
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_H264, 8, 4, 8, false, 0, 0),
        NEGOBS_ERR_UNSUPPORTED);
}

static void test_choose_format_prefers_rate_then_rank(void **state)
{
    /* A UVC stereo camera: YUYV at 2560x720 only at 5 fps, MJPEG at 30 */
    const negobs_v4l2_mode_t uvc[] = {
        {V4L2_PIX_FMT_YUYV, 2560, 720, 5000},
        {V4L2_PIX_FMT_YUYV, 1280, 480, 30000},
        {V4L2_PIX_FMT_MJPEG, 2560, 720, 30000},
        {V4L2_PIX_FMT_MJPEG, 1280, 480, 30000},
    };
    const negobs_v4l2_mode_t mono[] = {
        {V4L2_PIX_FMT_Y10, 1280, 800, 60000},
        {V4L2_PIX_FMT_GREY, 1280, 800, 60000},
        {V4L2_PIX_FMT_H264, 1280, 800, 60000},
    };
    const negobs_v4l2_mode_t unlisted[] = {{V4L2_PIX_FMT_YUYV, 0, 0, 0}};
    const negobs_v4l2_mode_t none[] = {{V4L2_PIX_FMT_H264, 640, 480, 30000}};
    (void)state;
    if (negobs_mjpeg_available()) {
        assert_int_equal(negobs_v4l2_choose_format(uvc, 4, 2560, 720, 30),
                         V4L2_PIX_FMT_MJPEG);
    } else {
        /* no decoder: YUYV at its 5 fps rather than nothing */
        assert_int_equal(negobs_v4l2_choose_format(uvc, 4, 2560, 720, 30),
                         V4L2_PIX_FMT_YUYV);
    }
    /* both fast enough at 1280x480: the cheaper format */
    assert_int_equal(negobs_v4l2_choose_format(uvc, 4, 1280, 480, 30),
                     V4L2_PIX_FMT_YUYV);
    assert_int_equal(negobs_v4l2_choose_format(uvc, 4, 2560, 720, 5),
                     V4L2_PIX_FMT_YUYV);
    assert_int_equal(negobs_v4l2_choose_format(mono, 3, 1280, 800, 30),
                     V4L2_PIX_FMT_GREY);
    assert_int_equal(negobs_v4l2_choose_format(mono, 1, 1280, 800, 30),
                     V4L2_PIX_FMT_Y10);
    /* no size listing: the best usable format */
    assert_int_equal(negobs_v4l2_choose_format(unlisted, 1, 640, 480, 30),
                     V4L2_PIX_FMT_YUYV);
    assert_int_equal(negobs_v4l2_choose_format(none, 1, 640, 480, 30), 0);
}

#ifdef NEGOBS_TEST_MJPEG
/* Encode w x h grey (or colour) pixels as a JPEG with libturbojpeg. */
static unsigned long encode(const uint8_t *px, int w, int h, int pf, int samp,
                            uint8_t *out, unsigned long cap)
{
    tjhandle t = tjInitCompress();
    unsigned char *jpeg = out;
    unsigned long n = cap;
    int rc;
    assert_non_null(t);
    rc = tjCompress2(t, px, w, 0, h, pf, &jpeg, &n, samp, 95,
                     TJFLAG_NOREALLOC);
    (void)tjDestroy(t);
    assert_int_equal(rc, 0);
    return n;
}

static void test_mjpeg_side_by_side_through_the_capture_path(void **state)
{
    enum { W = 128, H = 32 }; /* 2 eyes of 64x32, each -> 32x16 */
    static uint8_t px[H][W];
    static uint8_t jpeg[64 * 1024];
    static uint8_t scratch[W * H + 2 * 32 * 16];
    static uint8_t garbage[256];
    negobs_v4l2_conv_t c;
    negobs_image_u8_t l;
    negobs_image_u8_t r;
    negobs_bin_plan_t p;
    uint8_t ref[16][32];
    unsigned long n;
    int32_t w = 0;
    int32_t h = 0;
    int x;
    int y;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            /* smooth ramps, different per eye */
            px[y][x] = (uint8_t)(x < 64 ? 30 + x + y : 220 - (x - 64) - y);
        }
    }
    n = encode(&px[0][0], W, H, TJPF_GRAY, TJSAMP_GRAY, jpeg, sizeof jpeg);
    assert_int_equal(negobs_mjpeg_size(jpeg, n, &w, &h), NEGOBS_OK);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_MJPEG, W, H, 0, true, 32, 16),
        NEGOBS_OK);
    assert_int_equal(negobs_v4l2_conv_scratch_bytes(&c), sizeof scratch);
    assert_int_equal(
        negobs_v4l2_conv_frame(&c, jpeg, n, scratch, sizeof scratch, &l, &r),
        NEGOBS_OK);
    assert_int_equal(l.width, 32);
    assert_int_equal(r.height, 16);
    /* the binned original, eye by eye; JPEG at quality 95 is within a
     * few grey levels of it */
    assert_int_equal(negobs_bin_plan(64, 32, 32, 16, &p), NEGOBS_OK);
    negobs_bin_u8(&px[0][0], W, 1, &p, &ref[0][0], 32);
    for (y = 0; y < 16; y++) {
        for (x = 0; x < 32; x++) {
            assert_in_range(l.data[y * l.stride + x], ref[y][x] - 3,
                            ref[y][x] + 3);
        }
    }
    negobs_bin_u8(&px[0][64], W, 1, &p, &ref[0][0], 32);
    for (y = 0; y < 16; y++) {
        for (x = 0; x < 32; x++) {
            assert_in_range(r.data[y * r.stride + x], ref[y][x] - 3,
                            ref[y][x] + 3);
        }
    }
    /* a frame cut by a USB error, garbage, another size: refused */
    assert_int_equal(negobs_v4l2_conv_frame(&c, jpeg, n / 2u, scratch,
                                            sizeof scratch, &l, &r),
                     NEGOBS_ERR_CORRUPT);
    memset(garbage, 0x55, sizeof garbage);
    assert_int_equal(negobs_v4l2_conv_frame(&c, garbage, sizeof garbage,
                                            scratch, sizeof scratch, &l, &r),
                     NEGOBS_ERR_CORRUPT);
    garbage[0] = 0xFF; /* SOI, then nothing sensible */
    garbage[1] = 0xD8;
    assert_int_equal(negobs_v4l2_conv_frame(&c, garbage, sizeof garbage,
                                            scratch, sizeof scratch, &l, &r),
                     NEGOBS_ERR_CORRUPT);
    assert_int_equal(negobs_mjpeg_decode_grey(jpeg, n, W / 2, H, scratch, W),
                     NEGOBS_ERR_CORRUPT);
}

/* The frozen-stream check signs MJPEG frames by their compressed bytes
 * (bytesperline is 0 for them: signing "rows of bytesperline" signed
 * nothing, every frame had the same signature and every MJPEG camera read
 * as frozen after frozen_frames frames). */
static void test_mjpeg_frames_are_signed_by_their_data(void **state)
{
    enum { W = 64, H = 32 };
    static uint8_t px[H][W];
    static uint8_t jpeg_a[16 * 1024];
    static uint8_t jpeg_b[16 * 1024];
    negobs_v4l2_conv_t c;
    negobs_image_u8_t va;
    negobs_image_u8_t vb;
    unsigned long na;
    unsigned long nb;
    uint32_t seed = 3;
    int x;
    int y;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            px[y][x] = (uint8_t)(test_lcg_next(&seed) & 0xFFu);
        }
    }
    na = encode(&px[0][0], W, H, TJPF_GRAY, TJSAMP_GRAY, jpeg_a,
                sizeof jpeg_a);
    px[H / 2][W / 2] ^= 0x40u; /* one pixel of sensor noise */
    nb = encode(&px[0][0], W, H, TJPF_GRAY, TJSAMP_GRAY, jpeg_b,
                sizeof jpeg_b);
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_MJPEG, W, H, 0, false, 0, 0),
        NEGOBS_OK);
    negobs_v4l2_conv_raw_view(&c, jpeg_a, na, &va);
    negobs_v4l2_conv_raw_view(&c, jpeg_b, nb, &vb);
    assert_true(va.width > 0 && va.height > 0);
    assert_int_not_equal(negobs_frame_signature(&va),
                         negobs_frame_signature(&vb));
    assert_int_equal(negobs_frame_signature(&va), negobs_frame_signature(&va));
    /* uncompressed formats: the plane's rows as before */
    assert_int_equal(
        negobs_v4l2_conv_setup(&c, V4L2_PIX_FMT_GREY, W, H, 80, false, 0, 0),
        NEGOBS_OK);
    negobs_v4l2_conv_raw_view(&c, jpeg_a, 80u * H, &va);
    assert_int_equal(va.width, 80);
    assert_int_equal(va.height, H);
}

/* A colour 4:2:0 JPEG (what UVC cameras send): the grey decode is its
 * luma, BT.601 as JPEG defines it. */
static void test_mjpeg_colour_gives_its_luma(void **state)
{
    enum { W = 32, H = 16 };
    static uint8_t rgb[H][W][3];
    static uint8_t jpeg[32 * 1024];
    static uint8_t grey[H][W];
    unsigned long n;
    int x;
    int y;
    (void)state;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            rgb[y][x][0] = 200;
            rgb[y][x][1] = 100;
            rgb[y][x][2] = 50;
        }
    }
    n = encode(&rgb[0][0][0], W, H, TJPF_RGB, TJSAMP_420, jpeg, sizeof jpeg);
    assert_int_equal(negobs_mjpeg_decode_grey(jpeg, n, W, H, &grey[0][0], W),
                     NEGOBS_OK);
    /* Y = 0.299 R + 0.587 G + 0.114 B = 124.3 */
    assert_in_range(grey[H / 2][W / 2], 122, 126);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plan_sizes_of_common_cameras),
        cmocka_unit_test(test_bin_u8_is_the_block_mean),
        cmocka_unit_test(test_bin_u8_reads_packed_luma_with_a_step),
        cmocka_unit_test(test_y10_and_y16_become_the_top_8_bits),
        cmocka_unit_test(test_intrinsics_follow_the_binning),
        cmocka_unit_test(test_conv_side_by_side_grey_in_place),
        cmocka_unit_test(test_conv_side_by_side_yuyv_binned),
        cmocka_unit_test(test_conv_y16_two_nodes),
        cmocka_unit_test(test_choose_format_prefers_rate_then_rank),
#ifdef NEGOBS_TEST_MJPEG
        cmocka_unit_test(test_mjpeg_side_by_side_through_the_capture_path),
        cmocka_unit_test(test_mjpeg_colour_gives_its_luma),
        cmocka_unit_test(test_mjpeg_frames_are_signed_by_their_data),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
