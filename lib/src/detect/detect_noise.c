/* Step 6: the measured noise of the strip median per band of rows
 * (docs/DETECTION.md section 5, step 6). */
#include "detect_internal.h"

/*
 * MAD to sigma of the strip medians, Q14 (unit-less): the MAD comes in
 * 1/32 px times 256 and sigma goes out in 1/256 px (Q8), so
 * sigma_q8 = MAD_x256 * 8 / 256 * 1.4826 = MAD_x256 * 0.046331
 * ~= 759/16384 (0.01 % low). 1.4826 is the normal distribution's
 * MAD-to-sigma factor.
 */
enum { MAD_X256_TO_SIGMA_Q8_Q14 = 759 };

/* Count of bin i of one or two pooled strip histograms. */
static uint32_t pooled(const uint16_t *ha, const uint16_t *hb, int32_t i)
{
    return (uint32_t)ha[i] + ((hb != NULL) ? (uint32_t)hb[i] : 0u);
}

/*
 * Median and 1.4826 * MAD, both in 1/256 px, of one or two pooled
 * histograms of signed values in 1/32 px (bin i holds i - STRIP_BINS/2;
 * the end bins also hold everything beyond). Grouped-data formulas: a
 * bin spans +-1/2 of its value and is interpolated linearly. *spread_q8
 * is 0 with fewer than 16 values.
 */
static void hist_median_spread_q8(const uint16_t *ha, const uint16_t *hb,
                                  int32_t *median_q8, int32_t *spread_q8)
{
    uint32_t total = 0;
    uint32_t acc = 0;
    uint32_t in = 0;
    uint32_t prev = 0;
    int64_t med_x256 = 0; /* 1/32 px, times 256, from bin 0 */
    int64_t mad_x256 = 0;
    int32_t mb = 0;
    int32_t i;
    int32_t j;
    *median_q8 = 0;
    *spread_q8 = 0;
    for (i = 0; i < STRIP_BINS; i++) {
        total += pooled(ha, hb, i);
    }
    if (total < 16u) {
        return;
    }
    for (i = 0; i < STRIP_BINS; i++) {
        uint32_t c = pooled(ha, hb, i);
        if (2u * (acc + c) >= total) {
            med_x256 = (int64_t)i * 256 - 128 +
                       ((int64_t)total * 128 - (int64_t)acc * 256) /
                           (int64_t)c;
            mb = i;
            break;
        }
        acc += c;
    }
    /* MAD about the median bin: widen a window of bins around it until
     * it holds half of the values; interpolate in the last step. */
    in = pooled(ha, hb, mb);
    j = 0;
    while (2u * in < total && j < STRIP_BINS) {
        prev = in;
        j++;
        in += ((mb - j >= 0) ? pooled(ha, hb, mb - j) : 0u) +
              ((mb + j < STRIP_BINS) ? pooled(ha, hb, mb + j) : 0u);
    }
    if (j == 0) {
        /* Half of the values in the median's own bin. */
        mad_x256 = ((int64_t)total * 64) / (int64_t)in;
    } else {
        mad_x256 = (int64_t)j * 256 - 128 +
                   ((int64_t)total * 128 - (int64_t)prev * 256) /
                       (int64_t)(in - prev);
    }
    /* 1/32 px x 256 -> 1/256 px: x 8 / 256. */
    *median_q8 = (int32_t)((med_x256 - (int64_t)(STRIP_BINS / 2) * 256) / 32);
    *spread_q8 = (int32_t)geom_clamp_s64(
        (mad_x256 * MAD_X256_TO_SIGMA_Q8_Q14 + 8192) / 16384, 1, 1 << 20);
}

