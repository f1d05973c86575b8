/*
 * The per-strip scan (the answer to the paper's step 9) works on the
 * signed residual r = d_measured - d_ground of every valid pixel, in q4.
 * For a drop of h beyond an edge, r = -d_ground * h / (H + h) on every row
 * past the edge, whatever the pitch: that is the cue. Each row of a strip
 * is classified by majority vote of its valid pixels (equivalent to
 * testing the strip median, and O(1) per pixel):
 *
 *   DEFICIT   more than half have r <= -tau
 *   POSITIVE  more than half have r >= +tau (walls, up-steps: three
 *             of them, as for a drop, stop the scan; scan_closed)
 *   GROUND    more than half have |r| < tau
 *   INVALID   fewer than a quarter of the strip valid
 *   MIXED     none of these
 *
 * with tau(v) = max(d_g * h_t/(H + h_t), k * 1.25 * sigma / sqrt(n)),
 * h_t = h_thresh_pct% of h_min (h_min_near inside h_near_range, else
 * h_min_far), and 1.25 the efficiency loss of a median against a mean.
 * Rows are visited from the bottom (near) upwards (far) until the ground
 * model's range passes range_max or the strip leaves the corridor. A drop
 * needs min_support_mm of GROUND before it and min_edge_rows DEFICIT rows
 * (INVALID or MIXED rows inside the run neither count nor break it, up to
 * two). Its range comes from the ground model at the last GROUND row.
 */
#include "detect_internal.h"

/* Noise for row v: the larger of the ground estimate and the band's. */
int32_t det_sigma_at(const scan_ctx_t *s, int32_t v)
{
    int32_t b = (v - s->band_v0) / s->band_rows;
    b = negobs_clamp_s32(b, 0, NOISE_BANDS - 1);
    return geom_max_s32(s->sigma_q4, s->band_sigma_q4[b]);
}

/*
 * MAD of the differences of horizontal neighbours to the sigma of one
 * pixel, Q10 (unit-less): sigma = 1.4826 * MAD / sqrt(2) = 1.0484 * MAD
 * ~= 1073/1024 (0.05 % low). 1.4826 is the normal distribution's
 * MAD-to-sigma factor; sqrt(2) because a difference of two pixels has
 * twice the variance of one.
 */
enum { DIFF_MAD_TO_SIGMA_Q10 = 1073 };

/*
 * How far past the hole limit (mm) the type scan goes on reading before it
 * stops: a far rim at max_hole_mm needs min_edge_rows confirming rows,
 * which lie farther still, and a second plateau (stairs) one tread beyond
 * the edge must be reached. 0.5 m is slack for both, the value the
 * classifier was tuned with (docs/DETECTION.md, "Type"); it only bounds
 * the scan's cost, the hole test itself stays within max_hole_mm.
 */
enum { TYPE_SCAN_PAST_HOLE_MM = 500 };

/*
 * Threshold margin (mean deficit / tau, Q8: 256 = 1.0) of a missing-ground
 * strip, which has no measured deficit: 1.0 without a left image to tell
 * its kind; 1.5 for a band as textured as its ground (it should have
 * matched: an occlusion or drop cue), 0.5 for a bland band (nothing to
 * match, "unknown"). With 4 strips these give confidences 0.5, 0.75 and
 * 0.25 (docs/DETECTION.md, "Missing ground").
 */
enum {
    MISSING_MARGIN_Q8 = 256,
    MISSING_MARGIN_TEXTURED_Q8 = 384,
    MISSING_MARGIN_BLAND_Q8 = 128
};

/*
 * Noise per band of rows from horizontal neighbours: for a smooth surface
 * d(u+1) - d(u) has sigma*sqrt(2) and no model term, so a drop (a
 * horizontal edge) does not inflate it. sigma = 1.4826 * MAD / sqrt(2)
 * ~= MAD * 1073/1024. Stereo noise that is correlated along rows makes
 * this an underestimate, which is why it only ever raises the ground
 * estimate (det_sigma_at). Every 2nd row, all columns.
 */
