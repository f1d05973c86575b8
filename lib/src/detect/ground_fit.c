/*
 * Ground model estimation: v-disparity -> Hough -> plane -> track.
 *
 * 1. v-disparity. Over the bottom fit_rows_pct of the image (and never above
 *    the lowest horizon the priors allow: the principal row at pitch 0),
 *    every fit_step-th pixel with a valid disparity in a column strip of
 *    the support (ground_support.c: the strips whose own valid share
 *    reaches ground_min_valid_pct) is counted into a (row, disparity bin)
 *    histogram. When this bottom band gives no accepted fit, the whole fit
 *    runs again on the wide band: every row below that horizon.
 * 2. Constrained Hough. A flat ground is the line d = s*(v - v_h) in that
 *    histogram. Only lines whose (H, pitch) lie inside the physical
 *    priors of a worn camera (mount.c) are searched: 32 slopes
 *    s = B*cos(p)/H between the extremes, and for each slope the intercept k = s*v_h over the horizon
 *    rows the pitch range allows. A cell (v, d) votes k = s*v - d for every
 *    slope, weighted by its count: no divisions in the loop. The peak is
 *    taken on a 3-bin sum so noise that splits a line over two bins does
 *    not lose it.
 * 3. Plane refinement. Least squares of d = a*u + b*v + c on the samples
 *    within a gate of the current model (IRLS with 0/1 weights): once on
 *    the nearest third of the fit rows (counted from the nearest row with
 *    support), after which strips that mostly disagree with the plane
 *    leave the support (a front, a wall), once on the nearer half with a
 *    tighter gate, then twice on all fit rows with an asymmetric gate
 *    (+3 sigma / -2 sigma). Before each widening, the rows are only taken
 *    up to an edge: the first two sampled rows whose majority lies 3 sigma
 *    below the current model (ground_top). The unknowns are the
 *    corrections to the current plane, on centred coordinates, so every
 *    sum stays small.
 * 4. Noise. sigma = 1.4826 * MAD of the residuals of the samples in the
 *    nearer half of the fit rows (an overflow bin keeps far outliers
 *    counted), floored at sigma_min.
 * 5. Acceptance and tracking. The support must hold a quarter of the
 *    band's samples, the pose of the plane must be a possible floor
 *    (mount_pose_physical: the priors, never the configured hint) and
 *    enough samples must be inliers. An accepted fit is
 *    blended into the track when it agrees with it at three reference
 *    points, and replaces it after two frames of disagreement.
 *
 * TUNABLE: the gates (48, 3 sigma; then +3/-2 sigma, q4 floors 12/6) and
 * the 3 reference points.
 */
#include "ground_fit.h"

#include <string.h>

#include "detect_int.h"
#include "geom_internal.h"
#include "mount.h"
#include "negobs/fixed.h"

/* Ground fit limits: at most this many samples, so sums stay bounded. */

#define GFIT_MAX_SAMPLES 32768

static int32_t clamp_pitch(int32_t p)
{
    return negobs_clamp_s32(p, -10000, 70000);
}

/* Sampling step for a band of rows: fit_step_px, grown until the band
 * holds at most GFIT_MAX_SAMPLES samples. */
static int32_t band_step(const negobs_detect_config_t *cfg, int32_t rows)
{
    int32_t step = geom_max_s32(cfg->fit_step_px, 1);
    while (((int64_t)cfg->rig.width / step + 1) * (rows / step + 1) >
           GFIT_MAX_SAMPLES) {
        step++;
    }
    return step;
}

