/*
 * Stage 2 + 3: Canny seeds and Growing Correspondence Seeds on one strip.
 *
 * Seeds: every seed_step-th Canny edge pixel of a row is matched with 5x5
 * MNCC over its tile range; it becomes a seed when the best score is
 * >= seed_tau and beats every score two or more levels away by
 * seed_margin. The matches of the row just above the strip (previous strip)
 * are re-scored on the first row and pushed too, so growth continues across
 * strip borders, though not across the border of a row band (bands.c): the
 * bands grow independently, so they can run at once.
 *
 * Growing (docs/DISPARITY.md): pop the best candidate, evaluate the 12-point
 * neighbourhood (sets N1..N4), and from each set consider only its best
 * member q. q is accepted when
 *   c(q) >= tau,
 *   q is not yet in the matching table (a bitset of (v, u, d) triples), and
 *   c(q) + mu >= min(CbL(u), CbR(u - d))       (margin rule),
 * where CbL / CbR are the best scores accepted so far at q's left / right
 * pixel. Accepted candidates are pushed into the bounded bucket queue.
 *
 * Final selection (strict sub-kernel, simplified): the table keeps per left
 * and per right pixel the best candidate and the best score of any
 * candidate more than `zonegap` levels away (its X-zone competitor). A left
 * pixel keeps its best disparity d only if the right pixel u - d has its best
 * within zonegap of d and c(1 - beta) is above both competitors; otherwise
 * it is left for the DP to fill. This is the one-shot form of Sara's
 * confidently-stable matching (no iterative deletion), slightly sparser.
 *
 * Table scores are Q8 (c_q14 >> 6, 0 = none), disparities u8 (d - dmin).
 */
#include <string.h>

#include "stereo/stereo_int.h"

static uint8_t to_q8(int32_t c)
{
    int32_t v = c >> 6;
    return (uint8_t)negobs_clamp_s32(v, 1, 255);
}

static void table_update(uint8_t *bd, uint8_t *bc, uint8_t *c2, int32_t d,
                         uint8_t c, int32_t gap)
{
    if (*bd == STX_NONE8) {
        *bd = (uint8_t)d;
        *bc = c;
        return;
    }
    if (c > *bc) {
        int32_t dd = d - (int32_t)*bd;
        if (dd > gap || dd < -gap) {
            if (*bc > *c2) {
                *c2 = *bc;
            }
        }
        *bd = (uint8_t)d;
        *bc = c;
    } else {
        int32_t dd = d - (int32_t)*bd;
        if ((dd > gap || dd < -gap) && c > *c2) {
            *c2 = c;
        }
    }
}

/* Matching-table bit of strip cell (u, vr, dr). */
static inline size_t table_bit(const stx_t *s, int32_t u, int32_t vr,
                               int32_t dr)
{
    return ((size_t)vr * (size_t)s->w + (size_t)u) * (size_t)s->ndisp +
           (size_t)dr;
}

static inline int table_has(const stx_t *s, size_t bit)
{
    return (int)(((uint32_t)s->tbits[bit >> 3] >> (bit & 7u)) & 1u);
}

/* Accept the candidate at left / right strip pixels il / ir, level dr
 * (= d - dmin), packed as `item`, with score c (>= tau, not in the table)
 * when the margin rule holds; push it when accepted. */
static int accept_at(stx_t *s, ptrdiff_t il, ptrdiff_t ir, int32_t dr,
                     int32_t c, size_t bit, uint32_t item)
{
    uint8_t c8 = to_q8(c);
    int32_t lim = (s->lc[il] < s->rc[ir]) ? s->lc[il] : s->rc[ir];
    if ((int32_t)c8 + (s->cfg.ncc_mu_q14 >> 6) < lim) {
        return 0;
    }
    s->tbits[bit >> 3] = (uint8_t)(s->tbits[bit >> 3] | (1u << (bit & 7u)));
    table_update(&s->ld[il], &s->lc[il], &s->lc2[il], dr, c8, s->cfg.zonegap);
    table_update(&s->rd[ir], &s->rc[ir], &s->rc2[ir], dr, c8, s->cfg.zonegap);
    s->st.grown++;
    stx_queue_push(&s->q, item, c >> 6);
    return 1;
}

