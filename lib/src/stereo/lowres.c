/*
 * Stage 1: elementary 1/4-scale disparity map and the search range; stage 6:
 * the global vertical misalignment.
 *
 * Both images are reduced by 4x4 box averaging (the right image taken at the
 * vertical offset already estimated). Each low-res pixel is matched over
 * [dmin/4, dmax/4] with a zero-mean SAD on 3x3 windows:
 *   cost = sum |9 L - SL - (9 R - SR)|   (<= 9 * 9 * 255 * 2, fits int32)
 * A low-res disparity is kept only if the window has texture (mean absolute
 * deviation >= 3 grey levels), the best cost beats every cost at least two
 * levels away by 1/8, and the right pixel's own best match (left-right
 * check) lands within one level of it. From the kept values:
 *   global range = [1st, 99th percentile] * 4, widened by range_margin and
 *                  clipped to the configured [min_disp, max_disp];
 *   tile range   = min/max over the tile and its 8 neighbours, same margin,
 *                  clipped to the global range; a tile without a kept
 *                  value of its own gets the configured range, and the
 *                  global range (which bounds growth and the DP) is then
 *                  the configured one too: no evidence is not a narrow
 *                  range.
 * With fewer than 16 kept values the configured range is used unchanged.
 *
 * Vertical offset: up to 256 textured points on a grid are matched with
 * full-resolution MNCC over the configured range for every offset in
 * [-n, n]; the offset with the largest sum of best scores wins (ties go to
 * the smaller |offset|, then to the negative one).
 */
#include <string.h>

#include "stereo/stereo_int.h"
#include "stereo/stereo_simd.h"

static void downsample(const negobs_image_u8_t *img, int32_t voff,
                       uint8_t *out, int32_t lw, int32_t y4a, int32_t y4b)
{
    int32_t x4;
    int32_t y4;
    for (y4 = y4a; y4 < y4b; y4++) {
        const uint8_t *rows[4];
        int32_t k;
        for (k = 0; k < 4; k++) {
            int32_t y = negobs_clamp_s32(4 * y4 + k + voff, 0,
                                         img->height - 1);
            rows[k] = negobs_image_u8_row(img, y);
        }
        for (x4 = 0; x4 < lw; x4++) {
            uint32_t acc = 0;
            int32_t j;
            for (k = 0; k < 4; k++) {
                for (j = 0; j < 4; j++) {
                    acc += rows[k][4 * x4 + j];
                }
            }
            out[y4 * lw + x4] = (uint8_t)((acc + 8u) >> 4);
        }
    }
}

static int32_t box3(const uint8_t *p, int32_t stride)
{
    int32_t s = 0;
    int32_t k;
    for (k = -1; k <= 1; k++) {
        const uint8_t *q = p + (ptrdiff_t)k * stride;
        s += (int32_t)q[-1] + (int32_t)q[0] + (int32_t)q[1];
    }
    return s;
}

static int32_t zsad3(const uint8_t *a, int32_t sa, const uint8_t *b,
                     int32_t sb, int32_t stride)
{
    int32_t c = 0;
    int32_t k;
    int32_t j;
    for (k = -1; k <= 1; k++) {
        for (j = -1; j <= 1; j++) {
            int32_t t = 9 * ((int32_t)a[k * stride + j] -
                             (int32_t)b[k * stride + j]) -
                        (sa - sb);
            c += (t < 0) ? -t : t;
        }
    }
    return c;
}

void stx_zsad3_run_ref(const uint8_t *a, const uint8_t *b, int32_t stride,
                       int32_t n, int32_t *out)
{
    int32_t sa = box3(a, stride);
    int32_t l;
    for (l = 0; l < n; l++) {
        out[l] = zsad3(a, sa, b + l, box3(b + l, stride), stride);
    }
}

/* Flat 3x3 windows (mean absolute deviation < 3 grey levels) have no
 * reliable minimum, so they are not matched at all. */
static int lowres_textured(const uint8_t *a, int32_t sa, int32_t lw)
{
    int32_t tex = 0;
    int32_t k;
    for (k = 0; k < 9; k++) {
        int32_t t = 9 * (int32_t)a[(k / 3 - 1) * lw + (k % 3 - 1)] - sa;
        tex += (t < 0) ? -t : t;
    }
    return tex >= 9 * 9 * 3;
}

