/*
 * Stage 2 + 3: Canny seeds and Growing Correspondence Seeds on one strip.
 *
 * Seeds: every seed_step-th Canny edge pixel of a row is matched with 5x5
 * MNCC over its tile range; it becomes a seed when the best score is
 * >= seed_tau and beats every score two or more levels away by
 * seed_margin. The matches of the row just above the strip (previous strip)
 * are re-scored on the first row and pushed too, so growth continues across
 * strip borders.
 *
 * Growing (ALGORITHMS.md 1.3): pop the best candidate, evaluate the 16-point
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

/* Try to accept candidate (u, v, d) with score c; push it when accepted. */
static int try_accept(stx_t *s, int32_t u, int32_t v, int32_t d, int32_t c)
{
    int32_t w = s->w;
    int32_t vr = v - s->y0;
    int32_t dr = d - s->dmin;
    int32_t ur = u - d;
    size_t bit;
    ptrdiff_t il;
    ptrdiff_t ir;
    uint8_t c8;
    int32_t lim;

    if (c == STX_FLAT || c < s->cfg.ncc_tau_q14) {
        return 0;
    }
    bit = ((size_t)vr * (size_t)w + (size_t)u) * (size_t)s->ndisp + (size_t)dr;
    if (s->tbits[bit >> 3] & (1u << (bit & 7u))) {
        return 0;
    }
    il = (ptrdiff_t)vr * w + u;
    ir = (ptrdiff_t)vr * w + ur;
    c8 = to_q8(c);
    lim = (s->lc[il] < s->rc[ir]) ? s->lc[il] : s->rc[ir];
    if ((int32_t)c8 + (s->cfg.ncc_mu_q14 >> 6) < lim) {
        return 0;
    }
    s->tbits[bit >> 3] = (uint8_t)(s->tbits[bit >> 3] | (1u << (bit & 7u)));
    table_update(&s->ld[il], &s->lc[il], &s->lc2[il], dr, c8,
                 s->cfg.zonegap);
    table_update(&s->rd[ir], &s->rc[ir], &s->rc2[ir], dr, c8,
                 s->cfg.zonegap);
    s->st.grown++;
    stx_queue_push(&s->q, stx_pack(u, vr, dr), c >> 6);
    return 1;
}

static int32_t eval(stx_t *s, int32_t u, int32_t v, int32_t d)
{
    if (d < s->gdmin || d > s->gdmax) {
        return STX_FLAT;
    }
    s->st.visited_cells++;
    return stx_mncc_strip(s, u, v, d);
}

/* Neighbourhood sets as (du, dd, dv); dd = du - du'. */
static const int8_t nb_set[4][5][3] = {
    {{-1, 0, 0}, {-2, -1, 0}, {-1, 1, 0}, {0, 0, 0}, {0, 0, 0}},
    {{1, 0, 0}, {2, 1, 0}, {1, -1, 0}, {0, 0, 0}, {0, 0, 0}},
    {{0, 0, -1}, {1, 1, -1}, {-1, -1, -1}, {0, -1, -1}, {0, 1, -1}},
    {{0, 0, 1}, {1, 1, 1}, {-1, -1, 1}, {0, -1, 1}, {0, 1, 1}},
};
static const int nb_count[4] = {3, 3, 5, 5};

/* Everything the growing loop reads per cell, hoisted out of stx_t once per
 * strip: strip-relative rows (vr) and disparities (dr = d - dmin). */
typedef struct grow_ctx {
    int32_t w, ny, nd, dmin;
    int32_t drlo, drhi;      /* global range, relative to dmin            */
    uint32_t tex_min;
    const uint16_t *sl, *sr;
    const uint32_t *vl, *vr;
    const uint8_t *tbits;
    stx_cache_entry_t *cache;
    const uint8_t *lrow;     /* left pixel (0, y0 - 2)                   */
    const uint8_t *rrow;     /* right pixel (0, y0 + voff - 2)           */
    ptrdiff_t ls, rs;        /* strides                                  */
    int simd_ok_below;       /* u + 5 < this: 8-byte loads stay in rows  */
    uint32_t visited;
} grow_ctx_t;

/* Cell inside the strip and the global range? (outside: never a candidate,
 * never scored) */