/* accept_at() for candidate (u, v, d). */
static int accept_scored(stx_t *s, int32_t u, int32_t v, int32_t d, int32_t c,
                         size_t bit)
{
    int32_t vr = v - s->y0;
    int32_t dr = d - s->dmin;
    ptrdiff_t il = (ptrdiff_t)vr * s->w + u;
    return accept_at(s, il, il - d, dr, c, bit, stx_pack(u, vr, dr));
}

/* Try to accept candidate (u, v, d) with score c; push it when accepted. */
static int try_accept(stx_t *s, int32_t u, int32_t v, int32_t d, int32_t c)
{
    size_t bit;
    if (c == STX_FLAT || c < s->cfg.ncc_tau_q14) {
        return 0;
    }
    bit = table_bit(s, u, v - s->y0, d - s->dmin);
    if (table_has(s, bit)) {
        return 0;
    }
    return accept_scored(s, u, v, d, c, bit);
}

static int32_t eval(stx_t *s, int32_t u, int32_t v, int32_t d)
{
    if (d < s->gdmin || d > s->gdmax) {
        return STX_FLAT;
    }
    s->st.visited_cells++;
    return stx_mncc_strip(s, u, v, d);
}

/* The 12-point neighbourhood as (du, dd, dv), dd = du - du', grouped in
 * the sets N1 (left), N2 (right), N3 (up), N4 (down), 3 members each.
 * N3 and N4 keep the left column; the paper's diagonal members are
 * reached in two steps through N1 / N2 of the row above or below, for a
 * quarter fewer looks (docs/DISPARITY.md, "Stage 3"). */
#define NB_CELLS 12
static const int16_t nb_cell[NB_CELLS][3] = {
    {-1, 0, 0}, {-2, -1, 0}, {-1, 1, 0}, {1, 0, 0}, {2, 1, 0},  {1, -1, 0},
    {0, 0, -1}, {0, -1, -1}, {0, 1, -1}, {0, 0, 1}, {0, -1, 1}, {0, 1, 1},
};

/* Per-strip offsets of a neighbour relative to the popped cell, in every
 * index space the growing loop touches, so a cell costs additions only. */
typedef struct nb_off {
    int32_t du, dd, dv;
    ptrdiff_t pix; /* strip pixel index (left window statistics)      */
    ptrdiff_t rpx; /* the same for the right pixel (pix - dd)          */
    ptrdiff_t bit; /* matching-table bit                               */
    ptrdiff_t lp;  /* left window's top-left pixel                     */
    ptrdiff_t rp;  /* right window's top-left pixel                    */
    ptrdiff_t mo;  /* memo word (pix * memo_k)                         */
    uint32_t key;  /* packed cache key (fields never borrow: checked) */
    uint32_t hkey; /* key * the cache's hash multiplier (mod 2^32)     */
} nb_off_t;

/* What the growing loop reads: hoisted from stx_t once per strip, plus the
 * popped cell (strip-relative row vr, disparity dr = d - dmin). */
typedef struct grow_env {
    int32_t w, ny, drlo, drhi;
    uint32_t tex_min;
    const uint16_t *sl, *sr;
    const uint32_t *vl, *vr;
    const uint8_t *tbits;
    stx_cache_entry_t *cache;
    uint32_t *memo; /* NULL: compact profile                  */
    const uint8_t *memo_base;
    uint32_t memo_k, memo_gen; /* gen: the strip's stamp           */
    ptrdiff_t ls, rs;
    nb_off_t nb[NB_CELLS];
    /* popped cell */
    int32_t u, vrow, dr, ur;
    ptrdiff_t pix, rpix, bit0;
    const uint8_t *la, *rb;
    uint32_t *mrow; /* memo words of the popped pixel (fast profile) */
    uint32_t key0, hkey0;
    int interior;
} grow_env_t;