negobs_status_t gfit_carve(gfit_t *g, negobs_arena_t *ar,
                           const negobs_detect_config_t *cfg)
{
    const negobs_rig_t *rig = &cfg->rig;
    mount_box_t box;
    int32_t pmin;
    int32_t pmax;
    int32_t hmin;
    int32_t hmax;
    int32_t smin;
    int32_t cosmax;
    int32_t cosmin;
    int32_t sn;
    int32_t cs;
    int64_t vh_min_q4;
    int64_t vh_max_q4;
    int32_t vh_floor;
    int32_t fit_rows;
    int32_t i;

    memset(g, 0, sizeof *g);
    g->cfg = cfg;
    mount_search_box(cfg, &box);
    pmin = clamp_pitch(box.p_min_mdeg);
    pmax = clamp_pitch(box.p_max_mdeg);
    hmin = geom_max_s32(box.h_min_mm, 100);
    hmax = geom_max_s32(box.h_max_mm, hmin);

    /* Extremes of cos(pitch) over the range (cos is largest nearest 0). */
    negobs_sincos_q30(pmin, &sn, &cs);
    cosmin = cs;
    negobs_sincos_q30(pmax, &sn, &cs);
    cosmin = geom_min_s32(cosmin, cs);
    if (pmin <= 0 && pmax >= 0) {
        cosmax = 1 << 30;
    } else {
        int32_t c1;
        int32_t c2;
        negobs_sincos_q30(pmin, NULL, &c1);
        negobs_sincos_q30(pmax, NULL, &c2);
        cosmax = geom_max_s32(c1, c2);
    }
    /* Slopes s = B*cos/H in px/row Q12. */
    smin = (int32_t)(((int64_t)rig->baseline_um * cosmin /
                      ((int64_t)hmax * 1000)) >>
                     18);
    {
        int32_t smax = (int32_t)(((int64_t)rig->baseline_um * cosmax /
                                  ((int64_t)hmin * 1000)) >>
                                 18);
        int32_t span = smax - smin;
        g->n_slopes = GFIT_N_SLOPES;
        for (i = 0; i < GFIT_N_SLOPES; i++) {
            g->s_q12[i] = smin + (int32_t)(((int64_t)span * i +
                                            (GFIT_N_SLOPES - 1) / 2) /
                                           (GFIT_N_SLOPES - 1));
            if (g->s_q12[i] < 1) {
                g->s_q12[i] = 1;
            }
        }
    }
    /* Horizon rows v_h = cy - f*tan(p), Q4. */
    negobs_sincos_q30(pmax, &sn, &cs);
    vh_min_q4 = rig->cy_q4 - ((int64_t)rig->focal_q4 * sn) / cs;
    negobs_sincos_q30(pmin, &sn, &cs);
    vh_max_q4 = rig->cy_q4 - ((int64_t)rig->focal_q4 * sn) / cs;
    for (i = 0; i < GFIT_N_SLOPES; i++) {
        int64_t klo = ((int64_t)g->s_q12[i] * vh_min_q4) / 16;
        int64_t khi = ((int64_t)g->s_q12[i] * vh_max_q4) / 16;
        int64_t kbin = (khi - klo + GFIT_N_K - 3) / (GFIT_N_K - 2);
        /* At least half a pixel of disparity per intercept bin. */
        if (kbin < 2048) {
            kbin = 2048;
        }
        /* One spare bin on each side. */
        g->k_lo_q12[i] = klo - kbin;
        g->k_bin_q12[i] = kbin;
    }

    /* Fit rows: bottom share, and at least 4 rows below the lowest
     * horizon the priors allow. The wide band reaches up to that horizon
     * bound: every row where the floor of some possible mounting can be. */
    fit_rows = (rig->height * cfg->fit_rows_pct) / 100;
    vh_floor = (int32_t)(vh_max_q4 / 16) + 4;
    g->v_lo = geom_max_s32(rig->height - fit_rows, vh_floor);
    if (g->v_lo > rig->height - 8) {
        g->v_lo = rig->height - 8;
    }
    if (g->v_lo < 0) {
        g->v_lo = 0;
    }
    g->rows = rig->height - g->v_lo;
    g->wide_v_lo = negobs_clamp_s32(vh_floor, 0, g->v_lo);
    g->bin_q4 = 8;
    g->nbins = cfg->max_disp_q4 / g->bin_q4 + 1;
    g->step = band_step(cfg, g->rows);
    g->wide_step = band_step(cfg, rig->height - g->wide_v_lo);
    g->col_w = (rig->width + GFIT_COLS - 1) / GFIT_COLS;
    g->band_v_lo = g->v_lo;
    g->band_step = g->step;
    g->v_hi = rig->height - 1;
    g->d_top_q4 = gfit_range_top_q4(cfg);

    g->vhist = negobs_arena_take(ar, (size_t)(rig->height - g->wide_v_lo) *
                                         (size_t)g->nbins * sizeof(uint16_t));
    g->acc = negobs_arena_take(ar, (size_t)GFIT_N_SLOPES * GFIT_N_K *
                                       sizeof(uint32_t));
    g->absres = negobs_arena_take(ar, GFIT_ABS_BINS * sizeof(uint32_t));
    gfit_reset(g);
    return negobs_arena_status(ar);
}

