/*
 * Stage 5b: left-right (occlusion) check, speckle removal and the adaptive
 * mean filter, all in place on the Q4 disparity image with line-sized
 * scratch.
 *
 * LR check: each row is forward-warped into the right view keeping the
 * largest disparity per right column (a z-buffer); a left pixel whose right
 * column is claimed by a disparity more than 1 px larger is occluded there
 * and is dropped.
 *
 * Speckles: 4-connected regions whose neighbouring disparities differ by at
 * most speckle_diff_q4 are flood-filled with a list of at most
 * speckle_size + 1 entries and two bitmaps (visited, kept). A region that
 * overflows the list, or touches a kept pixel, is kept; a complete region
 * smaller than speckle_size is invalidated. Every left-over part of an
 * overflowed region touches a kept pixel, so no part of a large region is
 * ever removed. The result is therefore fixed by the components alone
 * (fewer than speckle_size pixels: removed), which lets bands mark their
 * own rows at the same time and clear them afterwards
 * (stx_speckle_mark_rows, stx_speckle_clear_rows).
 *
 * Gap fill (after the speckles): short invalid runs of a row are filled
 * from their ends, see gap_fill_row().
 *
 * Adaptive mean (after libelas `adaptiveMean`): separable,
 * horizontal then vertical, 9 taps; the weight of a neighbour is
 * max(0, 64 - |d_i - d_centre|) in Q4 (4 px triangle). A hole whose two
 * nearest valid neighbours on the line (within 4 px) agree to 1 px is filled
 * with their mean. Sum of weights * d <= 9 * 64 * 32767 < 2^25.
 */
#include <string.h>

#include "stereo/stereo_int.h"
#include "stereo/stereo_simd.h"

void stx_lr_check(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                  int32_t conf_stride)
{
    stx_lr_check_rows(s, disp, conf, conf_stride, 0, s->h);
}

void stx_lr_check_rows(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                       int32_t conf_stride, int32_t y0, int32_t y1)
{
    int32_t w = s->w;
    int32_t y;
    int16_t *zb = s->line;
    for (y = y0; y < y1; y++) {
        int16_t *row = negobs_image_s16_row(disp, y);
        int32_t x;
        for (x = 0; x < w; x++) {
            zb[x] = INT16_MIN;
        }
        for (x = 0; x < w; x++) {
            int32_t d4 = row[x];
            int32_t rx;
            if (d4 == NEGOBS_DISP_INVALID) {
                continue;
            }
            rx = x - negobs_rshift_round_s32(d4, 4);
            if (rx >= 0 && rx < w && d4 > zb[rx]) {
                zb[rx] = (int16_t)d4;
            }
        }
        for (x = 0; x < w; x++) {
            int32_t d4 = row[x];
            int32_t rx;
            if (d4 == NEGOBS_DISP_INVALID) {
                continue;
            }
            rx = x - negobs_rshift_round_s32(d4, 4);
            if (rx < 0 || rx >= w || zb[rx] > d4 + NEGOBS_DISP_ONE) {
                row[x] = NEGOBS_DISP_INVALID;
                if (conf != NULL) {
                    conf[(ptrdiff_t)y * conf_stride + x] = 0;
                }
                s->st.lr_rejected++;
            }
        }
    }
}

static int bit_get(const uint8_t *b, size_t i)
{
    return (b[i >> 3] >> (i & 7u)) & 1;
}

static void bit_set(uint8_t *b, size_t i)
{
    b[i >> 3] = (uint8_t)(b[i >> 3] | (1u << (i & 7u)));
}

/* Whether two valid neighbours belong to one speckle region. */
static inline int speckle_joined(int32_t a, int32_t b, int32_t diff)
{
    return a - b <= diff && b - a <= diff;
}