void det_band_noise(scan_ctx_t *s, uint32_t *hist, int32_t v_top,
                    int32_t v_end)
{
    const negobs_image_s16_t *d = s->disp;
    int32_t h = s->cfg->rig.height;
    int32_t b;
    int32_t v;
    int32_t u;
    if (v_top < 0) {
        v_top = 0;
    }
    if (v_top > h - 1) {
        v_top = h - 1;
    }
    s->band_v0 = v_top;
    s->band_rows = geom_max_s32((h - v_top + NOISE_BANDS - 1) / NOISE_BANDS,
                                1);
    memset(hist, 0, (size_t)NOISE_BANDS * NOISE_BINS * sizeof(uint32_t));
    for (v = v_top; v < v_end; v += 2) {
        const int16_t *row = negobs_image_s16_row(d, v);
        uint32_t *hb = hist + (size_t)(geom_min_s32((v - v_top) / s->band_rows,
                                                    NOISE_BANDS - 1)) *
                                  NOISE_BINS;
        for (u = 0; u + 1 < d->width; u++) {
            int32_t a = row[u];
            int32_t c = row[u + 1];
            int32_t x;
            if (a == NEGOBS_DISP_INVALID || c == NEGOBS_DISP_INVALID) {
                continue;
            }
            x = negobs_abs_s32(c - a);
            hb[(x < NOISE_BINS) ? x : NOISE_BINS - 1]++;
        }
    }
    for (b = 0; b < NOISE_BANDS; b++) {
        const uint32_t *hb = hist + (size_t)b * NOISE_BINS;
        uint32_t total = 0;
        uint32_t acc = 0;
        int32_t i;
        int32_t mad = 0;
        for (i = 0; i < NOISE_BINS; i++) {
            total += hb[i];
        }
        s->band_sigma_q4[b] = 0;
        if (total < 64u) {
            continue; /* too few pairs: rely on the ground estimate */
        }
        for (i = 0; i < NOISE_BINS; i++) {
            acc += hb[i];
            if (2u * acc >= total) {
                mad = i;
                break;
            }
        }
        s->band_sigma_q4[b] = (mad * DIFF_MAD_TO_SIGMA_Q10 + 512) / 1024;
    }
}

/* Per-row statistics of one strip. */
typedef struct row_stat {
    int32_t n;
    int32_t tau;
    int32_t dg; /* model at the strip centre, q4 */
    int32_t n_def;
    int32_t n_gnd;
    int32_t n_pos;
    int32_t n_deeper; /* below the first plateau by more than tau */
    int32_t n_up;     /* above half the first plateau's deficit     */
    int64_t sum_dg_def;
    int64_t sum_d_def;
    int64_t sum_r_def;
} row_stat_t;

/*
 * Classify one row of a strip. rho1_q15 > 0 additionally counts pixels
 * deeper than the first plateau (relative deficit rho1) by tau.
 */
static enum row_class classify_row(const scan_ctx_t *s, int32_t u0, int32_t u1,
                                   int32_t v, int32_t range_mm,
                                   int32_t rho1_q15, row_stat_t *st)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int16_t *row = negobs_image_s16_row(s->disp, v);
    const uint8_t *crow = (s->conf != NULL) ? negobs_image_u8_row(s->conf, v)
                                            : NULL;
    int32_t rr[MAX_STRIP_PX];
    int32_t gg[MAX_STRIP_PX];
    int32_t dd[MAX_STRIP_PX];
    int64_t base = (int64_t)s->plane->b_q20 * v + s->plane->c_q20;
    int64_t acc = base + (int64_t)s->plane->a_q20 * u0;
    int32_t h_t;
    int32_t tau_geo;
    int32_t tau_noise;
    int32_t u;
    int32_t i;
    int32_t hmm = s->frame->height_mm;

    memset(st, 0, sizeof *st);
    st->dg = (int32_t)geom_rshift_round_s64(
        base + (int64_t)s->plane->a_q20 * ((u0 + u1) / 2), 16);
    for (u = u0; u < u1; u++, acc += s->plane->a_q20) {
        int32_t d = row[u];
        if (d == NEGOBS_DISP_INVALID || d < 0 ||
            (crow != NULL && (int32_t)crow[u] < cfg->min_confidence)) {
            continue;
        }
        gg[st->n] = (int32_t)geom_rshift_round_s64(acc, 16);
        dd[st->n] = d;
        rr[st->n] = d - gg[st->n];
        st->n++;
    }
    if (st->n * 4 < (u1 - u0) || st->n < 3) {
        return ROW_INVALID;
    }
    h_t = det_h_t_at(cfg, range_mm);
    tau_geo = (int32_t)(((int64_t)st->dg * h_t) / (hmm + h_t));
    /* k * 1.25 * sigma / sqrt(n): k_q4*sigma_q4*5 / (4*sqrt(256 n)). */
    tau_noise = (int32_t)(((int64_t)cfg->k_sigma_q4 * det_sigma_at(s, v) * 5) /
                          (4 * (int64_t)negobs_isqrt_u32(
                                   (uint32_t)(256 * st->n))));
    st->tau = geom_max_s32(geom_max_s32(tau_geo, tau_noise), DEFICIT_MIN_Q4);
    for (i = 0; i < st->n; i++) {
        int32_t r = rr[i];
        if (rho1_q15 > 0 &&
            r > -(int32_t)(((int64_t)gg[i] * rho1_q15) >> 16)) {
            st->n_up++;
        }
        if (r <= -st->tau) {
            st->n_def++;
            st->sum_dg_def += gg[i];
            st->sum_d_def += dd[i];
            st->sum_r_def += r;
            if (rho1_q15 > 0 &&
                r <= -(int32_t)(((int64_t)gg[i] * rho1_q15) >> 15) - st->tau) {
                st->n_deeper++;
            }
        } else if (r >= st->tau) {
            st->n_pos++;
        } else {
            st->n_gnd++;
        }
    }
    if (st->n_def * 2 > st->n) {
        return ROW_DEFICIT;
    }
    if (st->n_pos * 2 > st->n) {
        return ROW_POSITIVE;
    }
    if (st->n_gnd * 2 > st->n) {
        return ROW_GROUND;
    }
    return ROW_MIXED;
}