/* The left-right check: the right pixel's own best match must land within
 * one level of bestd, else the match is an occlusion or a repeat. */
static int lowres_lr_agrees(const stx_t *s, int32_t x4, int32_t y4,
                            int32_t bestd, int32_t dmin4, int32_t dmax4)
{
    int32_t lw = s->lw;
    int32_t xr = x4 - bestd;
    const uint8_t *b = s->lo_r + (ptrdiff_t)y4 * lw + xr;
    int32_t rb = INT32_MAX;
    int32_t rd = -1;
    int32_t run[80]; /* one run of windows, scratch */
    int32_t d4;
    /* left windows xl = xr + d4 in [1, lw - 2]; the cost is
     * symmetric (|t| = |-t|), so the run kernel with the
     * right window fixed gives zsad3(a2, ., b, .) */
    int32_t dlo = (dmin4 > 1 - xr) ? dmin4 : 1 - xr;
    int32_t dhi = (dmax4 < lw - 2 - xr) ? dmax4 : lw - 2 - xr;
    if (dlo <= dhi) {
        stx_zsad3_run(b, s->lo_l + (ptrdiff_t)y4 * lw + xr + dlo, lw,
                      dhi - dlo + 1, run);
        for (d4 = dlo; d4 <= dhi; d4++) {
            int32_t c = run[d4 - dlo];
            if (c < rb) {
                rb = c;
                rd = d4;
            }
        }
    }
    return !(rd < bestd - 1 || rd > bestd + 1);
}

/* One low-res pixel's disparity level (disparity / 4), or
 * -1 when it is flat, ambiguous or fails the left-right check: only
 * trustworthy values may narrow the full-resolution search. */
static int32_t lowres_match(const stx_t *s, int32_t x4, int32_t y4,
                            int32_t dmin4, int32_t dmax4)
{
    int32_t lw = s->lw;
    const uint8_t *a = s->lo_l + (ptrdiff_t)y4 * lw + x4;
    int32_t sa = box3(a, lw);
    int32_t best = INT32_MAX;
    int32_t bestd = -1;
    int32_t second = INT32_MAX;
    int32_t d4;
    int32_t costs[80];
    int32_t run[80]; /* one run of windows, scratch */
    if (!lowres_textured(a, sa, lw)) {
        return -1;
    }
    /* the levels whose right window is inside: xr = x4 - d4 in
     * [1, lw - 2], scored as one run of right windows */
    {
        int32_t dlo = (dmin4 > x4 - (lw - 2)) ? dmin4 : x4 - (lw - 2);
        int32_t dhi = (dmax4 < x4 - 1) ? dmax4 : x4 - 1;
        for (d4 = dmin4; d4 <= dmax4; d4++) {
            costs[d4 - dmin4] = INT32_MAX;
        }
        if (dlo <= dhi) {
            stx_zsad3_run(a, s->lo_r + (ptrdiff_t)y4 * lw + (x4 - dhi), lw,
                          dhi - dlo + 1, run);
            for (d4 = dlo; d4 <= dhi; d4++) {
                costs[d4 - dmin4] = run[dhi - d4];
            }
        }
    }
    for (d4 = dmin4; d4 <= dmax4; d4++) {
        int32_t c = costs[d4 - dmin4];
        if (c < best) {
            best = c;
            bestd = d4;
        }
    }
    if (bestd < 0) {
        return -1;
    }
    for (d4 = dmin4; d4 <= dmax4; d4++) {
        int32_t dd = d4 - bestd;
        if ((dd >= 2 || dd <= -2) && costs[d4 - dmin4] < second) {
            second = costs[d4 - dmin4];
        }
    }
    if (second != INT32_MAX && second - best <= best / 8 + 9) {
        return -1;
    }
    if (!lowres_lr_agrees(s, x4, y4, bestd, dmin4, dmax4)) {
        return -1;
    }
    return bestd;
}

/* The global range from the 1st and 99th percentiles of the kept levels,
 * so a few wrong matches cannot widen it. */