void gfit_reset(gfit_t *g)
{
    g->tracked = 0;
    g->jumps = 0;
    g->fails = 0;
    g->sigma_q4 = g->cfg->sigma_min_q4;
    memset(&g->plane, 0, sizeof g->plane);
}

/* Hough peak over the v-disparity histogram. Returns 0 when empty. */
static int hough_line(gfit_t *g, negobs_ground_plane_t *plane)
{
    int32_t r;
    int32_t b;
    int32_t i;
    uint32_t best = 0;
    int32_t best_i = -1;
    int32_t best_k = 0;

    memset(g->acc, 0, (size_t)GFIT_N_SLOPES * GFIT_N_K * sizeof(uint32_t));
    for (r = 0; r < g->rows; r++) {
        const uint16_t *h = g->vhist + (size_t)r * (size_t)g->nbins;
        int32_t v = g->v_lo + r;
        for (b = 1; b < g->nbins; b++) {
            uint32_t c = h[b];
            int64_t d_q12;
            if (c == 0) {
                continue;
            }
            /* Bin centre, px Q12. */
            d_q12 = ((int64_t)b * g->bin_q4 + g->bin_q4 / 2) * 256;
            for (i = 0; i < g->n_slopes; i++) {
                int64_t k = (int64_t)g->s_q12[i] * v - d_q12;
                int64_t kb = (k - g->k_lo_q12[i]) / g->k_bin_q12[i];
                if (k >= g->k_lo_q12[i] && kb < GFIT_N_K) {
                    g->acc[i * GFIT_N_K + (int32_t)kb] += c;
                }
            }
        }
    }
    for (i = 0; i < g->n_slopes; i++) {
        const uint32_t *a = g->acc + (ptrdiff_t)i * GFIT_N_K;
        int32_t k;
        for (k = 1; k < GFIT_N_K - 1; k++) {
            uint32_t s = a[k - 1] + a[k] + a[k + 1];
            if (s > best) {
                best = s;
                best_i = i;
                best_k = k;
            }
        }
    }
    if (best_i < 0 || best == 0) {
        return 0;
    }
    {
        /* Weighted intercept inside the 3-bin window. */
        const uint32_t *a = g->acc + (ptrdiff_t)best_i * GFIT_N_K;
        int64_t kb = g->k_bin_q12[best_i];
        int64_t k0 = g->k_lo_q12[best_i] + (int64_t)best_k * kb + kb / 2;
        int64_t num = (int64_t)a[best_k + 1] - (int64_t)a[best_k - 1];
        int64_t k = k0 + (num * kb) / (int64_t)best;
        plane->a_q20 = 0;
        plane->b_q20 = g->s_q12[best_i] * 256;
        plane->c_q20 = (int32_t)geom_clamp_s64(-k * 256, -INT32_MAX,
                                               INT32_MAX);
    }
    return 1;
}

/* num / den * 2^shift (shift <= 16) with both normalised into range;
 * den != 0. */
static int64_t ratio_scaled(int64_t num, int64_t den, int32_t shift)
{
    const int64_t lim = (int64_t)1 << 44;
    while (num >= lim || num <= -lim || den >= lim || den <= -lim) {
        num = geom_asr_s64(num, 1);
        den = geom_asr_s64(den, 1);
    }
    if (den == 0) {
        return 0;
    }
    return negobs_div_round_s64(num * ((int64_t)1 << shift), den);
}