/* Floor distance and depth of the ground model at (u, v). */
void det_model_point(const scan_ctx_t *s, int32_t u, int32_t v, int32_t dg_q4,
                     int32_t *range_mm, int32_t *lat_mm, int32_t *depth_mm)
{
    int32_t z = negobs_depth_mm_from_disp_q4(&s->cfg->rig, dg_q4);
    if (z < 0) {
        z = NEGOBS_DEPTH_MAX_MM;
    }
    negobs_ground_floor_point(&s->cfg->rig, s->frame, u * 16, v * 16, z,
                              range_mm, lat_mm);
    if (depth_mm != NULL) {
        *depth_mm = z;
    }
}

int det_in_corridor(const scan_ctx_t *s, int32_t uc, int32_t dg_q4)
{
    /* |X| = |u - cx| * B / d <= W  <=>  |u - cx| * B_um <= W_um * d. */
    int64_t du = negobs_abs_s32(uc * 16 + 8 - s->cfg->rig.cx_q4);
    return du * s->cfg->rig.baseline_um <=
           (int64_t)s->cfg->corridor_half_width_mm * 1000 * dg_q4;
}

/* First column of strip si (the strips are centred in the frame). */
int32_t det_strip_u0(const negobs_detect_config_t *cfg, int32_t n_strips,
                     int32_t si)
{
    return (cfg->rig.width - n_strips * cfg->strip_px) / 2 +
           si * cfg->strip_px;
}

/* 1 when the floor point of column uc on row v (ground disparity dg_q4)
 * is in the field of view of both cameras: in the left image's columns
 * outside its rectification fill, and at uc - d_g in the right image,
 * inside it and outside its fill. Elsewhere no frame can match it, like
 * floor outside the image (docs/DETECTION.md 10.2, "Out of view"). */
int det_in_view(const scan_ctx_t *s, int32_t uc, int32_t v, int32_t dg_q4)
{
    int32_t ur_q4 = uc * 16 - dg_q4; /* the point in the right image */
    if (ur_q4 < 0) {
        return 0;
    }
    if (s->view_l_u0 != NULL &&
        (uc < s->view_l_u0[v] || uc >= s->view_l_u1[v])) {
        return 0;
    }
    return s->view_r_u0 == NULL ||
           (ur_q4 >= s->view_r_u0[v] * 16 && ur_q4 < s->view_r_u1[v] * 16);
}

/* First row of column uc whose floor, and that of every row below it,
 * lies beyond the matcher's range (the ground disparity reaches d_top_q4:
 * docs/DETECTION.md section 4, "Beyond the matcher's range"); the image's
 * height when the bottom row is within it. No frame measures that floor:
 * it is out of view, like floor below the image. */
