/*
 * Side-by-side split, crop and integer area binning, 16-bit mono to 8 bit
 * (see negobs_port/frame_convert.h for the geometry and the scaling).
 */
#include "negobs_port/frame_convert.h"

static bool dim_ok(int32_t v)
{
    return v >= 1 && v <= NEGOBS_MAX_DIM;
}

negobs_status_t negobs_sbs_eye_size(int32_t frame_w, int32_t frame_h,
                                    bool side_by_side, int32_t *eye_w,
                                    int32_t *eye_h)
{
    if (eye_w == NULL || eye_h == NULL || !dim_ok(frame_w) ||
        !dim_ok(frame_h)) {
        return NEGOBS_ERR_INVAL;
    }
    if (side_by_side && (frame_w % 2 != 0 || frame_w < 2)) {
        return NEGOBS_ERR_INVAL;
    }
    *eye_w = side_by_side ? frame_w / 2 : frame_w;
    *eye_h = frame_h;
    return NEGOBS_OK;
}

negobs_status_t negobs_bin_plan(int32_t eye_w, int32_t eye_h, int32_t out_w,
                                int32_t out_h, negobs_bin_plan_t *plan)
{
    int32_t k;
    if (plan == NULL || !dim_ok(eye_w) || !dim_ok(eye_h)) {
        return NEGOBS_ERR_INVAL;
    }
    if (out_w == 0 || out_h == 0) {
        out_w = eye_w;
        out_h = eye_h;
    }
    if (!dim_ok(out_w) || !dim_ok(out_h) || out_w > eye_w || out_h > eye_h) {
        return NEGOBS_ERR_INVAL;
    }
    k = eye_w / out_w < eye_h / out_h ? eye_w / out_w : eye_h / out_h;
    if (k > NEGOBS_BIN_MAX) {
        return NEGOBS_ERR_UNSUPPORTED;
    }
    plan->eye_w = eye_w;
    plan->eye_h = eye_h;
    plan->k = k;
    plan->out_w = out_w;
    plan->out_h = out_h;
    /* Centred crop, offsets rounded down to a multiple of k so that a
     * decoder that scales by a divisor of k (the JPEG DCT's 1/2, 1/4,
     * 1/8) lands on the same block grid. */
    plan->x0 = (eye_w - k * out_w) / 2 / k * k;
    plan->y0 = (eye_h - k * out_h) / 2 / k * k;
    return NEGOBS_OK;
}

bool negobs_bin_identity(const negobs_bin_plan_t *plan)
{
    return plan->k == 1 && plan->x0 == 0 && plan->y0 == 0 &&
           plan->out_w == plan->eye_w && plan->out_h == plan->eye_h;
}

void negobs_bin_u8(const uint8_t *src, size_t stride, size_t step,
                   const negobs_bin_plan_t *plan, uint8_t *dst,
                   size_t dst_stride)
{
    const size_t k = (size_t)plan->k;
    const uint32_t n = (uint32_t)(k * k);
    const uint8_t *org = src + (size_t)plan->y0 * stride +
                         (size_t)plan->x0 * step;
    int32_t oy;
    int32_t ox;
    for (oy = 0; oy < plan->out_h; oy++) {
        const uint8_t *blk_row = org + (size_t)oy * k * stride;
        uint8_t *d = dst + (size_t)oy * dst_stride;
        if (k == 1) {
            for (ox = 0; ox < plan->out_w; ox++) {
                d[ox] = blk_row[(size_t)ox * step];
            }
            continue;
        }
        for (ox = 0; ox < plan->out_w; ox++) {
            const uint8_t *b = blk_row + (size_t)ox * k * step;
            uint32_t sum = 0;
            size_t by;
            size_t bx;
            for (by = 0; by < k; by++) {
                const uint8_t *r = b + by * stride;
                for (bx = 0; bx < k; bx++) {
                    sum += r[bx * step];
                }
            }
            d[ox] = (uint8_t)((sum + n / 2u) / n);
        }
    }
}

void negobs_bin_u16le(const uint8_t *src, size_t stride, uint32_t shift,
                      const negobs_bin_plan_t *plan, uint8_t *dst,
                      size_t dst_stride)
{
    const size_t k = (size_t)plan->k;
    const uint32_t n = (uint32_t)(k * k);
    const uint8_t *org = src + (size_t)plan->y0 * stride +
                         (size_t)plan->x0 * 2u;
    int32_t oy;
    int32_t ox;
    for (oy = 0; oy < plan->out_h; oy++) {
        const uint8_t *blk_row = org + (size_t)oy * k * stride;
        uint8_t *d = dst + (size_t)oy * dst_stride;
        for (ox = 0; ox < plan->out_w; ox++) {
            const uint8_t *b = blk_row + (size_t)ox * k * 2u;
            uint32_t sum = 0;
            uint32_t v;
            size_t by;
            size_t bx;
            for (by = 0; by < k; by++) {
                const uint8_t *r = b + by * stride;
                for (bx = 0; bx < k; bx++) {
                    sum += (uint32_t)r[2u * bx] |
                           ((uint32_t)r[2u * bx + 1u] << 8);
                }
            }
            v = ((sum + n / 2u) / n) >> shift;
            d[ox] = (uint8_t)(v > 255u ? 255u : v);
        }
    }
}

/* round(num / den) for den > 0, either sign of num */
static int32_t div_round(int64_t num, int64_t den)
{
    return (int32_t)(num >= 0 ? (num + den / 2) / den
                              : -((-num + den / 2) / den));
}

void negobs_bin_intrinsics_q4(const negobs_bin_plan_t *plan, int32_t *f_q4,
                              int32_t *cx_q4, int32_t *cy_q4)
{
    const int64_t k = plan->k;
    /* (k - 1) / 2 pixels in q4 */
    const int64_t half_q4 = 8 * (k - 1);
    if (f_q4 != NULL) {
        *f_q4 = div_round(*f_q4, k);
    }
    if (cx_q4 != NULL && *cx_q4 >= 0) {
        *cx_q4 = div_round((int64_t)*cx_q4 - 16 * (int64_t)plan->x0 - half_q4,
                           k);
        /* a crop past the principal point: keep it on the image (a
         * negative value would read as "centre") */
        *cx_q4 = *cx_q4 < 0 ? 0 : *cx_q4;
    }
    if (cy_q4 != NULL && *cy_q4 >= 0) {
        *cy_q4 = div_round((int64_t)*cy_q4 - 16 * (int64_t)plan->y0 - half_q4,
                           k);
        *cy_q4 = *cy_q4 < 0 ? 0 : *cy_q4;
    }
}
