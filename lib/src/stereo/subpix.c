/*
 * Stage 5a, optional: the sub-pixel offset with its pull towards whole
 * pixels cancelled (config subpixel_halfshift).
 *
 * A parabola through the correlation at d - 1, d, d + 1 is biased
 * towards d: the estimate of a true offset t errs by about -a sin(2 pi t),
 * with a set by how sharp the texture's correlation peak is against the
 * pixel ("pixel locking"). Matching the right image shifted by half a
 * pixel puts its samples at d - 1/2 and d + 1/2, where the same bias has
 * the opposite sign, so the mean of the two estimates cancels most of it
 * (the error cancellation of Shimizu and Okutomi, 2005). On a floor, whose
 * disparity changes steadily from row to row, the bias is a ripple in the
 * rows with the period of one pixel of disparity, which a detector reads
 * as steps; docs/DISPARITY.md (stage 5) gives the measured figures.
 *
 * The shifted window takes b = R[x] + R[x - 1] (twice the linear
 * interpolation at x - 1/2) and pairs it with 2 L, so both sides keep the
 * MNCC's scale: with 9-bit values the window sums stay below 25 * 510 and
 * the n^2-variance terms below 2^28, so stx_mncc_num_den's int32 products
 * cannot overflow.
 */
#include "stereo/stereo_int.h"

/* Q8 offsets: one pixel = 256, the parabola clamped to half a pixel. */
#define SUBPIX_Q8_HALF 128

/* The left window at (x, y) and the shifted right columns around
 * disparity d: what the three shifted correlations share. */
typedef struct halfshift_win {
    const uint8_t *l[2 * STX_WIN_R + 1]; /* left rows, at column x - 2  */
    uint32_t sa, va;                     /* 2 L: sum and 25 Q - S^2     */
    /* b[j][i] = R[x0 + i] + R[x0 + i - 1] of right row j, x0 = x - d - 3:
     * the right windows of d - 3/2 .. d + 3/2 (5 columns + 3) */
    uint16_t b[2 * STX_WIN_R + 1][2 * STX_WIN_R + 4];
    uint32_t cs[2 * STX_WIN_R + 4]; /* column sums of b        */
    uint32_t cq[2 * STX_WIN_R + 4]; /* column sums of b^2      */
} halfshift_win_t;

/* Fills w for (x, y, d); 0 when a window of d - 3/2 .. d + 3/2 would
 * leave an image. */
static int halfshift_load(const stx_t *s, int32_t x, int32_t y, int32_t d,
                          halfshift_win_t *w)
{
    const negobs_image_u8_t *l = s->left;
    const negobs_image_u8_t *r = s->right;
    int32_t yr = y + s->voff;
    int32_t x0 = x - d - 3; /* R[x0 - 1 .. x0 + 7] are read */
    int32_t i;
    int32_t j;
    uint32_t sl = 0;
    uint32_t ql = 0;
    if (x - STX_WIN_R < 0 || x + STX_WIN_R >= l->width || y - STX_WIN_R < 0 ||
        y + STX_WIN_R >= l->height || x0 - 1 < 0 ||
        x0 + 2 * STX_WIN_R + 3 >= r->width || yr - STX_WIN_R < 0 ||
        yr + STX_WIN_R >= r->height) {
        return 0;
    }
    for (i = 0; i < 2 * STX_WIN_R + 4; i++) {
        w->cs[i] = 0;
        w->cq[i] = 0;
    }
    for (j = 0; j <= 2 * STX_WIN_R; j++) {
        const uint8_t *la = negobs_image_u8_row(l, y + j - STX_WIN_R) + x -
                            STX_WIN_R;
        const uint8_t *rb = negobs_image_u8_row(r, yr + j - STX_WIN_R) + x0;
        w->l[j] = la;
        for (i = 0; i <= 2 * STX_WIN_R; i++) {
            sl += la[i];
            ql += (uint32_t)la[i] * la[i];
        }
        for (i = 0; i < 2 * STX_WIN_R + 4; i++) {
            uint32_t b = (uint32_t)rb[i] + rb[i - 1];
            w->b[j][i] = (uint16_t)b;
            w->cs[i] += b;
            w->cq[i] += b * b;
        }
    }
    /* 2 L: the sum doubles, 25 Q - S^2 quadruples */
    w->sa = 2u * sl;
    w->va = 4u * (STX_WIN_N * ql - sl * sl);
    return 1;
}