int32_t det_range_row(const scan_ctx_t *s, int32_t uc)
{
    return gfit_row_in_range(s->plane, uc, s->cfg->rig.height - 1,
                             s->d_top_q4) +
           1;
}

/* tan 20 deg x 1000: the heading a straight walker's path may take off
 * the axis of a body-worn camera, which the corridor near the feet allows
 * for (thorax rotation in the gait +-5-7 deg, the strap's yaw on the body
 * up to 10 deg, veering a few deg; docs/DETECTION.md 10.2, "The
 * corridor"). */
#define CORRIDOR_HEADING_PERMILLE 364

/* Half-width of the walking corridor at floor distance range_mm: the body's
 * lane at the feet (corridor_near_half_mm) widened by the heading
 * allowance, capped at corridor_half_width_mm (reached from 0.96 m with the
 * defaults, so everything farther is scanned and vouched as before). */
int32_t negobs_detect_corridor_half_mm(const negobs_detect_config_t *cfg,
                                       int32_t range_mm)
{
    int64_t w = (int64_t)cfg->corridor_near_half_mm +
                ((int64_t)geom_max_s32(range_mm, 0) *
                 CORRIDOR_HEADING_PERMILLE) /
                    1000;
    return (int32_t)geom_clamp_s64(w, 0, cfg->corridor_half_width_mm);
}

/* 1 when the centre of strip si lies in the walking corridor at row v of
 * the ground model (+-corridor_half_width_mm, det_in_corridor) and in the
 * view of both cameras (det_in_view): the right camera sees the floor
 * point of column u at u - d_g, so where u < d_g (the left image's first
 * columns near the feet) no frame can match it. The cells' noise and the
 * strips' support are measured over this. */
int det_strip_in_corridor(const scan_ctx_t *s, int32_t n_strips, int32_t si,
                          int32_t v)
{
    int32_t uc = det_strip_u0(s->cfg, n_strips, si) + s->cfg->strip_px / 2;
    int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
    return dgc > 0 && det_in_view(s, uc, v, dgc) &&
           det_in_corridor(s, uc, dgc);
}

/* 1 when the walk must vouch for strip si at row v: in the corridor and
 * the view (det_strip_in_corridor) and within the corridor's half-width at
 * its floor distance, which is narrower near the feet
 * (negobs_detect_corridor_half_mm). The rule's scan and the noise keep the
 * full width at every range. */
int det_strip_in_walk(const scan_ctx_t *s, int32_t n_strips, int32_t si,
                      int32_t v)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t uc = det_strip_u0(cfg, n_strips, si) + cfg->strip_px / 2;
    int32_t dgc;
    int32_t range = 0;
    int32_t w;
    if (!det_strip_in_corridor(s, n_strips, si, v)) {
        return 0;
    }
    if (cfg->corridor_near_half_mm >= cfg->corridor_half_width_mm) {
        return 1; /* no narrowing (a head-worn camera) */
    }
    dgc = negobs_ground_disp_q4(s->plane, uc, v);
    det_model_point(s, uc, v, dgc, &range, NULL, NULL);
    w = negobs_detect_corridor_half_mm(cfg, range);
    /* |X| = |u - cx| * B / d <= w, as det_in_corridor. */
    return (int64_t)negobs_abs_s32(uc * 16 + 8 - cfg->rig.cx_q4) *
               cfg->rig.baseline_um <=
           (int64_t)w * 1000 * dgc;
}

/*
 * Mean absolute horizontal grey-level difference over columns u0..u1-1 and
 * rows v0..v1-1 of img, in 1/16 grey level (the LOW_TEXTURE measure, on
 * every pixel; 64-bit sum). -1 when the box holds no pixel pair.
 */
static int32_t box_texture_q4(const negobs_image_u8_t *img, int32_t u0,
                              int32_t u1, int32_t v0, int32_t v1)
{
    int64_t sum = 0;
    int64_t n = 0;
    int32_t v;
    u0 = negobs_clamp_s32(u0, 0, img->width - 1);
    u1 = negobs_clamp_s32(u1, 0, img->width - 1); /* last pair: u1-1, u1 */
    v0 = negobs_clamp_s32(v0, 0, img->height);
    v1 = negobs_clamp_s32(v1, 0, img->height);
    for (v = v0; v < v1; v++) {
        const uint8_t *row = negobs_image_u8_row(img, v);
        int32_t u;
        for (u = u0; u < u1; u++) {
            sum += negobs_abs_s32((int32_t)row[u + 1] - (int32_t)row[u]);
            n++;
        }
    }
    return (n > 0) ? (int32_t)((sum * 16) / n) : -1;
}

