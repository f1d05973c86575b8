/*
 * Half-resolution pass for weakly textured floors.
 *
 * The matcher correlates 5x5 windows. On a smooth floor the grain inside
 * such a window is about as strong as the sensor noise, and near the feet,
 * where the floor is magnified most, the true match's correlation falls
 * below the growth threshold: the map there is the DP's guess with a low
 * confidence, which the detector rightly does not use, and the frame has
 * no information. A 2x2 area average halves the noise's amplitude and
 * brings four times the floor into each window, so the same matcher on
 * the half-size pair correlates the true match well above the threshold
 * (docs/DETECTION.md, "Weak texture: the half-resolution pass", gives the
 * figures).
 *
 * The full-resolution map stays the primary one: where its confidence is
 * high enough for the detector and its window holds texture it is kept as
 * it is (twice the resolution, sharper edges). The pixels the detector
 * would not use take the half-size value when that one is confident, and
 * so do confident ones measured in a window without texture (the
 * detector's own texture test, detect_texture.c): there the correlation
 * is high because the window is bland, not because the match is right,
 * and the detector would refuse any deficit read from it; the half-size
 * window, four times the floor with half the noise, holds the texture
 * the full-size one lacks. The pass runs only when the weak pixels are a
 * sizeable share of the rows the detector reads, so a textured floor
 * costs nothing more and gives the same output.
 */
#include "coarse.h"

#include <stddef.h>

#include "detect/detect_int.h"

static int32_t half_up(int32_t v)
{
    return (v + 1) / 2;
}

int pl_coarse_config(const negobs_pipeline_config_t *cfg,
                     negobs_stereo_config_t *out)
{
    const negobs_stereo_config_t *f = &cfg->stereo;
    size_t bytes;
    int32_t tile;
    int32_t off;

    if (!cfg->coarse_pass) {
        return 0;
    }
    *out = *f;
    out->width = f->width / 2;
    out->height = f->height / 2;
    /* the half-size pair's disparities are half the full ones: the range
     * keeps every full-size value (min rounded down, max up) */
    out->min_disp = f->min_disp / 2;
    out->max_disp = half_up(f->max_disp);
    out->range_margin = half_up(f->range_margin);
    tile = ((f->tile_size / 2) / 4) * 4;
    out->tile_size = (tile < 8) ? 8 : tile;
    out->strip_rows = (f->strip_rows / 2 < 8) ? 8 : f->strip_rows / 2;
    out->seed_step = half_up(f->seed_step);
    out->speckle_size = f->speckle_size / 4;
    out->gap_fill = f->gap_fill / 2;
    /* a quarter of the pixels: half the queue is still twice as much per
     * pixel as the full-size matcher has */
    out->queue_capacity = (f->queue_capacity / 2 < 16) ? 16
                                                       : f->queue_capacity / 2;
    /* Memory: the pass runs on weak frames only, and the compact profile
     * gives the same output as the fast one (negobs/stereo.h) in a
     * fraction of the memory, which on a wearable goes to the full-size
     * matcher's threads first. */
    out->memory_profile = NEGOBS_STEREO_PROFILE_COMPACT;
    /* Its disparities are doubled, and the 2x2 averages make a texture's
     * correlation peak half as wide in pixels, so the parabola's pull
     * towards whole pixels, doubled, would ripple the floor by about
     * +-0.1 px with a period of 2 px of disparity (a worn-asphalt floor
     * measured: docs/DISPARITY.md, stage 5): cancel it. */
    out->subpixel_halfshift = 1;
    /* a fixed offset halves like every length; a searched one is held at
     * the full-size result each frame (pipeline.c) */
    off = f->vertical_offset;
    out->vertical_offset = (off >= 0) ? (off + 1) / 2 : -((1 - off) / 2);
    return negobs_stereo_workspace_size(out, &bytes) == NEGOBS_OK;
}

void pl_bin2_u8(const negobs_image_u8_t *src, const negobs_image_u8_t *dst)
{
    int32_t x;
    int32_t y;
    for (y = 0; y < dst->height; y++) {
        const uint8_t *a = negobs_image_u8_row(src, 2 * y);
        const uint8_t *b = negobs_image_u8_row(src, 2 * y + 1);
        uint8_t *o = negobs_image_u8_row(dst, y);
        for (x = 0; x < dst->width; x++) {
            ptrdiff_t x2 = (ptrdiff_t)2 * x;
            uint32_t s = (uint32_t)a[x2] + a[x2 + 1] + b[x2] + b[x2 + 1];
            o[x] = (uint8_t)((s + 2u) >> 2);
        }
    }
}

