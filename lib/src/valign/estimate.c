/*
 * Vertical misalignment estimate: per-tile sub-pixel offsets from a 7x7
 * Moravec NCC search, a least-squares model fit, the tracked model.
 * The header (negobs/valign.h) gives the method; this file the arithmetic.
 *
 * Fixed point and overflow:
 * - Window sums: 49 * 255^2 < 2^22; 49 * sum(l*r) < 2^28; the covariance
 *   and variances are < 2^28, the MNCC numerator 2 * cov * 2^14 < 2^43
 *   (int64). Scores are Q14 in [-16384, 16384].
 * - Tile sums: <= 8^2 samples * 2^14 = 2^20.
 * - Fit: coordinates in half-tile units |u|, |v| <= 15, tile offsets Q4
 *   |o| <= 16 * 5. Normal-matrix entries <= 256 * 225 < 2^16, so the 3x3
 *   determinant and Cramer numerators stay below 2^51 (int64).
 */
#include <string.h>

#include "arena.h"
#include "negobs/fixed.h"
#include "negobs/valign.h"
#include "valign_int.h"

#define VALIGN_READY 0x56414c47u /* "VALG" */
#define VALIGN_NO_TILE INT32_MIN

void negobs_valign_config_default(negobs_valign_config_t *cfg, int32_t width,
                                  int32_t height)
{
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->enable = 0;
    cfg->width = width;
    cfg->height = height;
    cfg->min_disp = 0;
    cfg->max_disp = 63;
    cfg->max_offset = 4;
    cfg->kind = NEGOBS_VALIGN_AFFINE;
    cfg->tiles_x = 8;
    cfg->tiles_y = 6;
    cfg->samples = 3;
    cfg->texture_min = 49 * 49 * 9;
    cfg->match_min_q14 = 8192;
    cfg->min_tiles = 4;
    cfg->smooth_q15 = 8192;
}