/* MNCC (Q14) of the loaded left window against the right one at
 * disparity d - 3/2 + k (k = 0..3), STX_FLAT when both are flat: left
 * column x + i meets R at x + i - d + 3/2 - k, the mean of R[m] and
 * R[m - 1] for m = x + i - d + 2 - k, so b's columns 3 - k .. 7 - k. */
static int32_t halfshift_mncc(const stx_t *s, const halfshift_win_t *w,
                              int32_t k)
{
    int32_t c0 = 3 - k;
    uint32_t sb = 0;
    uint32_t qb = 0;
    uint32_t slb = 0;
    int32_t i;
    int32_t j;
    int32_t n2;
    int32_t den;
    for (i = 0; i <= 2 * STX_WIN_R; i++) {
        sb += w->cs[c0 + i];
        qb += w->cq[c0 + i];
    }
    for (j = 0; j <= 2 * STX_WIN_R; j++) {
        const uint8_t *a = w->l[j];
        const uint16_t *b = &w->b[j][c0];
        for (i = 0; i <= 2 * STX_WIN_R; i++) {
            slb += (uint32_t)a[i] * b[i];
        }
    }
    /* both values doubled (2 L against b): the cross sum is 2 slb, and
     * the texture floor in n^2 variance scales by 4 */
    if (!stx_mncc_num_den(2u * slb, w->sa, w->va, sb, STX_WIN_N * qb - sb * sb,
                          4u * (uint32_t)s->cfg.texture_min, &n2, &den)) {
        return STX_FLAT;
    }
    return stx_frac_q14(n2, den);
}

/* Vertex of the parabola through (-1, m), (0, c), (1, p) in Q8, clamped
 * to half a pixel; 0 with *ok = 0 when the three are no peak. The scores
 * are Q14, so |16 (m - p)| < 2^20 and the quotient fits easily. */
static int32_t parabola_q8(int32_t m, int32_t c, int32_t p, int *ok)
{
    int32_t den = m - 2 * c + p;
    int64_t o;
    if (den >= 0) {
        *ok = 0;
        return 0;
    }
    o = negobs_div_round_s64((int64_t)256 * (m - p), (int64_t)2 * den);
    *ok = 1;
    if (o > SUBPIX_Q8_HALF) {
        return SUBPIX_Q8_HALF;
    }
    return (o < -SUBPIX_Q8_HALF) ? -SUBPIX_Q8_HALF : (int32_t)o;
}

int32_t stx_subpix_halfshift_q4(const stx_t *s, int32_t x, int32_t y,
                                int32_t d, int32_t cm, int32_t c0, int32_t cp,
                                int32_t off_q4)
{
    halfshift_win_t w;
    int32_t lo;
    int32_t mid;
    int32_t hi;
    int32_t e1;
    int32_t e2;
    int32_t sum;
    int ok;
    e1 = parabola_q8(cm, c0, cp, &ok);
    if (!ok || !halfshift_load(s, x, y, d, &w)) {
        return off_q4;
    }
    /* the shifted samples' peak is the better of d -+ 1/2 (k = 1, 2);
     * the parabola goes through it and its other neighbour */
    lo = halfshift_mncc(s, &w, 1);
    hi = halfshift_mncc(s, &w, 2);
    if (lo == STX_FLAT || hi == STX_FLAT) {
        return off_q4;
    }
    if (lo >= hi) {
        mid = lo;
        lo = halfshift_mncc(s, &w, 0);
        e2 = -SUBPIX_Q8_HALF;
    } else {
        mid = hi;
        hi = halfshift_mncc(s, &w, 3);
        e2 = SUBPIX_Q8_HALF;
    }
    if (lo == STX_FLAT || hi == STX_FLAT) {
        return off_q4;
    }
    e2 += parabola_q8(lo, mid, hi, &ok);
    if (!ok) {
        return off_q4;
    }
    /* mean of the two in Q4: (e1 + e2) / 2 / 16 */
    sum = (int32_t)negobs_div_round_s64((int64_t)e1 + e2, 32);
    return negobs_clamp_s32(sum, -NEGOBS_DISP_ONE / 2, NEGOBS_DISP_ONE / 2);
}