int32_t pl_weak_permille(const negobs_image_u8_t *conf, int32_t y0, int32_t x0,
                         int32_t min_conf)
{
    uint32_t weak = 0;
    uint32_t n;
    int32_t x;
    int32_t y;
    if (y0 < 0) {
        y0 = 0;
    }
    if (x0 < 0) {
        x0 = 0;
    }
    if (y0 >= conf->height || x0 >= conf->width) {
        return 0;
    }
    n = (uint32_t)(conf->height - y0) * (uint32_t)(conf->width - x0);
    for (y = y0; y < conf->height; y++) {
        const uint8_t *c = negobs_image_u8_row(conf, y);
        for (x = x0; x < conf->width; x++) {
            weak += ((int32_t)c[x] < min_conf) ? 1u : 0u;
        }
    }
    /* n <= 4096 * 4096: weak * 1000 fits 64 bits, not always 32 */
    return (int32_t)(((uint64_t)weak * 1000u) / n);
}

/* Is the full-size window of the 2x2 block whose top-left pixel is (x, y)
 * textured? Its window is centred on that pixel; one test serves the four
 * pixels the half-size pixel covers. Windows that would leave the image
 * count as textured: their values are judged by their confidence alone. */
static int block_textured(const negobs_image_u8_t *left, int32_t noise_med,
                          int32_t x, int32_t y)
{
    if (left == NULL || x < 2 || y < 2 || x > left->width - 3 ||
        y > left->height - 3) {
        return 1;
    }
    return det_window_textured(left, noise_med, x, y);
}

/* A full-size pixel (*d, *c) takes the half-size value (hd, hc) when its
 * own is weak or was measured without texture (textured 0), and the
 * half-size one is confident and in range; returns 1 when it did. */
static inline uint32_t fuse_pixel(int16_t *d, uint8_t *c, int32_t hd,
                                  int32_t hc, int textured, int32_t min_conf,
                                  int32_t dmin_q4, int32_t dmax_q4)
{
    /* the half-size pixel x/2 is centred on full-size x 2(x/2) + 0.5,
     * within half a pixel of x: on a floor whose disparity changes by a
     * fraction of a pixel per row that is noise, not bias */
    const int32_t v = 2 * hd;
    if (((int32_t)*c >= min_conf && textured) || hc < min_conf ||
        hd == NEGOBS_DISP_INVALID || v < dmin_q4 || v > dmax_q4) {
        return 0;
    }
    *d = (int16_t)v;
    *c = (uint8_t)hc;
    return 1;
}

uint32_t pl_coarse_fuse(const negobs_image_u8_t *left,
                        negobs_image_s16_t *disp, negobs_image_u8_t *conf,
                        const negobs_image_s16_t *half_disp,
                        const negobs_image_u8_t *half_conf, int32_t y0,
                        int32_t min_conf, int32_t dmin_q4, int32_t dmax_q4)
{
    uint32_t replaced = 0;
    const int32_t noise_med = (left != NULL) ? det_noise_median(left) : 0;
    int32_t y1 = 2 * half_disp->height;
    int32_t x1 = 2 * half_disp->width;
    int32_t bx;
    int32_t by;
    if (y0 < 0) {
        y0 = 0;
    }
    y1 = (y1 < disp->height) ? y1 : disp->height;
    x1 = (x1 < disp->width) ? x1 : disp->width;
    for (by = y0 / 2; 2 * by < y1; by++) {
        const int16_t *hd = negobs_image_s16_row(half_disp, by);
        const uint8_t *hc = negobs_image_u8_row(half_conf, by);
        for (bx = 0; 2 * bx < x1; bx++) {
            int textured = -1; /* tested only when a pixel needs it */
            int32_t k;
            if (hc[bx] < min_conf || hd[bx] == NEGOBS_DISP_INVALID) {
                continue;
            }
            for (k = 0; k < 4; k++) {
                const int32_t x = 2 * bx + (k & 1);
                const int32_t y = 2 * by + (k >> 1);
                uint8_t *c;
                if (x >= x1 || y < y0 || y >= y1) {
                    continue;
                }
                c = negobs_image_u8_row(conf, y) + x;
                if ((int32_t)*c >= min_conf && textured < 0) {
                    textured = block_textured(left, noise_med, 2 * bx, 2 * by);
                }
                replaced += fuse_pixel(negobs_image_s16_row(disp, y) + x, c,
                                       hd[bx], hc[bx], textured != 0, min_conf,
                                       dmin_q4, dmax_q4);
            }
        }
    }
    return replaced;
}