/* Raw 5x5 cross sum of neighbour o's windows (both inside the image). */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline uint32_t
grow_cross(const grow_env_t *g, const nb_off_t *o, int32_t qu, int interior)
{
    const uint8_t *a = g->la + o->lp;
    const uint8_t *b = g->rb + o->rp;
#if defined(STX_CROSS5_SIMD)
    /* the 8-byte loads end at column qu + 5 (the right one at
     * qur + 5 <= qu + 5) */
    if (interior || qu + 5 < g->w) {
        return stx_cross5_simd(a, g->ls, b, g->rs);
    }
#else
    (void)qu;
    (void)interior;
#endif
    return stx_cross5_ref(a, g->ls, b, g->rs);
}

/* The MNCC fraction of neighbour o (left pixel il, windows inside the
 * image) into *nn / *dn; left as 0 / 0 when a window is flat. Same values
 * as stx_mncc_num_den(): with vl, vr != 0 their sum (each < 2^24) is not
 * 0, so only the texture test remains. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void
grow_score(const grow_env_t *g, const nb_off_t *o, ptrdiff_t il, int32_t qu,
           int interior, int32_t *nn, int32_t *dn)
{
    ptrdiff_t ir = g->rpix + o->rpx;
    uint32_t vl = g->vl[il];
    uint32_t vrr = g->vr[ir];
    uint32_t den;
    uint32_t x;
    if (vl == 0u || vrr == 0u) {
        return;
    }
    den = vl + vrr;
    if (den < g->tex_min) {
        return;
    }
    x = grow_cross(g, o, qu, interior);
    *nn = 2 * ((int32_t)((uint32_t)STX_WIN_N * x) -
               (int32_t)((uint32_t)g->sl[il] * (uint32_t)g->sr[ir]));
    *dn = (int32_t)den;
}

/* Both windows of neighbour o inside the image (qu, qur its left and
 * right columns). */
static inline int member_inside(const grow_env_t *g, int32_t qu, int32_t qur,
                                int interior)
{
    return interior || (qu >= STX_WIN_R && qu < g->w - STX_WIN_R &&
                        qur >= STX_WIN_R && qur < g->w - STX_WIN_R);
}

/* Fast profile: the score of neighbour o from the strip's memo, computed
 * and kept on its first look. The memo holds every cell of the band, so
 * the compact profile's cache in front of it would only add a probe to
 * every look. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void
member_memo(const grow_env_t *g, const nb_off_t *o, int32_t qu, int32_t qur,
            int interior, int32_t *nn, int32_t *dn)
{
    ptrdiff_t il = g->pix + o->pix;
    uint32_t k;
    if (!member_inside(g, qu, qur, interior)) {
        return;
    }
    k = (uint32_t)(g->dr + o->dd) - (uint32_t)g->memo_base[il];
    if (k < g->memo_k) {
        uint32_t *mw = g->mrow + o->mo + (ptrdiff_t)k;
        uint32_t mv = *mw;
        if ((mv >> STX_MEMO_NUM_BITS) == g->memo_gen) {
            /* the denominator is two loads, cheaper than a bigger word */
            uint32_t nb = mv & STX_MEMO_NUM_MASK;
            if (nb != 0u) {
                *nn = stx_memo_num2(nb);
                *dn = (int32_t)(g->vl[il] + g->vr[g->rpix + o->rpx]);
            }
        } else {
            grow_score(g, o, il, qu, interior, nn, dn);
            *mw = stx_memo_pack(g->memo_gen, *nn, *dn);
        }
    } else {
        grow_score(g, o, il, qu, interior, nn, dn);
    }
}

