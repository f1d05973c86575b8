/*
 * Stage 4: two-stage dynamic programming (Sun 2002), banded around the GCS
 * disparities.
 *
 * Stage 1 runs along each row over the states d of a per-column band:
 *   matched pixel (GCS d):  [d - band, d + band]; the GCS cell (d) scores
 *                           1.0 and the other cells are unvisited (neutral),
 *                           or with dp_rescore every cell is scored with MNCC
 *   hole pixel:             [min(dl, dr) - band, max(dl, dr) + band] from the
 *                           nearest matched pixels left/right on the row;
 *                           these cells are never scored ("unvisited") and
 *                           get the neutral score dp_neutral_q14.
 *   Y(x, d) = cost(x, d) + max( Y(x-1, d-1), Y(x-1, d), Y(x-1, d+1),
 *                               max_d' Y(x-1, d') - dp_jump )
 * i.e. Sun's |dd| <= 1 smoothness plus a penalised jump, which the band
 * needs where it moves by more than one level between columns.
 * Stage 2 (dp_stage2.c) runs down the end column x = W-1 over the
 * normalised end scores Y(W-1, y, d) - max_d Y(W-1, y, d) with the same
 * recurrence and picks one end disparity per row; each row is then
 * back-tracked from it.
 *
 * Memory: one row of pointers and costs (W x D bytes + W x D int16), the
 * stage-2 pointers (H x D bytes). Stage 1 runs twice per row (once to feed
 * stage 2, once with pointers for the back-track), recomputing its costs,
 * instead of keeping W x H x D pointers, except where scratch idle during
 * the DP is lent to it (dp_store.c: the growth's memo in the fast profile,
 * its strip scratch otherwise): the feeding pass keeps the band cells'
 * pointers (~5.5 per pixel; a byte each in the memo, two bits in the
 * smaller strip scratch) and jump targets of as many rows as fit, and
 * those rows are back-tracked without running stage 1 again. The GCS
 * correlation of the selected cell is not kept (it would cost a byte per
 * pixel), so it scores 1.0; with dp_rescore = 1 the band is re-correlated
 * instead (20 % slower on Cones, same quality).
 *
 * Scaling and overflow: costs are Q14 in [-16384, 16384], dp_jump is
 * limited to [0, 32768], so |Y| <= W * 49152 < 2^28 for W <= 4096 and the
 * NEG sentinel (-2^30) is never reached by a real path. Stage 2 sums up to
 * 4096 rows of values >= -2^28 in int64.
 */
#include <string.h>

#include "stereo/dp_store.h"
#include "stereo/stereo_int.h"

#define NEG32 STX_DP_NEG32

/* Bands of one row; returns their cells (states summed over the columns),
 * or 0 when the row has no GCS match at all (the bands are then left as
 * they were: nothing reads them). A run of holes between two matches (or a
 * match and the row's end) shares one band, so it is found once per run
 * and stored. */
static int32_t row_bands(stx_t *s, const int16_t *g)
{
    const int32_t w = s->w;
    const int32_t b = s->cfg.band;
    const int32_t lo_lim = s->gdmin;
    const int32_t hi_lim = s->gdmax;
    int16_t *blo = s->blo;
    int16_t *bhi = s->bhi;
    uint8_t *bscored = s->bscored;
    int32_t last = NEGOBS_DISP_INVALID; /* nearest match on the left */
    int32_t x = 0;
    int32_t span = 0; /* the cells but one per column */

    while (x < w) {
        int32_t lo;
        int32_t hi;
        if (g[x] != NEGOBS_DISP_INVALID) {
            last = g[x];
            lo = negobs_clamp_s32(last - b, lo_lim, hi_lim);
            hi = negobs_clamp_s32(last + b, lo, hi_lim);
            blo[x] = (int16_t)lo;
            bhi[x] = (int16_t)hi;
            bscored[x] = 1u;
            span += hi - lo;
            x++;
        } else {
            int32_t e = x + 1;
            int32_t dl = last;
            int32_t dr;
            while (e < w && g[e] == NEGOBS_DISP_INVALID) {
                e++;
            }
            dr = (e < w) ? g[e] : NEGOBS_DISP_INVALID;
            if (dl == NEGOBS_DISP_INVALID) {
                if (dr == NEGOBS_DISP_INVALID) {
                    return 0; /* the whole row is one run of holes */
                }
                dl = dr;
            }
            if (dr == NEGOBS_DISP_INVALID) {
                dr = dl;
            }
            lo = negobs_clamp_s32(((dl < dr) ? dl : dr) - b, lo_lim, hi_lim);
            hi = negobs_clamp_s32(((dl > dr) ? dl : dr) + b, lo, hi_lim);
            span += (hi - lo) * (e - x);
            for (; x < e; x++) {
                blo[x] = (int16_t)lo;
                bhi[x] = (int16_t)hi;
                bscored[x] = 0u;
            }
        }
    }
    return span + w;
}