/*
 * One IRLS step: least squares for a correction plane on the samples with
 * |residual| <= gate_q4. Returns the inlier count; updates *plane when the
 * system is well conditioned.
 *
 * The residual keeps 8 fractional bits of the model (1/4096 px): rounded
 * to whole q4 it carried the model's rounding error, which along a row of
 * a plane without roll is one constant and drifts slowly from row to row,
 * so the fit read part of that sawtooth as slope, and a second step on
 * the same samples moved the plane again. On the matched map of an exactly
 * rendered flat 320x240 frame (pitch 20 deg, H 1.2 m) this alone tilted
 * the fit by 0.2 deg (20.58 -> 20.38 deg; the rest was the matcher's
 * border bias, stereo/refine.c); on generated maps the plane was 10/256 px
 * off, 2/256 now (test_ground_fit_is_unbiased_on_a_clean_flat_map).
 *
 * Scaling: x, y centred, |x|, |y| < 2^12; residuals |r| <= gate < 2^8 q4,
 * so |r_q12| < 2^16; at most 2^15 samples, so n*Sxx < 2^54 and n*Sxr <
 * 2^58 (Sx*Sr < 2^27 * 2^31). Centred moments are shifted into 30 bits
 * before the 2x2 products (< 2^61).
 */
static int32_t refine_step(const gfit_t *g, const negobs_image_s16_t *disp,
                           const negobs_image_u8_t *conf,
                           negobs_ground_plane_t *plane, int32_t gate_q4,
                           int32_t neg_gate_q4, int32_t v_top)
{
    const negobs_rig_t *rig = &g->cfg->rig;
    int32_t uc = rig->width / 2;
    int32_t vc = g->v_lo + g->rows / 2;
    int64_t n = 0;
    int64_t sx = 0, sy = 0, sr = 0, sxx = 0, sxy = 0, syy = 0, sxr = 0,
            syr = 0;
    int64_t cxx, cxy, cyy, cxr, cyr;
    int64_t det;
    int64_t al_q16;
    int64_t be_q16;
    int64_t ga_q16;
    int32_t v;
    int32_t u;
    int sh = 0;

    for (v = g->v_hi; v >= v_top; v -= g->step) {
        const int16_t *row = negobs_image_s16_row(disp, v);
        int64_t base = (int64_t)plane->b_q20 * v + plane->c_q20;
        for (u = g->step / 2; u < rig->width; u += g->step) {
            int32_t d = row[u];
            int64_t r; /* q12: 1/256 of a q4 step */
            int64_t x;
            int64_t y;
            if (!gfit_sample_ok(g, conf, u, v, d)) {
                continue;
            }
            r = geom_rshift_round_s64(
                (int64_t)d * 65536 - (base + (int64_t)plane->a_q20 * u), 8);
            if (r > (int64_t)gate_q4 * 256 ||
                r < -(int64_t)neg_gate_q4 * 256) {
                continue;
            }
            x = u - uc;
            y = v - vc;
            n++;
            sx += x;
            sy += y;
            sr += r;
            sxx += x * x;
            sxy += x * y;
            syy += y * y;
            sxr += x * r;
            syr += y * r;
        }
    }
    if (n < 16) {
        return (int32_t)n;
    }
    cxx = n * sxx - sx * sx;
    cxy = n * sxy - sx * sy;
    cyy = n * syy - sy * sy;
    cxr = n * sxr - sx * sr;
    cyr = n * syr - sy * sr;
    {
        int64_t m = cxx;
        int64_t t[4];
        int j;
        t[0] = cxy < 0 ? -cxy : cxy;
        t[1] = cyy;
        t[2] = cxr < 0 ? -cxr : cxr;
        t[3] = cyr < 0 ? -cyr : cyr;
        for (j = 0; j < 4; j++) {
            if (t[j] > m) {
                m = t[j];
            }
        }
        while ((m >> sh) >= ((int64_t)1 << 30)) {
            sh++;
        }
    }
    cxx = geom_asr_s64(cxx, sh);
    cxy = geom_asr_s64(cxy, sh);
    cyy = geom_asr_s64(cyy, sh);
    cxr = geom_asr_s64(cxr, sh);
    cyr = geom_asr_s64(cyr, sh);
    det = cxx * cyy - cxy * cxy;
    /* Ill-conditioned (samples nearly on a line): refuse to update. */
    if (cxx <= 0 || cyy <= 0 || det <= (cxx * cyy) / 16) {
        return (int32_t)n;
    }
    /* Corrections in q4 per px, Q16 (= px Q20); r is q12, so 2^8 more. */
    al_q16 = ratio_scaled(cxr * cyy - cyr * cxy, det, 8);
    be_q16 = ratio_scaled(cyr * cxx - cxr * cxy, det, 8);
    ga_q16 = negobs_div_round_s64(sr * 256 - al_q16 * sx - be_q16 * sy, n);
    plane->a_q20 = (int32_t)geom_clamp_s64(plane->a_q20 + al_q16, -INT32_MAX,
                                           INT32_MAX);
    plane->b_q20 = (int32_t)geom_clamp_s64(plane->b_q20 + be_q16, -INT32_MAX,
                                           INT32_MAX);
    plane->c_q20 = (int32_t)geom_clamp_s64(plane->c_q20 + ga_q16 -
                                               al_q16 * uc - be_q16 * vc,
                                           -INT32_MAX, INT32_MAX);
    return (int32_t)n;
}