/* Compact profile (no memo): neighbouring seeds share most of their
 * neighbourhoods, and a small direct-mapped cache catches about a quarter
 * of the correlations. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void
member_cached(const grow_env_t *g, const nb_off_t *o, int32_t qu, int32_t qur,
              int interior, int32_t *nn, int32_t *dn)
{
    uint32_t key = g->key0 + o->key;
    stx_cache_entry_t *e =
        &g->cache[(g->hkey0 + o->hkey) >> (32 - STX_CACHE_BITS)];
    if (e->key == key) {
        *nn = e->num2;
        *dn = e->den;
        return;
    }
    if (member_inside(g, qu, qur, interior)) {
        grow_score(g, o, g->pix + o->pix, qu, interior, nn, dn);
    }
    e->key = key;
    e->num2 = *nn;
    e->den = *dn;
}

/* Best member of the set nb[first .. end) as a fraction; returns its index
 * or -1 (no member scored, or the set cannot accept anything). Inline with
 * literal bounds at each call, so the compiler unrolls the set. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline int
set_best(const grow_env_t *g, int first, int end, int interior, int use_memo,
         int32_t *bn_out, int32_t *bden_out, uint32_t *visited)
{
    /* -2/1 lies below every score (an MNCC fraction is >= -1), so the
     * first scored member always replaces it without a test of its own */
    int32_t bn = -2;
    int32_t bden = 1;
    int bm = -1;
    int fresh = 0;
    int m;
    /* a set whose members are all in the table (or outside) can accept
     * nothing: skip its correlations (exact pruning) */
    for (m = first; m < end; m++) {
        const nb_off_t *o = &g->nb[m];
        ptrdiff_t bit = g->bit0 + o->bit;
        if ((interior ||
             ((uint32_t)(g->u + o->du) < (uint32_t)g->w &&
              (uint32_t)(g->vrow + o->dv) < (uint32_t)g->ny &&
              g->dr + o->dd >= g->drlo && g->dr + o->dd <= g->drhi)) &&
            !((g->tbits[bit >> 3] >> (bit & 7)) & 1)) {
            fresh = 1;
            break;
        }
    }
    if (!fresh) {
        return -1;
    }
    for (m = first; m < end; m++) {
        const nb_off_t *o = &g->nb[m];
        int32_t qu = g->u + o->du;
        int32_t qur = g->ur + o->du - o->dd;
        int32_t nn;
        int32_t dn;
        if (!interior &&
            ((uint32_t)qu >= (uint32_t)g->w ||
             (uint32_t)(g->vrow + o->dv) >= (uint32_t)g->ny ||
             g->dr + o->dd < g->drlo || g->dr + o->dd > g->drhi)) {
            continue; /* outside: never scored */
        }
        nn = 0;
        dn = 0;
        /* every look counts, whichever structure answers it: the
         * statistic is the same in both profiles and for every number of
         * band workers (whose memo bands differ) */
        (*visited)++;
        if (use_memo) {
            member_memo(g, o, qu, qur, interior, &nn, &dn);
        } else {
            member_cached(g, o, qu, qur, interior, &nn, &dn);
        }
        if (dn == 0) {
            continue; /* window outside the image or flat */
        }
        /* nn/dn > bn/bden, both dens > 0 (products < 2^50) */
        if ((int64_t)nn * bden > (int64_t)bn * dn) {
            bn = nn;
            bden = dn;
            bm = m;
        }
    }
    *bn_out = bn;
    *bden_out = bden;
    return bm;
}

/* try_accept for neighbour nb of the popped cell, whose score is still
 * held as the fraction num2 / den (den > 0): the table and tau are tested
 * before the division, which most growth candidates never need. Same
 * decisions as try_accept(stx_frac_q14()). The neighbour's indices are
 * the popped cell's plus its offsets (its packed item too: an in-range
 * neighbour's fields never borrow). */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline int
try_accept_frac(stx_t *s, const grow_env_t *g, const nb_off_t *o, int32_t num2,
                int32_t den)
{
    size_t bit = (size_t)(g->bit0 + o->bit);
    if (table_has(s, bit) ||
        !stx_frac_reaches(num2, den, s->cfg.ncc_tau_q14)) {
        return 0;
    }
    return accept_at(s, g->pix + o->pix, g->rpix + o->rpx, g->dr + o->dd,
                     stx_frac_q14(num2, den), bit, g->key0 - 1u + o->key);
}