static void lowres_global_range(stx_t *s, uint32_t kept, int32_t nd4,
                                int32_t dmin4, int32_t dmin, int32_t dmax)
{
    int32_t margin = s->cfg.range_margin;
    uint32_t cut = kept / 100u;
    uint32_t cum = 0;
    int32_t lo = 0;
    int32_t hi = nd4 - 1;
    int32_t i;
    for (i = 0; i < nd4; i++) {
        cum += s->hist[i];
        if (cum > cut) {
            lo = i;
            break;
        }
    }
    cum = 0;
    for (i = nd4 - 1; i >= 0; i--) {
        cum += s->hist[i];
        if (cum > cut) {
            hi = i;
            break;
        }
    }
    s->gdmin = negobs_clamp_s32(4 * (lo + dmin4) - 2 - margin, dmin, dmax);
    s->gdmax = negobs_clamp_s32(4 * (hi + dmin4) + 2 + margin, s->gdmin, dmax);
}

/* Each tile's own min/max of the kept values, in the upper half of the
 * tile arrays (the lower half is written from it by the dilation). */
static void lowres_tile_own(stx_t *s, int32_t dmin4)
{
    int32_t lw = s->lw;
    int32_t lh = s->lh;
    int32_t ntile = s->tw * s->th;
    int32_t t4 = s->tile / 4;
    int16_t *olo = s->tile_lo + ntile;
    int16_t *ohi = s->tile_hi + ntile;
    int32_t x4;
    int32_t y4;
    int32_t i;
    for (i = 0; i < ntile; i++) {
        olo[i] = INT16_MAX;
        ohi[i] = INT16_MIN;
    }
    for (y4 = 0; y4 < lh; y4++) {
        for (x4 = 0; x4 < lw; x4++) {
            uint8_t v = s->lo_d[y4 * lw + x4];
            int32_t ti;
            int32_t d;
            if (v == STX_NONE8) {
                continue;
            }
            ti = (y4 / t4) * s->tw + (x4 / t4);
            if (y4 / t4 >= s->th || x4 / t4 >= s->tw) {
                continue;
            }
            d = 4 * ((int32_t)v + dmin4);
            if (d < olo[ti]) {
                olo[ti] = (int16_t)d;
            }
            if (d > ohi[ti]) {
                ohi[ti] = (int16_t)d;
            }
        }
    }
}

/* Each tile's range is its own and its 8 neighbours' min/max, since a
 * surface crossing a tile border must be found from both sides. */
static void lowres_tile_dilate(stx_t *s, int32_t dmin, int32_t dmax)
{
    int32_t margin = s->cfg.range_margin;
    int32_t ntile = s->tw * s->th;
    const int16_t *olo = s->tile_lo + ntile;
    const int16_t *ohi = s->tile_hi + ntile;
    int32_t tx;
    int32_t ty;
    int32_t i;
    int unknown = 0;
    for (ty = 0; ty < s->th; ty++) {
        for (tx = 0; tx < s->tw; tx++) {
            int32_t l = INT16_MAX;
            int32_t h = INT16_MIN;
            int32_t dy;
            int32_t dx;
            for (dy = -1; dy <= 1; dy++) {
                for (dx = -1; dx <= 1; dx++) {
                    int32_t yy = ty + dy;
                    int32_t xx = tx + dx;
                    int32_t ti;
                    if (yy < 0 || yy >= s->th || xx < 0 || xx >= s->tw) {
                        continue;
                    }
                    ti = yy * s->tw + xx;
                    if (olo[ti] < l) {
                        l = olo[ti];
                    }
                    if (ohi[ti] > h) {
                        h = ohi[ti];
                    }
                }
            }
            i = ty * s->tw + tx;
            if (olo[i] > ohi[i]) {
                /* No value of its own: the neighbours say nothing
                 * about what is here (a smooth near floor shows no
                 * texture at 1/4 scale and has the largest
                 * disparities of the frame), so search it all. */
                s->tile_lo[i] = (int16_t)dmin;
                s->tile_hi[i] = (int16_t)dmax;
                unknown = 1;
            } else {
                l = negobs_clamp_s32(l - 2 - margin, s->gdmin, s->gdmax);
                h = negobs_clamp_s32(h + 2 + margin, l, s->gdmax);
                s->tile_lo[i] = (int16_t)l;
                s->tile_hi[i] = (int16_t)h;
            }
        }
    }
    if (unknown) {
        s->gdmin = dmin;
        s->gdmax = dmax;
    }
}

