/*
 * The ground fit's support (docs/DETECTION.md section 4, "Support"): which
 * column strips of the fit rows show a floor the fit may use.
 */
#include <string.h>

#include "geom_internal.h"
#include "ground_fit.h"
#include "negobs/fixed.h"

/*
 * Support: the column strips whose own valid share reaches
 * ground_min_valid_pct. A strip covered by an object nearer than the
 * search range (hands), or by a surface the matcher cannot read, holds no
 * floor the fit can use; its few chance matches are left out, and it does
 * not dilute the share of the strips that do show floor.
 *
 * The histogram, and the nearest row with support (v_bot): the first
 * sampled row from the bottom where a quarter of the support's columns
 * hold a usable sample, the rule by which a row votes in ground_top. The
 * refinement's "nearest third" and "nearer half" count from there: rows
 * covered by a near object hold no ground under the feet.
 */
void gfit_support(gfit_t *g, const negobs_image_s16_t *disp,
                  const negobs_image_u8_t *conf, const int16_t *view_u0,
                  const int16_t *view_u1, gfit_support_t *sup)
{
    const negobs_detect_config_t *cfg = g->cfg;
    const negobs_rig_t *rig = &cfg->rig;
    int32_t v;
    int32_t u;
    int32_t i;

    memset(sup, 0, sizeof *sup);
    memset(g->vhist, 0, (size_t)g->rows * (size_t)g->nbins * sizeof(uint16_t));
    for (v = g->v_hi; v >= g->v_lo; v -= g->step) {
        const int16_t *row = negobs_image_s16_row(disp, v);
        for (u = g->step / 2; u < rig->width; u += g->step) {
            if (view_u0 != NULL && (u < view_u0[v] || u >= view_u1[v])) {
                continue; /* out of view: no floor to find there */
            }
            sup->col_n[u / g->col_w]++;
            sup->col_valid[u / g->col_w] += (uint32_t)gfit_sample_valid(
                conf, cfg->ground_min_confidence, u, v, row[u]);
        }
    }
    for (i = 0; i < GFIT_COLS; i++) {
        sup->samples += sup->col_n[i];
        sup->valid += sup->col_valid[i];
        g->col_ok[i] = (uint8_t)(sup->col_n[i] > 0u &&
                                 (uint64_t)sup->col_valid[i] * 100u >=
                                     (uint64_t)sup->col_n[i] *
                                         (uint32_t)cfg->ground_min_valid_pct);
        if (g->col_ok[i]) {
            sup->support += sup->col_n[i];
            sup->support_valid += sup->col_valid[i];
        }
    }
    g->support_cols = 0;
    for (u = g->step / 2; u < rig->width; u += g->step) {
        g->support_cols += g->col_ok[u / g->col_w];
    }
    g->v_bot = -1;
    for (v = g->v_hi; v >= g->v_lo; v -= g->step) {
        const int16_t *row = negobs_image_s16_row(disp, v);
        uint16_t *h = g->vhist + (size_t)(v - g->v_lo) * (size_t)g->nbins;
        int32_t n_row = 0;
        for (u = g->step / 2; u < rig->width; u += g->step) {
            int32_t d = row[u];
            if ((view_u0 != NULL && (u < view_u0[v] || u >= view_u1[v])) ||
                !gfit_sample_ok(g, conf, u, v, d)) {
                continue;
            }
            n_row++;
            if (d / g->bin_q4 < g->nbins) {
                h[d / g->bin_q4]++;
            }
        }
        if (g->v_bot < 0 && 4 * n_row >= g->support_cols && n_row > 0) {
            g->v_bot = v;
        }
    }
    g->near_rows = (g->v_bot >= g->v_lo) ? g->v_bot + 1 - g->v_lo : g->rows;
}

/*
 * Line support: after the seed step, a column strip stays in the support
 * only when at least half of its usable samples in the nearer half of the
 * rows (counted from v_bot, where the ground under the feet is) lie within
 * the seed's gate (48 q4, 3 px) of the seed plane. A strip filled by a
 * cupboard front, a wall or a chair stands 3-7 px above the floor there on
 * the reference rig; left in, its samples made the noise estimate (a MAD,
 * which assumes the floor is the majority) several px wide, the gates
 * opened, and the plane bent toward the front (a front over 60 % of the
 * band's width: rejected).
 */
uint32_t gfit_line_support(gfit_t *g, const negobs_image_s16_t *disp,
                           const negobs_image_u8_t *conf,
                           const negobs_ground_plane_t *plane,
                           const gfit_support_t *sup, uint32_t *valid_out)
{
    const negobs_rig_t *rig = &g->cfg->rig;
    uint32_t n[GFIT_COLS];
    uint32_t agree[GFIT_COLS];
    uint32_t kept = 0;
    int32_t v;
    int32_t u;
    int32_t i;
    memset(n, 0, sizeof n);
    memset(agree, 0, sizeof agree);
    for (v = g->v_hi; v >= g->v_lo + g->near_rows / 2; v -= g->step) {
        const int16_t *row = negobs_image_s16_row(disp, v);
        int64_t base = (int64_t)plane->b_q20 * v + plane->c_q20;
        for (u = g->step / 2; u < rig->width; u += g->step) {
            int32_t d = row[u];
            int32_t r;
            if (!gfit_sample_ok(g, conf, u, v, d)) {
                continue;
            }
            r = d - (int32_t)geom_rshift_round_s64(
                        base + (int64_t)plane->a_q20 * u, 16);
            n[u / g->col_w]++;
            agree[u / g->col_w] += negobs_abs_s32(r) <= 48;
        }
    }
    *valid_out = 0;
    for (i = 0; i < GFIT_COLS; i++) {
        if (g->col_ok[i] && 2u * agree[i] < n[i]) {
            g->col_ok[i] = 0;
        }
        if (g->col_ok[i]) {
            kept += sup->col_n[i];
            *valid_out += sup->col_valid[i];
        }
    }
    g->support_cols = 0;
    for (u = g->step / 2; u < rig->width; u += g->step) {
        g->support_cols += g->col_ok[u / g->col_w];
    }
    return kept;
}