static inline int cell_inside(const grow_ctx_t *g, int32_t u, int32_t vr,
                              int32_t dr)
{
    return (uint32_t)u < (uint32_t)g->w && (uint32_t)vr < (uint32_t)g->ny &&
           dr >= g->drlo && dr <= g->drhi;
}

static inline int cell_in_table(const grow_ctx_t *g, int32_t u, int32_t vr,
                                int32_t dr)
{
    size_t bit = ((size_t)vr * (size_t)g->w + (size_t)u) * (size_t)g->nd +
                 (size_t)dr;
    return (int)(((uint32_t)g->tbits[bit >> 3] >> (bit & 7u)) & 1u);
}

/* MNCC fraction of an inside cell, uncached (stx_mncc_frac on the hoisted
 * context); 0 when the windows leave the image or are flat. */
static inline int cell_score(const grow_ctx_t *g, int32_t u, int32_t vr,
                             int32_t dr, int32_t *num, int32_t *den)
{
    int32_t d = dr + g->dmin;
    int32_t ur = u - d;
    ptrdiff_t il;
    ptrdiff_t ir;
    uint32_t vl;
    uint32_t vrr;
    uint32_t x;
    const uint8_t *a;
    const uint8_t *b;
    if (u < STX_WIN_R || u >= g->w - STX_WIN_R || ur < STX_WIN_R ||
        ur >= g->w - STX_WIN_R) {
        return 0;
    }
    il = (ptrdiff_t)vr * g->w + u;
    ir = il - d;
    vl = g->vl[il];
    vrr = g->vr[ir];
    if (vl == 0u || vrr == 0u) {
        return 0;
    }
    a = g->lrow + (ptrdiff_t)vr * g->ls + (u - STX_WIN_R);
    b = g->rrow + (ptrdiff_t)vr * g->rs + (ur - STX_WIN_R);
#if STX_CROSS5_SIMD
    if (u < g->simd_ok_below) {
        x = stx_cross5_simd(a, g->ls, b, g->rs);
    } else {
        x = stx_cross5_ref(a, g->ls, b, g->rs);
    }
#else
    x = stx_cross5_ref(a, g->ls, b, g->rs);
#endif
    return stx_mncc_num_den(x, g->sl[il], vl, g->sr[ir], vrr, g->tex_min,
                            num, den);
}

/* Cached fraction of an inside cell. Neighbouring seeds share most of
 * their 16-neighbourhoods: a small direct-mapped cache catches about a
 * quarter of the correlations; `visited` counts the misses. */
static inline int cell_frac(grow_ctx_t *g, int32_t u, int32_t vr, int32_t dr,
                            int32_t *num, int32_t *den)
{
    uint32_t key = stx_pack(u, vr, dr) + 1u;
    stx_cache_entry_t *e =
        &g->cache[(key * 2654435761u) >> (32 - STX_CACHE_BITS)];
    int ok;
    if (e->key == key) {
        *num = e->num2;
        *den = e->den;
        return e->den != 0;
    }
    g->visited++;
    ok = cell_score(g, u, vr, dr, num, den);
    e->key = key;
    e->num2 = ok ? *num : 0;
    e->den = ok ? *den : 0;
    return ok;
}