/* Stage 1 forward pass; returns the index (d - dmin) of the best end.
 * `keep` is a literal at both call sites, so the compiler can drop the
 * pointer stores of the feeding pass. Pointers and costs go to s->p1 and
 * s->cost with stride ndisp. */
static inline int32_t stage1_run(stx_t *s, int32_t y, int keep)
{
    int32_t w = s->w;
    int32_t nd = s->ndisp;
    int32_t dmin = s->dmin;
    int32_t jump = s->cfg.dp_jump_q14;
    int32_t neutral = s->cfg.dp_neutral_q14;
    int rescore = s->cfg.dp_rescore;
    int32_t *yp = s->yprev + 1; /* index -1 .. nd valid */
    int32_t *yc = s->ycur + 1;
    int32_t x;
    int32_t i;
    int32_t bestp = 0;
    int32_t argp = 0;
    int32_t plo = 0;
    int32_t phi = -1; /* band of yc's stale content (column x-2) */
    int32_t qlo = 0;  /* band of yp's content (column x-1)          */
    int32_t qhi = -1;
    int32_t lo;
    int32_t hi;

    for (i = -1; i <= nd; i++) {
        yp[i] = NEG32;
        yc[i] = NEG32;
    }
    for (x = 0; x < w; x++) {
        int32_t bcur = NEG32;
        int32_t acur = 0;
        int scored = s->bscored[x];
        int16_t *crow = s->cost + (ptrdiff_t)x * nd;
        uint8_t *prow = s->p1 + (ptrdiff_t)x * nd;
        /* without rescoring the band is neutral but for the GCS cell */
        int32_t gi = (scored && !rescore) ? s->gcs_cur[x] - dmin : -2;
        int32_t cjump = bestp - jump;
        lo = s->blo[x] - dmin;
        hi = s->bhi[x] - dmin;
        for (i = plo; i <= phi; i++) {
            yc[i] = NEG32;
        }
        for (i = lo; i <= hi; i++) {
            int32_t c = neutral;
            int32_t m;
            int32_t t;
            if (i == gi) {
                c = STX_ONE_Q14;
            } else if (scored && rescore) {
                s->st.visited_cells++;
                c = stx_mncc_strip(s, x, y, i + dmin);
                if (c == STX_FLAT) {
                    c = neutral;
                }
            }
            if (x == 0) {
                m = 0;
                t = 1;
            } else {
                m = yp[i];
                t = 1;
                if (yp[i - 1] > m) {
                    m = yp[i - 1];
                    t = 0;
                }
                if (yp[i + 1] > m) {
                    m = yp[i + 1];
                    t = 2;
                }
                if (cjump > m) {
                    m = cjump;
                    t = 3;
                }
            }
            yc[i] = m + c;
            if (keep) {
                crow[i] = (int16_t)c;
                prow[i] = (uint8_t)t;
            }
            if (yc[i] > bcur) {
                bcur = yc[i];
                acur = i;
            }
        }
        if (keep) {
            s->jump_to[x] = (int16_t)argp;
        }
        {
            int32_t *tmp = yp;
            yp = yc;
            yc = tmp;
        }
        /* yc now holds column x-1: its band is the previous lo/hi */
        plo = qlo;
        phi = qhi;
        qlo = lo;
        qhi = hi;
        bestp = bcur;
        argp = acur;
    }
    /* yp holds the last column; copy it to yprev for the caller */
    if (yp != s->yprev + 1) {
        memcpy(s->yprev, s->ycur, (size_t)(nd + 2) * sizeof *s->yprev);
    }
    return argp;
}