void stx_speckle(stx_t *s, negobs_image_s16_t *disp)
{
    int32_t w = s->w;
    int32_t h = s->h;
    int32_t lim = s->cfg.speckle_size;
    int32_t diff = s->cfg.speckle_diff_q4;
    size_t npx = (size_t)w * (size_t)h;
    int32_t y;
    int32_t x;

    if (lim <= 1) {
        return;
    }
    memset(s->vis, 0, (npx + 7u) / 8u);
    memset(s->keep, 0, (npx + 7u) / 8u);
    for (y = 0; y < h; y++) {
        for (x = 0; x < w; x++) {
            size_t p = (size_t)y * (size_t)w + (size_t)x;
            int32_t n = 0;
            int32_t head = 0;
            int big = 0;
            int32_t i;
            int32_t dp;
            if (bit_get(s->vis, p)) {
                continue;
            }
            dp = negobs_image_s16_row(disp, y)[x];
            if (dp == NEGOBS_DISP_INVALID) {
                continue;
            }
            /* joined to a kept pixel on the left or above (kept pixels are
             * valid): the same region, so kept too, without a flood; its
             * other unvisited pixels get their turn the same way */
            if ((x > 0 && bit_get(s->keep, p - 1u) &&
                 speckle_joined(negobs_image_s16_row(disp, y)[x - 1], dp,
                                diff)) ||
                (y > 0 && bit_get(s->keep, p - (size_t)w) &&
                 speckle_joined(negobs_image_s16_row(disp, y - 1)[x], dp,
                                diff))) {
                bit_set(s->vis, p);
                bit_set(s->keep, p);
                continue;
            }
            bit_set(s->vis, p);
            s->flood[n++] = (uint32_t)p;
            /* a large region stops flooding (as the band pass does): the
             * rest of it is connected to the pixels kept here, so a later
             * flood from any of them touches a kept pixel and keeps it */
            while (head < n && !big) {
                uint32_t q = s->flood[head++];
                int32_t qy = (int32_t)(q / (uint32_t)w);
                int32_t qx = (int32_t)(q - (uint32_t)qy * (uint32_t)w);
                int32_t dq = negobs_image_s16_row(disp, qy)[qx];
                int k;
                for (k = 0; k < 4; k++) {
                    int32_t rx = qx + ((k == 0) ? -1 : ((k == 1) ? 1 : 0));
                    int32_t ry = qy + ((k == 2) ? -1 : ((k == 3) ? 1 : 0));
                    size_t r;
                    int32_t dr;
                    if (rx < 0 || rx >= w || ry < 0 || ry >= h) {
                        continue;
                    }
                    dr = negobs_image_s16_row(disp, ry)[rx];
                    if (dr == NEGOBS_DISP_INVALID || dr - dq > diff ||
                        dq - dr > diff) {
                        continue;
                    }
                    r = (size_t)ry * (size_t)w + (size_t)rx;
                    if (bit_get(s->keep, r)) {
                        big = 1;
                    }
                    if (bit_get(s->vis, r)) {
                        continue;
                    }
                    if (n > lim) {
                        big = 1;
                        continue;
                    }
                    bit_set(s->vis, r);
                    s->flood[n++] = (uint32_t)r;
                }
            }
            if (big || n >= lim) {
                for (i = 0; i < n; i++) {
                    bit_set(s->keep, s->flood[i]);
                }
            } else {
                for (i = 0; i < n; i++) {
                    uint32_t q = s->flood[i];
                    int32_t qy = (int32_t)(q / (uint32_t)w);
                    int32_t qx = (int32_t)(q - (uint32_t)qy * (uint32_t)w);
                    negobs_image_s16_row(disp, qy)[qx] = NEGOBS_DISP_INVALID;
                }
                s->st.speckles_removed += (uint32_t)n;
            }
        }
    }
}

/* Row-aligned bit of (x, y) in the speckle bitmaps: a band's rows own
 * whole bytes, so bands mark their own pixels at the same time. */
static size_t speckle_bit(const stx_t *s, int32_t x, int32_t y)
{
    return (size_t)y * (((size_t)s->w + 7u) & ~(size_t)7u) + (size_t)x;
}

static int in_list(const uint32_t *list, int32_t n, uint32_t p)
{
    int32_t i;
    for (i = 0; i < n; i++) {
        if (list[i] == p) {
            return 1;
        }
    }
    return 0;
}

