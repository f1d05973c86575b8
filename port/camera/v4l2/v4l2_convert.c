/*
 * V4L2 buffer -> processing images: luma, side-by-side split, crop and
 * bin (see negobs_port/v4l2_convert.h).
 */
#include <string.h>

#include "negobs_port/camera_v4l2.h"
#include "negobs_port/mjpeg.h"
#include "negobs_port/v4l2_convert.h"

#define FCC_YUYV NEGOBS_FOURCC('Y', 'U', 'Y', 'V')
#define FCC_UYVY NEGOBS_FOURCC('U', 'Y', 'V', 'Y')
#define FCC_Y10 NEGOBS_FOURCC('Y', '1', '0', ' ')
#define FCC_Y16 NEGOBS_FOURCC('Y', '1', '6', ' ')
#define FCC_MJPG NEGOBS_FOURCC('M', 'J', 'P', 'G')

static bool is_16bit(uint32_t fourcc)
{
    return fourcc == FCC_Y10 || fourcc == FCC_Y16;
}

/* Bytes of one luma sample as stored in the buffer. */
static size_t sample_step(uint32_t fourcc)
{
    return (negobs_v4l2_format_packed(fourcc) || is_16bit(fourcc)) ? 2u : 1u;
}

negobs_status_t negobs_v4l2_conv_setup(negobs_v4l2_conv_t *c, uint32_t fourcc,
                                       int32_t width, int32_t height,
                                       uint32_t bytesperline,
                                       bool side_by_side, int32_t out_w,
                                       int32_t out_h)
{
    int32_t eye_w;
    int32_t eye_h;
    negobs_status_t s;
    if (c == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (negobs_v4l2_format_rank(fourcc) < 0) {
        return NEGOBS_ERR_UNSUPPORTED;
    }
    s = negobs_sbs_eye_size(width, height, side_by_side, &eye_w, &eye_h);
    if (s != NEGOBS_OK) {
        return s;
    }
    if (fourcc != FCC_MJPG &&
        (size_t)bytesperline < (size_t)width * sample_step(fourcc)) {
        return NEGOBS_ERR_INVAL;
    }
    memset(c, 0, sizeof *c);
    s = negobs_bin_plan(eye_w, eye_h, out_w, out_h, &c->plan);
    if (s != NEGOBS_OK) {
        return s;
    }
    c->fourcc = fourcc;
    c->width = width;
    c->height = height;
    c->bytesperline = bytesperline;
    c->side_by_side = side_by_side;
    /* An 8-bit plane that needs no binning is only described; a crop at
     * k = 1 too (an offset into the plane). */
    c->in_place = sample_step(fourcc) == 1u && c->plan.k == 1;
    return NEGOBS_OK;
}

static size_t decoded_bytes(const negobs_v4l2_conv_t *c)
{
    return c->fourcc == FCC_MJPG ? (size_t)c->width * (size_t)c->height : 0u;
}

size_t negobs_v4l2_conv_scratch_bytes(const negobs_v4l2_conv_t *c)
{
    size_t eyes = c->side_by_side ? 2u : 1u;
    size_t out = c->in_place
                     ? 0u
                     : eyes * (size_t)c->plan.out_w * (size_t)c->plan.out_h;
    return decoded_bytes(c) + out;
}

static void describe(negobs_image_u8_t *img, uint8_t *data, int32_t w,
                     int32_t h, size_t stride)
{
    img->data = data;
    img->width = w;
    img->height = h;
    img->stride = (int32_t)stride;
}

negobs_status_t negobs_v4l2_conv_frame(const negobs_v4l2_conv_t *c,
                                       uint8_t *base, size_t bytesused,
                                       uint8_t *scratch, size_t scratch_bytes,
                                       negobs_image_u8_t *left,
                                       negobs_image_u8_t *right)
{
    const negobs_bin_plan_t *p;
    uint8_t *src;
    size_t stride;
    size_t step;
    size_t eyes;
    size_t e;
    size_t out_plane;
    if (c == NULL || base == NULL || left == NULL ||
        (c->side_by_side && right == NULL)) {
        return NEGOBS_ERR_INVAL;
    }
    p = &c->plan;
    eyes = c->side_by_side ? 2u : 1u;
    if (negobs_v4l2_conv_scratch_bytes(c) > 0u &&
        (scratch == NULL ||
         scratch_bytes < negobs_v4l2_conv_scratch_bytes(c))) {
        return NEGOBS_ERR_NOSPACE;
    }
    step = sample_step(c->fourcc);
    if (c->fourcc == FCC_MJPG) {
        negobs_status_t s = negobs_mjpeg_decode_grey(
            base, bytesused, c->width, c->height, scratch, (size_t)c->width);
        if (s != NEGOBS_OK) {
            return s;
        }
        src = scratch;
        stride = (size_t)c->width;
    } else {
        /* Enough bytes for every luma sample of the last row. */
        size_t need = (size_t)c->bytesperline * (size_t)(c->height - 1) +
                      (size_t)c->width * step;
        if (bytesused < need) {
            return NEGOBS_ERR_CORRUPT;
        }
        src = base + (c->fourcc == FCC_UYVY ? 1u : 0u);
        stride = c->bytesperline;
    }
    out_plane = (size_t)p->out_w * (size_t)p->out_h;
    for (e = 0; e < eyes; e++) {
        negobs_image_u8_t *img = e == 0 ? left : right;
        uint8_t *eye = src + e * (size_t)p->eye_w * step;
        uint8_t *dst;
        if (c->in_place) {
            describe(img, eye + (size_t)p->y0 * stride + (size_t)p->x0,
                     p->out_w, p->out_h, stride);
            continue;
        }
        dst = scratch + decoded_bytes(c) + e * out_plane;
        if (is_16bit(c->fourcc)) {
            negobs_bin_u16le(eye, stride, c->fourcc == FCC_Y10 ? 2u : 8u, p,
                             dst, (size_t)p->out_w);
        } else {
            negobs_bin_u8(eye, stride, step, p, dst, (size_t)p->out_w);
        }
        describe(img, dst, p->out_w, p->out_h, (size_t)p->out_w);
    }
    return NEGOBS_OK;
}

void negobs_v4l2_conv_raw_view(const negobs_v4l2_conv_t *c, uint8_t *base,
                               size_t bytesused, negobs_image_u8_t *out)
{
    out->data = base;
    if (c->fourcc != FCC_MJPG) {
        out->width = (int32_t)c->bytesperline;
        out->height = c->height;
        out->stride = (int32_t)c->bytesperline;
        return;
    }
    out->width = bytesused > (size_t)INT32_MAX ? INT32_MAX
                                               : (int32_t)bytesused;
    out->height = bytesused > 0u ? 1 : 0;
    out->stride = out->width;
}