/* The four sets of the popped cell. `interior` and `use_memo` are
 * literals at every call site (forced inline), so the usual interior cell
 * runs without any per-member bounds test. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void
grow_cell(stx_t *s, const grow_env_t *g, int interior, int use_memo,
          uint32_t *visited)
{
    int k;
    for (k = 0; k < 4; k++) {
        int32_t bn = 0;
        int32_t bden = 0;
        int bm;
        /* literal bounds per set (3 members each) */
        if (k == 0) {
            bm = set_best(g, 0, 3, interior, use_memo, &bn, &bden, visited);
        } else if (k == 1) {
            bm = set_best(g, 3, 6, interior, use_memo, &bn, &bden, visited);
        } else if (k == 2) {
            bm = set_best(g, 6, 9, interior, use_memo, &bn, &bden, visited);
        } else {
            bm = set_best(g, 9, 12, interior, use_memo, &bn, &bden, visited);
        }
        if (bm >= 0) { /* then bden > 0 */
            (void)try_accept_frac(s, g, &g->nb[bm], bn, bden);
        }
    }
}

/* `use_memo` is a literal at both call sites (grow): forced inline, so the
 * compact profile's loop carries no memo test and stays today's code. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void
grow_run(stx_t *s, int use_memo)
{
    const int32_t nd = s->ndisp;
    const int32_t dmin = s->dmin;
    /* pixel (0, y0) of each image; offset only to windows inside it */
    const uint8_t *lrow;
    const uint8_t *rrow;
    uint32_t visited = 0;
    grow_env_t g;
    uint32_t item;
    int m;

    g.w = s->w;
    g.ny = s->y1 - s->y0;
    g.drlo = s->gdmin - s->dmin;
    g.drhi = s->gdmax - s->dmin;
    g.tex_min = (uint32_t)s->cfg.texture_min;
    g.sl = s->sl;
    g.sr = s->sr;
    g.vl = s->vl;
    g.vr = s->vr;
    g.tbits = s->tbits;
    g.cache = s->cache;
    g.memo = s->memo;
    g.memo_base = s->memo_base;
    g.mrow = NULL;
    g.memo_k = (uint32_t)s->memo_k;
    g.memo_gen = s->memo_gen;
    g.ls = s->left->stride;
    g.rs = s->right->stride;
    lrow = s->left->data + (ptrdiff_t)s->y0 * g.ls;
    rrow = s->right->data + ((ptrdiff_t)s->y0 + s->voff) * g.rs;
    for (m = 0; m < NB_CELLS; m++) {
        int32_t du = nb_cell[m][0];
        int32_t dd = nb_cell[m][1];
        int32_t dv = nb_cell[m][2];
        nb_off_t *o = &g.nb[m];
        o->du = du;
        o->dd = dd;
        o->dv = dv;
        o->pix = (ptrdiff_t)dv * g.w + du;
        o->rpx = o->pix - dd;
        o->bit = o->pix * nd + dd;
        o->lp = (ptrdiff_t)(dv - STX_WIN_R) * g.ls + du - STX_WIN_R;
        o->rp = (ptrdiff_t)(dv - STX_WIN_R) * g.rs + (du - dd) - STX_WIN_R;
        o->mo = o->pix * (ptrdiff_t)g.memo_k;
        /* added (mod 2^32) to a packed key: a sum, not stx_pack's OR */
        o->key = ((uint32_t)du << 20) + ((uint32_t)dv << 8) + (uint32_t)dd;
        o->hkey = o->key * STX_CACHE_HASH;
    }

    while (stx_queue_pop(&s->q, &item)) {
        g.u = stx_unpack_u(item);
        g.vrow = stx_unpack_v(item);
        g.dr = stx_unpack_d(item);
        g.ur = g.u - (g.dr + dmin);
        g.pix = (ptrdiff_t)g.vrow * g.w + g.u;
        g.rpix = g.pix + (g.ur - g.u);
        g.bit0 = g.pix * nd + g.dr;
        g.la = lrow + (ptrdiff_t)g.vrow * g.ls + g.u;
        g.rb = rrow + (ptrdiff_t)g.vrow * g.rs + g.ur;
        g.key0 = item + 1u;
        g.hkey0 = g.key0 * STX_CACHE_HASH;
        if (use_memo) {
            g.mrow = g.memo + g.pix * (ptrdiff_t)g.memo_k;
        }
        /* every neighbour inside the strip and range, and every window
         * (and 8-byte SIMD load) inside the image: the usual case, where
         * the per-cell bounds tests can be skipped */
        g.interior = g.u >= 2 * STX_WIN_R && g.u + 8 < g.w &&
                     g.ur >= 2 * STX_WIN_R && g.vrow >= 1 &&
                     g.vrow + 1 < g.ny && g.dr - 1 >= g.drlo &&
                     g.dr + 1 <= g.drhi;
        if (g.interior) {
            grow_cell(s, &g, 1, use_memo, &visited);
        } else {
            grow_cell(s, &g, 0, use_memo, &visited);
        }
    }
    s->st.visited_cells += visited;
}