/*
 * Where a found drop's edge really is. The run fires where the deficit first
 * clears tau; a drop a little shallower than h_t shows its deficit on every
 * row past its edge and clears tau only where noise adds to it. Suite walks
 * of the target rig: a 5 cm step beyond h_near_range, against h_t = 80 mm,
 * was found up to 2 m past its edge (estimated 74-84 mm). The rows the rule
 * read as GROUND before the run then already lie on the lower surface.
 *
 * So the edge is moved nearer to the change point: over the rows from the
 * last ground row e down to sup_v (where the support became long enough,
 * so it stays supported), each row scores (n_low - n_high) / n in Q8, where
 * n_low counts pixels nearer to the plateau rho1 than to the ground
 * (classify_row's n_up is the rest); the edge goes below the row where the
 * running sum from e peaks, when the peak exceeds one whole row (256).
 * INVALID rows score 0. A plain edge, with ground rows before the run,
 * scores about -256 per row and stays put. Returns the new last ground row.
 *
 * rho1 must be the settled plateau. The first run's rows are blurred, so
 * its plateau is too shallow (15 cm curbs read 9-11 cm); measured against
 * it, the small error of the fitted plane on the 6 cm baseline rig (0.55
 * deg of pitch on one frame) made the ground rows before real 10-30 cm
 * edges score as lower surface: 7-26 % of those frames came out more than
 * 10 % too near, against 0-5 % before and 3-6 % with the settled plateau.
 */
static int32_t edge_change_point(const scan_ctx_t *s, int32_t u0, int32_t u1,
                                 int32_t e, int32_t sup_v, int32_t rho1_q15)
{
    const int32_t uc = (u0 + u1) / 2;
    int32_t best = e;
    int32_t acc = 0;
    int32_t peak = 256;
    int32_t v;

    if (rho1_q15 <= 0) {
        return e;
    }
    for (v = e; v < sup_v; v++) {
        row_stat_t st;
        int32_t range = 0;
        int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
        det_model_point(s, uc, v, dgc, &range, NULL, NULL);
        if (classify_row(s, u0, u1, v, range, rho1_q15, &st) == ROW_INVALID) {
            continue;
        }
        acc += ((st.n - 2 * st.n_up) * 256) / st.n;
        if (acc > peak) {
            peak = acc;
            best = v + 1;
        }
    }
    return best;
}

/* State of one strip's scan from near to far. */
typedef struct scan_state {
    int32_t sup_start; /* range of the first ground row, -1: none */
    int32_t supported;
    int32_t sup_v; /* row where the support became long enough */
    int32_t last_g_v;
    int32_t last_g_r;
    int32_t last_g_dg;
    int32_t gap;
    int32_t run;
    int32_t run_skip;
    int32_t pos_run;  /* POSITIVE rows seen in a row (wall, up-step)  */
    int32_t pos_skip; /* INVALID or MIXED rows inside that run       */
    int64_t sdg;
    int64_t sd;
    int64_t sr;
    int64_t stau;
    int32_t miss_len; /* invalid band beyond the last ground row */
    int32_t phase;    /* 0 scan, 1 classify after a drop          */
    int32_t rho1;
    int32_t back;
    int32_t deeper;
    int32_t settle; /* rows after the edge run, before classifying */
    int64_t s2dg;
    int64_t s2d;
} scan_state_t;

/* What the scan of a strip does after a row. */
enum scan_step { SCAN_NEXT = 0, SCAN_STOP, SCAN_MISSING };

/*
 * The first deficit rows past an edge are blurred by the matcher's windows
 * and DP, so the plateau they give is too shallow: a plain curb then
 * looked "deeper" a few rows on (typed STAIRS) and its height read low
 * (15 cm curbs at 9-11 cm). The next min_edge_rows rows measure it again;
 * the deeper of the two plateaus is kept and classification starts after
 * them.
 */
