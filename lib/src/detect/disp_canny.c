/*
 * Canny on the disparity map, computed in a small window around each
 * hazard's edge row instead of over the frame: the cue is only read there,
 * and the window keeps the scratch at a few rows of the image width.
 */
#include "disp_canny.h"

#include "canny_core.h"
#include "negobs/fixed.h"

/* Passes of forward + backward raster sweeps for the hysteresis. One pair
 * follows any chain that is monotone in raster order; each further pair
 * one more turn of a winding chain. */
#define DCANNY_HYST_PASSES 8

size_t dcanny_mag_bytes(int32_t width)
{
    return (size_t)3 * (size_t)width * sizeof(uint16_t);
}

size_t dcanny_label_bytes(int32_t width)
{
    return (size_t)DCANNY_WIN_ROWS * (size_t)width;
}

/* Sobel gradients of disp_q4 at (u, v); 0 when the 3x3 neighbourhood holds
 * an invalid pixel. |gx|, |gy| <= 4 * 65535, so int32 holds them. */
static int sobel_q4(const negobs_image_s16_t *d, int32_t u, int32_t v,
                    int32_t *gx, int32_t *gy)
{
    const int16_t *r0 = negobs_image_s16_row(d, v - 1);
    const int16_t *r1 = negobs_image_s16_row(d, v);
    const int16_t *r2 = negobs_image_s16_row(d, v + 1);
    int32_t i;
    for (i = -1; i <= 1; i++) {
        if (r0[u + i] == NEGOBS_DISP_INVALID ||
            r1[u + i] == NEGOBS_DISP_INVALID ||
            r2[u + i] == NEGOBS_DISP_INVALID) {
            return 0;
        }
    }
    *gx = ((int32_t)r0[u + 1] + 2 * (int32_t)r1[u + 1] + (int32_t)r2[u + 1]) -
          ((int32_t)r0[u - 1] + 2 * (int32_t)r1[u - 1] + (int32_t)r2[u - 1]);
    *gy = ((int32_t)r2[u - 1] + 2 * (int32_t)r2[u] + (int32_t)r2[u + 1]) -
          ((int32_t)r0[u - 1] + 2 * (int32_t)r0[u] + (int32_t)r0[u + 1]);
    return 1;
}

/* L1 Sobel magnitude at (u, v), 1 <= u < width - 1, 1 <= v < height - 1;
 * 0 near an invalid pixel, saturated at 65535. */
static int32_t dcanny_grad(const negobs_image_s16_t *d, int32_t u, int32_t v)
{
    int32_t gx;
    int32_t gy;
    int32_t m;
    if (!sobel_q4(d, u, v, &gx, &gy)) {
        return 0;
    }
    m = negobs_abs_s32(gx) + negobs_abs_s32(gy);
    return (m > 65535) ? 65535 : m;
}

int32_t dcanny_band_max(const negobs_image_s16_t *d, int32_t v_top)
{
    int32_t gmax = 0;
    int32_t u;
    int32_t v;
    for (v = (v_top < 1) ? 1 : v_top; v < d->height - 1; v += 2) {
        for (u = 1; u < d->width - 1; u += 2) {
            int32_t g = dcanny_grad(d, u, v);
            if (g > gmax) {
                gmax = g;
            }
        }
    }
    return gmax;
}

/* Magnitudes of row v, columns c0 .. c0 + n - 1, 0 outside the image. */
static void mag_row(const negobs_image_s16_t *d, int32_t v, int32_t c0,
                    int32_t n, uint16_t *out)
{
    int32_t c;
    for (c = 0; c < n; c++) {
        int32_t u = c0 + c;
        out[c] = (v >= 1 && v < d->height - 1 && u >= 1 && u < d->width - 1)
                     ? (uint16_t)dcanny_grad(d, u, v)
                     : 0u;
    }
}