static void grow_compact(stx_t *s)
{
    grow_run(s, 0);
}
static void grow_fast(stx_t *s)
{
    grow_run(s, 1);
}

static void grow(stx_t *s)
{
    if (s->memo != NULL) {
        grow_fast(s);
    } else {
        grow_compact(s);
    }
}

/* eval(s, u, v, d) for d = lo .. hi into sc[d - lo] (lo, hi inside the
 * global range, hi <= u - STX_WIN_R): the left window, its statistics and
 * bounds are looked up once for the whole range. */
static void seed_scores(stx_t *s, int32_t u, int32_t v, int32_t lo, int32_t hi,
                        int32_t *sc)
{
    int32_t w = s->w;
    ptrdiff_t il = (ptrdiff_t)(v - s->y0) * w + u;
    uint32_t vl = s->vl[il];
    uint32_t sl = s->sl[il];
    uint32_t tex = (uint32_t)s->cfg.texture_min;
    ptrdiff_t ls = s->left->stride;
    ptrdiff_t rs = s->right->stride;
    int32_t yr = v + s->voff;
    const uint16_t *srp = s->sr;
    const uint32_t *vrp = s->vr;
    /* vl != 0: the left window is inside the image; the right rows are
     * checked too, so no pointer is ever formed outside the images */
    int ok_left = u >= STX_WIN_R && u < w - STX_WIN_R && vl != 0u &&
                  yr >= STX_WIN_R && yr < s->h - STX_WIN_R;
    const uint8_t *a = NULL;
    const uint8_t *rrow = NULL;
    int32_t d;
    if (ok_left) {
        a = negobs_image_u8_row(s->left, v - STX_WIN_R) + u - STX_WIN_R;
        rrow = negobs_image_u8_row(s->right, yr - STX_WIN_R);
    }
    if (hi >= lo) {
        s->st.visited_cells += (uint32_t)(hi - lo + 1);
    }
    d = lo;
#if defined(STX_CROSS5X3_SIMD)
    /* three disparities d .. d + 2 at once while their right windows
     * (top-left columns u - d - 4 .. u - d - 2) are inside the row, with
     * the 8-byte loads ending at u - d + 3 and u + 5 */
    if (ok_left && u + 5 < w) {
        for (; d + 2 <= hi && u - d - 2 >= STX_WIN_R && u - d + 3 < w;
             d += 3) {
            uint32_t x3[3];
            int32_t k;
            stx_cross5x3_simd(a, ls, rrow + u - d - 4, rs, x3);
            for (k = 0; k < 3; k++) {
                /* window of d + k starts at (u - d - 4) + 2 - k */
                int32_t dk = d + k;
                int32_t n2;
                int32_t den;
                sc[dk - lo] = STX_FLAT;
                if (vrp[il - dk] != 0u &&
                    stx_mncc_num_den(x3[2 - k], sl, vl, srp[il - dk],
                                     vrp[il - dk], tex, &n2, &den)) {
                    sc[dk - lo] = stx_frac_q14(n2, den);
                }
            }
        }
    }
#endif
    for (; d <= hi; d++) {
        int32_t ur = u - d;
        int32_t n2;
        int32_t den;
        uint32_t x;
        const uint8_t *b;
        sc[d - lo] = STX_FLAT;
        if (!ok_left || ur < STX_WIN_R || ur >= w - STX_WIN_R ||
            vrp[il - d] == 0u) {
            continue;
        }
        b = rrow + ur - STX_WIN_R;
#if defined(STX_CROSS5_SIMD)
        x = (u + 5 < w) ? stx_cross5_simd(a, ls, b, rs)
                        : stx_cross5_ref(a, ls, b, rs);
#else
        x = stx_cross5_ref(a, ls, b, rs);
#endif
        if (stx_mncc_num_den(x, sl, vl, srp[il - d], vrp[il - d], tex, &n2,
                             &den)) {
            sc[d - lo] = stx_frac_q14(n2, den);
        }
    }
}