/* The normal distribution's MAD-to-sigma factor 1.4826 ~= 759/512, Q9
 * (unit-less, 0.01 % low). */
enum { NORMAL_MAD_TO_SIGMA_Q9 = 759 };

/*
 * The last ground row seen from the feet: walking up from row v_from
 * (exclusive) to v_limit in sampling steps, the first two sampled rows in
 * a row whose majority of samples lies tau_q4 or more below plane are a
 * lower surface beyond an edge, and the ground ends below them. Returns
 * the last row before them (v_limit when there is none).
 *
 * Why: with a drop's edge inside the fit rows (1.3-1.8 m on the target
 * rig), a few rows of lower surface at the far end of the least-squares
 * lever tilt the plane. A 15 cm curb at 1.42 m on the 6 cm rig made the
 * near-half fit 1085 mm / 14.8 deg for 1219 mm / 20.7 deg, and every
 * range of the frame read 15-19 % too far (a vouched range beyond the
 * drop). A lower surface only reads below the ground and always lies
 * farther (higher in the image) than its edge, so trimming from the top
 * is all that is needed. tau: 3 sigma of the per-pixel noise, so that a
 * row's median cannot fall there by chance (the floor is the asymmetric
 * gate's 6 q4); two rows, as one row could be a painted line. Rows with
 * too few samples to vote neither count nor break a run.
 */
static int32_t ground_top(const gfit_t *g, const negobs_image_s16_t *disp,
                          const negobs_image_u8_t *conf,
                          const negobs_ground_plane_t *plane, int32_t v_from,
                          int32_t v_limit, int32_t tau_q4)
{
    const negobs_rig_t *rig = &g->cfg->rig;
    int32_t top = v_from;
    int32_t run = 0;
    int32_t v;
    for (v = v_from - g->step; v >= v_limit; v -= g->step) {
        const int16_t *row = negobs_image_s16_row(disp, v);
        int64_t acc = (int64_t)plane->b_q20 * v + plane->c_q20 +
                      (int64_t)plane->a_q20 * (g->step / 2);
        int32_t n = 0;
        int32_t n_def = 0;
        int32_t u;
        for (u = g->step / 2; u < rig->width;
             u += g->step, acc += (int64_t)plane->a_q20 * g->step) {
            int32_t d = row[u];
            if (!gfit_sample_ok(g, conf, u, v, d)) {
                continue;
            }
            n++;
            n_def += d - (int32_t)geom_rshift_round_s64(acc, 16) <= -tau_q4;
        }
        if (4 * n < g->support_cols) {
            continue; /* under a quarter of the support sampled: no vote */
        }
        if (2 * n_def > n) {
            if (++run >= 2) {
                return top;
            }
        } else {
            run = 0;
            top = v;
        }
    }
    return (run > 0) ? top : v_limit;
}