/* One flood of the band pass from pixel p of rows [y0, y1): the pixels of
 * the band it takes are marked visited, and kept when the region is
 * large. Pixels outside the band are read, never marked: the flood keeps
 * them in s->flood_out so it takes each once. A region is large when the
 * flood overflows the list or touches a kept pixel (then it stops: the
 * verdict cannot change); else it holds its whole region (every visited
 * pixel of the band it meets is kept or belongs to a region already
 * complete, which it cannot touch). */
static void speckle_flood_band(stx_t *s, const negobs_image_s16_t *disp,
                               int32_t px, int32_t py, int32_t y0, int32_t y1)
{
    int32_t w = s->w;
    int32_t lim = s->cfg.speckle_size;
    int32_t diff = s->cfg.speckle_diff_q4;
    int32_t n = 0;
    int32_t nout = 0;
    int32_t head = 0;
    int big = 0;
    int32_t i;
    bit_set(s->vis, speckle_bit(s, px, py));
    s->flood[n++] = (uint32_t)(py * w + px);
    while (head < n && !big) {
        uint32_t q = s->flood[head++];
        int32_t qy = (int32_t)(q / (uint32_t)w);
        int32_t qx = (int32_t)(q - (uint32_t)qy * (uint32_t)w);
        int32_t dq = negobs_image_s16_row(disp, qy)[qx];
        int k;
        for (k = 0; k < 4 && !big; k++) {
            int32_t rx = qx + ((k == 0) ? -1 : ((k == 1) ? 1 : 0));
            int32_t ry = qy + ((k == 2) ? -1 : ((k == 3) ? 1 : 0));
            uint32_t r;
            int32_t dr;
            int inside;
            if (rx < 0 || rx >= w || ry < 0 || ry >= s->h) {
                continue;
            }
            dr = negobs_image_s16_row(disp, ry)[rx];
            if (dr == NEGOBS_DISP_INVALID || dr - dq > diff ||
                dq - dr > diff) {
                continue;
            }
            r = (uint32_t)(ry * w + rx);
            inside = (ry >= y0 && ry < y1);
            if (inside) {
                size_t b = speckle_bit(s, rx, ry);
                if (bit_get(s->keep, b)) {
                    big = 1;
                    continue;
                }
                if (bit_get(s->vis, b)) {
                    continue;
                }
            } else if (in_list(s->flood_out, nout, r)) {
                continue;
            }
            if (n > lim) {
                big = 1;
                continue;
            }
            if (inside) {
                bit_set(s->vis, speckle_bit(s, rx, ry));
            } else {
                s->flood_out[nout++] = r;
            }
            s->flood[n++] = r;
        }
    }
    if (big || n >= lim) {
        for (i = 0; i < n; i++) {
            int32_t qy = (int32_t)(s->flood[i] / (uint32_t)w);
            int32_t qx = (int32_t)(s->flood[i] - (uint32_t)qy * (uint32_t)w);
            if (qy >= y0 && qy < y1) {
                bit_set(s->keep, speckle_bit(s, qx, qy));
            }
        }
    }
}

void stx_speckle_mark_rows(stx_t *s, const negobs_image_s16_t *disp,
                           int32_t y0, int32_t y1)
{
    int32_t diff = s->cfg.speckle_diff_q4;
    size_t rowbytes = ((size_t)s->w + 7u) / 8u;
    int32_t y;
    int32_t x;
    if (s->cfg.speckle_size <= 1) {
        return;
    }
    memset(s->vis + (size_t)y0 * rowbytes, 0, (size_t)(y1 - y0) * rowbytes);
    memset(s->keep + (size_t)y0 * rowbytes, 0, (size_t)(y1 - y0) * rowbytes);
    for (y = y0; y < y1; y++) {
        const int16_t *row = negobs_image_s16_row(disp, y);
        const int16_t *up = (y > y0) ? negobs_image_s16_row(disp, y - 1)
                                     : NULL;
        for (x = 0; x < s->w; x++) {
            size_t b = speckle_bit(s, x, y);
            if (row[x] == NEGOBS_DISP_INVALID || bit_get(s->vis, b)) {
                continue;
            }
            /* joined to a kept pixel of this band on the left or above:
             * kept without a flood (as in stx_speckle) */
            if ((x > 0 && bit_get(s->keep, b - 1u) &&
                 speckle_joined(row[x - 1], row[x], diff)) ||
                (up != NULL && bit_get(s->keep, speckle_bit(s, x, y - 1)) &&
                 speckle_joined(up[x], row[x], diff))) {
                bit_set(s->vis, b);
                bit_set(s->keep, b);
                continue;
            }
            speckle_flood_band(s, disp, x, y, y0, y1);
        }
    }
}