static void seed_edges(stx_t *s)
{
    int32_t w = s->w;
    int32_t v;
    int32_t step = s->cfg.seed_step;
    int32_t sc[NEGOBS_STEREO_MAX_RANGE];
    for (v = s->y0; v < s->y1; v++) {
        const uint8_t *e = s->edge + (ptrdiff_t)(v - s->y0) * w;
        int32_t n = 0;
        int32_t u;
        for (u = STX_WIN_R; u < w - STX_WIN_R; u++) {
            int32_t lo;
            int32_t hi;
            int32_t end;
            int32_t d;
            int32_t best = STX_FLAT;
            int32_t bestd = 0;
            int32_t second = STX_FLAT;
            if (!e[u]) {
                continue;
            }
            if ((n++ % step) != 0) {
                continue;
            }
            stx_tile_range(s, u, v, &lo, &hi);
            lo = (lo < s->gdmin) ? s->gdmin : lo;
            hi = (hi > s->gdmax) ? s->gdmax : hi;
            end = (hi < u - STX_WIN_R) ? hi : u - STX_WIN_R;
            seed_scores(s, u, v, lo, end, sc);
            /* STX_FLAT is INT32_MIN, below every score: "c > best" skips
             * flat cells and takes the first of equal scores */
            for (d = lo; d <= end; d++) {
                int32_t c = sc[d - lo];
                if (c > best) {
                    best = c;
                    bestd = d;
                }
            }
            if (best == STX_FLAT || best < s->cfg.seed_tau_q14) {
                continue;
            }
            /* the best score two or more levels away */
            for (d = lo; d <= bestd - 2; d++) {
                second = (sc[d - lo] > second) ? sc[d - lo] : second;
            }
            for (d = bestd + 2; d <= end; d++) {
                second = (sc[d - lo] > second) ? sc[d - lo] : second;
            }
            if (second != STX_FLAT && best - second < s->cfg.seed_margin_q14) {
                continue;
            }
            if (try_accept(s, u, v, bestd, best)) {
                s->st.seeds++;
            }
        }
    }
}

static void seed_carry(stx_t *s, const negobs_image_s16_t *out)
{
    const int16_t *prev;
    int32_t u;
    if (s->y0 == 0 || s->y0 == s->band_y0) {
        return; /* growth never crosses a band border */
    }
    prev = negobs_image_s16_row(out, s->y0 - 1);
    for (u = 0; u < s->w; u++) {
        int32_t d = prev[u];
        if (d == NEGOBS_DISP_INVALID) {
            continue;
        }
        (void)try_accept(s, u, s->y0, d, eval(s, u, s->y0, d));
    }
}