/* The configured range everywhere; 1 when the 1/4-scale map is to be
 * made (auto_range and a frame large enough for it). */
int stx_lowres_begin(stx_t *s)
{
    int32_t dmin = s->dmin;
    int32_t dmax = s->dmin + s->ndisp - 1;
    int32_t ntile = s->tw * s->th;
    int32_t i;
    s->gdmin = dmin;
    s->gdmax = dmax;
    for (i = 0; i < ntile; i++) {
        s->tile_lo[i] = (int16_t)dmin;
        s->tile_hi[i] = (int16_t)dmax;
    }
    if (!s->cfg.auto_range || s->lw < 5 || s->lh < 3) {
        return 0;
    }
    memset(s->lo_d, STX_NONE8, (size_t)s->lw * (size_t)s->lh);
    return 1;
}

int32_t stx_lowres_levels(const stx_t *s)
{
    return (s->dmin + s->ndisp - 1 + 3) / 4 - s->dmin / 4 + 1;
}

void stx_lowres_downsample_rows(stx_t *s, int32_t y4a, int32_t y4b)
{
    downsample(s->left, 0, s->lo_l, s->lw, y4a, y4b);
    downsample(s->right, s->voff, s->lo_r, s->lw, y4a, y4b);
}

uint32_t stx_lowres_match_rows(stx_t *s, int32_t y4a, int32_t y4b,
                               uint32_t *hist)
{
    int32_t lw = s->lw;
    int32_t dmin4 = s->dmin / 4;
    int32_t dmax4 = (s->dmin + s->ndisp - 1 + 3) / 4;
    uint32_t kept = 0;
    int32_t x4;
    int32_t y4;
    memset(hist, 0, (size_t)(dmax4 - dmin4 + 2) * sizeof *hist);
    y4a = (y4a > 1) ? y4a : 1;
    y4b = (y4b < s->lh - 1) ? y4b : s->lh - 1;
    for (y4 = y4a; y4 < y4b; y4++) {
        for (x4 = 1; x4 < lw - 1; x4++) {
            int32_t bestd = lowres_match(s, x4, y4, dmin4, dmax4);
            if (bestd < 0) {
                continue;
            }
            s->lo_d[y4 * lw + x4] = (uint8_t)(bestd - dmin4);
            hist[bestd - dmin4]++;
            kept++;
        }
    }
    return kept;
}

void stx_lowres_finish(stx_t *s, uint32_t kept)
{
    int32_t dmin = s->dmin;
    int32_t dmax = s->dmin + s->ndisp - 1;
    int32_t dmin4 = dmin / 4;
    /* too few values to trust: keep the configured range */
    if (kept < 16u) {
        return;
    }
    lowres_global_range(s, kept, stx_lowres_levels(s), dmin4, dmin, dmax);
    lowres_tile_own(s, dmin4);
    lowres_tile_dilate(s, dmin, dmax);
}

void stx_lowres_range(stx_t *s)
{
    if (!stx_lowres_begin(s)) {
        return;
    }
    stx_lowres_downsample_rows(s, 0, s->lh);
    stx_lowres_finish(s, stx_lowres_match_rows(s, 0, s->lh, s->hist));
}

void stx_tile_range(const stx_t *s, int32_t x, int32_t y, int32_t *lo,
                    int32_t *hi)
{
    int32_t tx = negobs_clamp_s32(x / s->tile, 0, s->tw - 1);
    int32_t ty = negobs_clamp_s32(y / s->tile, 0, s->th - 1);
    *lo = s->tile_lo[ty * s->tw + tx];
    *hi = s->tile_hi[ty * s->tw + tx];
}

/* Add (sign 1) or remove (sign -1) column x of rows y-2 .. y+2 to a
 * running window sum and sum of squares (unsigned, exact mod 2^32). */