/* Empty yc's stale band [plo, phi] (column x-2) where column x's band
 * [lo, hi] will not overwrite it: the cells outside a column's band must
 * read as NEG32 for the next column and for stage 2. */
static inline void clear_stale(int32_t *yc, int32_t plo, int32_t phi,
                               int32_t lo, int32_t hi)
{
    int32_t i;
    int32_t e = (phi < lo - 1) ? phi : lo - 1;
    for (i = plo; i <= e; i++) {
        yc[i] = NEG32;
    }
    for (i = (plo > hi + 1) ? plo : hi + 1; i <= phi; i++) {
        yc[i] = NEG32;
    }
}

/* Stage 1 of the feeding pass without rescoring: only the end column's
 * scores (left in yprev) and each column's best value are needed, not the
 * pointers nor the argmax, and every band cell but the GCS one costs the
 * same neutral score. So each cell is the max of four values plus one
 * constant, and the GCS cell gets its difference afterwards: the same sums
 * as stage1_run(s, y, 0) (m + neutral + (1.0 - neutral) = m + 1.0, no
 * overflow: |Y| < 2^28), in a loop the compiler can vectorise. */
static void stage1_feed(stx_t *s)
{
    const int32_t w = s->w;
    const int32_t nd = s->ndisp;
    const int32_t dmin = s->dmin;
    const int32_t jump = s->cfg.dp_jump_q14;
    const int32_t neutral = s->cfg.dp_neutral_q14;
    int32_t *yp = s->yprev + 1; /* index -1 .. nd valid */
    int32_t *yc = s->ycur + 1;
    /* the row's inputs in locals: the stores below cannot move them */
    const uint8_t *const bscored = s->bscored;
    const int16_t *const gcs = s->gcs_cur;
    const int16_t *const blo = s->blo;
    const int16_t *const bhi = s->bhi;
    int32_t x;
    int32_t i;
    int32_t bestp = 0;
    int32_t plo = 0;
    int32_t phi = -1; /* band of yc's stale content (column x-2) */
    int32_t qlo = 0;  /* band of yp's content (column x-1)          */
    int32_t qhi = -1;

    for (i = -1; i <= nd; i++) {
        yp[i] = NEG32;
        yc[i] = NEG32;
    }
    for (x = 0; x < w; x++) {
        int32_t bcur = NEG32;
        int32_t gi = bscored[x] ? gcs[x] - dmin : -2;
        int32_t lo = blo[x] - dmin;
        int32_t hi = bhi[x] - dmin;
        clear_stale(yc, plo, phi, lo, hi);
        if (x == 0) {
            for (i = lo; i <= hi; i++) {
                yc[i] = neutral;
            }
            bcur = (lo <= hi) ? neutral : NEG32;
        } else {
            const int32_t cjump = bestp - jump;
            const int32_t *restrict pp = yp;
            int32_t *restrict cc = yc;
            for (i = lo; i <= hi; i++) {
                int32_t m = pp[i];
                int32_t v;
                m = (pp[i - 1] > m) ? pp[i - 1] : m;
                m = (pp[i + 1] > m) ? pp[i + 1] : m;
                m = (cjump > m) ? cjump : m;
                v = m + neutral;
                cc[i] = v;
                bcur = (v > bcur) ? v : bcur;
            }
        }
        if (gi >= lo && gi <= hi) {
            yc[gi] += STX_ONE_Q14 - neutral;
            if (yc[gi] > bcur) {
                bcur = yc[gi];
            }
        }
        {
            int32_t *tmp = yp;
            yp = yc;
            yc = tmp;
        }
        plo = qlo;
        phi = qhi;
        qlo = lo;
        qhi = hi;
        bestp = bcur;
    }
    if (yp != s->yprev + 1) {
        memcpy(s->yprev, s->ycur, (size_t)(nd + 2) * sizeof *s->yprev);
    }
}