void stx_memo_clear(stx_t *s)
{
    if (s->memo != NULL) {
        memset(s->memo, 0,
               (size_t)s->sh * (size_t)s->w * (size_t)s->memo_k *
                   sizeof *s->memo);
    }
    s->memo_gen = 0;
}

/* Fast profile: a new stamp for the strip and each pixel's memo band,
 * centred on its tile's coarse range (the cells growth visits cluster
 * around the surface the 1/4-scale map found). */
static void memo_strip(stx_t *s)
{
    int32_t k = s->memo_k;
    int32_t top = s->ndisp - k;
    int32_t v;
    if (s->memo == NULL) {
        return;
    }
    if (s->memo_gen >= STX_MEMO_GEN_MAX) {
        stx_memo_clear(s); /* stamps wrapped: every word must read empty */
    }
    s->memo_gen++;
    for (v = s->y0; v < s->y1; v++) {
        uint8_t *b = s->memo_base + (ptrdiff_t)(v - s->y0) * s->w;
        int32_t u;
        for (u = 0; u < s->w; u += s->tile) {
            int32_t lo;
            int32_t hi;
            int32_t n = (u + s->tile < s->w) ? s->tile : s->w - u;
            stx_tile_range(s, u, v, &lo, &hi);
            memset(
                b + u,
                (int)negobs_clamp_s32((lo + hi) / 2 - s->dmin - k / 2, 0, top),
                (size_t)n);
        }
    }
}

void stx_gcs_strip(stx_t *s, negobs_image_s16_t *out)
{
    int32_t w = s->w;
    int32_t n = s->y1 - s->y0;
    size_t cells = (size_t)n * (size_t)w;
    int32_t beta = s->cfg.ssk_beta_q8;
    int32_t gap = s->cfg.zonegap;
    int32_t v;

    memset(s->ld, STX_NONE8, cells);
    memset(s->rd, STX_NONE8, cells);
    memset(s->lc, 0, cells);
    memset(s->lc2, 0, cells);
    memset(s->rc, 0, cells);
    memset(s->rc2, 0, cells);
    memset(s->tbits, 0, (cells * (size_t)s->ndisp + 7u) / 8u);
    stx_queue_reset(&s->q);
    if (s->cache != NULL) { /* compact profile: no memo */
        memset(s->cache, 0, sizeof(stx_cache_entry_t) << STX_CACHE_BITS);
    }
    memo_strip(s);

    seed_carry(s, out);
    seed_edges(s);
    grow(s);
    if (s->q.peak > s->st.queue_peak) {
        s->st.queue_peak = s->q.peak;
    }
    s->st.queue_overflows += s->q.overflows;

    {
        /* the tables in locals: the int16 output stores cannot move them */
        const uint8_t *const ld = s->ld;
        const uint8_t *const lc = s->lc;
        const uint8_t *const lc2 = s->lc2;
        const uint8_t *const rd = s->rd;
        const uint8_t *const rc2 = s->rc2;
        const int32_t dmin = s->dmin;
        uint32_t matched = 0;
        for (v = 0; v < n; v++) {
            int16_t *o = negobs_image_s16_row(out, s->y0 + v);
            ptrdiff_t row = (ptrdiff_t)v * w;
            int32_t u;
            for (u = 0; u < w; u++) {
                ptrdiff_t il = row + u;
                int32_t dr = ld[il];
                ptrdiff_t ir;
                int32_t lim;
                int32_t dd;
                o[u] = NEGOBS_DISP_INVALID;
                if (dr == STX_NONE8) {
                    continue;
                }
                ir = il - (dr + dmin);
                dd = (int32_t)rd[ir] - dr;
                if (dd > gap || dd < -gap) {
                    continue;
                }
                lim = (int32_t)lc[il] * (256 - beta);
                if ((int32_t)lc2[il] * 256 >= lim ||
                    (int32_t)rc2[ir] * 256 >= lim) {
                    continue;
                }
                o[u] = (int16_t)(dr + dmin);
                matched++;
            }
        }
        s->st.gcs_matched += matched;
    }
}