static void col5(const negobs_image_u8_t *img, int32_t x, int32_t y,
                 uint32_t *sum, uint32_t *sq, int sign)
{
    uint32_t a = 0;
    uint32_t q = 0;
    int32_t k;
    for (k = -STX_WIN_R; k <= STX_WIN_R; k++) {
        uint32_t g = negobs_image_u8_row(img, y + k)[x];
        a += g;
        q += g * g;
    }
    if (sign > 0) {
        *sum += a;
        *sq += q;
    } else {
        *sum -= a;
        *sq -= q;
    }
}

/* The sampling grid of the vertical search: steps (sx, sy) and rows. */
static void vertical_grid(const stx_t *s, int32_t *sx, int32_t *sy)
{
    *sx = (s->w / 12 < 4) ? 4 : s->w / 12;
    *sy = (s->h / 12 < 4) ? 4 : s->h / 12;
}

int32_t stx_vertical_grid_rows(const stx_t *s)
{
    int32_t sx;
    int32_t sy;
    int32_t y0;
    vertical_grid(s, &sx, &sy);
    y0 = sy / 2 + 6;
    return (s->h - 6 > y0) ? (s->h - 6 - y0 + sy - 1) / sy : 0;
}

void stx_vertical_scores(stx_t *s, int32_t n, int32_t g0, int32_t g1,
                         int64_t *score)
{
    int32_t sx;
    int32_t sy;
    int32_t k;
    int32_t dmax = s->dmin + s->ndisp - 1;
    uint32_t tex = (uint32_t)s->cfg.texture_min;

    vertical_grid(s, &sx, &sy);
    for (k = 0; k <= 2 * n; k++) {
        /* order 0, -1, +1, -2, +2 ... so ties keep the smaller |offset| */
        int32_t off = (k & 1) ? -((k + 1) / 2) : (k / 2);
        int32_t x;
        int32_t g;
        score[k] = 0;
        for (g = g0; g < g1; g++) {
            int32_t y = sy / 2 + 6 + g * sy;
            int32_t yr = y + off;
            if (yr < STX_WIN_R || yr >= s->h - STX_WIN_R) {
                continue;
            }
            for (x = sx / 2 + 2; x < s->w - 2; x += sx) {
                int32_t bc = 0;
                int32_t d;
                uint32_t sl;
                uint32_t vl;
                stx_sums5(s->left, x, y, &sl, &vl);
                if (vl == 0u) {
                    continue;
                }
                /* right window sums slide left one column per d: add
                 * the new left column, drop the old right one (the same
                 * integers stx_sums5 adds up) */
                uint32_t rs = 0;
                uint32_t rq = 0;
                if (s->dmin <= dmax && s->dmin <= x - 2) {
                    int32_t j;
                    for (j = -STX_WIN_R; j <= STX_WIN_R; j++) {
                        col5(s->right, x - s->dmin + j, yr, &rs, &rq, 1);
                    }
                }
                for (d = s->dmin; d <= dmax && d <= x - 2; d++) {
                    uint32_t sr = rs;
                    uint32_t vr = (uint32_t)STX_WIN_N * rq - rs * rs;
                    int32_t c;
                    if (d + 1 <= dmax && d + 1 <= x - 2) {
                        col5(s->right, x - d + STX_WIN_R, yr, &rs, &rq, -1);
                        col5(s->right, x - d - 1 - STX_WIN_R, yr, &rs, &rq, 1);
                    }
                    if (vr == 0u) {
                        continue;
                    }
                    c = stx_mncc_q14(
                        stx_cross5(s->left, x, y, s->right, x - d, yr), sl, vl,
                        sr, vr, tex);
                    if (c != STX_FLAT && c > bc) {
                        bc = c;
                    }
                }
                score[k] += bc;
            }
        }
    }
}

int32_t stx_vertical_pick(const int64_t *score, int32_t n)
{
    int64_t best_score = -1;
    int32_t best = 0;
    int32_t k;
    for (k = 0; k <= 2 * n; k++) {
        int32_t off = (k & 1) ? -((k + 1) / 2) : (k / 2);
        if (score[k] > best_score) {
            best_score = score[k];
            best = off;
        }
    }
    return best;
}

int32_t stx_vertical_estimate(stx_t *s, int32_t n)
{
    int64_t score[2 * STX_VSEARCH_MAX + 1];
    stx_vertical_scores(s, n, 0, stx_vertical_grid_rows(s), score);
    return stx_vertical_pick(score, n);
}
