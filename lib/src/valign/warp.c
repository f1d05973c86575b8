/*
 * Vertical resampling of the right image by a misalignment model.
 *
 * Fixed point: the model is evaluated in Q16 (|offset| <= 64 px = 2^22,
 * |slope| <= 2^10 times |coordinate| <= 2^12 = 2^22: the sum stays below
 * 2^24), rounded half-up to 1/16 px, and split into a whole row k (floor)
 * and a weight f in 0..15. The blend r0 * (16 - f) + r1 * f is at most
 * 255 * 16, rounded half-up back to 8 bits.
 */
#include "negobs/valign.h"

#include <string.h>

#include "negobs/fixed.h"
#include "valign_int.h"

/* floor(a / 16) for any sign, without relying on >> of negatives. */
static inline int32_t floor_div16(int32_t a)
{
    return (a >= 0) ? a / 16 : -((15 - a) / 16);
}

/* The two source rows and the weight of an offset of q4/16 rows at row y
 * (rows clamped to the image). */
static inline void row_pair(const negobs_image_u8_t *right, int32_t y,
                            int32_t q4, const uint8_t **r0, const uint8_t **r1,
                            int32_t *f)
{
    int32_t k = floor_div16(q4);
    int32_t h = right->height;
    *f = q4 - 16 * k;
    *r0 = negobs_image_u8_row(right, negobs_clamp_s32(y + k, 0, h - 1));
    *r1 = negobs_image_u8_row(right, negobs_clamp_s32(y + k + 1, 0, h - 1));
}

static inline uint8_t blend(const uint8_t *r0, const uint8_t *r1, int32_t x,
                            int32_t f)
{
    return (uint8_t)(((uint32_t)r0[x] * (uint32_t)(16 - f) +
                      (uint32_t)r1[x] * (uint32_t)f + 8u) >>
                     4);
}

static int overlaps(const negobs_image_u8_t *a, const negobs_image_u8_t *b)
{
    const uint8_t *a0 = a->data;
    const uint8_t *a1 = a->data + (size_t)(a->height - 1) * (size_t)a->stride +
                        (size_t)a->width;
    const uint8_t *b0 = b->data;
    const uint8_t *b1 = b->data + (size_t)(b->height - 1) * (size_t)b->stride +
                        (size_t)b->width;
    return a0 < b1 && b0 < a1;
}

int valign_model_ok(const negobs_valign_model_t *m)
{
    return m != NULL &&
           negobs_abs_s32(m->offset_q16) <= VALIGN_OFFSET_LIMIT_Q16 &&
           negobs_abs_s32(m->slope_y_q16) <= NEGOBS_VALIGN_SLOPE_LIMIT_Q16 &&
           negobs_abs_s32(m->slope_x_q16) <= NEGOBS_VALIGN_SLOPE_LIMIT_Q16;
}

negobs_status_t negobs_valign_warp(const negobs_valign_model_t *model,
                                   const negobs_image_u8_t *right,
                                   negobs_image_u8_t *out)
{
    int32_t w;
    int32_t h;
    int32_t y;

    if (!valign_model_ok(model) || negobs_image_u8_check(right) != NEGOBS_OK ||
        negobs_image_u8_check(out) != NEGOBS_OK ||
        right->width != out->width || right->height != out->height ||
        overlaps(right, out)) {
        return NEGOBS_ERR_INVAL;
    }
    w = right->width;
    h = right->height;
    for (y = 0; y < h; y++) {
        uint8_t *dst = negobs_image_u8_row(out, y);
        /* Q16 offset at column 0 of this row */
        int32_t base = model->offset_q16 + model->slope_y_q16 * (y - h / 2) -
                       model->slope_x_q16 * (w / 2);
        int32_t x;
        if (model->slope_x_q16 == 0) {
            const uint8_t *r0;
            const uint8_t *r1;
            int32_t f;
            row_pair(right, y, negobs_rshift_round_s32(base, 12), &r0, &r1,
                     &f);
            if (f == 0) {
                memcpy(dst, r0, (size_t)w);
                continue;
            }
            for (x = 0; x < w; x++) {
                dst[x] = blend(r0, r1, x, f);
            }
            continue;
        }
        /* The Q16 offset grows by slope_x per column; the Q4 value (and
         * with it the two source rows and the weight) only changes when
         * the offset leaves [q4 * 4096 - 2048, q4 * 4096 + 2048), so it is
         * recomputed at those crossings only. Same result as rounding at
         * every pixel. */
        {
            int32_t o = base;
            int32_t q4 = negobs_rshift_round_s32(o, 12);
            int32_t lo = q4 * 4096 - 2048;
            const uint8_t *r0;
            const uint8_t *r1;
            int32_t f;
            row_pair(right, y, q4, &r0, &r1, &f);
            for (x = 0; x < w; x++) {
                if (o < lo || o >= lo + 4096) {
                    q4 = negobs_rshift_round_s32(o, 12);
                    lo = q4 * 4096 - 2048;
                    row_pair(right, y, q4, &r0, &r1, &f);
                }
                dst[x] = blend(r0, r1, x, f);
                o += model->slope_x_q16;
            }
        }
    }
    return NEGOBS_OK;
}