/*
 * Noise of the quantity the rule actually tests: the median residual of
 * one row of one strip. Deriving it from the per-pixel sigma as
 * 1.25 * sigma / sqrt(strip_px) assumes independent pixels; matcher errors
 * are not (5x5 windows, DP along rows, calibration residue), and on the
 * real SurDis pair the strip median spreads 0.2-0.4 px where that formula
 * says 0.16 (docs/journal/detection-findings.md, item 6). So it is measured: for every
 * row of each band and every strip whose centre is in the corridor,
 * e = strip median of (d - d_g). Per band: the median of e (the ground
 * model's offset there) and sigma = 1.4826 * MAD(e) about it (the
 * spread). Past the edge of a drop reported as a candidate this frame,
 * e is taken against the nearer of the ground and the drop's first
 * plateau (-rho1 * d_g): a real hazard in the band must not read as
 * noise and hide itself behind NOISY. Those rows are not left out: a
 * candidate made by noise would then remove its own noise from the
 * measurement (with 0.35 px of row-correlated noise one frame in six
 * passed that way). A lone strip's hit is not a candidate. Rows past a
 * wall or up-step are left out only when the obstacle is unmistakable:
 * BLOCK_ROWS rows in a row at least 1 px and 3 per-pixel sigmas above
 * the ground. The scan's own POSITIVE rows (residual >= tau, a fraction
 * of a pixel) are not enough: row-correlated noise read that way by a
 * strip hid itself (the ground model of SurDis is off by up to +0.7 px at
 * 4 m).
 * Each band is pooled with
 * the next nearer one: near the warning range a band holds only ~40 strip
 * rows on the 320x240 rig, and a MAD from so few varied by 2x between
 * frames of the same scene. A band with fewer than 16 strip rows is not
 * measured; see det_strip_sigma_at.
 *
 * Scaling: d and d_g are q4; 2 * median is in q5 (1/32 px); e goes to a
 * 128-bin histogram of 1/32 px centred on 0 (beyond +-2 px in the end
 * bins: such a band is NOISY whatever the interpolation). Counts are
 * uint16: a band holds at most height/8 rows x width/4 strips.
 */
/* Strip-median residual e (1/32 px) of strip si on row v, against the
 * nearer of the ground and a reported drop's plateau past its edge; 0
 * when the row is outside the corridor or the view (det_in_view) or has
 * too few voting pixels. */
static int strip_row_e(const scan_ctx_t *s, const detect_priv_t *p, int32_t v,
                       int32_t si, int32_t *rr, int32_t *e_out,
                       int corridor_only)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const strip_hit_t *hit = &p->hits[si];
    const int16_t *row = negobs_image_s16_row(s->disp, v);
    const uint8_t *crow = (s->conf != NULL) ? negobs_image_u8_row(s->conf, v)
                                            : NULL;
    int32_t u0 = det_strip_u0(cfg, p->n_strips, si);
    int32_t u1 = u0 + cfg->strip_px;
    int32_t uc = (u0 + u1) / 2;
    int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
    int64_t acc = (int64_t)s->plane->b_q20 * v + s->plane->c_q20 +
                  (int64_t)s->plane->a_q20 * u0;
    int32_t n = 0;
    int32_t e;
    int32_t u;
    if (dgc <= 0 || (corridor_only && (!det_in_view(s, uc, v, dgc) ||
                                       !det_in_corridor(s, uc, dgc)))) {
        return 0;
    }
    for (u = u0; u < u1; u++, acc += s->plane->a_q20) {
        int32_t d = row[u];
        if (d == NEGOBS_DISP_INVALID || d < 0 ||
            (crow != NULL && (int32_t)crow[u] < cfg->min_confidence)) {
            continue;
        }
        rr[n++] = d - (int32_t)geom_rshift_round_s64(acc, 16);
    }
    if (n * 4 < cfg->strip_px || n < 3) {
        return 0; /* an INVALID row for the scan as well */
    }
    e = det_median2_s32(rr, n);
    if (hit->reported && hit->type != NEGOBS_HAZARD_UNKNOWN &&
        v < hit->edge_v) {
        /* Past the edge of a candidate: compare with the nearer of the
         * ground and the drop's first plateau. */
        int32_t ref_q5 = -(int32_t)(((int64_t)dgc * 2 * hit->rho1_q15) >> 15);
        if (negobs_abs_s32(e - ref_q5) < negobs_abs_s32(e)) {
            e -= ref_q5;
        }
    }
    *e_out = e;
    return 1;
}

int det_strip_row_e(const scan_ctx_t *s, const detect_priv_t *p, int32_t v,
                    int32_t si, int32_t *rr, int32_t *e_out)
{
    int16_t *m = p->row_e + (size_t)v * (size_t)p->n_strips + (size_t)si;
    int32_t e = 0;
    if (*m == ROW_E_NONE) {
        return 0;
    }
    if (*m != ROW_E_UNSET) {
        *e_out = *m;
        return 1;
    }
    if (!strip_row_e(s, p, v, si, rr, &e, 1)) {
        *m = ROW_E_NONE;
        return 0;
    }
    if (e > ROW_E_NONE && e <= INT16_MAX) {
        *m = (int16_t)e;
    }
    *e_out = e;
    return 1;
}

