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

/* Is (u, v, d) already in the matching table? (u, d checked by caller) */
static int in_table(const stx_t *s, int32_t u, int32_t v, int32_t d)
{
    size_t bit;
    if (u < 0 || u >= s->w || v < s->y0 || v >= s->y1 || d < s->gdmin ||
        d > s->gdmax) {
        return 1; /* outside: never a candidate */
    }
    bit = ((size_t)(v - s->y0) * (size_t)s->w + (size_t)u) *
              (size_t)s->ndisp + (size_t)(d - s->dmin);
    return (int)(((uint32_t)s->tbits[bit >> 3] >> (bit & 7u)) & 1u);
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

/* Numerator / denominator of a candidate for comparisons without division.
 * Returns 0 when the cell is out of range or flat. */
static int frac(stx_t *s, int32_t u, int32_t v, int32_t d, int32_t *num,
                int32_t *den)
{
    uint32_t key;
    stx_cache_entry_t *e;
    int ok;
    if (d < s->gdmin || d > s->gdmax || u < 0 || u >= s->w || v < s->y0 ||
        v >= s->y1) {
        return 0;
    }
    /* neighbouring seeds share most of their 16-neighbourhoods: a small
     * direct-mapped cache catches about a quarter of the correlations */
    key = stx_pack(u, v - s->y0, d - s->dmin) + 1u;
    e = &s->cache[(key * 2654435761u) >> (32 - STX_CACHE_BITS)];
    if (e->key == key) {
        *num = e->num2;
        *den = e->den;
        return e->den != 0;
    }
    s->st.visited_cells++;
    ok = stx_mncc_frac(s, u, v, d, num, den);
    e->key = key;
    e->num2 = ok ? *num : 0;
    e->den = ok ? *den : 0;
    return ok;
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
    {{-1, 0, 0}, {-2, -1, 0}, {-1, 1, 0}, {0, 0, 99}, {0, 0, 99}},
    {{1, 0, 0}, {2, 1, 0}, {1, -1, 0}, {0, 0, 99}, {0, 0, 99}},
    {{0, 0, -1}, {1, 1, -1}, {-1, -1, -1}, {0, -1, -1}, {0, 1, -1}},
    {{0, 0, 1}, {1, 1, 1}, {-1, -1, 1}, {0, -1, 1}, {0, 1, 1}},
};

static void grow(stx_t *s)
{
    uint32_t item;
    while (stx_queue_pop(&s->q, &item)) {
        int32_t u = stx_unpack_u(item);
        int32_t v = stx_unpack_v(item) + s->y0;
        int32_t d = stx_unpack_d(item) + s->dmin;
        int k;
        for (k = 0; k < 4; k++) {
            int32_t bn = 0;
            int32_t bden = 0;
            int32_t bu = 0;
            int32_t bv = 0;
            int32_t bd = 0;
            int m;
            int fresh = 0;
            /* a set whose members are all in the table (or outside) can
             * accept nothing: skip its correlations (exact pruning) */
            for (m = 0; m < 5 && nb_set[k][m][2] != 99; m++) {
                if (!in_table(s, u + nb_set[k][m][0], v + nb_set[k][m][2],
                              d + nb_set[k][m][1])) {
                    fresh = 1;
                    break;
                }
            }
            if (!fresh) {
                continue;
            }
            for (m = 0; m < 5; m++) {
                int32_t qu;
                int32_t qv;
                int32_t qd;
                int32_t nn;
                int32_t dn;
                if (nb_set[k][m][2] == 99) {
                    break;
                }
                qu = u + nb_set[k][m][0];
                qd = d + nb_set[k][m][1];
                qv = v + nb_set[k][m][2];
                if (!frac(s, qu, qv, qd, &nn, &dn)) {
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
                (void)try_accept(s, bu, bv, bd, stx_frac_q14(bn, bden));
            }
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