/* Stage 1 with pointers without rescoring: stage1_run(s, y, 1) with the
 * GCS cell's score added after the band loop (as in stage1_feed), so the
 * loop carries no per-cell cost test. Raising one cell cannot move the
 * first argmax anywhere but to that cell. The cost row is left unwritten:
 * only score_at() reads it, and only with dp_rescore. The pointers go to
 * `cells` as `layout` says (STX_P1_*: with stride ndisp, or column after
 * column from each band's low end, a byte or two bits each), each column's
 * jump target to jump_to (int16 for STX_P1_STRIDED, else bytes: ndisp <=
 * 256). Returns the last column's argmax and leaves its scores in yprev,
 * as stage1_feed does. */
static inline __attribute__((always_inline)) int32_t stage1_keep(
    stx_t *s, uint8_t *cells, void *jump_to, int layout)
{
    const int32_t w = s->w;
    const int32_t nd = s->ndisp;
    const int32_t dmin = s->dmin;
    const int32_t jump = s->cfg.dp_jump_q14;
    const int32_t neutral = s->cfg.dp_neutral_q14;
    int32_t *yp = s->yprev + 1; /* index -1 .. nd valid */
    int32_t *yc = s->ycur + 1;
    /* the row's inputs and outputs in locals: the pointer stores (bytes,
     * which may alias anything) would otherwise reload them per column */
    const uint8_t *const bscored = s->bscored;
    const int16_t *const gcs = s->gcs_cur;
    const int16_t *const blo = s->blo;
    const int16_t *const bhi = s->bhi;
    uint8_t *prow = cells;
    stx_bitw_t bw;
    int32_t x;
    int32_t i;
    int32_t bestp = 0;
    int32_t argp = 0;
    int32_t plo = 0;
    int32_t phi = -1; /* band of yc's stale content (column x-2) */
    int32_t qlo = 0;  /* band of yp's content (column x-1)          */
    int32_t qhi = -1;

    bw.base = cells;
    bw.pos = 0;
    bw.word = 0;
    bw.n = 0;
    for (i = -1; i <= nd; i++) {
        yp[i] = NEG32;
        yc[i] = NEG32;
    }
    for (x = 0; x < w; x++) {
        int32_t bcur = NEG32;
        int32_t acur = 0;
        int32_t gi = bscored[x] ? gcs[x] - dmin : -2;
        int32_t lo = blo[x] - dmin;
        int32_t hi = bhi[x] - dmin;
        clear_stale(yc, plo, phi, lo, hi);
        if (x == 0) {
            for (i = lo; i <= hi; i++) {
                yc[i] = neutral;
                if (layout == STX_P1_BITS) {
                    stx_bitw_put(&bw, 1u);
                } else {
                    prow[layout == STX_P1_BYTES ? i - lo : i] = 1u;
                }
            }
            if (lo <= hi) {
                bcur = neutral;
                acur = lo;
            }
        } else {
            const int32_t cjump = bestp - jump;
            const int32_t *restrict pp = yp;
            int32_t *restrict cc = yc;
            for (i = lo; i <= hi; i++) {
                int32_t m = pp[i];
                int32_t t = 1;
                int32_t v;
                if (pp[i - 1] > m) {
                    m = pp[i - 1];
                    t = 0;
                }
                if (pp[i + 1] > m) {
                    m = pp[i + 1];
                    t = 2;
                }
                if (cjump > m) {
                    m = cjump;
                    t = 3;
                }
                v = m + neutral;
                cc[i] = v;
                if (layout == STX_P1_BITS) {
                    stx_bitw_put(&bw, (uint32_t)t);
                } else {
                    prow[layout == STX_P1_BYTES ? i - lo : i] = (uint8_t)t;
                }
                if (v > bcur) {
                    bcur = v;
                    acur = i;
                }
            }
        }
        if (gi >= lo && gi <= hi) {
            int32_t v = yc[gi] + (STX_ONE_Q14 - neutral);
            yc[gi] = v;
            if (v > bcur || (v == bcur && gi < acur)) {
                bcur = v;
                acur = gi;
            }
        }
        if (layout == STX_P1_STRIDED) {
            ((int16_t *)jump_to)[x] = (int16_t)argp;
            prow += nd;
        } else {
            ((uint8_t *)jump_to)[x] = (uint8_t)argp;
            prow += hi - lo + 1;
        }
        {
            int32_t *tmp = yp;
            yp = yc;
            yc = tmp;
        }
        plo = qlo;
        phi = qhi;
        qlo = lo;
        qhi = hi;
        bestp = bcur;
        argp = acur;
    }
    if (yp != s->yprev + 1) {
        memcpy(s->yprev, s->ycur, (size_t)(nd + 2) * sizeof *s->yprev);
    }
    if (layout == STX_P1_BITS && bw.n > 0) {
        stx_bitw_flush(&bw);
    }
    return argp;
}