/* Count e (1/32 px) in the histogram of row v's band. */
static void strip_hist_add(const scan_ctx_t *s, uint16_t *hist, int32_t v,
                           int32_t e)
{
    uint16_t *hb = hist + (size_t)geom_min_s32((v - s->band_v0) / s->band_rows,
                                               NOISE_BANDS - 1) *
                              STRIP_BINS;
    e = negobs_clamp_s32(e + STRIP_BINS / 2, 0, STRIP_BINS - 1);
    if (hb[e] < 0xFFFFu) {
        hb[e]++;
    }
}

/*
 * 1 when the closure of strip si at foot_v bars the lane (BAR_H_MM,
 * BAR_RUN_MM): walking up from the foot, BLOCK_ROWS rows whose strip
 * median d is a point at least BAR_H_MM above the floor and within
 * BAR_RUN_MM of the foot's floor distance, nearer or farther. A point at
 * disparity d on the ray of row v, where the floor has d_g, stands
 * h = H (d - d_g) / d above it (similar triangles along the ray; d_g <= 0
 * above the horizon keeps the formula). Rows are read upward without the
 * corridor test (the face of a near obstacle rises into rows whose floor
 * lies beyond the corridor's width) until BLOCK_ROWS rows in a row lie
 * beyond the band, or to the top of the image.
 */
static int closure_bars(const scan_ctx_t *s, const detect_priv_t *p,
                        int32_t si, int32_t foot_v, int32_t *rr)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t u0 = det_strip_u0(cfg, p->n_strips, si);
    int32_t uc = u0 + cfg->strip_px / 2;
    int32_t foot_mm = 0;
    int32_t n_tall = 0;
    int32_t n_past = 0;
    int32_t v;
    det_model_point(s, uc, foot_v, negobs_ground_disp_q4(s->plane, uc, foot_v),
                    &foot_mm, NULL, NULL);
    for (v = foot_v; v >= 0 && n_tall < BLOCK_ROWS && n_past < BLOCK_ROWS;
         v--) {
        const int16_t *row = negobs_image_s16_row(s->disp, v);
        const uint8_t *crow = (s->conf != NULL)
                                  ? negobs_image_u8_row(s->conf, v)
                                  : NULL;
        int32_t n = 0;
        int32_t d_q4;
        int32_t dg_q4;
        int32_t r_mm = 0;
        int32_t u;
        for (u = u0; u < u0 + cfg->strip_px; u++) {
            if (row[u] == NEGOBS_DISP_INVALID || row[u] <= 0 ||
                (crow != NULL && (int32_t)crow[u] < cfg->min_confidence)) {
                continue;
            }
            rr[n++] = row[u];
        }
        if (n * 4 < cfg->strip_px || n < 3) {
            continue;
        }
        d_q4 = det_median2_s32(rr, n) / 2;
        dg_q4 = negobs_ground_disp_q4(s->plane, uc, v);
        if (d_q4 <= 0) {
            continue;
        }
        det_model_point(s, uc, v, d_q4, &r_mm, NULL, NULL);
        /* BLOCK_ROWS rows in a row beyond the band: the face, if any, is
         * below (the top of an up-step, the floor past a low object) */
        n_past = (r_mm > foot_mm + BAR_RUN_MM) ? n_past + 1 : 0;
        n_tall += (int64_t)s->frame->height_mm * (d_q4 - dg_q4) >=
                      (int64_t)BAR_H_MM * d_q4 &&
                  negobs_abs_s32(r_mm - foot_mm) <= BAR_RUN_MM;
    }
    return n_tall >= BLOCK_ROWS;
}