static void grow(stx_t *s)
{
    grow_ctx_t g;
    uint32_t item;

    g.w = s->w;
    g.ny = s->y1 - s->y0;
    g.nd = s->ndisp;
    g.dmin = s->dmin;
    g.drlo = s->gdmin - s->dmin;
    g.drhi = s->gdmax - s->dmin;
    g.tex_min = (uint32_t)s->cfg.texture_min;
    g.sl = s->sl;
    g.sr = s->sr;
    g.vl = s->vl;
    g.vr = s->vr;
    g.tbits = s->tbits;
    g.cache = s->cache;
    g.ls = s->left->stride;
    g.rs = s->right->stride;
    /* row pointers of strip row 0 minus the window radius; only ever
     * offset to rows inside the image (cell_score checks the windows) */
    g.lrow = s->left->data + ((ptrdiff_t)s->y0 - STX_WIN_R) * g.ls;
    g.rrow = s->right->data + ((ptrdiff_t)s->y0 + s->voff - STX_WIN_R) * g.rs;
    g.simd_ok_below = s->w - 5; /* ur <= u, same width: covers the right */
    g.visited = 0;

    while (stx_queue_pop(&s->q, &item)) {
        int32_t u = stx_unpack_u(item);
        int32_t vr = stx_unpack_v(item);
        int32_t dr = stx_unpack_d(item);
        int k;
        for (k = 0; k < 4; k++) {
            const int8_t(*set)[3] = nb_set[k];
            int n = nb_count[k];
            int32_t bn = 0;
            int32_t bden = 0;
            int32_t bu = 0;
            int32_t bv = 0;
            int32_t bd = 0;
            int m;
            int fresh = 0;
            /* a set whose members are all in the table (or outside) can
             * accept nothing: skip its correlations (exact pruning) */
            for (m = 0; m < n; m++) {
                int32_t qu = u + set[m][0];
                int32_t qd = dr + set[m][1];
                int32_t qv = vr + set[m][2];
                if (cell_inside(&g, qu, qv, qd) &&
                    !cell_in_table(&g, qu, qv, qd)) {
                    fresh = 1;
                    break;
                }
            }
            if (!fresh) {
                continue;
            }
            for (m = 0; m < n; m++) {
                int32_t qu = u + set[m][0];
                int32_t qd = dr + set[m][1];
                int32_t qv = vr + set[m][2];
                int32_t nn;
                int32_t dn;
                if (!cell_inside(&g, qu, qv, qd) ||
                    !cell_frac(&g, qu, qv, qd, &nn, &dn)) {
                    continue;
                }
                /* nn/dn > bn/bden, both dens > 0 (products < 2^50) */
                if (bden == 0 ||
                    (int64_t)nn * bden > (int64_t)bn * dn) {
                    bn = nn;
                    bden = dn;
                    bu = qu;
                    bv = qv;
                    bd = qd;
                }
            }
            if (bden != 0) {
                (void)try_accept(s, bu, bv + s->y0, bd + s->dmin,
                                 stx_frac_q14(bn, bden));
            }
        }
    }
    s->st.visited_cells += g.visited;
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
            for (d = lo; d <= hi && d <= u - STX_WIN_R; d++) {
                int32_t c = eval(s, u, v, d);
                sc[d - lo] = c;
                if (c != STX_FLAT && (best == STX_FLAT || c > best)) {
                    best = c;
                    bestd = d;
                }
            }
            if (best == STX_FLAT || best < s->cfg.seed_tau_q14) {
                continue;
            }
            for (d = lo; d <= hi && d <= u - STX_WIN_R; d++) {
                int32_t c = sc[d - lo];
                if (d >= bestd - 1 && d <= bestd + 1) {
                    continue;
                }
                if (c != STX_FLAT && (second == STX_FLAT || c > second)) {
                    second = c;
                }
            }
            if (second != STX_FLAT &&
                best - second < s->cfg.seed_margin_q14) {
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
    if (s->y0 == 0) {
        return;
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
    memset(s->cache, 0, sizeof(stx_cache_entry_t) << STX_CACHE_BITS);

    seed_carry(s, out);
    seed_edges(s);
    grow(s);
    if (s->q.peak > s->st.queue_peak) {
        s->st.queue_peak = s->q.peak;
    }
    s->st.queue_overflows += s->q.overflows;

    for (v = 0; v < n; v++) {
        int16_t *o = negobs_image_s16_row(out, s->y0 + v);
        int32_t u;
        for (u = 0; u < w; u++) {
            ptrdiff_t il = (ptrdiff_t)v * w + u;
            int32_t dr = s->ld[il];
            int32_t ur;
            ptrdiff_t ir;
            int32_t c;
            int32_t lim;
            int32_t dd;
            o[u] = NEGOBS_DISP_INVALID;
            if (dr == STX_NONE8) {
                continue;
            }
            ur = u - (dr + s->dmin);
            ir = (ptrdiff_t)v * w + ur;
            dd = (int32_t)s->rd[ir] - dr;
            if (dd > gap || dd < -gap) {
                continue;
            }
            c = s->lc[il];
            lim = c * (256 - beta);
            if ((int32_t)s->lc2[il] * 256 >= lim ||
                (int32_t)s->rc2[ir] * 256 >= lim) {
                continue;
            }
            o[u] = (int16_t)(dr + s->dmin);
            s->st.gcs_matched++;
        }
    }
}