/* The two-bit form out of line (inline, it made the byte form's code in
 * stx_dp_row slower). */
static __attribute__((noinline)) int32_t stage1_keep_bits(stx_t *s,
                                                          uint8_t *rec)
{
    return stage1_keep(s, rec + s->w + 1, rec, STX_P1_BITS);
}

static int32_t stage1(stx_t *s, int32_t y, int keep)
{
    return keep ? stage1_run(s, y, 1) : stage1_run(s, y, 0);
}

static int32_t score_at(stx_t *s, int32_t x, int32_t y, int32_t d)
{
    if (!s->cfg.dp_rescore || d < s->blo[x] || d > s->bhi[x] ||
        !s->bscored[x]) {
        if (d < s->gdmin || d > s->gdmax) {
            return STX_FLAT;
        }
        s->st.visited_cells++;
        return stx_mncc_strip(s, x, y, d);
    }
    {
        int32_t c = s->cost[(ptrdiff_t)x * s->ndisp + (d - s->dmin)];
        return c;
    }
}

/* What score3() reads for one row, looked up once per row. */
typedef struct score_row {
    const stx_t *s;
    int32_t w, gdmin, gdmax;
    uint32_t tex_min;
    int row_ok;           /* y inside the strip                     */
    ptrdiff_t il0;        /* strip index of (0, y)                  */
    ptrdiff_t ls, rs;     /* strides                                */
    ptrdiff_t loff, roff; /* offsets of the windows' top rows       */
    uint32_t visited;     /* cells scored, added to the stats once  */
} score_row_t;

static void score_row_init(score_row_t *r, const stx_t *s, int32_t y)
{
    r->s = s;
    r->w = s->w;
    r->gdmin = s->gdmin;
    r->gdmax = s->gdmax;
    r->tex_min = (uint32_t)s->cfg.texture_min;
    r->row_ok = y >= s->y0 && y < s->y1;
    r->il0 = (ptrdiff_t)(y - s->y0) * s->w;
    r->ls = s->left->stride;
    r->rs = s->right->stride;
    r->loff = (ptrdiff_t)(y - STX_WIN_R) * r->ls;
    r->roff = (ptrdiff_t)(y + s->voff - STX_WIN_R) * r->rs;
    r->visited = 0;
}

/* score_at(d - 1), score_at(d), score_at(d + 1) without dp_rescore, in
 * one go: the left window, its statistics and the bounds are shared. Same
 * values and visited count as three stx_mncc_strip() calls. */
