/*
 * Integer Canny edge detector on the left image, used to place seeds.
 *
 * Sobel gradients gx, gy (|g| <= 1020 each), L1 magnitude |gx| + |gy|
 * (<= 2040, uint16), non-maximum suppression along the gradient direction
 * quantised to 4 sectors with the integer slope test
 * |gy| * 1000 < |gx| * 414 (tan 22.5 deg = 0.4142), then two thresholds
 * and hysteresis. Hysteresis is bounded: weak pixels are promoted when an
 * 8-neighbour is strong, in one forward and one backward raster pass over
 * the strip (no stack, no recursion); chains longer than that are cut,
 * which only costs a few seeds.
 */
#include <string.h>

#include "stereo/stereo_int.h"

static void sobel(const negobs_image_u8_t *img, int32_t x, int32_t y,
                  int32_t *gx, int32_t *gy)
{
    const uint8_t *a = negobs_image_u8_row(img, y - 1) + x;
    const uint8_t *b = negobs_image_u8_row(img, y) + x;
    const uint8_t *c = negobs_image_u8_row(img, y + 1) + x;
    *gx = ((int32_t)a[1] + 2 * (int32_t)b[1] + (int32_t)c[1]) -
          ((int32_t)a[-1] + 2 * (int32_t)b[-1] + (int32_t)c[-1]);
    *gy = ((int32_t)c[-1] + 2 * (int32_t)c[0] + (int32_t)c[1]) -
          ((int32_t)a[-1] + 2 * (int32_t)a[0] + (int32_t)a[1]);
}

uint32_t stx_canny_strip(stx_t *s, int32_t y0, int32_t y1)
{
    const negobs_image_u8_t *img = s->left;
    int32_t w = s->w;
    int32_t n = y1 - y0;
    int32_t lo = s->cfg.canny_low;
    int32_t hi = s->cfg.canny_high;
    int32_t r;
    int32_t x;
    uint32_t count = 0;

    /* magnitude rows y0-1 .. y1 (index r+1 holds row y0+r) */
    for (r = -1; r <= n; r++) {
        int32_t y = y0 + r;
        uint16_t *m = s->mag + (ptrdiff_t)(r + 1) * w;
        memset(m, 0, (size_t)w * sizeof *m);
        if (y < 1 || y >= s->h - 1) {
            continue;
        }
        for (x = 1; x < w - 1; x++) {
            int32_t gx;
            int32_t gy;
            sobel(img, x, y, &gx, &gy);
            m[x] = (uint16_t)(negobs_abs_s32(gx) + negobs_abs_s32(gy));
        }
    }
    memset(s->edge, 0, (size_t)n * (size_t)w);
    for (r = 0; r < n; r++) {
        int32_t y = y0 + r;
        const uint16_t *mu = s->mag + (ptrdiff_t)r * w;
        const uint16_t *mc = mu + w;
        const uint16_t *md = mc + w;
        uint8_t *e = s->edge + (ptrdiff_t)r * w;
        if (y < 1 || y >= s->h - 1) {
            continue;
        }
        for (x = 1; x < w - 1; x++) {
            int32_t m = mc[x];
            int32_t gx;
            int32_t gy;
            int32_t ax;
            int32_t ay;
            int32_t n1;
            int32_t n2;
            if (m < lo) {
                continue;
            }
            sobel(img, x, y, &gx, &gy);
            ax = negobs_abs_s32(gx);
            ay = negobs_abs_s32(gy);
            if (ay * 1000 < ax * 414) {
                n1 = mc[x - 1];
                n2 = mc[x + 1];
            } else if (ay * 414 > ax * 1000) {
                n1 = mu[x];
                n2 = md[x];
            } else if ((gx > 0) == (gy > 0)) {
                n1 = mu[x - 1];
                n2 = md[x + 1];
            } else {
                n1 = mu[x + 1];
                n2 = md[x - 1];
            }
            /* ties: keep the first along the direction (>= / >) */
            if (m >= n1 && m > n2) {
                e[x] = (uint8_t)((m >= hi) ? 2u : 1u);
            }
        }
    }
    /* hysteresis: forward then backward pass */
    {
        int pass;
        for (pass = 0; pass < 2; pass++) {
            int32_t i;
            int32_t total = n * w;
            for (i = 0; i < total; i++) {
                int32_t p = pass ? total - 1 - i : i;
                int32_t py = p / w;
                int32_t px = p - py * w;
                int32_t dy;
                if (s->edge[p] != 1u) {
                    continue;
                }
                for (dy = -1; dy <= 1; dy++) {
                    int32_t dx;
                    if (py + dy < 0 || py + dy >= n) {
                        continue;
                    }
                    for (dx = -1; dx <= 1; dx++) {
                        if (px + dx < 0 || px + dx >= w) {
                            continue;
                        }
                        if (s->edge[p + dy * w + dx] == 2u) {
                            s->edge[p] = 2u;
                        }
                    }
                }
            }
        }
        for (r = 0; r < n * w; r++) {
            if (s->edge[r] == 2u) {
                s->edge[r] = 1u;
                count++;
            } else {
                s->edge[r] = 0u;
            }
        }
    }
    return count;
}