static negobs_status_t check_config(const negobs_valign_config_t *c)
{
    if (c == NULL || c->width < 16 || c->height < 16 ||
        c->width > NEGOBS_MAX_DIM || c->height > NEGOBS_MAX_DIM ||
        c->min_disp < 0 || c->max_disp < c->min_disp ||
        c->max_disp >= c->width || c->max_disp - c->min_disp > 255 ||
        c->max_offset < 1 || c->max_offset > NEGOBS_VALIGN_MAX_OFFSET ||
        c->kind < NEGOBS_VALIGN_CONST || c->kind > NEGOBS_VALIGN_AFFINE ||
        c->tiles_x < 1 || c->tiles_x > NEGOBS_VALIGN_MAX_TILES ||
        c->tiles_y < 1 || c->tiles_y > NEGOBS_VALIGN_MAX_TILES ||
        c->samples < 1 || c->samples > NEGOBS_VALIGN_MAX_SAMPLES ||
        c->texture_min < 0 || c->match_min_q14 < 0 ||
        c->match_min_q14 > 16384 || c->min_tiles < 1 || c->smooth_q15 < 1 ||
        c->smooth_q15 > 32768 ||
        /* each tile must hold a window plus the vertical search */
        c->width / c->tiles_x < 2 * VALIGN_WIN_R + 1 ||
        c->height / c->tiles_y < 2 * VALIGN_WIN_R + 1) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

static void carve(negobs_arena_t *a, const negobs_valign_config_t *c,
                  negobs_valign_t *ctx)
{
    size_t tiles = (size_t)c->tiles_x * (size_t)c->tiles_y;
    size_t nk = (size_t)c->max_offset * 2u + 1u;
    int32_t *sum = negobs_arena_take(a, tiles * nk * sizeof(int32_t));
    int32_t *n = negobs_arena_take(a, tiles * sizeof(int32_t));
    int32_t *off = negobs_arena_take(a, tiles * sizeof(int32_t));
    if (ctx != NULL) {
        ctx->tile_sum = sum;
        ctx->tile_n = n;
        ctx->tile_off_q4 = off;
    }
}

negobs_status_t negobs_valign_workspace_size(const negobs_valign_config_t *cfg,
                                             size_t *bytes_out)
{
    negobs_arena_t a;
    if (bytes_out == NULL || check_config(cfg) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    negobs_arena_init(&a, NULL, 0);
    carve(&a, cfg, NULL);
    *bytes_out = negobs_arena_used(&a);
    return NEGOBS_OK;
}

negobs_status_t negobs_valign_init(negobs_valign_t *ctx,
                                   const negobs_valign_config_t *cfg,
                                   void *workspace, size_t workspace_bytes)
{
    negobs_arena_t a;
    if (ctx == NULL || workspace == NULL || check_config(cfg) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    if (!negobs_arena_aligned(workspace)) {
        return NEGOBS_ERR_ALIGN;
    }
    memset(ctx, 0, sizeof *ctx);
    negobs_arena_init(&a, workspace, workspace_bytes);
    carve(&a, cfg, ctx);
    if (negobs_arena_status(&a) != NEGOBS_OK) {
        return negobs_arena_status(&a);
    }
    ctx->cfg = *cfg;
    ctx->dmin = cfg->min_disp;
    ctx->dmax = cfg->max_disp;
    ctx->ready = VALIGN_READY;
    return NEGOBS_OK;
}

negobs_status_t negobs_valign_set_disp_range(negobs_valign_t *ctx,
                                             int32_t min_disp,
                                             int32_t max_disp)
{
    if (ctx == NULL || ctx->ready != VALIGN_READY) {
        return NEGOBS_ERR_STATE;
    }
    if (min_disp > max_disp) {
        return NEGOBS_ERR_INVAL;
    }
    ctx->dmin = negobs_clamp_s32(min_disp, ctx->cfg.min_disp,
                                 ctx->cfg.max_disp);
    ctx->dmax = negobs_clamp_s32(max_disp, ctx->dmin, ctx->cfg.max_disp);
    return NEGOBS_OK;
}

negobs_valign_model_t negobs_valign_model(const negobs_valign_t *ctx)
{
    negobs_valign_model_t m;
    memset(&m, 0, sizeof m);
    if (ctx != NULL && ctx->ready == VALIGN_READY) {
        m = ctx->model;
    }
    return m;
}

/* Sum and 49 * sum of squares minus sum^2 of the 7x7 window at (x, y). */
static void win_stats(const negobs_image_u8_t *img, int32_t x, int32_t y,
                      int32_t *sum, int32_t *var)
{
    int32_t s = 0;
    int32_t q = 0;
    int32_t j;
    for (j = -VALIGN_WIN_R; j <= VALIGN_WIN_R; j++) {
        const uint8_t *p = negobs_image_u8_row(img, y + j) + x;
        int32_t i;
        for (i = -VALIGN_WIN_R; i <= VALIGN_WIN_R; i++) {
            int32_t g = p[i];
            s += g;
            q += g * g;
        }
    }
    *sum = s;
    *var = VALIGN_WIN_N * q - s * s;
}

/* MNCC (Q14) of the left window at (xl, y) and the right one at (xr, yr). */
static int32_t mncc_q14(const negobs_image_u8_t *l, int32_t xl, int32_t y,
                        int32_t sl, int32_t vl, const negobs_image_u8_t *r,
                        int32_t xr, int32_t yr)
{
    int32_t sr = 0;
    int32_t qr = 0;
    int32_t lr = 0;
    int32_t j;
    int64_t cov;
    int64_t den;
    for (j = -VALIGN_WIN_R; j <= VALIGN_WIN_R; j++) {
        const uint8_t *pl = negobs_image_u8_row(l, y + j) + xl;
        const uint8_t *pr = negobs_image_u8_row(r, yr + j) + xr;
        int32_t i;
        for (i = -VALIGN_WIN_R; i <= VALIGN_WIN_R; i++) {
            int32_t g = pr[i];
            sr += g;
            qr += g * g;
            lr += g * pl[i];
        }
    }
    cov = (int64_t)VALIGN_WIN_N * lr - (int64_t)sl * sr;
    den = (int64_t)vl + ((int64_t)VALIGN_WIN_N * qr - (int64_t)sr * sr);
    if (den <= 0) {
        return 0;
    }
    return (int32_t)(2 * cov * 16384 / den);
}

/* Score curves of every tile for offsets -n..n (one pass). */
static int32_t score_tiles(negobs_valign_t *ctx, const negobs_image_u8_t *l,
                           const negobs_image_u8_t *r, int32_t n)
{
    const negobs_valign_config_t *c = &ctx->cfg;
    int32_t w = c->width;
    int32_t h = c->height;
    int32_t nk = 2 * n + 1;
    int32_t used = 0;
    int32_t ty;
    int32_t tx;

    for (ty = 0; ty < c->tiles_y; ty++) {
        int32_t y0 = ty * h / c->tiles_y;
        int32_t y1 = (ty + 1) * h / c->tiles_y;
        for (tx = 0; tx < c->tiles_x; tx++) {
            int32_t x0 = tx * w / c->tiles_x;
            int32_t x1 = (tx + 1) * w / c->tiles_x;
            int32_t t = ty * c->tiles_x + tx;
            int32_t *sum = ctx->tile_sum + (size_t)t * (size_t)nk;
            int32_t sj;
            memset(sum, 0, (size_t)nk * sizeof *sum);
            ctx->tile_n[t] = 0;
            for (sj = 0; sj < c->samples; sj++) {
                int32_t y = y0 + (2 * sj + 1) * (y1 - y0) / (2 * c->samples);
                int32_t si;
                if (y - VALIGN_WIN_R - n < 0 || y + VALIGN_WIN_R + n >= h) {
                    continue;
                }
                for (si = 0; si < c->samples; si++) {
                    int32_t x = x0 +
                                (2 * si + 1) * (x1 - x0) / (2 * c->samples);
                    int32_t best[2 * NEGOBS_VALIGN_MAX_OFFSET + 1] = {0};
                    int32_t top = INT32_MIN;
                    int32_t sl;
                    int32_t vl;
                    int32_t k;
                    if (x - VALIGN_WIN_R < 0 || x + VALIGN_WIN_R >= w) {
                        continue;
                    }
                    win_stats(l, x, y, &sl, &vl);
                    if (vl < c->texture_min || vl <= 0) {
                        continue;
                    }
                    for (k = -n; k <= n; k++) {
                        int32_t b = 0;
                        int32_t d;
                        for (d = ctx->dmin; d <= ctx->dmax; d++) {
                            int32_t xr = x - d;
                            int32_t s;
                            if (xr - VALIGN_WIN_R < 0) {
                                break;
                            }
                            s = mncc_q14(l, x, y, sl, vl, r, xr, y + k);
                            if (s > b) {
                                b = s;
                            }
                        }
                        best[k + n] = b;
                        if (b > top) {
                            top = b;
                        }
                    }
                    if (top < c->match_min_q14) {
                        continue;
                    }
                    for (k = 0; k < nk; k++) {
                        sum[k] += best[k];
                    }
                    ctx->tile_n[t]++;
                    used++;
                }
            }
        }
    }
    return used;
}

/* Sub-pixel offset (Q4) of each tile's curve, or VALIGN_NO_TILE. */
static void tile_offsets(negobs_valign_t *ctx, int32_t n)
{
    const negobs_valign_config_t *c = &ctx->cfg;
    int32_t nk = 2 * n + 1;
    int32_t t;
    for (t = 0; t < c->tiles_x * c->tiles_y; t++) {
        const int32_t *sum = ctx->tile_sum + (size_t)t * (size_t)nk;
        int32_t kb = 0;
        int32_t k;
        int32_t den;
        int32_t dq4;
        ctx->tile_off_q4[t] = VALIGN_NO_TILE;
        if (ctx->tile_n[t] < 2) {
            continue;
        }
        for (k = 1; k < nk; k++) {
            if (sum[k] > sum[kb]) {
                kb = k;
            }
        }
        if (kb == 0 || kb == nk - 1) {
            continue; /* peak at the search limit: no vertex to place */
        }
        den = sum[kb - 1] - 2 * sum[kb] + sum[kb + 1];
        if (den >= 0 || -den < ctx->tile_n[t] * VALIGN_CURV_MIN_Q14) {
            continue;
        }
        dq4 = (int32_t)negobs_div_round_s64(
            8 * (int64_t)(sum[kb - 1] - sum[kb + 1]), den);
        dq4 = negobs_clamp_s32(dq4, -8, 8);
        ctx->tile_off_q4[t] = 16 * (kb - n) + dq4;
    }
}

static int64_t det3(int64_t m[3][3])
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Least squares of tile offsets (Q4) against a + b*v + c*u in half-tile
 * units, over tiles whose |residual| <= cut (all when cut < 0). Returns the
 * number of tiles used; sol = {num_a, num_v, num_u}, *det the common
 * denominator (> 0), or 0 tiles when the system is singular. */
typedef struct fit {
    int64_t num[3];
    int64_t det;
    int32_t tiles;
    int32_t kind;
} fit_t;

static inline int32_t half_u(const negobs_valign_config_t *c, int32_t tx)
{
    return 2 * tx - (c->tiles_x - 1);
}

static inline int32_t half_v(const negobs_valign_config_t *c, int32_t ty)
{
    return 2 * ty - (c->tiles_y - 1);
}

/* Model value at a tile, Q4 (rounded). */
static int32_t fit_eval_q4(const fit_t *f, int32_t u, int32_t v)
{
    if (f->det <= 0) {
        return 0; /* no fit: callers only pass fits with tiles */
    }
    return (int32_t)negobs_div_round_s64(
        f->num[0] + f->num[1] * v + f->num[2] * u, f->det);
}

static int32_t fit_tiles(const negobs_valign_t *ctx, const fit_t *prev,
                         int32_t cut, int32_t kind, fit_t *out)
{
    const negobs_valign_config_t *c = &ctx->cfg;
    int64_t m[3][3];
    int64_t rhs[3];
    int32_t ty;
    int32_t tx;
    int32_t n = 0;
    int32_t i;

    memset(m, 0, sizeof m);
    memset(rhs, 0, sizeof rhs);
    for (ty = 0; ty < c->tiles_y; ty++) {
        for (tx = 0; tx < c->tiles_x; tx++) {
            int32_t o = ctx->tile_off_q4[ty * c->tiles_x + tx];
            int64_t e[3];
            int32_t a;
            int32_t b;
            if (o == VALIGN_NO_TILE) {
                continue;
            }
            if (prev != NULL &&
                negobs_abs_s32(o - fit_eval_q4(prev, half_u(c, tx),
                                               half_v(c, ty))) > cut) {
                continue;
            }
            e[0] = 1;
            e[1] = (kind >= NEGOBS_VALIGN_ROWS) ? half_v(c, ty) : 0;
            e[2] = (kind >= NEGOBS_VALIGN_AFFINE) ? half_u(c, tx) : 0;
            for (a = 0; a < 3; a++) {
                for (b = 0; b < 3; b++) {
                    m[a][b] += e[a] * e[b];
                }
                rhs[a] += e[a] * o;
            }
            n++;
        }
    }
    /* unused unknowns: identity rows, so they solve to 0 */
    for (i = kind + 1; i < 3; i++) {
        m[i][i] = 1;
    }
    memset(out, 0, sizeof *out);
    out->kind = kind;
    if (n == 0) {
        return 0;
    }
    out->det = det3(m);
    if (out->det <= 0) {
        return 0; /* singular (e.g. one row of tiles for a row slope) */
    }
    for (i = 0; i < 3; i++) {
        int64_t mi[3][3];
        int32_t r;
        memcpy(mi, m, sizeof mi);
        for (r = 0; r < 3; r++) {
            mi[r][i] = rhs[r];
        }
        out->num[i] = det3(mi);
    }
    out->tiles = n;
    return n;
}

/* Median of |residual| (Q4) over the tiles the fit used. */
static int32_t fit_mad_q4(const negobs_valign_t *ctx, const fit_t *f,
                          const fit_t *gate, int32_t cut)
{
    const negobs_valign_config_t *c = &ctx->cfg;
    /* residuals of at most 16 * 16 tiles, clamped to 0..255: a count per
     * value finds the median without sorting */
    uint16_t hist[256];
    int32_t ty;
    int32_t tx;
    int32_t n = 0;
    int32_t acc = 0;
    int32_t v;
    memset(hist, 0, sizeof hist);
    for (ty = 0; ty < c->tiles_y; ty++) {
        for (tx = 0; tx < c->tiles_x; tx++) {
            int32_t o = ctx->tile_off_q4[ty * c->tiles_x + tx];
            int32_t u = half_u(c, tx);
            int32_t vv = half_v(c, ty);
            if (o == VALIGN_NO_TILE) {
                continue;
            }
            if (gate != NULL &&
                negobs_abs_s32(o - fit_eval_q4(gate, u, vv)) > cut) {
                continue;
            }
            hist[negobs_clamp_s32(negobs_abs_s32(o - fit_eval_q4(f, u, vv)), 0,
                                  255)]++;
            n++;
        }
    }
    for (v = 0; v < 256; v++) {
        acc += hist[v];
        if (2 * acc >= n) {
            return v;
        }
    }
    return 255;
}

/* Convert a fit to the Q16 model. */
static void fit_model(const negobs_valign_config_t *c, const fit_t *f,
                      negobs_valign_model_t *m)
{
    int64_t cv_q16;
    int64_t cu_q16;
    memset(m, 0, sizeof *m);
    if (f->det <= 0) {
        return; /* no fit: the zero model */
    }
    cv_q16 = negobs_div_round_s64(f->num[1] * 4096, f->det);
    cu_q16 = negobs_div_round_s64(f->num[2] * 4096, f->det);
    /* one half-tile unit is h / (2 * tiles_y) rows */
    m->offset_q16 = (int32_t)negobs_div_round_s64(f->num[0] * 4096, f->det);
    m->slope_y_q16 = (int32_t)negobs_div_round_s64(cv_q16 * 2 * c->tiles_y,
                                                   c->height);
    m->slope_x_q16 = (int32_t)negobs_div_round_s64(cu_q16 * 2 * c->tiles_x,
                                                   c->width);
}

/* Residual gate of the second fit: 3 MADs, never below 1/4 px. */
static inline int32_t geom_cut(int32_t mad_q4)
{
    return (3 * mad_q4 > 4) ? 3 * mad_q4 : 4;
}

/* One pass: offsets within +-n rows, robust fit; 1 when accepted. */
static int32_t estimate_pass(negobs_valign_t *ctx, const negobs_image_u8_t *l,
                             const negobs_image_u8_t *r, int32_t n,
                             negobs_valign_model_t *m,
                             negobs_valign_stats_t *st)
{
    const negobs_valign_config_t *c = &ctx->cfg;
    fit_t f1;
    fit_t f2;
    int32_t kind = c->kind;
    int32_t used = score_tiles(ctx, l, r, n);
    int32_t mad;
    int32_t cut;

    memset(m, 0, sizeof *m);
    memset(&f1, 0, sizeof f1);
    tile_offsets(ctx, n);
    /* a slope needs tiles at two heights or columns: fall back */
    while (kind >= NEGOBS_VALIGN_CONST &&
           fit_tiles(ctx, NULL, 0, kind, &f1) < c->min_tiles) {
        if (kind == NEGOBS_VALIGN_CONST) {
            break;
        }
        kind--;
    }
    if (st != NULL) {
        st->samples_used = used;
        st->tiles_used = 0;
        st->resid_q4 = 0;
    }
    if (f1.tiles < c->min_tiles) {
        return 0;
    }
    mad = fit_mad_q4(ctx, &f1, NULL, 0);
    cut = geom_cut(mad);
    if (fit_tiles(ctx, &f1, cut, kind, &f2) < c->min_tiles) {
        f2 = f1;
        cut = INT32_MAX;
    }
    fit_model(c, &f2, m);
    if (!valign_model_ok(m) ||
        negobs_abs_s32(m->offset_q16) > (c->max_offset + 1) * 65536) {
        memset(m, 0, sizeof *m);
        return 0;
    }
    if (st != NULL) {
        st->tiles_used = f2.tiles;
        st->resid_q4 = fit_mad_q4(ctx, &f2, &f1, cut);
    }
    return 1;
}

static negobs_status_t check_images(const negobs_valign_t *ctx,
                                    const negobs_image_u8_t *l,
                                    const negobs_image_u8_t *r,
                                    const negobs_image_u8_t *o)
{
    if (negobs_image_u8_check(l) != NEGOBS_OK ||
        negobs_image_u8_check(r) != NEGOBS_OK ||
        negobs_image_u8_check(o) != NEGOBS_OK || l->width != ctx->cfg.width ||
        l->height != ctx->cfg.height || r->width != l->width ||
        r->height != l->height || o->width != l->width ||
        o->height != l->height || o->data == r->data || o->data == l->data) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

static inline int32_t add_sat(int32_t a, int32_t b, int32_t lim)
{
    return negobs_clamp_s32(a + b, -lim, lim);
}

/* acc += residual, each term kept within the limits a model may carry. */
static void model_add(negobs_valign_model_t *acc,
                      const negobs_valign_model_t *residual)
{
    acc->offset_q16 = add_sat(acc->offset_q16, residual->offset_q16,
                              VALIGN_OFFSET_LIMIT_Q16);
    acc->slope_y_q16 = add_sat(acc->slope_y_q16, residual->slope_y_q16,
                               NEGOBS_VALIGN_SLOPE_LIMIT_Q16);
    acc->slope_x_q16 = add_sat(acc->slope_x_q16, residual->slope_x_q16,
                               NEGOBS_VALIGN_SLOPE_LIMIT_Q16);
}

negobs_status_t negobs_valign_estimate(negobs_valign_t *ctx,
                                       const negobs_image_u8_t *left,
                                       const negobs_image_u8_t *right,
                                       negobs_image_u8_t *scratch,
                                       negobs_valign_model_t *model,
                                       negobs_valign_stats_t *stats)
{
    negobs_valign_stats_t st;
    negobs_valign_stats_t st2;
    negobs_valign_model_t m1;
    negobs_valign_model_t m2;
    negobs_status_t rc;
    int32_t n2;

    if (ctx == NULL || ctx->ready != VALIGN_READY) {
        return NEGOBS_ERR_STATE;
    }
    if (model == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    rc = check_images(ctx, left, right, scratch);
    if (rc != NEGOBS_OK) {
        return rc;
    }
    memset(&st, 0, sizeof st);
    memset(model, 0, sizeof *model);
    st.accepted = estimate_pass(ctx, left, right, ctx->cfg.max_offset, &m1,
                                &st);
    if (st.accepted) {
        /* second pass on the pair aligned by the first: what is left is
         * small, where the parabola vertex is unbiased */
        rc = negobs_valign_warp(&m1, right, scratch);
        if (rc != NEGOBS_OK) {
            return rc;
        }
        n2 = (ctx->cfg.max_offset < 2) ? ctx->cfg.max_offset : 2;
        if (estimate_pass(ctx, left, scratch, n2, &m2, &st2)) {
            model_add(&m1, &m2);
        }
        *model = m1;
    }
    st.frame = *model;
    st.model = *model;
    if (stats != NULL) {
        *stats = st;
    }
    return NEGOBS_OK;
}

/* a + (b - a) * g / 32768, rounded (g in 1..32768). */
static inline int32_t blend_q15(int32_t a, int32_t b, int32_t g)
{
    return a + (int32_t)negobs_div_round_s64(((int64_t)b - a) * g, 32768);
}

negobs_status_t negobs_valign_process(negobs_valign_t *ctx,
                                      const negobs_image_u8_t *left,
                                      const negobs_image_u8_t *right,
                                      negobs_image_u8_t *out,
                                      negobs_valign_stats_t *stats)
{
    negobs_valign_stats_t st;
    negobs_valign_model_t m;
    negobs_status_t rc;
    int32_t n2;
    int32_t warped = 0;

    if (ctx == NULL || ctx->ready != VALIGN_READY) {
        return NEGOBS_ERR_STATE;
    }
    rc = check_images(ctx, left, right, out);
    if (rc != NEGOBS_OK) {
        return rc;
    }
    memset(&st, 0, sizeof st);
    memset(&m, 0, sizeof m);
    n2 = (ctx->cfg.max_offset < 2) ? ctx->cfg.max_offset : 2;
    if (ctx->have_model && ctx->misses < VALIGN_REACQUIRE) {
        /* steady state: only what the tracked model leaves, over +-2 rows
         * (5 offsets instead of 2 passes over 9 + 5) */
        rc = negobs_valign_warp(&ctx->model, right, out);
        if (rc != NEGOBS_OK) {
            return rc;
        }
        st.accepted = estimate_pass(ctx, left, out, n2, &m, &st);
        if (st.accepted) {
            negobs_valign_model_t residual = m;
            m = ctx->model;
            model_add(&m, &residual);
        } else {
            /* out already holds right warped by the unchanged model */
            warped = 1;
        }
    } else {
        rc = negobs_valign_estimate(ctx, left, right, out, &m, &st);
        if (rc != NEGOBS_OK) {
            return rc;
        }
    }
    if (st.accepted) {
        ctx->misses = 0;
        if (!ctx->have_model) {
            ctx->model = m;
            ctx->have_model = 1;
        } else {
            int32_t g = ctx->cfg.smooth_q15;
            ctx->model.offset_q16 = blend_q15(ctx->model.offset_q16,
                                              m.offset_q16, g);
            ctx->model.slope_y_q16 = blend_q15(ctx->model.slope_y_q16,
                                               m.slope_y_q16, g);
            ctx->model.slope_x_q16 = blend_q15(ctx->model.slope_x_q16,
                                               m.slope_x_q16, g);
        }
    } else if (ctx->have_model && ctx->misses < VALIGN_REACQUIRE) {
        /* a run of frames the residual search cannot place (a jolt moved
         * the cameras by more than it covers, or no texture) ends in a
         * full search */
        ctx->misses++;
    }
    st.frame = m;
    st.model = ctx->model;
    if (!warped) {
        rc = negobs_valign_warp(&ctx->model, right, out);
    }
    if (stats != NULL) {
        *stats = st;
    }
    return rc;
}