void stx_speckle_clear_rows(stx_t *s, negobs_image_s16_t *disp, int32_t y0,
                            int32_t y1)
{
    int32_t y;
    int32_t x;
    if (s->cfg.speckle_size <= 1) {
        return;
    }
    for (y = y0; y < y1; y++) {
        int16_t *row = negobs_image_s16_row(disp, y);
        for (x = 0; x < s->w; x++) {
            size_t b = speckle_bit(s, x, y);
            if (row[x] != NEGOBS_DISP_INVALID && !bit_get(s->keep, b)) {
                row[x] = NEGOBS_DISP_INVALID;
                s->st.speckles_removed++;
            }
        }
    }
}

/*
 * Gap fill: the invalid runs of a row that are at most cfg.gap_fill px long
 * get a value from their two ends. A run between a far surface and a nearer
 * one is the background hidden from the right camera only if it is about
 * as wide as the disparity step: an occlusion next to a step of J px is J
 * px wide. Such a run gets the smaller end, the background; a run with
 * the nearer surface on its left is split where the left image has its
 * edge (details at the two places below). Any other run (ends that agree
 * to 1 px, or a run much wider than the step between its ends: a slanted
 * surface without texture, or pixels the LR check or the speckle filter
 * dropped) is joined linearly. A run touching the left or right border
 * takes its only end (the left border strip has no match at all); with one
 * end only, a == b, so such a run always counts as a surface. Filled
 * pixels get confidence NEGOBS_STEREO_CONF_FILLED, below any
 * matched pixel, so consumers that threshold the confidence (detection's
 * deficit test) ignore them.
 */

/* Whether a run of n px between the Q4 ends a and b is filled linearly
 * rather than with the background. "Much wider than the step" is
 * n > 3 * step + 4 px: the factor 3 and the 4 px (the 5x5 window's
 * reach on both sides) leave room for an occlusion widened by fattening
 * and the LR check; on Middlebury, 2x or 1.5x the step cost 0.1-1.8 points
 * of bad1 on Aloe and Poster and gained no more on Flowerpots (13.2 ->
 * 11.4 %). |a - b| < 2^16 and n <= 1024: no overflow. */
static inline int run_is_surface(int32_t a, int32_t b, int32_t n)
{
    int32_t step_q4 = negobs_abs_s32(a - b);
    return step_q4 <= NEGOBS_DISP_ONE ||
           n * NEGOBS_DISP_ONE > 3 * step_q4 + 4 * NEGOBS_DISP_ONE;
}

/* The column c in [c0, c1) with the largest |img[c] - img[c - 1]|, the
 * first on ties; c0 >= 1. */
static inline int32_t strongest_step(const uint8_t *img, int32_t c0,
                                     int32_t c1)
{
    int32_t best = -1;
    int32_t at = c0;
    int32_t c;
    for (c = c0; c < c1; c++) {
        int32_t g = negobs_abs_s32((int32_t)img[c] - (int32_t)img[c - 1]);
        if (g > best) {
            best = g;
            at = c;
        }
    }
    return at;
}

/* After an occlusion run ending at column x (background a on its left),
 * the first column that keeps the near surface's value: the strongest
 * grey-level step in (x, x + 3], searched only over pixels that still
 * read nearer than the background by more than 1 px. */
static inline int32_t near_edge_column(const int16_t *row, const uint8_t *img,
                                       int32_t w, int32_t x, int32_t a)
{
    int32_t c1 = x + 1;
    while (c1 <= x + 3 && c1 < w && row[c1] != NEGOBS_DISP_INVALID &&
           row[c1] > a + NEGOBS_DISP_ONE) {
        c1++;
    }
    return (c1 > x + 1) ? strongest_step(img, x + 1, c1) : x + 1;
}