static void scan_settle(const scan_ctx_t *s, int32_t u0, int32_t u1,
                        enum row_class rc, const row_stat_t *st,
                        scan_state_t *ss, strip_hit_t *hit)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int32_t uc = (u0 + u1) / 2;
    ss->settle++;
    if (rc == ROW_DEFICIT) {
        ss->s2dg += st->sum_dg_def;
        ss->s2d += st->sum_d_def;
    }
    if (ss->settle == cfg->min_edge_rows && ss->s2d > 0 &&
        ss->s2dg > ss->s2d) {
        int32_t rho2 = (int32_t)(((ss->s2dg - ss->s2d) * 32768) / ss->s2dg);
        if (rho2 > ss->rho1) {
            ss->rho1 = rho2;
            hit->rho1_q15 = ss->rho1;
            hit->drop_mm = (int32_t)geom_clamp_s64(
                ((int64_t)s->frame->height_mm * (ss->s2dg - ss->s2d)) /
                    ss->s2d,
                0, 100000);
        }
    }
    if (ss->settle == cfg->min_edge_rows) {
        /* With the settled plateau (the first run's is too shallow, so
         * ground rows read nearer to it): move the edge to the change
         * point. */
        int32_t ev = edge_change_point(s, u0, u1, hit->edge_v, ss->sup_v,
                                       ss->rho1);
        if (ev != hit->edge_v) {
            hit->edge_v = ev;
            det_model_point(s, uc, ev, negobs_ground_disp_q4(s->plane, uc, ev),
                            &hit->range_mm, &hit->lateral_mm, &hit->depth_mm);
        }
    }
}

/* Classify the drop found: hole (ground or far wall again), stairs (a
 * second, deeper plateau) or plain drop. */
static enum scan_step scan_classify(const scan_ctx_t *s, int32_t u0,
                                    int32_t u1, int32_t v, int32_t range,
                                    enum row_class rc, const row_stat_t *st,
                                    scan_state_t *ss, strip_hit_t *hit)
{
    const negobs_detect_config_t *cfg = s->cfg;
    hit->top_v = v;
    if (range - hit->range_mm > cfg->max_hole_mm + TYPE_SCAN_PAST_HOLE_MM) {
        return SCAN_STOP;
    }
    if (ss->settle < cfg->min_edge_rows) {
        scan_settle(s, u0, u1, rc, st, ss, hit);
        return SCAN_NEXT;
    }
    if ((rc == ROW_GROUND || rc == ROW_POSITIVE) && st->n_up * 2 > st->n) {
        /* Back up to the ground (closer to it than to the plateau): the
         * far rim or far wall of a hole. */
        ss->deeper = 0;
        if (++ss->back >= cfg->min_edge_rows &&
            range - hit->range_mm <= cfg->max_hole_mm) {
            hit->type = NEGOBS_HAZARD_HOLE;
            return SCAN_STOP;
        }
    } else if (rc == ROW_DEFICIT && st->n_deeper * 2 > st->n) {
        ss->back = 0;
        if (++ss->deeper >= cfg->min_edge_rows) {
            hit->type = NEGOBS_HAZARD_STAIRS;
            return SCAN_STOP;
        }
    } else if (rc == ROW_DEFICIT) {
        ss->back = 0;
        ss->deeper = 0;
    }
    return SCAN_NEXT;
}

/* A deficit run long enough after supported ground: the drop is found. */
static void scan_found(const scan_ctx_t *s, int32_t uc, int32_t v,
                       scan_state_t *ss, strip_hit_t *hit)
{
    hit->found = 1;
    hit->type = NEGOBS_HAZARD_DROP;
    hit->edge_v = ss->last_g_v;
    hit->top_v = v;
    det_model_point(s, uc, ss->last_g_v, ss->last_g_dg, &hit->range_mm,
                    &hit->lateral_mm, &hit->depth_mm);
    /* Same-ray relation h = H * (d_g / d_far - 1). */
    if (ss->sd > 0) {
        hit->drop_mm = (int32_t)geom_clamp_s64(
            ((int64_t)s->frame->height_mm * (ss->sdg - ss->sd)) / ss->sd, 0,
            100000);
    } else {
        hit->drop_mm = 100000;
        hit->h_lower = 1;
    }
    hit->margin_q8 = (ss->stau > 0)
                         ? (int32_t)geom_clamp_s64((-ss->sr * 256) / ss->stau,
                                                   0, 1 << 20)
                         : 0;
    ss->rho1 = (ss->sdg > 0)
                   ? (int32_t)(((ss->sdg - ss->sd) * 32768) / ss->sdg)
                   : 0;
    hit->rho1_q15 = ss->rho1;
    ss->phase = 1;
    ss->back = 0;
    ss->deeper = 0;
}

