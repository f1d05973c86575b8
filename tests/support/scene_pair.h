/*
 * Generated stereo pairs with exact ground truth (integer only, so the same
 * bytes come out on every target; the digest uses them too).
 *
 * Scene, in left-image coordinates, disparity in 1/256 px:
 *   - a slanted ground plane: d grows linearly from d_top at row 0 to
 *     d_bottom at the last row (like a floor seen by a wearable camera);
 *   - a drop-off: in the lower right quarter the ground is `drop` px
 *     farther (a negative obstacle: a step down);
 *   - a fronto-parallel box at disparity `box` in the upper left.
 * Texture: uniform noise smoothed by [1 2 1] in x and y. The right image is
 * rendered by forward-warping each left row (linear interpolation of the
 * texture between neighbouring left pixels, nearest surface wins), then
 * shifted down by `voff` rows: left row y is right row y + voff.
 */
#ifndef NEGOBS_TEST_SCENE_PAIR_H
#define NEGOBS_TEST_SCENE_PAIR_H

#include <stdint.h>
#include <string.h>

#include "test_rng.h"

#define SYNTH_MAX_W 400
#define SYNTH_MAX_H 300

typedef struct synth_scene {
    int32_t w, h;
    int32_t d_top_q8, d_bottom_q8;
    int32_t drop_q8; /* subtracted in the lower right quarter          */
    int32_t box_q8;  /* box disparity (0 = no box)                     */
    int32_t voff;    /* right row = left row + voff                    */
    uint32_t seed;
} synth_scene_t;

static inline int32_t synth_disp_q8(const synth_scene_t *sc, int32_t x,
                                    int32_t y)
{
    int32_t d = sc->d_top_q8 +
                (sc->d_bottom_q8 - sc->d_top_q8) * y / (sc->h - 1);
    if (x >= sc->w / 2 && y >= sc->h / 2) {
        d -= sc->drop_q8;
    }
    if (sc->box_q8 > 0 && x >= sc->w / 8 && x < sc->w / 8 + sc->w / 4 &&
        y >= sc->h / 8 && y < sc->h / 8 + sc->h / 4) {
        d = sc->box_q8;
    }
    return d;
}

/*
 * Fill left, right (stride w) and gt_q4 (disparity * 16, rounded) and the
 * occlusion mask occ (1 = not visible in the right image).
 * tex is scratch of w*h bytes.
 *
 * fine_rows > 0 makes the texture of the bottom fine_rows rows (rounded
 * down to whole 4x4 blocks of the left image) zero-mean in every 4x4
 * block: as textured as elsewhere at full resolution, flat at 1/4 scale
 * (a smooth floor whose grain only shows up close).
 */