static void score3(score_row_t *r, int32_t x, int32_t d, int32_t c[3])
{
    const stx_t *s = r->s;
    const int32_t w = r->w;
    int32_t j;
    ptrdiff_t il = r->il0 + x;
    int left_ok = x >= STX_WIN_R && x < w - STX_WIN_R && r->row_ok &&
                  s->vl[il] != 0u;
    const uint8_t *a = NULL;
    uint32_t sl = 0;
    uint32_t vl = 0;
    if (left_ok) {
        a = s->left->data + r->loff + x - STX_WIN_R;
        sl = s->sl[il];
        vl = s->vl[il];
    }
#if defined(STX_CROSS5X3_SIMD)
    /* the usual case: all three cells in range and inside; the right
     * windows' top-left columns are ur - 1 .. ur + 1 - 2, one 8-byte load
     * per row from x - d - 3 (ends at x - d + 4 < w), the left one ends at
     * x + 5 < w; vr != 0 proves the right rows are inside the image */
    if (left_ok && d - 1 >= r->gdmin && d + 1 <= r->gdmax &&
        x - d - 1 >= STX_WIN_R && x - d + 4 < w && x + 5 < w &&
        s->vr[il - d + 1] != 0u && s->vr[il - d] != 0u &&
        s->vr[il - d - 1] != 0u) {
        uint32_t xs3[3];
        stx_cross5x3_simd(a, r->ls, s->right->data + r->roff + x - d - 3,
                          r->rs, xs3);
        r->visited += 3u;
        for (j = 0; j < 3; j++) {
            int32_t dj = d - 1 + j;
            int32_t n2;
            int32_t den;
            /* right window of dj starts at x - dj - 2 = (x - d - 3) + 2 - j */
            c[j] = STX_FLAT;
            if (stx_mncc_num_den(xs3[2 - j], sl, vl, s->sr[il - dj],
                                 s->vr[il - dj], r->tex_min, &n2, &den)) {
                c[j] = stx_frac_q14(n2, den);
            }
        }
        return;
    }
#endif
    for (j = 0; j < 3; j++) {
        int32_t dj = d - 1 + j;
        int32_t ur = x - dj;
        int32_t n2;
        int32_t den;
        const uint8_t *b;
        uint32_t xs;
        uint32_t vr;
        c[j] = STX_FLAT;
        if (dj < r->gdmin || dj > r->gdmax) {
            continue;
        }
        r->visited++;
        if (!left_ok || ur < STX_WIN_R || ur >= w - STX_WIN_R) {
            continue;
        }
        vr = s->vr[il - dj];
        if (vr == 0u) {
            continue;
        }
        b = s->right->data + r->roff + ur - STX_WIN_R;
#if defined(STX_CROSS5_SIMD)
        xs = (x + 5 < w) ? stx_cross5_simd(a, r->ls, b, r->rs)
                         : stx_cross5_ref(a, r->ls, b, r->rs);
#else
        xs = stx_cross5_ref(a, r->ls, b, r->rs);
#endif
        if (stx_mncc_num_den(xs, sl, vl, s->sr[il - dj], vr, r->tex_min, &n2,
                             &den)) {
            c[j] = stx_frac_q14(n2, den);
        }
    }
}

/* Integer disparities of one row into outrow, back-tracked from end
 * disparity d (inside the last column's band) over the pointers `cells`
 * (n of them, in stage1_keep's `layout`, a literal) and the jump
 * targets. */
static inline __attribute__((always_inline)) void back_track(
    const stx_t *s, int32_t d, const uint8_t *cells, int32_t n,
    const void *jump, int16_t *outrow, int layout)
{
    const int16_t *const blo = s->blo;
    const int16_t *const bhi = s->bhi;
    const int32_t dmin = s->dmin;
    const uint8_t *p = cells + n; /* end of column x's pointers (bytes) */
    size_t b = (size_t)n * 2u;    /* the same in bits (two-bit fields)  */
    int32_t x;
    for (x = s->w - 1; x >= 0; x--) {
        int32_t lo = blo[x];
        int t;
        outrow[x] = (int16_t)d;
        if (x == 0) {
            break;
        }
        if (layout == STX_P1_BITS) {
            size_t k;
            b -= (size_t)(bhi[x] - lo + 1) * 2u;
            k = b + (size_t)(d - lo) * 2u;
            t = (cells[k >> 3] >> (k & 7u)) & 3;
        } else if (layout == STX_P1_BYTES) {
            p -= bhi[x] - lo + 1;
            t = p[d - lo];
        } else {
            t = cells[(ptrdiff_t)x * s->ndisp + (d - dmin)];
        }
        if (t == 3) {
            d = ((layout == STX_P1_STRIDED) ? ((const int16_t *)jump)[x]
                                            : ((const uint8_t *)jump)[x]) +
                dmin;
        } else {
            d = d + t - 1;
        }
        d = negobs_clamp_s32(d, blo[x - 1], bhi[x - 1]);
    }
}