static uint32_t gap_fill_row(int16_t *row, uint8_t *crow, const uint8_t *img,
                             int32_t w, int32_t max_len)
{
    uint32_t filled = 0;
    int32_t x = 0;
    while (x < w) {
        int32_t x0;
        int32_t a;
        int32_t b;
        int32_t n;
        int32_t k;
        int surface;
        int32_t split;
        if (row[x] != NEGOBS_DISP_INVALID) {
            x++;
            continue;
        }
        x0 = x;
        while (x < w && row[x] == NEGOBS_DISP_INVALID) {
            x++;
        }
        n = x - x0;
        if (n > max_len || (x0 == 0 && x == w)) {
            continue; /* too long, or a row without any value */
        }
        a = (x0 > 0) ? row[x0 - 1] : row[x];
        b = (x < w) ? row[x] : a;
        surface = run_is_surface(a, b, n);
        /* A nearer surface on the left and the background on the right
         * is no occlusion (those lie left of a near object): the object's
         * border is somewhere in the run, at its strongest grey-level
         * step. Left of it the near end, right of it the background. */
        split = x0;
        if (!surface && a > b) {
            split = strongest_step(img, x0, x + 1);
        }
        for (k = 0; k < n; k++) {
            int32_t d;
            if (x0 + k < split) {
                d = a;
            } else if (surface) {
                /* |b - a| < 2^16 and n <= 1024: the product fits 64 bits */
                d = a + (int32_t)negobs_div_round_s64(
                            (int64_t)(b - a) * (k + 1), n + 1);
            } else {
                d = (a < b) ? a : b;
            }
            row[x0 + k] = (int16_t)d;
            if (crow != NULL) {
                crow[x0 + k] = NEGOBS_STEREO_CONF_FILLED;
            }
        }
        filled += (uint32_t)n;
        /* Background on the left, a nearer surface on the right: the run
         * is an occlusion, and the near surface's first pixels usually
         * belong to it too (their 5x5 windows straddle the edge and the
         * near texture wins, "fattening"). They get the background up to
         * the strongest grey-level step among the near surface's first 3
         * px (at least its first pixel), where the object's border is.
         * A fixed 1 px was the best blind choice; 2-3 blind pixels helped
         * Poster but cost Flowerpots 0.5-0.9 point. */
        if (!surface && b > a) {
            int32_t e = near_edge_column(row, img, w, x, a);
            for (; x < e; x++) {
                row[x] = (int16_t)a;
                if (crow != NULL) {
                    crow[x] = NEGOBS_STEREO_CONF_FILLED;
                }
                filled++;
            }
        }
    }
    return filled;
}

void stx_gap_fill(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                  int32_t conf_stride)
{
    stx_gap_fill_rows(s, disp, conf, conf_stride, 0, s->h);
}

void stx_gap_fill_rows(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                       int32_t conf_stride, int32_t y0, int32_t y1)
{
    int32_t y;
    for (y = y0; y < y1; y++) {
        s->st.gap_filled += gap_fill_row(
            negobs_image_s16_row(disp, y),
            (conf != NULL) ? conf + (ptrdiff_t)y * conf_stride : NULL,
            negobs_image_u8_row(s->left, y), s->w, s->cfg.gap_fill);
    }
}

/* Weight of a valid neighbour v for centre c: 64 - |v - c| in Q4, 0
 * beyond 4 px (another surface). */
static inline int32_t amean_weight(int32_t v, int32_t c)
{
    int32_t wt = 64 - negobs_abs_s32(v - c);
    return (wt > 0) ? wt : 0;
}

/* The adaptive mean at sample i of a line `in` of n samples. The taps i - j and
 * i + j count only together: where one of them lies beyond the frame
 * border or in a hole, neither does. With both there, a linear profile
 * (a slanted surface: the ground along a column) weighs them alike and
 * keeps its centre value; with one side only it did not, and within 4 px
 * of the border or a hole the mean pulled a ground map towards the side
 * it saw: the last rows of a 320x240 ground map 0.07-0.17 px low (ground
 * gradient 0.09 px per row), which tilted the ground fit, leaning on those
 * rows, by 0.2 deg. Sharing the smaller weight of each pair as well
 * removed the bias too but smoothed less beside depth edges (Cones bad1
 * 4.52 -> 4.76 % against 4.64 % this way). */