static inline void synth_render_fine(const synth_scene_t *sc,
                                     int32_t fine_rows, uint8_t *left,
                                     uint8_t *right, int16_t *gt_q4,
                                     uint8_t *occ, uint8_t *tex)
{
    int32_t w = sc->w;
    int32_t h = sc->h;
    int32_t x;
    int32_t y;
    uint32_t s = sc->seed;
    static uint8_t raw[SYNTH_MAX_W * SYNTH_MAX_H];
    static int32_t zbuf[SYNTH_MAX_W];
    static uint8_t rrow[SYNTH_MAX_H][SYNTH_MAX_W];

    for (y = 0; y < h; y++) {
        for (x = 0; x < w; x++) {
            raw[y * w + x] = (uint8_t)(test_lcg_next(&s) & 0xFFu);
        }
    }
    for (y = 0; y < h; y++) {
        for (x = 0; x < w; x++) {
            int32_t acc = 0;
            int32_t k;
            int32_t j;
            for (k = -1; k <= 1; k++) {
                for (j = -1; j <= 1; j++) {
                    int32_t yy = y + k;
                    int32_t xx = x + j;
                    int32_t wt = (2 - (k < 0 ? -k : k)) *
                                 (2 - (j < 0 ? -j : j));
                    yy = (yy < 0) ? 0 : ((yy >= h) ? h - 1 : yy);
                    xx = (xx < 0) ? 0 : ((xx >= w) ? w - 1 : xx);
                    acc += wt * raw[yy * w + xx];
                }
            }
            tex[y * w + x] = (uint8_t)((acc + 8) / 16);
        }
    }
    if (fine_rows > 0) {
        int32_t bx;
        int32_t by;
        int32_t y0 = ((h - fine_rows + 3) / 4) * 4;
        for (by = y0; by + 4 <= h; by += 4) {
            for (bx = 0; bx + 4 <= w; bx += 4) {
                int32_t sum = 0;
                int32_t k;
                for (k = 0; k < 16; k++) {
                    sum += tex[(by + k / 4) * w + bx + k % 4];
                }
                for (k = 0; k < 16; k++) {
                    uint8_t *t = &tex[(by + k / 4) * w + bx + k % 4];
                    int32_t v = 128 + 2 * (16 * (int32_t)*t - sum) / 16;
                    *t = (uint8_t)((v < 0) ? 0 : ((v > 255) ? 255 : v));
                }
            }
        }
    }
    memcpy(left, tex, (size_t)w * (size_t)h);
    for (y = 0; y < h; y++) {
        for (x = 0; x < w; x++) {
            int32_t d = synth_disp_q8(sc, x, y);
            gt_q4[y * w + x] = (int16_t)((d + 8) >> 4);
        }
        /* forward warp: right pixel xr sees left position x + t where
         * f(x) = 256 x - d(x) brackets 256 xr; nearest surface wins */
        for (x = 0; x < w; x++) {
            zbuf[x] = -1;
            /* unseen by the left camera: unrelated texture */
            rrow[y][x] = tex[((y + h / 2) % h) * w + (w - 1 - x)];
        }
        for (x = 0; x + 1 < w; x++) {
            int32_t d0 = synth_disp_q8(sc, x, y);
            int32_t d1 = synth_disp_q8(sc, x + 1, y);
            int32_t f0 = 256 * x - d0;
            int32_t f1 = 256 * (x + 1) - d1;
            int32_t xr;
            if (f1 <= f0) {
                continue; /* folded: hidden span */
            }
            for (xr = (f0 + 255) / 256; 256 * xr < f1; xr++) {
                int32_t t;
                int32_t dz;
                int32_t v;
                if (xr < 0 || xr >= w || 256 * xr < f0) {
                    continue;
                }
                t = ((256 * xr - f0) * 256) / (f1 - f0); /* Q8 in [0,1) */
                dz = d0 + ((d1 - d0) * t) / 256;
                if (dz <= zbuf[xr]) {
                    continue;
                }
                zbuf[xr] = dz;
                v = (tex[y * w + x] * (256 - t) + tex[y * w + x + 1] * t +
                     128) /
                    256;
                rrow[y][xr] = (uint8_t)v;
            }
        }
        for (x = 0; x < w; x++) {
            int32_t d = synth_disp_q8(sc, x, y);
            int32_t f = 256 * x - d + 128;
            int32_t xr = (f >= 0) ? f / 256 : -1;
            occ[y * w + x] = (uint8_t)(xr < 0 || xr >= w ||
                                       zbuf[xr] > d + 128);
        }
    }
    for (y = 0; y < h; y++) {
        int32_t src = y - sc->voff;
        if (src < 0 || src >= h) {
            for (x = 0; x < w; x++) {
                right[y * w + x] = (uint8_t)(test_lcg_next(&s) & 0xFFu);
            }
        } else {
            memcpy(right + y * w, rrow[src], (size_t)w);
        }
    }
}

static inline void synth_render(const synth_scene_t *sc, uint8_t *left,
                                uint8_t *right, int16_t *gt_q4, uint8_t *occ,
                                uint8_t *tex)
{
    synth_render_fine(sc, 0, left, right, gt_q4, occ, tex);
}

/* bad-pixel share (x1000) and density (x1000) over visible pixels inside a
 * margin; err_q4 is the bad threshold in 1/16 px. */
static inline void synth_score(const synth_scene_t *sc, const int16_t *disp,
                               const int16_t *gt, const uint8_t *occ,
                               int32_t margin, int32_t err_q4,
                               int32_t *bad_permille, int32_t *dens_permille)
{
    int32_t x;
    int32_t y;
    int32_t n = 0;
    int32_t nv = 0;
    int32_t bad = 0;
    for (y = margin; y < sc->h - margin; y++) {
        for (x = margin; x < sc->w - margin; x++) {
            int32_t i = y * sc->w + x;
            int32_t e;
            if (occ[i] || x - gt[i] / 16 < margin) {
                continue;
            }
            n++;
            if (disp[i] == INT16_MIN) {
                continue;
            }
            nv++;
            e = disp[i] - gt[i];
            if (e > err_q4 || e < -err_q4) {
                bad++;
            }
        }
    }
    *bad_permille = (nv > 0) ? (int32_t)((int64_t)bad * 1000 / nv) : 1000;
    *dens_permille = (n > 0) ? (int32_t)((int64_t)nv * 1000 / n) : 0;
}

#endif /* NEGOBS_TEST_SCENE_PAIR_H */
