/* The ground fit's rows within the matcher's disparity range. */
#include "ground_fit.h"

#include "geom_internal.h"

/*
 * Beyond the matcher's range (docs/DETECTION.md section 4, "Beyond the
 * matcher's range"). A camera with a long focal length and baseline,
 * mounted low or pitched down, sees the floor near the feet at more
 * disparity than the matcher searches (stereo.max_disp). No value there
 * is right: the rows where the floor leaves the range read its top, and
 * below them the matcher carries whatever its growth and DP bring. Fitted
 * with the rest, those rows tilted the plane (a 0.9 m / 35 deg camera with
 * f = 700 px and B = 120 mm, searched to 63 px, fitted 1.04-1.07 m /
 * 43-45 deg) and the rule read a drop at the feet on every frame of a
 * flat walk. So the fit reads only the rows above the topmost one where a
 * quarter of the usable samples (4 at least: one stray value is not a
 * surface) lie at the range's top; such a row shows a surface the matcher
 * cannot measure, and the floor below it is nearer still.
 */
int32_t gfit_range_rows_hi(const gfit_t *g, const negobs_image_s16_t *disp,
                           const negobs_image_u8_t *conf)
{
    const negobs_rig_t *rig = &g->cfg->rig;
    int32_t hi = rig->height - 1;
    int32_t v;
    for (v = rig->height - 1; v >= g->v_lo; v -= g->step) {
        const int16_t *row = negobs_image_s16_row(disp, v);
        int32_t n = 0;
        int32_t n_top = 0;
        int32_t u;
        for (u = g->step / 2; u < rig->width; u += g->step) {
            int32_t d = row[u];
            if (gfit_sample_valid(conf, g->cfg->ground_min_confidence, u, v,
                                  d)) {
                n++;
                n_top += d >= g->d_top_q4;
            }
        }
        if (n_top >= 4 && 4 * n_top >= n) {
            hi = v - g->step;
        }
    }
    return hi;
}

/* The nearest row at or above hi (on the fit's grid) whose floor, on the
 * plane, lies within the matcher's range at both image borders. */
int32_t gfit_plane_rows_hi(const gfit_t *g, const negobs_ground_plane_t *pl,
                           int32_t hi)
{
    const int32_t w = g->cfg->rig.width;
    while (hi >= 0 && (negobs_ground_disp_q4(pl, 0, hi) >= g->d_top_q4 ||
                       negobs_ground_disp_q4(pl, w - 1, hi) >= g->d_top_q4)) {
        hi -= g->step;
    }
    return hi;
}

/* The fit reads rows up to hi. The bottom band moves up with it, as
 * many rows as were cut (not above the wide band's top): it is the
 * nearest floor in view, and the bottom rows show none. */
void gfit_range_cut(gfit_t *g, int32_t hi)
{
    const int32_t bottom = g->cfg->rig.height - 1;
    g->v_hi = hi;
    if (!g->wide) {
        g->v_lo = geom_max_s32(g->band_v_lo - (bottom - hi), g->wide_v_lo);
        g->rows = bottom + 1 - g->v_lo;
    }
}

/* The nearest row whose floor, on the plane, the matcher can measure at
 * the centre column: height-1 unless the floor there lies beyond the
 * range; never below the rows the fit read. */
int32_t gfit_near_row(const gfit_t *g, const negobs_ground_plane_t *pl)
{
    return geom_max_s32(
        gfit_row_in_range(pl, g->cfg->rig.width / 2, g->v_hi, g->d_top_q4), 0);
}