/*
 * 1 when the rows above the model amount to a closure (a wall or an
 * up-step's face and top): min_edge_rows POSITIVE rows, with at most 2
 * INVALID or MIXED rows between them and no GROUND or DEFICIT row, the
 * evidence the rule asks of a drop before it reports one. A closure's
 * rows all stand above the model, so the scan stops a row or two later
 * than on its first row and reads nothing new. One or two POSITIVE rows
 * alone are the matcher's row-correlated noise: a strip median's error
 * runs +-0.2 px over 5-10 rows on weak texture at B = 6 cm, against a
 * tau of 0.2-0.25 px, and stopping on the first such row ended the scan
 * of most strips of a worn-asphalt walk within 0.5 m of the feet, before
 * the curb they should have found. Such a row is read as MIXED (*rc).
 */
static int scan_closed(const negobs_detect_config_t *cfg, enum row_class *rc,
                       scan_state_t *ss)
{
    switch (*rc) {
    case ROW_POSITIVE:
        ss->pos_skip = 0;
        if (++ss->pos_run >= cfg->min_edge_rows) {
            return 1;
        }
        *rc = ROW_MIXED;
        break;
    case ROW_GROUND:
    case ROW_DEFICIT: ss->pos_run = 0; break;
    default:
        if (ss->pos_run > 0 && ++ss->pos_skip > 2) {
            ss->pos_run = 0;
        }
        break;
    }
    return 0;
}

/* One row of the scan before a drop is found. */
static enum scan_step scan_row(const scan_ctx_t *s, int32_t uc, int32_t v,
                               int32_t dgc, int32_t range, enum row_class rc,
                               const row_stat_t *st, scan_state_t *ss,
                               strip_hit_t *hit)
{
    const negobs_detect_config_t *cfg = s->cfg;
    if (scan_closed(cfg, &rc, ss)) {
        if (ss->supported && ss->miss_len >= cfg->min_gap_mm) {
            return SCAN_MISSING;
        }
        return SCAN_STOP; /* wall or up-step: nothing beyond is visible */
    }
    switch (rc) {
    case ROW_GROUND:
        if (ss->sup_start < 0) {
            ss->sup_start = range;
        }
        ss->last_g_v = v;
        ss->last_g_r = range;
        ss->last_g_dg = dgc;
        if (!ss->supported && range - ss->sup_start >= cfg->min_support_mm) {
            ss->supported = 1;
            ss->sup_v = v;
        }
        ss->gap = 0;
        ss->run = 0;
        ss->run_skip = 0;
        ss->miss_len = 0;
        break;
    case ROW_DEFICIT:
        ss->gap = 0;
        if (!ss->supported) {
            /* Lower surface before any supported ground. */
            ss->sup_start = -1;
            ss->run = 0;
            break;
        }
        if (ss->run == 0) {
            ss->sdg = ss->sd = ss->sr = ss->stau = 0;
            ss->run_skip = 0;
        }
        ss->run++;
        ss->sdg += st->sum_dg_def;
        ss->sd += st->sum_d_def;
        ss->sr += st->sum_r_def;
        ss->stau += (int64_t)st->tau * st->n_def;
        if (ss->run >= cfg->min_edge_rows) {
            scan_found(s, uc, v, ss, hit);
        }
        break;
    case ROW_INVALID:
    case ROW_MIXED:
    default:
        if (ss->run > 0) {
            if (++ss->run_skip > 2) {
                ss->run = 0;
                ss->run_skip = 0;
            }
        }
        if (!ss->supported) {
            if (++ss->gap > 2) {
                ss->sup_start = -1;
            }
            break;
        }
        if (rc == ROW_INVALID && ss->run == 0) {
            ss->miss_len = range - ss->last_g_r;
        }
        break;
    }
    return SCAN_NEXT;
}

/*
 * Missing ground: supported ground, then no data for min_gap_mm up to the
 * end of the scan (or up to a far wall, at row v). The occlusion shadow of
 * a drop h at range R is about R*h/H long, so h >= H*L/R.
 */