/* MAD-based sigma (q4) of all valid fit-ROI samples against plane. */
static int32_t noise_sigma(gfit_t *g, const negobs_image_s16_t *disp,
                           const negobs_image_u8_t *conf,
                           const negobs_ground_plane_t *plane)
{
    const negobs_rig_t *rig = &g->cfg->rig;
    uint32_t total = 0;
    uint32_t acc = 0;
    int32_t v;
    int32_t u;
    int32_t b;
    int32_t mad = GFIT_ABS_BINS - 1;

    /* Only the nearer half of the fit rows: the ground under the user's
     * feet is almost always there, so a drop farther up the fit region
     * does not inflate the estimate. */
    memset(g->absres, 0, GFIT_ABS_BINS * sizeof(uint32_t));
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
            r = negobs_abs_s32(r);
            if (r >= GFIT_ABS_BINS) {
                r = GFIT_ABS_BINS - 1;
            }
            g->absres[r]++;
            total++;
        }
    }
    if (total == 0) {
        return g->cfg->sigma_max_q4 + 1;
    }
    for (b = 0; b < GFIT_ABS_BINS; b++) {
        acc += g->absres[b];
        if (2u * acc >= total) {
            mad = b;
            break;
        }
    }
    /* +0.5 q4 for the integer quantisation of r. */
    return geom_max_s32((mad * NORMAL_MAD_TO_SIGMA_Q9 + 256 + 380) / 512,
                        g->cfg->sigma_min_q4);
}

/* Largest disparity difference of two planes at 3 reference points. */
static int32_t plane_gap_q4(const gfit_t *g, const negobs_ground_plane_t *p,
                            const negobs_ground_plane_t *q, int32_t *ref_q4)
{
    const negobs_rig_t *rig = &g->cfg->rig;
    int32_t us[3];
    int32_t vs[3];
    int32_t worst = 0;
    int i;
    us[0] = rig->width / 2;
    vs[0] = rig->height - 1;
    us[1] = rig->width / 4;
    vs[1] = g->v_lo;
    us[2] = (3 * rig->width) / 4;
    vs[2] = g->v_lo;
    *ref_q4 = negobs_ground_disp_q4(p, us[0], vs[0]);
    for (i = 0; i < 3; i++) {
        int32_t dd = negobs_abs_s32(negobs_ground_disp_q4(p, us[i], vs[i]) -
                                    negobs_ground_disp_q4(q, us[i], vs[i]));
        worst = geom_max_s32(worst, dd);
    }
    return worst;
}

static int32_t blend(int32_t old, int32_t now, int32_t gain_q15)
{
    int64_t d = (int64_t)now - old;
    return (int32_t)(old + geom_rshift_round_s64(d * gain_q15, 15));
}

/*
 * The fit on the current band of rows (g->v_lo, g->rows, g->step): the
 * support strips, the v-disparity histogram, the Hough line, the IRLS
 * refinement and the acceptance tests. Returns 1 with *fit and *sigma_q4
 * when the plane is accepted; out gets the shares, the inliers and the
 * reason of a failure.
 */
