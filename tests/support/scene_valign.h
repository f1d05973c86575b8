/*
 * Generated pairs with an exact, known vertical misalignment (integer only).
 *
 * A smooth texture (uniform noise, two 3x3 box passes) is the scene. The
 * left image samples it on the pixel grid; the right one samples it at
 * (x + d(y), y - off(x, y)) with bilinear weights in 1/256 px, so left row
 * y matches right row y + off (the convention of negobs/valign.h) and left
 * column x matches right column x - d. d grows from d_top to d_bottom
 * down the frame, like a floor seen by a wearable camera.
 */
#ifndef NEGOBS_TEST_SCENE_VALIGN_H
#define NEGOBS_TEST_SCENE_VALIGN_H

#include <stdint.h>
#include <string.h>

#include "test_rng.h"

#define GEN_W 320
#define GEN_H 240
#define GEN_PAD 16
#define GEN_TW (GEN_W + 2 * GEN_PAD + 64)
#define GEN_TH (GEN_H + 2 * GEN_PAD)

typedef struct gen_model {
    int32_t off_q16;     /* at (w/2, h/2)                       */
    int32_t slope_y_q16; /* per row                              */
    int32_t slope_x_q16; /* per column                           */
} gen_model_t;

static uint8_t gen_tex[GEN_TH][GEN_TW];

static inline void gen_texture(uint32_t seed)
{
    static uint16_t a[GEN_TH][GEN_TW];
    static uint16_t b[GEN_TH][GEN_TW];
    int32_t x;
    int32_t y;
    int32_t pass;
    for (y = 0; y < GEN_TH; y++) {
        for (x = 0; x < GEN_TW; x++) {
            a[y][x] = (uint16_t)(test_lcg_next(&seed) >> 16);
        }
    }
    for (pass = 0; pass < 2; pass++) {
        for (y = 0; y < GEN_TH; y++) {
            for (x = 0; x < GEN_TW; x++) {
                int32_t s = 0;
                int32_t j;
                int32_t i;
                for (j = -1; j <= 1; j++) {
                    for (i = -1; i <= 1; i++) {
                        int32_t yy = y + j < 0 ? 0
                                               : (y + j >= GEN_TH ? GEN_TH - 1
                                                                  : y + j);
                        int32_t xx = x + i < 0 ? 0
                                               : (x + i >= GEN_TW ? GEN_TW - 1
                                                                  : x + i);
                        s += a[yy][xx];
                    }
                }
                b[y][x] = (uint16_t)((s + 4) / 9);
            }
        }
        memcpy(a, b, sizeof a);
    }
    /* stretch the contrast the boxes took away: mean 128, x3 */
    for (y = 0; y < GEN_TH; y++) {
        for (x = 0; x < GEN_TW; x++) {
            int32_t v = 128 + 3 * ((int32_t)a[y][x] - 128);
            gen_tex[y][x] = (uint8_t)(v < 0 ? 0 : (v > 255 ? 255 : v));
        }
    }
}

/*
 * Paving-like texture: faint noise crossed by dark joints of slope 1/8,
 * 12 rows apart, and steep cross joints. On such lines a vertical misalignment of v rows moves the
 * best horizontal match by 8 v columns: the failure seen on real paving.
 */
static inline void gen_texture_joints(uint32_t seed)
{
    int32_t x;
    int32_t y;
    for (y = 0; y < GEN_TH; y++) {
        for (x = 0; x < GEN_TW; x++) {
            int32_t m = (8 * y - x) % 96;
            int32_t dist;
            int32_t v;
            m = m < 0 ? m + 96 : m;
            dist = m < 48 ? m : 96 - m; /* 8 units = 1 row */
            v = 150 + (int32_t)(test_lcg_next(&seed) >> 21) - 4;
            if (dist < 12) {
                v -= 70 * (12 - dist) / 12;
            }
            /* the cross joints of the slabs, steep (slope -3), 40 columns
             * apart: they pin the horizontal match the flat ones cannot */
            m = (3 * x + y) % 120;
            dist = m < 60 ? m : 120 - m;
            if (dist < 4) {
                v -= 50 * (4 - dist) / 4;
            }
            v = v < 0 ? 0 : v;
            gen_tex[y][x] = (uint8_t)v;
        }
    }
}

/* Bilinear sample of the texture at image (x, y_q8 / 256), x integer. */
static inline uint8_t gen_sample(int32_t x, int32_t y_q8)
{
    int32_t yt = y_q8 + GEN_PAD * 256;
    int32_t y0 = yt / 256;
    int32_t f = yt - 256 * y0;
    int32_t xt = x + GEN_PAD;
    int32_t v;
    if (y0 < 0) {
        y0 = 0;
        f = 0;
    }
    if (y0 >= GEN_TH - 1) {
        y0 = GEN_TH - 2;
        f = 256;
    }
    v = gen_tex[y0][xt] * (256 - f) + gen_tex[y0 + 1][xt] * f;
    return (uint8_t)((v + 128) / 256);
}

static inline int32_t gen_disp(int32_t y, int32_t d_top, int32_t d_bottom)
{
    return d_top + (d_bottom - d_top) * y / (GEN_H - 1);
}

/* left, right: GEN_W x GEN_H, stride GEN_W. */
static inline void gen_pair(const gen_model_t *m, int32_t d_top,
                            int32_t d_bottom, uint8_t *left, uint8_t *right)
{
    int32_t x;
    int32_t y;
    for (y = 0; y < GEN_H; y++) {
        int32_t d = gen_disp(y, d_top, d_bottom);
        for (x = 0; x < GEN_W; x++) {
            /* off at the right pixel, Q16 -> Q8 */
            int32_t off_q16 = m->off_q16 + m->slope_y_q16 * (y - GEN_H / 2) +
                              m->slope_x_q16 * (x - GEN_W / 2);
            int32_t off_q8 = (off_q16 >= 0) ? (off_q16 + 128) / 256
                                            : -((-off_q16 + 128) / 256);
            left[y * GEN_W + x] = gen_sample(x, y * 256);
            right[y * GEN_W + x] = gen_sample(x + d, y * 256 - off_q8);
        }
    }
}

#endif /* NEGOBS_TEST_SCENE_VALIGN_H */
