/*
 * V4L2 pixel-format handling, kept free of device access so it can be
 * unit-tested: which formats we take, how big a frame must be, and where
 * the luma plane is.
 */
#include <string.h>

#include "negobs_port/camera_v4l2.h"
#include "negobs_port/mjpeg.h"

#define FCC_GREY NEGOBS_FOURCC('G', 'R', 'E', 'Y')
#define FCC_NV12 NEGOBS_FOURCC('N', 'V', '1', '2')
#define FCC_NV21 NEGOBS_FOURCC('N', 'V', '2', '1')
#define FCC_YU12 NEGOBS_FOURCC('Y', 'U', '1', '2')
#define FCC_YV12 NEGOBS_FOURCC('Y', 'V', '1', '2')
#define FCC_YUYV NEGOBS_FOURCC('Y', 'U', 'Y', 'V')
#define FCC_UYVY NEGOBS_FOURCC('U', 'Y', 'V', 'Y')
#define FCC_Y10 NEGOBS_FOURCC('Y', '1', '0', ' ')
#define FCC_Y16 NEGOBS_FOURCC('Y', '1', '6', ' ')
#define FCC_MJPG NEGOBS_FOURCC('M', 'J', 'P', 'G')

/* Preference order: luma in place first, then a copy of every other
 * byte, then 16-bit mono (a pass that averages and shifts), MJPEG last
 * (a decode: the most CPU per pixel). */
static const uint32_t format_order[] = {
    FCC_GREY, FCC_NV12, FCC_NV21, FCC_YU12, FCC_YV12,
    FCC_YUYV, FCC_UYVY, FCC_Y10,  FCC_Y16,  FCC_MJPG,
};

int negobs_v4l2_format_rank(uint32_t fourcc)
{
    size_t i;
    if (fourcc == FCC_MJPG && !negobs_mjpeg_available()) {
        return -1;
    }
    for (i = 0; i < sizeof format_order / sizeof format_order[0]; i++) {
        if (format_order[i] == fourcc) {
            return (int)i;
        }
    }
    return -1;
}

bool negobs_v4l2_format_packed(uint32_t fourcc)
{
    return fourcc == FCC_YUYV || fourcc == FCC_UYVY;
}

static bool is_420(uint32_t fourcc)
{
    return fourcc == FCC_NV12 || fourcc == FCC_NV21 || fourcc == FCC_YU12 ||
           fourcc == FCC_YV12;
}

size_t negobs_v4l2_frame_bytes(uint32_t fourcc, int32_t height,
                               uint32_t bytesperline)
{
    size_t plane;
    if (negobs_v4l2_format_rank(fourcc) < 0 || height <= 0) {
        return 0;
    }
    if (fourcc == FCC_MJPG) {
        /* compressed: no size to expect; SOI + EOI at least */
        return NEGOBS_V4L2_MJPEG_MIN_BYTES;
    }
    plane = (size_t)bytesperline * (size_t)height;
    return is_420(fourcc) ? plane + plane / 2u : plane;
}

negobs_status_t negobs_v4l2_check_format(uint32_t fourcc, int32_t width,
                                         int32_t height, uint32_t bytesperline,
                                         uint32_t sizeimage)
{
    uint32_t bpp;
    if (negobs_v4l2_format_rank(fourcc) < 0) {
        return NEGOBS_ERR_UNSUPPORTED;
    }
    if (width < 1 || height < 1 || width > NEGOBS_MAX_DIM ||
        height > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    if (fourcc == FCC_MJPG) {
        /* bytesperline is 0 for compressed formats; sizeimage is the
         * driver's largest frame */
        return sizeimage >= NEGOBS_V4L2_MJPEG_MIN_BYTES ? NEGOBS_OK
                                                        : NEGOBS_ERR_INVAL;
    }
    bpp = (negobs_v4l2_format_packed(fourcc) || fourcc == FCC_Y10 ||
           fourcc == FCC_Y16)
              ? 2u
              : 1u;
    if (bytesperline < (uint32_t)width * bpp ||
        bytesperline > 4u * (uint32_t)NEGOBS_MAX_DIM * bpp) {
        return NEGOBS_ERR_INVAL;
    }
    if ((size_t)sizeimage <
        negobs_v4l2_frame_bytes(fourcc, height, bytesperline)) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

negobs_status_t negobs_v4l2_luma(uint32_t fourcc, uint8_t *base,
                                 size_t bytesused, int32_t width,
                                 int32_t height, uint32_t bytesperline,
                                 uint8_t *scratch, size_t scratch_bytes,
                                 negobs_image_u8_t *out)
{
    bool packed;
    size_t need;
    int32_t x;
    int32_t y;
    if (negobs_v4l2_format_rank(fourcc) < 0 || fourcc == FCC_Y10 ||
        fourcc == FCC_Y16 || fourcc == FCC_MJPG) {
        return NEGOBS_ERR_UNSUPPORTED; /* negobs_v4l2_conv_frame() */
    }
    if (base == NULL || out == NULL || width < 1 || height < 1) {
        return NEGOBS_ERR_INVAL;
    }
    packed = negobs_v4l2_format_packed(fourcc);
    /* Enough bytes for every luma sample of the last row. */
    need = (size_t)bytesperline * (size_t)(height - 1) +
           (size_t)width * (packed ? 2u : 1u);
    if (bytesused < need) {
        return NEGOBS_ERR_CORRUPT;
    }
    if (!packed) {
        /* GREY and 4:2:0 planar: the Y plane is first, hand it out. */
        out->data = base;
        out->width = width;
        out->height = height;
        out->stride = (int32_t)bytesperline;
        return NEGOBS_OK;
    }
    if (scratch == NULL || scratch_bytes < (size_t)width * (size_t)height) {
        return NEGOBS_ERR_NOSPACE;
    }
    {
        /* YUYV: Y at even bytes; UYVY: Y at odd bytes. */
        size_t off = fourcc == FCC_UYVY ? 1u : 0u;
        for (y = 0; y < height; y++) {
            const uint8_t *src = base + (size_t)y * bytesperline + off;
            uint8_t *dst = scratch + (size_t)y * (size_t)width;
            for (x = 0; x < width; x++) {
                dst[x] = src[(size_t)2 * (size_t)x];
            }
        }
    }
    out->data = scratch;
    out->width = width;
    out->height = height;
    out->stride = width;
    return NEGOBS_OK;
}

uint32_t negobs_v4l2_backoff_ms(uint32_t failures)
{
    uint32_t ms = NEGOBS_V4L2_BACKOFF_MIN_MS;
    while (failures > 0 && ms < NEGOBS_V4L2_BACKOFF_MAX_MS) {
        ms *= 2u;
        failures--;
    }
    return ms > NEGOBS_V4L2_BACKOFF_MAX_MS ? NEGOBS_V4L2_BACKOFF_MAX_MS : ms;
}