static int fit_band(gfit_t *g, const negobs_image_s16_t *disp,
                    const negobs_image_u8_t *conf, const int16_t *view_u0,
                    const int16_t *view_u1, gfit_out_t *out,
                    negobs_ground_plane_t *fit_out, int32_t *sigma_out)
{
    const negobs_detect_config_t *cfg = g->cfg;
    const negobs_rig_t *rig = &cfg->rig;
    negobs_ground_plane_t fit;
    negobs_ground_pose_t pose;
    gfit_support_t sup;
    uint32_t samples;
    uint32_t support;
    uint32_t support_valid;
    int32_t inl = 0;
    int32_t sigma = 0;
    int ok = 0;

    memset(out, 0, sizeof *out);
    gfit_support(g, disp, conf, view_u0, view_u1, &sup);
    samples = sup.samples;
    support = sup.support;
    support_valid = sup.support_valid;
    out->valid_permille = samples ? (int32_t)((sup.valid * 1000u) / samples)
                                  : 0;
    out->support_permille = samples ? (int32_t)((support * 1000u) / samples)
                                    : 0;
    /* Too little support: the strips that show floor span under a quarter
     * of the fit rows in view. The plane's roll (its u term) is then fitted
     * over less than a quarter of the width, a lever four times shorter
     * than the image's, and a scene whose floor shows only there (a gap
     * between furniture) is as likely not floor at all. */
    if (samples == 0u || 4u * support < samples || support == 0u) {
        out->reasons |= NEGOBS_DEGRADED_FEW_GROUND;
    } else if (hough_line(g, &fit)) {
        /* Every frame starts again from the Hough line and the nearer half
         * of the fit rows, where the ground under the feet dominates even
         * with an edge in the fit rows. (Seeding from the track instead
         * lets a lower surface inside the fit rows pull the plane down a
         * little more every frame.) */
        int32_t v_seed = g->v_lo + (2 * g->near_rows) / 3;
        int32_t v_near;
        int32_t v_top;
        refine_step(g, disp, conf, &fit, 48, 48, v_seed);
        support = gfit_line_support(g, disp, conf, &fit, &sup, &support_valid);
        if (4u * support < samples || support == 0u) {
            /* no planar support over a quarter of the width */
            out->support_permille = (int32_t)((support * 1000u) / samples);
            out->reasons |= NEGOBS_DEGRADED_GROUND_REJECTED;
            return 0;
        }
        out->support_permille = (int32_t)((support * 1000u) / samples);
        sigma = noise_sigma(g, disp, conf, &fit);
        v_near = ground_top(g, disp, conf, &fit, v_seed,
                            g->v_lo + g->near_rows / 2,
                            geom_max_s32(3 * sigma, 6));
        refine_step(g, disp, conf, &fit, geom_max_s32(3 * sigma, 12),
                    geom_max_s32(3 * sigma, 12), v_near);
        sigma = noise_sigma(g, disp, conf, &fit);
        v_top = ground_top(g, disp, conf, &fit, v_near, g->v_lo,
                           geom_max_s32(3 * sigma, 6));
        /* Then all fit rows with an asymmetric gate: a lower surface only
         * gives negative residuals, and a drop of h_min at the far end of
         * the fit rows is only ~1.2 sigma... 3 sigma below the ground, so
         * the negative side is cut at 2 sigma (bias ~0.05 sigma). */
        refine_step(g, disp, conf, &fit, geom_max_s32(3 * sigma, 12),
                    geom_max_s32(2 * sigma, 6), v_top);
        sigma = noise_sigma(g, disp, conf, &fit);
        inl = refine_step(g, disp, conf, &fit, geom_max_s32(3 * sigma, 12),
                          geom_max_s32(2 * sigma, 6), v_top);
        sigma = noise_sigma(g, disp, conf, &fit);
        out->inliers = inl;
        if ((int64_t)inl * 100 >=
                (int64_t)support_valid * cfg->ground_min_inlier_pct &&
            inl >= 64 &&
            negobs_ground_pose_from_plane(rig, &fit, &pose, NULL) ==
                NEGOBS_OK &&
            mount_pose_physical(cfg, &pose)) {
            ok = 1;
        }
    }
    if (!ok) {
        if (!(out->reasons & NEGOBS_DEGRADED_FEW_GROUND)) {
            out->reasons |= NEGOBS_DEGRADED_GROUND_REJECTED;
        }
        return 0;
    }
    *fit_out = fit;
    *sigma_out = sigma;
    return 1;
}

static void set_band(gfit_t *g, int wide)
{
    g->wide = wide;
    g->v_lo = wide ? g->wide_v_lo : g->band_v_lo;
    g->step = wide ? g->wide_step : g->band_step;
    g->rows = g->cfg->rig.height - g->v_lo;
}