static inline int16_t amean_at(const int16_t *in, int32_t n, int32_t i)
{
    int32_t c = in[i];
    int32_t k;
    if (c != NEGOBS_DISP_INVALID) {
        int32_t sw = 64; /* the centre is its own neighbour */
        int32_t sd = 64 * c;
        int32_t j;
        for (j = 1; j <= 4; j++) {
            int32_t wl;
            int32_t wr;
            if (i - j < 0 || i + j >= n) {
                break; /* the border: no pair from here on */
            }
            if (in[i - j] == NEGOBS_DISP_INVALID ||
                in[i + j] == NEGOBS_DISP_INVALID) {
                continue; /* a hole on one side: neither tap counts */
            }
            wl = amean_weight(in[i - j], c);
            wr = amean_weight(in[i + j], c);
            sw += wl + wr;
            sd += wl * (int32_t)in[i - j] + wr * (int32_t)in[i + j];
        }
        return (int16_t)stx_div_round_pos(sd, sw);
    } else {
        int32_t a = NEGOBS_DISP_INVALID;
        int32_t b = NEGOBS_DISP_INVALID;
        for (k = 1; k <= 4 && a == NEGOBS_DISP_INVALID; k++) {
            if (i - k >= 0) {
                a = in[i - k];
            }
        }
        for (k = 1; k <= 4 && b == NEGOBS_DISP_INVALID; k++) {
            if (i + k < n) {
                b = in[i + k];
            }
        }
        if (a != NEGOBS_DISP_INVALID && b != NEGOBS_DISP_INVALID &&
            negobs_abs_s32(a - b) <= NEGOBS_DISP_ONE) {
            return (int16_t)((a + b) / 2);
        }
        return NEGOBS_DISP_INVALID;
    }
}

void stx_amean8_ref(const int16_t *const tap[9], int32_t kl, int32_t kr,
                    int16_t *out)
{
    int32_t l;
    /* lane l is the centre of a line whose ends lie kl and kr samples
     * away: exactly amean_at() there */
    for (l = 0; l < 8; l++) {
        int16_t line[9];
        int32_t j;
        for (j = 4 - kl; j <= 4 + kr; j++) {
            line[j] = tap[j][l];
        }
        out[l] = amean_at(line + 4 - kl, 1 + kl + kr, kl);
    }
}

/* One line of the adaptive mean: in -> out, n samples; with SIMD, the
 * interior in steps of 8 lanes. */
static void amean_line(const int16_t *in, int16_t *out, int32_t n)
{
    int32_t i = 0;
#if defined(NEGOBS_SIMD)
    for (; i < 4 && i < n; i++) {
        out[i] = amean_at(in, n, i);
    }
    /* lanes i .. i + 7 read i - 4 .. i + 11 */
    for (; i + 11 < n; i += 8) {
        const int16_t *tap[9];
        int32_t j;
        for (j = 0; j < 9; j++) {
            tap[j] = in + i + j - 4;
        }
        stx_amean8_simd(tap, 4, 4, out + i);
    }
    /* one more block ending 4 samples before the end, overlapping the
     * previous one (same values) */
    if (i < n - 4 && n - 12 >= 4) {
        const int16_t *tap[9];
        int32_t j;
        i = n - 12;
        for (j = 0; j < 9; j++) {
            tap[j] = in + i + j - 4;
        }
        stx_amean8_simd(tap, 4, 4, out + i);
        i += 8;
    }
#endif
    for (; i < n; i++) {
        out[i] = amean_at(in, n, i);
    }
}

#if defined(NEGOBS_SIMD)
/* The vertical pass over columns x .. x + 7, in place: the inputs of the
 * 4 rows above, already overwritten, are kept in a ring. */