void stx_dp_row(stx_t *s, int32_t y, const int16_t *gcsrow, int pass,
                int16_t *outrow, uint8_t *confrow)
{
    int32_t w = s->w;
    int32_t nd = s->ndisp;
    int32_t dmin = s->dmin;
    int32_t x;
    int32_t d;
    score_row_t srow;
    int32_t cells = row_bands(s, gcsrow);
    int have = cells > 0;
    uint8_t *rec;

    s->gcs_cur = gcsrow;

    if (pass == 0) {
        rec = have ? stx_dp_store_take(s, cells) : NULL;
        if (rec != NULL) {
            /* stage 1 once: its pointers kept for the back-track */
            rec[w] = (uint8_t)((stx_dp_store_layout(s) == STX_P1_BITS)
                                   ? stage1_keep_bits(s, rec)
                                   : stage1_keep(s, rec + w + 1, rec,
                                                 STX_P1_BYTES));
        } else if (have && !s->cfg.dp_rescore) {
            stage1_feed(s);
        } else if (have) {
            (void)stage1(s, y, 0);
        }
        if (s->yend != NULL) {
            /* bands run at once: stage 2 takes the rows in order later */
            s->yhave[y] = (uint8_t)have;
            if (have) {
                memcpy(s->yend + (ptrdiff_t)y * nd, s->yprev + 1,
                       (size_t)nd * sizeof *s->yend);
            }
        } else {
            stx_dp_stage2_feed(s, y, have, s->yprev + 1);
        }
        return;
    }
    if (!have) {
        for (x = 0; x < w; x++) {
            outrow[x] = NEGOBS_DISP_INVALID;
            if (confrow != NULL) {
                confrow[x] = 0;
            }
        }
        return;
    }
    rec = stx_dp_store_take(s, cells);
    if (rec != NULL) {
        d = s->dend[y];
        if (d < s->blo[w - 1] || d > s->bhi[w - 1]) {
            /* (the clamp keeps the record's reads inside the bands) */
            d = negobs_clamp_s32(rec[w] + dmin, s->blo[w - 1], s->bhi[w - 1]);
        }
        if (stx_dp_store_layout(s) == STX_P1_BITS) {
            back_track(s, d, rec + w + 1, cells, rec, outrow, STX_P1_BITS);
        } else {
            back_track(s, d, rec + w + 1, cells, rec, outrow, STX_P1_BYTES);
        }
    } else {
        int32_t endarg = s->cfg.dp_rescore ? stage1(s, y, 1)
                                           : stage1_keep(s, s->p1, s->jump_to,
                                                         STX_P1_STRIDED);
        d = s->dend[y];
        if (d < s->blo[w - 1] || d > s->bhi[w - 1]) {
            d = endarg + dmin;
        }
        back_track(s, d, s->p1, cells, s->jump_to, outrow, STX_P1_STRIDED);
    }
    /* stage 5a: sub-pixel refinement and confidence */
    score_row_init(&srow, s, y);
    for (x = 0; x < w; x++) {
        int32_t di = outrow[x];
        int32_t c0;
        int32_t cm;
        int32_t cp;
        if (s->cfg.dp_rescore) {
            c0 = score_at(s, x, y, di);
            cm = score_at(s, x, y, di - 1);
            cp = score_at(s, x, y, di + 1);
        } else {
            int32_t c3[3];
            score3(&srow, x, di, c3);
            cm = c3[0];
            c0 = c3[1];
            cp = c3[2];
        }
        int32_t off = 0;
        int32_t conf = 0;
        if (c0 != STX_FLAT && cm != STX_FLAT && cp != STX_FLAT) {
            int32_t den = cm - 2 * c0 + cp;
            if (den < 0) {
                int64_t o = negobs_div_round_s64((int64_t)16 * (cm - cp),
                                                 (int64_t)2 * den);
                off = (int32_t)((o > 8) ? 8 : ((o < -8) ? -8 : o));
                if (s->cfg.subpixel_halfshift) {
                    off = stx_subpix_halfshift_q4(s, x, y, di, cm, c0, cp,
                                                  off);
                }
            }
        }
        if (c0 != STX_FLAT) {
            conf = (c0 > 0) ? (c0 * 255) >> 14 : 0;
            if (!s->bscored[x]) {
                conf >>= 1;
            }
            /* a measured value, however weak, stays above the fill and
             * textureless codes (negobs/stereo.h) */
            conf = (conf > NEGOBS_STEREO_CONF_MATCHED_MIN)
                       ? conf
                       : NEGOBS_STEREO_CONF_MATCHED_MIN;
        } else {
            conf = NEGOBS_STEREO_CONF_FLAT;
        }
        outrow[x] = (int16_t)(di * NEGOBS_DISP_ONE + off);
        if (confrow != NULL) {
            confrow[x] = (uint8_t)negobs_clamp_s32(conf, 0, 255);
        }
    }
    s->st.visited_cells += srow.visited;
}