/* fit_band on the rows within the matcher's range: above the rows that
 * read its top, then (at most twice) above where the fitted plane itself
 * leaves it, since rows of garbage need not read the range's top. */
static int fit_in_range(gfit_t *g, const negobs_image_s16_t *disp,
                        const negobs_image_u8_t *conf, const int16_t *view_u0,
                        const int16_t *view_u1, gfit_out_t *out,
                        negobs_ground_plane_t *fit, int32_t *sigma)
{
    int i;
    gfit_range_cut(g, gfit_range_rows_hi(g, disp, conf));
    if (!fit_band(g, disp, conf, view_u0, view_u1, out, fit, sigma)) {
        return 0;
    }
    for (i = 0; i < 2; i++) {
        int32_t hi = gfit_plane_rows_hi(g, fit, g->v_hi);
        if (hi == g->v_hi) {
            break;
        }
        gfit_range_cut(g, hi);
        if (!fit_band(g, disp, conf, view_u0, view_u1, out, fit, sigma)) {
            return 0;
        }
    }
    return 1;
}

void gfit_process(gfit_t *g, const negobs_image_s16_t *disp,
                  const negobs_image_u8_t *conf, const int16_t *view_u0,
                  const int16_t *view_u1, gfit_out_t *out)
{
    const negobs_detect_config_t *cfg = g->cfg;
    const negobs_rig_t *rig = &cfg->rig;
    negobs_ground_plane_t fit;
    int32_t sigma = 0;
    int ok;

    memset(out, 0, sizeof *out);
    set_band(g, 0);
    ok = fit_in_range(g, disp, conf, view_u0, view_u1, out, &fit, &sigma);
    if (!ok && g->wide_v_lo < g->band_v_lo) {
        /* No floor in the bottom band (hands, furniture or an unmatched
         * surface over it): look for it in every row where the floor of a
         * possible mounting can lie (section 4, "Where the fit looks"). */
        gfit_out_t wide;
        memset(&wide, 0, sizeof wide);
        set_band(g, 1);
        if (fit_in_range(g, disp, conf, view_u0, view_u1, &wide, &fit,
                         &sigma)) {
            *out = wide;
            out->wide = 1;
            ok = 1;
        }
        set_band(g, 0);
    }
    out->v_near = g->cfg->rig.height - 1;
    if (!ok) {
        if (++g->fails > 3) {
            g->tracked = 0;
        }
        return;
    }
    g->fails = 0;
    if (!g->tracked) {
        g->plane = fit;
        g->tracked = 1;
        g->jumps = 0;
        g->sigma_q4 = sigma;
    } else {
        int32_t ref;
        int32_t gap = plane_gap_q4(g, &g->plane, &fit, &ref);
        int32_t gate = geom_max_s32(cfg->track_gate_q4, ref / 10);
        if (gap <= gate) {
            g->plane.a_q20 = blend(g->plane.a_q20, fit.a_q20,
                                   cfg->track_gain_q15);
            g->plane.b_q20 = blend(g->plane.b_q20, fit.b_q20,
                                   cfg->track_gain_q15);
            g->plane.c_q20 = blend(g->plane.c_q20, fit.c_q20,
                                   cfg->track_gain_q15);
            g->jumps = 0;
        } else if (++g->jumps >= 2) {
            /* The new ground persisted: take it. */
            g->plane = fit;
            g->jumps = 0;
        }
        g->sigma_q4 = blend(g->sigma_q4, sigma, cfg->track_gain_q15);
    }
    out->plane = g->plane;
    out->v_near = gfit_near_row(g, &g->plane);
    out->sigma_q4 = geom_max_s32(g->sigma_q4, cfg->sigma_min_q4);
    if (negobs_ground_pose_from_plane(rig, &g->plane, &out->pose,
                                      &out->frame) != NEGOBS_OK) {
        out->reasons |= NEGOBS_DEGRADED_GROUND_REJECTED;
        g->tracked = 0;
        return;
    }
    out->ok = 1;
}