static void scan_missing(const scan_ctx_t *s, int32_t u0, int32_t u1,
                         int32_t v, const scan_state_t *ss, strip_hit_t *hit)
{
    const int32_t uc = (u0 + u1) / 2;
    hit->found = 1;
    hit->type = NEGOBS_HAZARD_UNKNOWN;
    hit->edge_v = ss->last_g_v;
    hit->top_v = geom_max_s32(v, 0);
    det_model_point(s, uc, ss->last_g_v, ss->last_g_dg, &hit->range_mm,
                    &hit->lateral_mm, &hit->depth_mm);
    hit->drop_mm = (hit->range_mm > 0)
                       ? (int32_t)(((int64_t)s->frame->height_mm *
                                    ss->miss_len) /
                                   hit->range_mm)
                       : 0;
    hit->h_lower = 1;
    hit->margin_q8 = MISSING_MARGIN_Q8;
    /* Missing ground: a bland band is "unknown" (nothing to match); a band
     * as textured as the matched ground before it, at least half of its
     * gradient, failed to match where it should have: an occlusion or
     * drop cue. The reference is this frame's own ground, so the split
     * does not depend on the camera's noise or the surface: synthetic
     * noise alone gives 36/16 grey levels against 85-124 for its ground,
     * SurDis pavement only 29-48. */
    if (s->left != NULL && hit->edge_v > hit->top_v) {
        int32_t rows = hit->edge_v - hit->top_v;
        int32_t t_band = box_texture_q4(s->left, u0, u1, hit->top_v + 1,
                                        hit->edge_v);
        int32_t t_gnd = box_texture_q4(s->left, u0, u1, hit->edge_v,
                                       hit->edge_v + rows);
        if (t_band >= 0 && t_gnd > 0 && 2 * t_band >= t_gnd) {
            hit->textured = 1;
            hit->margin_q8 = MISSING_MARGIN_TEXTURED_Q8;
        } else {
            hit->margin_q8 = MISSING_MARGIN_BLAND_Q8;
        }
    }
}

void det_scan_strip(const scan_ctx_t *s, int32_t u0, int32_t u1,
                    strip_hit_t *hit)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int32_t uc = (u0 + u1) / 2;
    scan_state_t ss;
    row_stat_t st;
    int32_t v;
    int32_t range = 0;

    memset(&ss, 0, sizeof ss);
    ss.sup_start = -1;
    ss.sup_v = -1;
    ss.last_g_v = -1;
    memset(hit, 0, sizeof *hit);
    hit->u0 = u0;
    hit->u1 = u1;
    hit->unit_drop_mm = -1;
    /* rows covered by a near occluder, or whose floor lies beyond the
     * matcher's range, are out of view, like rows below the image: the
     * scan starts above them */
    hit->occl_v = geom_min_s32(det_strip_occluder(s, u0, u1),
                               det_range_row(s, uc));
    for (v = hit->occl_v - 1; v >= 0; v--) {
        enum row_class rc;
        enum scan_step step;
        int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
        if (dgc < s->d_min_q4 || dgc <= 0) {
            break;
        }
        if (ss.phase == 0 && !det_in_corridor(s, uc, dgc)) {
            break;
        }
        det_model_point(s, uc, v, dgc, &range, NULL, NULL);
        rc = classify_row(s, u0, u1, v, range, (ss.phase == 1) ? ss.rho1 : 0,
                          &st);
        if (ss.phase == 1) {
            if (scan_classify(s, u0, u1, v, range, rc, &st, &ss, hit) ==
                SCAN_STOP) {
                break;
            }
            continue;
        }
        step = scan_row(s, uc, v, dgc, range, rc, &st, &ss, hit);
        if (step == SCAN_STOP) {
            return;
        }
        if (step == SCAN_MISSING) {
            scan_missing(s, u0, u1, v, &ss, hit);
            return;
        }
    }
    if (hit->found) {
        if (hit->type != NEGOBS_HAZARD_UNKNOWN) {
            hit->unit_drop_mm = det_unit_drop_mm(s, u0, u1, hit->edge_v);
        }
        return;
    }
    if (!(ss.supported && ss.miss_len >= cfg->min_gap_mm)) {
        return;
    }
    scan_missing(s, u0, u1, v, &ss, hit);
}