void det_strip_noise(scan_ctx_t *s, detect_priv_t *p, uint16_t *hist)
{
    const int32_t h = s->cfg->rig.height;
    int32_t rr[MAX_STRIP_PX];
    int32_t b;
    int32_t v;
    int32_t si;
    size_t i;

    for (i = 0; i < (size_t)h * (size_t)p->n_strips; i++) {
        p->row_e[i] = ROW_E_UNSET; /* a new frame's memo */
    }
    /* Pass 1: where does a wall or up-step close each strip? Rows far
     * above the ground (1 px and 3 per-pixel sigmas: more than the ground
     * model's own offsets, +0.7 px at most on SurDis) for BLOCK_ROWS rows
     * in a row; the strip is closed from the foot of that rise (the last
     * row below a quarter of the threshold), so the ramp up the face of
     * a wall is not measured as ground noise either. */
    int32_t any_candidate = 0;
    int32_t any_closed = 0;
    for (si = 0; si < p->n_strips; si++) {
        p->hits[si].blocked_v = -1;
        p->hits[si].pos_run = 0;
        p->hits[si].bars = 0;
        any_candidate |= p->hits[si].reported;
    }
    /* Pass 1 also fills the histogram; it is complete unless a strip
     * closed (its rise was counted) or pass 1 did not run. */
    memset(hist, 0, (size_t)NOISE_BANDS * STRIP_BINS * sizeof(uint16_t));
    for (si = 0; si < p->n_strips && !any_candidate; si++) {
        /* Only on frames without a candidate: a drop's far wall or rim
         * is positive too, and on SurDis (1.5 m warning range) closing
         * strips beside a HOLE candidate on the steps let the frame say
         * CLEAR. */
        strip_hit_t *hs = &p->hits[si];
        int32_t foot = -1;
        int32_t entered = 0;
        for (v = h - 1; v >= s->band_v0 && hs->blocked_v < 0; v--) {
            int32_t e;
            int32_t thr = geom_max_s32(BLOCK_MIN_Q5, 6 * det_sigma_at(s, v));
            if (v >= hs->occl_v) {
                continue; /* a near occluder: out of view */
            }
            if (det_strip_row_e(s, p, v, si, rr, &e)) {
                entered = 1;
                strip_hist_add(s, hist, v, e);
            } else if (!entered || !strip_row_e(s, p, v, si, rr, &e, 0)) {
                /* Once in the corridor, a strip is followed up the face of
                 * an obstacle standing there, whose rows lie where the
                 * ground model's floor is beyond the corridor's width. */
                continue;
            }
            if (e * 4 < thr) {
                foot = v - 1;
            }
            if (e >= thr) {
                if (++hs->pos_run >= BLOCK_ROWS) {
                    hs->blocked_v = (foot >= 0) ? foot : v;
                    hs->bars = closure_bars(s, p, si, hs->blocked_v, rr);
                    any_closed = 1;
                }
            } else {
                hs->pos_run = 0;
            }
        }
    }
    /* Pass 2, only when needed: the histogram of rows before any closure. */
    if (any_candidate || any_closed) {
        memset(hist, 0, (size_t)NOISE_BANDS * STRIP_BINS * sizeof(uint16_t));
    }
    for (v = h - 1; v >= s->band_v0 && (any_candidate || any_closed); v--) {
        for (si = 0; si < p->n_strips; si++) {
            int32_t e;
            if (v <= p->hits[si].blocked_v || v >= p->hits[si].occl_v ||
                !det_strip_row_e(s, p, v, si, rr, &e)) {
                continue; /* beyond a wall: nothing to vouch for there */
            }
            strip_hist_add(s, hist, v, e);
        }
    }
    for (b = 0; b < NOISE_BANDS; b++) {
        hist_median_spread_q8(
            hist + (size_t)b * STRIP_BINS,
            (b + 1 < NOISE_BANDS) ? hist + (size_t)(b + 1) * STRIP_BINS : NULL,
            &s->band_bias_q8[b], &s->band_strip_q8[b]);
    }
}

/* Measured spread of the strip median at row v (1/256 px), and in
 * *offset_q8 the median itself (the ground model's offset there). Where
 * too few strip rows could be measured, the independent-pixel value
 * 1.25 * sigma / sqrt(strip_px) stands in, with offset 0: with so little
 * data in the band the rule itself reads those rows as INVALID, not as
 * ground. */
int32_t det_strip_sigma_at(const scan_ctx_t *s, int32_t v, int32_t *offset_q8)
{
    int32_t b = (v - s->band_v0) / s->band_rows;
    b = negobs_clamp_s32(b, 0, NOISE_BANDS - 1);
    *offset_q8 = 0;
    if (s->band_strip_q8[b] > 0) {
        *offset_q8 = s->band_bias_q8[b];
        return s->band_strip_q8[b];
    }
    /* sigma_q4 * 16 * 1.25 / sqrt(strip) = sigma_q4 * 20 * 16 /
     * sqrt(256 * strip). */
    return (
        int32_t)(((int64_t)det_sigma_at(s, v) * 320) /
                 (int64_t)negobs_isqrt_u32((uint32_t)s->cfg->strip_px * 256u));
}
