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

#include "canny_core.h"
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

/* The strong threshold's floor: a step of one grey level gives an L1
 * Sobel magnitude of 4, so 16 is four levels across the 3x3 window; below
 * it a "strongest share" of a flat strip would be quantisation alone. */
#define CANNY_HIGH_FLOOR 16
/* Histogram bins below canny_high (at most; bins are a power of two wide) */
#define CANNY_BINS 64

/*
 * The strip's strong threshold: canny_high, or less when fewer than
 * canny_top_permille of its pixels reach it. On a low-contrast floor (an
 * underexposed camera, smooth concrete whose grain fades with distance)
 * no gradient reaches a threshold set for textured scenes, and a strip
 * without edges has no seed: its matches can only come from a
 * neighbour's growth. The seeds there are still held to seed_tau_q14 and
 * seed_margin_q14, which is what makes a seed trustworthy; the edge only
 * places it. The share is taken per strip (its own contrast: the far
 * floor's grain is weaker than the near floor's) over the strip's
 * magnitude rows 1..n (rows 0 and n+1 are the neighbours' borders), to
 * the lower edge of the histogram bin that reaches it. Textured strips,
 * where the share reaches canny_high, keep the fixed thresholds exactly.
 */
static int32_t strip_high(const stx_t *s, int32_t y0, int32_t n,
                          uint32_t strong, uint32_t total)
{
    const int32_t high = s->cfg.canny_high;
    const int32_t w = s->w;
    uint32_t hist[CANNY_BINS + 2];
    uint32_t need;
    uint32_t acc = 0;
    int32_t shift = 0;
    int32_t top;
    int32_t b;
    int32_t r;
    int32_t x;
    /* total <= 255 x 4096 rows x columns: x 1000 fits 32 bits */
    need = (total * (uint32_t)s->cfg.canny_top_permille + 999u) / 1000u;
    /* the usual case, a textured strip: no histogram */
    if (s->cfg.canny_top_permille <= 0 || high <= CANNY_HIGH_FLOOR ||
        total == 0u || strong >= need) {
        return high;
    }
    while ((high >> shift) > CANNY_BINS) {
        shift++;
    }
    top = (high >> shift) + 1; /* the bin of magnitudes >= high */
    memset(hist, 0, sizeof hist);
    for (r = 0; r < n; r++) {
        const uint16_t *m = s->mag + (ptrdiff_t)(r + 1) * w;
        int32_t y = y0 + r;
        if (y < 1 || y >= s->h - 1) {
            continue;
        }
        for (x = 1; x < w - 1; x++) {
            int32_t v = m[x];
            hist[(v >= high) ? top : (v >> shift)]++;
        }
    }
    for (b = top; b >= 0; b--) {
        acc += hist[b];
        if (acc >= need) {
            break;
        }
    }
    if (b >= top) {
        return high;
    }
    b = (b < 0) ? 0 : b;
    return ((b << shift) > CANNY_HIGH_FLOOR) ? (b << shift) : CANNY_HIGH_FLOOR;
}

uint32_t stx_canny_strip(stx_t *s, int32_t y0, int32_t y1)
{
    const negobs_image_u8_t *img = s->left;
    int32_t w = s->w;
    int32_t n = y1 - y0;
    int32_t lo;
    int32_t hi;
    int32_t r;
    int32_t x;
    uint32_t count = 0;
    uint32_t strong = 0; /* the strip's own rows' magnitudes >= canny_high */
    uint32_t total = 0;

    /* magnitude rows y0-1 .. y1 (index r+1 holds row y0+r) */
    for (r = -1; r <= n; r++) {
        int32_t y = y0 + r;
        uint16_t *m = s->mag + (ptrdiff_t)(r + 1) * w;
        const int own = r >= 0 && r < n;
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
        if (own) {
            const int32_t high = s->cfg.canny_high;
            for (x = 1; x < w - 1; x++) {
                strong += (m[x] >= high) ? 1u : 0u;
            }
            total += (uint32_t)(w - 2);
        }
    }
    hi = strip_high(s, y0, n, strong, total);
    /* the weak threshold in proportion; exactly canny_low at canny_high */
    lo = (hi == s->cfg.canny_high)
             ? s->cfg.canny_low
             : (int32_t)(((int64_t)hi * s->cfg.canny_low) /
                         (s->cfg.canny_high > 0 ? s->cfg.canny_high : 1));
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
            if (m < lo) {
                continue;
            }
            sobel(img, x, y, &gx, &gy);
            if (canny_nms_keep(m, gx, gy, mu, mc, md, x)) {
                e[x] = (uint8_t)((m >= hi) ? 2u : 1u);
            }
        }
    }
    /* hysteresis: one forward and one backward sweep */
    (void)canny_hyst_sweep(s->edge, n, w, 0);
    (void)canny_hyst_sweep(s->edge, n, w, 1);
    for (r = 0; r < n * w; r++) {
        if (s->edge[r] == 2u) {
            s->edge[r] = 1u;
            count++;
        } else {
            s->edge[r] = 0u;
        }
    }
    return count;
}