int32_t dcanny_support(const negobs_image_s16_t *d, int32_t gmax,
                       int32_t high_permille, int32_t low_permille, int32_t u0,
                       int32_t u1, int32_t edge_v, const dcanny_scratch_t *sc)
{
    int32_t hi = (int32_t)(((int64_t)gmax * high_permille) / 1000);
    int32_t lo = (int32_t)(((int64_t)hi * low_permille) / 1000);
    int32_t wr0;
    int32_t wr1;
    int32_t wc0;
    int32_t wc1;
    int32_t nr;
    int32_t nc;
    int32_t ms;
    int32_t r;
    int32_t c;
    int32_t pass;
    int32_t count = 0;

    if (hi < 1 || d->width < 3 || d->height < 3 || d->width > sc->width) {
        return 0;
    }
    if (lo < 1) {
        lo = 1; /* a zero magnitude (flat or next to a hole) is no edge */
    }
    /* window, inside the rows and columns where Sobel is defined */
    wr0 = negobs_clamp_s32(edge_v - DCANNY_ROWS_ABOVE - DCANNY_MARGIN, 1,
                           d->height - 2);
    wr1 = negobs_clamp_s32(edge_v + DCANNY_ROWS_BELOW + DCANNY_MARGIN, 1,
                           d->height - 2);
    wc0 = negobs_clamp_s32(u0 - DCANNY_MARGIN, 1, d->width - 2);
    wc1 = negobs_clamp_s32(u1 + DCANNY_MARGIN, 1, d->width - 2);
    if (wr0 > wr1 || wc0 > wc1 || u0 > u1) {
        return 0;
    }
    nr = wr1 - wr0 + 1;
    nc = wc1 - wc0 + 1;
    ms = nc + 2;

    /* magnitudes of three rows at a time: ring slot k holds window row
     * r - 1 + k (mod 3), with a one-pixel ring of columns for the NMS */
    for (r = 0; r < 2; r++) {
        mag_row(d, wr0 - 1 + r, wc0 - 1, ms, sc->mag + (ptrdiff_t)r * ms);
    }
    for (r = 0; r < nr; r++) {
        uint16_t *next = sc->mag + (ptrdiff_t)((r + 2) % 3) * ms;
        const uint16_t *mu = sc->mag + (ptrdiff_t)(r % 3) * ms + 1;
        const uint16_t *mc = sc->mag + (ptrdiff_t)((r + 1) % 3) * ms + 1;
        const uint16_t *md = next + 1;
        uint8_t *lab = sc->label + (ptrdiff_t)r * nc;
        mag_row(d, wr0 + r + 1, wc0 - 1, ms, next);
        for (c = 0; c < nc; c++) {
            int32_t m = mc[c];
            int32_t gx = 0;
            int32_t gy = 0;
            lab[c] = 0u;
            if (m < lo || !sobel_q4(d, wc0 + c, wr0 + r, &gx, &gy)) {
                continue;
            }
            /* |gx|, |gy| <= 4 * 65535 < 2^21 */
            if (canny_nms_keep(m, gx, gy, mu, mc, md, c)) {
                lab[c] = (uint8_t)((m >= hi) ? 2u : 1u);
            }
        }
    }

    for (pass = 0; pass < DCANNY_HYST_PASSES; pass++) {
        int32_t n = canny_hyst_sweep(sc->label, nr, nc, 0);
        n += canny_hyst_sweep(sc->label, nr, nc, 1);
        if (n == 0) {
            break;
        }
    }

    for (r = edge_v - DCANNY_ROWS_ABOVE; r <= edge_v + DCANNY_ROWS_BELOW;
         r++) {
        const uint8_t *lab;
        if (r < wr0 || r > wr1) {
            continue;
        }
        lab = sc->label + (ptrdiff_t)(r - wr0) * nc;
        for (c = (u0 > wc0) ? u0 : wc0; c <= u1 && c <= wc1; c++) {
            count += (lab[c - wc0] == 2u) ? 1 : 0;
        }
    }
    return count;
}
