/*
 * Integer 5x5 Moravec NCC (MNCC), the similarity of every matching stage.
 *
 *   S = sum of 25 grey values           <= 6 375        (13 bits)
 *   Q = sum of 25 squares               <= 1 625 625    (21 bits)
 *   V = 25 Q - S^2   (= 25^2 variance)  <= 10 160 156   (24 bits)
 *   X = sum of 25 products L R          <= 1 625 625    (21 bits)
 *   num = 25 X - SL SR                  |num| <= sqrt(VL VR) < 2^24
 *   MNCC = 2 num / (VL + VR)            in [-1, 1], VL + VR < 2^25
 *
 * MNCC (Moravec NCC) is used instead of Pearson NCC because it needs
 * no square root and is the measure the GCS thresholds were tuned for; it
 * also penalises a contrast change between the windows.
 *
 * Scaling and overflow: every sum fits int32/uint32. For the Q14 result the
 * numerator 2|num| and the denominator VL+VR (2|num| <= VL+VR by the AM-GM
 * inequality) are shifted right together until the denominator is below
 * 2^17, so (2|num| << 14) < 2^31 and a 32-bit division suffices; the result
 * is rounded towards zero, |MNCC_q14| <= 16384.
 */
#include <string.h>

#include "stereo/stereo_int.h"
#include "stereo/stereo_simd.h"

void stx_stats_row_ref(const uint8_t *const rows[5], int32_t w, uint16_t *so,
                       uint32_t *vo)
{
    /* running horizontal sum of 5 column sums (ring of 5) */
    uint32_t cs[5];
    uint32_t cq[5];
    uint32_t ss = 0;
    uint32_t qq = 0;
    int32_t x;
    int32_t k;

    for (x = 0; x < w; x++) {
        uint32_t c = 0;
        uint32_t q = 0;
        int32_t slot = x % 5;
        for (k = 0; k < 5; k++) {
            uint32_t p = rows[k][x];
            c += p;
            q += p * p;
        }
        if (x >= 5) {
            ss -= cs[slot];
            qq -= cq[slot];
        }
        cs[slot] = c;
        cq[slot] = q;
        ss += c;
        qq += q;
        if (x >= 4) {
            int32_t xc = x - STX_WIN_R;
            so[xc] = (uint16_t)ss;
            vo[xc] = (uint32_t)STX_WIN_N * qq - ss * ss;
        }
    }
}

void stx_stats_rows(const negobs_image_u8_t *img, int32_t ya, int32_t n,
                    uint16_t *s, uint32_t *v)
{
    int32_t w = img->width;
    int32_t r;

    for (r = 0; r < n; r++) {
        int32_t y = ya + r;
        uint16_t *so = s + (ptrdiff_t)r * w;
        uint32_t *vo = v + (ptrdiff_t)r * w;
        const uint8_t *rows[5];
        int32_t k;

        memset(so, 0, (size_t)w * sizeof *so);
        memset(vo, 0, (size_t)w * sizeof *vo);
        if (y < STX_WIN_R || y >= img->height - STX_WIN_R) {
            continue;
        }
        for (k = 0; k < 5; k++) {
            rows[k] = negobs_image_u8_row(img, y - STX_WIN_R + k);
        }
        stx_stats_row(rows, w, so, vo);
    }
}

int32_t stx_mncc_q14(uint32_t sum_lr, uint32_t sl, uint32_t vl, uint32_t sr,
                     uint32_t vr, uint32_t tex_min)
{
    int32_t n2;
    int32_t den;
    if (!stx_mncc_num_den(sum_lr, sl, vl, sr, vr, tex_min, &n2, &den)) {
        return STX_FLAT;
    }
    return stx_frac_q14(n2, den);
}

int32_t stx_mncc_strip(const stx_t *s, int32_t u, int32_t v, int32_t d)
{
    int32_t n2;
    int32_t den;
    if (!stx_mncc_frac(s, u, v, d, &n2, &den)) {
        return STX_FLAT;
    }
    return stx_frac_q14(n2, den);
}

void stx_sums5(const negobs_image_u8_t *img, int32_t x, int32_t y,
               uint32_t *sum, uint32_t *var)
{
    uint32_t a = 0;
    uint32_t q = 0;
    int32_t k;
    int32_t j;
    for (k = -STX_WIN_R; k <= STX_WIN_R; k++) {
        const uint8_t *p = negobs_image_u8_row(img, y + k) + x;
        for (j = -STX_WIN_R; j <= STX_WIN_R; j++) {
            uint32_t g = p[j];
            a += g;
            q += g * g;
        }
    }
    *sum = a;
    *var = (uint32_t)STX_WIN_N * q - a * a;
}

int32_t stx_mncc_direct(const stx_t *s, int32_t u, int32_t v, int32_t d,
                        int32_t voff)
{
    int32_t ur = u - d;
    int32_t vr = v + voff;
    uint32_t sl;
    uint32_t vl;
    uint32_t sr;
    uint32_t vrr;

    if (u < STX_WIN_R || u >= s->w - STX_WIN_R || ur < STX_WIN_R ||
        ur >= s->w - STX_WIN_R || v < STX_WIN_R || v >= s->h - STX_WIN_R ||
        vr < STX_WIN_R || vr >= s->h - STX_WIN_R) {
        return STX_FLAT;
    }
    stx_sums5(s->left, u, v, &sl, &vl);
    stx_sums5(s->right, ur, vr, &sr, &vrr);
    if (vl == 0u || vrr == 0u) {
        return STX_FLAT;
    }
    return stx_mncc_q14(stx_cross5(s->left, u, v, s->right, ur, vr), sl, vl,
                        sr, vrr, (uint32_t)s->cfg.texture_min);
}

void stx_strip_stats(stx_t *s, int32_t y0, int32_t y1)
{
    s->y0 = y0;
    s->y1 = y1;
    stx_stats_rows(s->left, y0, y1 - y0, s->sl, s->vl);
    stx_stats_rows(s->right, y0 + s->voff, y1 - y0, s->sr, s->vr);
}