static void amean_cols8(negobs_image_s16_t *disp, int32_t h, int32_t x,
                        uint8_t *conf, int32_t conf_stride)
{
    int16_t ring[4][8];
    int32_t y;
    for (y = 0; y < h; y++) {
        const int16_t *tap[9];
        int16_t out[8];
        int16_t *row = negobs_image_s16_row(disp, y) + x;
        int32_t kl = (y < 4) ? y : 4;
        int32_t kr = (h - 1 - y < 4) ? h - 1 - y : 4;
        int32_t j;
        int32_t l;
        for (j = 1; j <= kl; j++) {
            tap[4 - j] = ring[(y - j) & 3];
        }
        tap[4] = row;
        for (j = 1; j <= kr; j++) {
            tap[4 + j] = negobs_image_s16_row(disp, y + j) + x;
        }
        stx_amean8_simd(tap, kl, kr, out);
        memcpy(ring[y & 3], row, sizeof out);
        memcpy(row, out, sizeof out);
        for (l = 0; conf != NULL && l < 8; l++) {
            if (ring[y & 3][l] == NEGOBS_DISP_INVALID &&
                out[l] != NEGOBS_DISP_INVALID) {
                conf[(ptrdiff_t)y * conf_stride + x + l] =
                    NEGOBS_STEREO_CONF_FILLED;
            }
        }
    }
}
#endif

void stx_adaptive_mean(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                       int32_t conf_stride)
{
    stx_amean_rows(s, disp, conf, conf_stride, 0, s->h);
    stx_amean_cols(s, disp, conf, conf_stride, 0, s->w);
}

/* A hole the mean fills was not measured there: it is marked like the gap
 * fill's pixels, not left with the confidence it had before the LR check
 * or the speckle filter removed its value. */
void stx_amean_rows(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                    int32_t conf_stride, int32_t y0, int32_t y1)
{
    int32_t w = s->w;
    int32_t x;
    int32_t y;
    for (y = y0; y < y1; y++) {
        int16_t *row = negobs_image_s16_row(disp, y);
        memcpy(s->line, row, (size_t)w * sizeof *row);
        amean_line(s->line, row, w);
        for (x = 0; conf != NULL && x < w; x++) {
            if (s->line[x] == NEGOBS_DISP_INVALID &&
                row[x] != NEGOBS_DISP_INVALID) {
                conf[(ptrdiff_t)y * conf_stride + x] =
                    NEGOBS_STEREO_CONF_FILLED;
            }
        }
    }
}

void stx_amean_cols(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                    int32_t conf_stride, int32_t x0, int32_t x1)
{
    int32_t h = s->h;
    int32_t x = x0;
    int32_t y;
#if defined(NEGOBS_SIMD)
    /* columns are independent: any split of [x0, x1) gives the same map */
    for (; x + 8 <= x1; x += 8) {
        amean_cols8(disp, h, x, conf, conf_stride);
    }
#endif
    for (; x < x1; x++) {
        for (y = 0; y < h; y++) {
            s->line[y] = negobs_image_s16_row(disp, y)[x];
        }
        amean_line(s->line, s->line2, h);
        for (y = 0; y < h; y++) {
            negobs_image_s16_row(disp, y)[x] = s->line2[y];
            if (conf != NULL && s->line[y] == NEGOBS_DISP_INVALID &&
                s->line2[y] != NEGOBS_DISP_INVALID) {
                conf[(ptrdiff_t)y * conf_stride + x] =
                    NEGOBS_STEREO_CONF_FILLED;
            }
        }
    }
}

/* A value d at column x puts the match at x - d in the right image; when
 * that is left of column 0 the right camera never saw the point, and the
 * value can only come from the gap fill or the mean (or a wrong match):
 * on the Middlebury sets most of these are wrong. Counted in out_of_view;
 * the confidence is cleared by the caller's final pass. Only the first
 * gdmax + 1 columns can hold such a value. */
void stx_out_of_view(stx_t *s, negobs_image_s16_t *disp)
{
    int32_t y;
    int32_t xend = (s->gdmax + 1 < s->w) ? s->gdmax + 1 : s->w;
    for (y = 0; y < s->h; y++) {
        int16_t *row = negobs_image_s16_row(disp, y);
        int32_t x;
        for (x = 0; x < xend; x++) {
            if (row[x] != NEGOBS_DISP_INVALID &&
                (int32_t)row[x] > x * NEGOBS_DISP_ONE) {
                row[x] = NEGOBS_DISP_INVALID;
                s->st.out_of_view++;
            }
        }
    }
}
