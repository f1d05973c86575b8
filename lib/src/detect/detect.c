/*
 * Negative-obstacle detector: gating, ground model, per-strip scan,
 * hazard merging, disparity-edge support and temporal logic.
 *
 * The per-strip scan (the answer to the paper's step 9) works on the
 * signed residual r = d_measured - d_ground of every valid pixel, in q4.
 * For a drop of h beyond an edge, r = -d_ground * h / (H + h) on every row
 * past the edge, whatever the pitch: that is the cue. Each row of a strip
 * is classified by majority vote of its valid pixels (equivalent to
 * testing the strip median, and O(1) per pixel):
 *
 *   DEFICIT   more than half have r <= -tau
 *   POSITIVE  more than half have r >= +tau (walls, up-steps: stop here)
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
#include "negobs/detect.h"

#include <string.h>

#include "negobs/stereo.h" /* the confidence scale of the disparity map */

#include "arena.h"
#include "detect_int.h"
#include "disp_canny.h"
#include "geom_internal.h"
#include "ground_fit.h"
#include "temporal.h"

#define DETECT_MAGIC 0x4E474454u /* "NGDT" */
#define MAX_STRIP_PX 64

enum row_class {
    ROW_INVALID = 0,
    ROW_GROUND,
    ROW_DEFICIT,
    ROW_POSITIVE,
    ROW_MIXED
};

typedef struct strip_hit {
    int32_t found;
    negobs_hazard_type_t type;
    int32_t u0;
    int32_t u1;
    int32_t edge_v;   /* last ground row (bottom of the box)         */
    int32_t top_v;    /* farthest row examined for this hazard       */
    int32_t range_mm;
    int32_t lateral_mm;
    int32_t depth_mm;
    int32_t drop_mm;
    int32_t h_lower;
    int32_t textured;  /* missing ground: 1 textured band, 0 bland/unknown */
    int32_t margin_q8; /* mean deficit / tau, Q8                     */
    int32_t rho1_q15;  /* relative deficit of the first plateau       */
    int32_t reported;  /* part of a candidate of this frame           */
    /* strip_noise: where a wall or up-step closes the strip (the foot of
     * its rise; rows at or above it are not measured), or -1; the run of
     * rows far above the ground so far */
    int32_t blocked_v;
    int32_t pos_run;
} strip_hit_t;

/* A strip is closed by a positive obstacle after this many consecutive
 * rows whose strip median is at least BLOCK_MIN_Q5 (1/32 px) and 3 times
 * the row's per-pixel sigma above the ground model. */
#define BLOCK_ROWS 4
#define BLOCK_MIN_Q5 32

#define NOISE_BANDS 8
#define NOISE_BINS 64
/* Signed strip-median residuals, 1/32 px bins centred on 0: +-2 px. */
#define STRIP_BINS 128

typedef struct detect_priv {
    uint32_t magic;
    gfit_t gfit;
    temporal_t temporal;
    strip_hit_t *hits;
    int32_t n_strips;
    uint32_t *band_hist; /* NOISE_BANDS x NOISE_BINS |horizontal diff| */
    uint16_t *strip_hist; /* NOISE_BANDS x STRIP_BINS strip medians    */
    dcanny_scratch_t canny; /* disparity Canny around a hazard's edge  */
    /* ground-drop cue: the camera height and pitch over the ground under
     * the feet, followed on clean frames only */
    int32_t ref_ok;
    int32_t ref_height_mm;
    int32_t ref_pitch_mdeg;
    uint32_t drop_since_ms; /* first frame of the current cue           */
    int32_t drop_on;
    /* before the reference: first frame whose ground lay
     * ground_verify_mm or more below the configured height */
    uint32_t unverified_since_ms;
    int32_t unverified_on;
    /* last clean frame with a rule candidate within h_near_range_mm: it
     * corroborates a smaller ground-drop rise for hold_ms */
    uint32_t near_cand_ms;
    int32_t near_cand_on;
} detect_priv_t;

/* The cue needs a steady pitch: a pitch change of more than this between
 * the reference and the frame also moves the estimated height. */
#define GROUND_DROP_PITCH_MDEG 3000

void negobs_detect_config_default(negobs_detect_config_t *cfg, int32_t width,
                                  int32_t height)
{
    memset(cfg, 0, sizeof *cfg);
    negobs_camera_default(&cfg->cam, width, height);
    cfg->cam_height_mm = 1200;
    cfg->cam_height_tol_mm = 300;
    cfg->cam_pitch_mdeg = 20000;
    cfg->cam_pitch_tol_mdeg = 15000;
    cfg->cam_roll_tol_mdeg = 12000;
    cfg->max_disp_q4 = 64 * 16;
    /* Stereo confidence is 255 * NCC, halved where the DP filled a pixel
     * the seed growing did not reach. Deficits on filled or weakly
     * matched pixels are mostly the matcher carrying a disparity across
     * a bland region (a painted stripe read ~1 px low was confirmed as a
     * hole): only grown pixels with NCC >= 0.47 vote. */
    cfg->min_confidence = 120;
    /* The ground fit needs more pixels than the deficit test: on real
     * frames most ground pixels are weakly matched (SurDis: only ~15 %
     * grown with NCC >= 0.63; 120 lost the ground on every frame). But
     * DP-filled pixels (<= 63) of a bland patch under the feet dragged the
     * fit (H 1.2 -> 1.3 m, then false drops at 3 m), so they stay out. */
    cfg->ground_min_confidence = 64;
    cfg->fit_rows_pct = 25;
    cfg->fit_step_px = 2;
    cfg->ground_min_valid_pct = 25;
    cfg->ground_min_inlier_pct = 30;
    cfg->track_gain_q15 = 32768;
    cfg->track_gate_q4 = 24;
    cfg->sigma_min_q4 = 2;
    cfg->sigma_max_q4 = 24;
    cfg->range_max_mm = 5000;
    cfg->range_warn_mm = 4000;
    cfg->range_imminent_mm = 1500;
    cfg->ttc_imminent_ms = 1200;
    cfg->corridor_half_width_mm = 600;
    cfg->strip_px = 16;
    cfg->h_min_far_mm = 100;
    cfg->h_min_near_mm = 50;
    cfg->h_near_range_mm = 2000;
    cfg->h_thresh_pct = 80;
    cfg->k_sigma_q4 = 48;
    cfg->min_edge_rows = 3;
    cfg->min_support_mm = 250;
    cfg->min_gap_mm = 400;
    cfg->max_hole_mm = 1000;
    cfg->merge_range_mm = 300;
    cfg->min_strips = 2;
    cfg->missing_policy = NEGOBS_MISSING_CAUTION;
    cfg->canny_thresh_permille = 70;
    cfg->canny_low_permille = 400;
    cfg->confirm_k = 3;
    cfg->confirm_n = 5;
    cfg->clear_m = 5;
    cfg->hold_ms = 3000;
    cfg->hold_speed_mm_s = 1400;
    cfg->max_speed_mm_s = 2000;
    cfg->assoc_range_mm = 400;
    cfg->assoc_lateral_mm = 600;
    cfg->hold_bottom_rows = 24;
    cfg->ground_drop_mm = 100;
    cfg->ground_drop_max_ms = 5000;
    cfg->ground_verify_mm = 50;
    cfg->ground_drop_corroborated_mm = 70;
    cfg->sync_tol_ms = 5;
    cfg->max_frame_age_ms = 150;
    cfg->dark_mean_min = 20;
    cfg->dark_max_permille = 700;
    cfg->saturated_max_permille = 250;
    cfg->texture_min_q4 = 24;
}

negobs_status_t negobs_detect_config_preset(negobs_detect_config_t *cfg,
                                            negobs_sensitivity_t preset)
{
    if (cfg == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    switch (preset) {
    case NEGOBS_SENS_SENSITIVE:
        cfg->h_min_far_mm = 80;
        cfg->h_min_near_mm = 40;
        cfg->k_sigma_q4 = 40;
        cfg->confirm_k = 2;
        cfg->confirm_n = 4;
        break;
    case NEGOBS_SENS_BALANCED:
        cfg->h_min_far_mm = 100;
        cfg->h_min_near_mm = 50;
        cfg->k_sigma_q4 = 48;
        cfg->confirm_k = 3;
        cfg->confirm_n = 5;
        break;
    case NEGOBS_SENS_CONSERVATIVE:
        cfg->h_min_far_mm = 120;
        cfg->h_min_near_mm = 60;
        cfg->k_sigma_q4 = 56;
        cfg->confirm_k = 4;
        cfg->confirm_n = 6;
        break;
    default:
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

static int in_range(int32_t x, int32_t lo, int32_t hi)
{
    return x >= lo && x <= hi;
}

static negobs_status_t config_check(const negobs_detect_config_t *c)
{
    if (c == NULL || negobs_camera_check(&c->cam) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    if (!in_range(c->cam_height_mm, 200, 5000) ||
        !in_range(c->cam_height_tol_mm, 0, c->cam_height_mm - 100) ||
        !in_range(c->cam_pitch_mdeg, -10000, 70000) ||
        !in_range(c->cam_pitch_tol_mdeg, 0, 45000) ||
        !in_range(c->cam_roll_tol_mdeg, 0, 45000) ||
        !in_range(c->max_disp_q4, 16, 512 * 16) ||
        !in_range(c->min_confidence, 0, 255) ||
        !in_range(c->ground_min_confidence, 0, 255) ||
        !in_range(c->fit_rows_pct, 10, 100) ||
        !in_range(c->fit_step_px, 1, 16) ||
        !in_range(c->ground_min_valid_pct, 0, 100) ||
        !in_range(c->ground_min_inlier_pct, 0, 100) ||
        !in_range(c->track_gain_q15, 1, 32768) ||
        !in_range(c->track_gate_q4, 1, 1024) ||
        !in_range(c->sigma_min_q4, 1, 64) ||
        !in_range(c->sigma_max_q4, c->sigma_min_q4, 256)) {
        return NEGOBS_ERR_INVAL;
    }
    if (!in_range(c->range_max_mm, 500, 50000) ||
        !in_range(c->range_warn_mm, 0, c->range_max_mm) ||
        !in_range(c->range_imminent_mm, 0, c->range_warn_mm) ||
        !in_range(c->ttc_imminent_ms, 0, 10000) ||
        !in_range(c->corridor_half_width_mm, 100, 5000) ||
        !in_range(c->strip_px, 4, MAX_STRIP_PX) ||
        c->strip_px > c->cam.width ||
        !in_range(c->h_min_far_mm, 10, 2000) ||
        !in_range(c->h_min_near_mm, 10, 2000) ||
        !in_range(c->h_near_range_mm, 0, 50000) ||
        !in_range(c->h_thresh_pct, 10, 200) ||
        !in_range(c->k_sigma_q4, 0, 256) ||
        !in_range(c->min_edge_rows, 1, 64) ||
        !in_range(c->min_support_mm, 0, 5000) ||
        !in_range(c->min_gap_mm, 50, 10000) ||
        !in_range(c->max_hole_mm, 0, 10000) ||
        !in_range(c->merge_range_mm, 0, 5000) ||
        !in_range(c->min_strips, 1, 64) ||
        !in_range(c->missing_policy, 0, 3) ||
        !in_range(c->canny_thresh_permille, 1, 1000) ||
        !in_range(c->canny_low_permille, 0, 1000)) {
        return NEGOBS_ERR_INVAL;
    }
    if (!in_range(c->confirm_n, 1, 31) ||
        !in_range(c->confirm_k, 1, c->confirm_n) ||
        !in_range(c->clear_m, 1, 1000) || !in_range(c->hold_ms, 0, 60000) ||
        !in_range(c->hold_speed_mm_s, 0, 5000) ||
        !in_range(c->max_speed_mm_s, 0, 10000) ||
        !in_range(c->assoc_range_mm, 0, 5000) ||
        !in_range(c->assoc_lateral_mm, 0, 5000) ||
        !in_range(c->hold_bottom_rows, 0, c->cam.height) ||
        !in_range(c->ground_drop_mm, 0, 2000) ||
        !in_range(c->ground_drop_max_ms, 0, 600000) ||
        !in_range(c->ground_verify_mm, 1, 2000) ||
        !in_range(c->ground_drop_corroborated_mm, 0, 2000) ||
        !in_range(c->sync_tol_ms, 0, 1000) ||
        !in_range(c->max_frame_age_ms, 1, 60000) ||
        !in_range(c->dark_mean_min, 0, 255) ||
        !in_range(c->dark_max_permille, 0, 1000) ||
        !in_range(c->saturated_max_permille, 0, 1000) ||
        !in_range(c->texture_min_q4, 0, 4096)) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

/* The single carve function: measures with a NULL arena base. */
static negobs_status_t carve(negobs_arena_t *ar,
                             const negobs_detect_config_t *cfg,
                             detect_priv_t **out)
{
    detect_priv_t tmp;
    detect_priv_t *p = negobs_arena_take(ar, sizeof(detect_priv_t));
    negobs_status_t st;
    if (p == NULL) {
        p = &tmp; /* measuring: carve into a scratch descriptor */
    }
    memset(p, 0, sizeof *p);
    st = gfit_carve(&p->gfit, ar, cfg);
    if (st != NEGOBS_OK) {
        return st;
    }
    p->n_strips = cfg->cam.width / cfg->strip_px;
    p->hits = negobs_arena_take(ar, (size_t)p->n_strips * sizeof(strip_hit_t));
    p->band_hist = negobs_arena_take(
        ar, (size_t)NOISE_BANDS * NOISE_BINS * sizeof(uint32_t));
    p->strip_hist = negobs_arena_take(
        ar, (size_t)NOISE_BANDS * STRIP_BINS * sizeof(uint16_t));
    p->canny.mag = negobs_arena_take(ar, dcanny_mag_bytes(cfg->cam.width));
    p->canny.label =
        negobs_arena_take(ar, dcanny_label_bytes(cfg->cam.width));
    p->canny.width = cfg->cam.width;
    *out = (p == &tmp) ? NULL : p;
    return negobs_arena_status(ar);
}

negobs_status_t negobs_detect_workspace_size(const negobs_detect_config_t *cfg,
                                             size_t *bytes_out)
{
    negobs_arena_t ar;
    detect_priv_t *p;
    negobs_status_t st;
    if (bytes_out == NULL || config_check(cfg) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    negobs_arena_init(&ar, NULL, 0);
    st = carve(&ar, cfg, &p);
    if (st != NEGOBS_OK) {
        return st;
    }
    *bytes_out = negobs_arena_used(&ar);
    return NEGOBS_OK;
}

negobs_status_t negobs_detect_init(negobs_detect_t *ctx,
                                   const negobs_detect_config_t *cfg,
                                   void *workspace, size_t workspace_bytes)
{
    negobs_arena_t ar;
    detect_priv_t *p = NULL;
    negobs_status_t st;
    if (ctx == NULL || workspace == NULL || config_check(cfg) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    ctx->priv = NULL;
    ctx->cfg = *cfg;
    negobs_arena_init(&ar, workspace, workspace_bytes);
    if (negobs_arena_status(&ar) != NEGOBS_OK) {
        return negobs_arena_status(&ar);
    }
    /* Carve against the context's own copy so pointers stay valid. */
    st = carve(&ar, &ctx->cfg, &p);
    if (st != NEGOBS_OK || p == NULL) {
        return (st != NEGOBS_OK) ? st : NEGOBS_ERR_NOSPACE;
    }
    temporal_reset(&p->temporal, &ctx->cfg);
    p->magic = DETECT_MAGIC;
    ctx->priv = p;
    return NEGOBS_OK;
}

negobs_status_t negobs_detect_photo_stats(const negobs_image_u8_t *img,
                                          negobs_photo_stats_t *out)
{
    int32_t x;
    int32_t y;
    uint64_t sum = 0;
    uint64_t grad = 0;
    uint32_t n = 0;
    uint32_t ng = 0;
    uint32_t dark = 0;
    uint32_t sat = 0;
    if (out == NULL || negobs_image_u8_check(img) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    for (y = 0; y < img->height; y += 2) {
        const uint8_t *row = negobs_image_u8_row(img, y);
        for (x = 0; x < img->width; x += 2) {
            uint32_t p = row[x];
            sum += p;
            n++;
            dark += (p <= 8u) ? 1u : 0u;
            sat += (p >= 250u) ? 1u : 0u;
            if (x + 1 < img->width) {
                int32_t g = (int32_t)row[x + 1] - (int32_t)p;
                grad += (uint32_t)negobs_abs_s32(g);
                ng++;
            }
        }
    }
    if (n == 0) {
        return NEGOBS_ERR_INVAL; /* no pixel sampled */
    }
    out->mean = (int32_t)(sum / n);
    out->dark_permille = (int32_t)(((uint64_t)dark * 1000u) / n);
    out->saturated_permille = (int32_t)(((uint64_t)sat * 1000u) / n);
    out->texture_q4 = ng ? (int32_t)((grad * 16u) / ng) : 0;
    return NEGOBS_OK;
}

static uint32_t photo_reasons(const negobs_detect_config_t *cfg,
                              const negobs_photo_stats_t *s)
{
    uint32_t r = 0;
    if (s->mean < cfg->dark_mean_min ||
        s->dark_permille > cfg->dark_max_permille) {
        r |= NEGOBS_DEGRADED_TOO_DARK;
    }
    if (s->saturated_permille > cfg->saturated_max_permille) {
        r |= NEGOBS_DEGRADED_SATURATED;
    }
    if (s->texture_q4 < cfg->texture_min_q4) {
        r |= NEGOBS_DEGRADED_LOW_TEXTURE;
    }
    return r;
}

/* Scan context shared by the strips of one frame. */
typedef struct scan_ctx {
    const negobs_detect_config_t *cfg;
    const negobs_image_s16_t *disp;
    const negobs_image_u8_t *conf;
    const negobs_image_u8_t *left; /* NULL: no texture check */
    const negobs_ground_plane_t *plane;
    const negobs_ground_frame_t *frame;
    int32_t sigma_q4;
    int32_t d_min_q4; /* ground disparity at range_max */
    int32_t band_v0;  /* first row of the noise bands    */
    int32_t band_rows;/* rows per band (>= 1)            */
    int32_t band_sigma_q4[NOISE_BANDS];
    /* Measured spread and offset of the strip median (1/256 px), per
     * band pooled with the next nearer one; spread 0: too few strip rows
     * (strip_noise). */
    int32_t band_strip_q8[NOISE_BANDS];
    int32_t band_bias_q8[NOISE_BANDS];
} scan_ctx_t;

/* Noise for row v: the larger of the ground estimate and the band's. */
static int32_t sigma_at(const scan_ctx_t *s, int32_t v)
{
    int32_t b = (v - s->band_v0) / s->band_rows;
    b = negobs_clamp_s32(b, 0, NOISE_BANDS - 1);
    return geom_max_s32(s->sigma_q4, s->band_sigma_q4[b]);
}

/*
 * Noise per band of rows from horizontal neighbours: for a smooth surface
 * d(u+1) - d(u) has sigma*sqrt(2) and no model term, so a drop (a
 * horizontal edge) does not inflate it. sigma = 1.4826 * MAD / sqrt(2)
 * ~= MAD * 1073/1024. Stereo noise that is correlated along rows makes
 * this an underestimate, which is why it only ever raises the ground
 * estimate (sigma_at). Every 2nd row, all columns.
 */
static void band_noise(scan_ctx_t *s, uint32_t *hist, int32_t v_top)
{
    const negobs_image_s16_t *d = s->disp;
    int32_t h = s->cfg->cam.height;
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
    for (v = v_top; v < h; v += 2) {
        const int16_t *row = negobs_image_s16_row(d, v);
        uint32_t *hb = hist + (size_t)(geom_min_s32(
                                  (v - v_top) / s->band_rows,
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
        s->band_sigma_q4[b] = (mad * 1073 + 512) / 1024;
    }
}

/* Per-row statistics of one strip. */
typedef struct row_stat {
    int32_t n;
    int32_t tau;
    int32_t dg;       /* model at the strip centre, q4 */
    int32_t n_def;
    int32_t n_gnd;
    int32_t n_pos;
    int32_t n_deeper; /* below the first plateau by more than tau */
    int32_t n_up;     /* above half the first plateau's deficit     */
    int64_t sum_dg_def;
    int64_t sum_d_def;
    int64_t sum_r_def;
} row_stat_t;

static int32_t h_min_at(const negobs_detect_config_t *cfg, int32_t range_mm)
{
    return (range_mm <= cfg->h_near_range_mm) ? cfg->h_min_near_mm
                                              : cfg->h_min_far_mm;
}

/*
 * Classify one row of a strip. rho1_q15 > 0 additionally counts pixels
 * deeper than the first plateau (relative deficit rho1) by tau.
 */
static enum row_class classify_row(const scan_ctx_t *s, int32_t u0,
                                   int32_t u1, int32_t v, int32_t range_mm,
                                   int32_t rho1_q15, row_stat_t *st)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int16_t *row = negobs_image_s16_row(s->disp, v);
    const uint8_t *crow = (s->conf != NULL)
                              ? negobs_image_u8_row(s->conf, v)
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
    h_t = (h_min_at(cfg, range_mm) * cfg->h_thresh_pct) / 100;
    tau_geo = (int32_t)(((int64_t)st->dg * h_t) / (hmm + h_t));
    /* k * 1.25 * sigma / sqrt(n): k_q4*sigma_q4*5 / (4*sqrt(256 n)). */
    tau_noise = (int32_t)(((int64_t)cfg->k_sigma_q4 * sigma_at(s, v) * 5) /
                          (4 * (int64_t)negobs_isqrt_u32(
                                   (uint32_t)(256 * st->n))));
    st->tau = geom_max_s32(geom_max_s32(tau_geo, tau_noise), 1);
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
static void model_point(const scan_ctx_t *s, int32_t u, int32_t v,
                        int32_t dg_q4, int32_t *range_mm, int32_t *lat_mm,
                        int32_t *depth_mm)
{
    int32_t z = negobs_depth_mm_from_disp_q4(&s->cfg->cam, dg_q4);
    if (z < 0) {
        z = NEGOBS_DEPTH_MAX_MM;
    }
    negobs_ground_floor_point(&s->cfg->cam, s->frame, u * 16, v * 16, z,
                              range_mm, lat_mm);
    if (depth_mm != NULL) {
        *depth_mm = z;
    }
}

static int in_corridor(const scan_ctx_t *s, int32_t uc, int32_t dg_q4)
{
    /* |X| = |u - cx| * B / d <= W  <=>  |u - cx| * B_um <= W_um * d. */
    int64_t du = negobs_abs_s32(uc * 16 + 8 - s->cfg->cam.cx_q4);
    return du * s->cfg->cam.baseline_um <=
           (int64_t)s->cfg->corridor_half_width_mm * 1000 * dg_q4;
}

/* First column of strip si (the strips are centred in the frame). */
static int32_t strip_u0(const negobs_detect_config_t *cfg, int32_t n_strips,
                        int32_t si)
{
    return (cfg->cam.width - n_strips * cfg->strip_px) / 2 +
           si * cfg->strip_px;
}

/* 1 when the centre of strip si lies in the walking corridor at row v of
 * the ground model. */
static int strip_in_corridor(const scan_ctx_t *s, int32_t n_strips,
                             int32_t si, int32_t v)
{
    int32_t uc = strip_u0(s->cfg, n_strips, si) + s->cfg->strip_px / 2;
    int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
    return dgc > 0 && in_corridor(s, uc, dgc);
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
        model_point(s, uc, v, dgc, &range, NULL, NULL);
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

static void scan_strip(const scan_ctx_t *s, int32_t u0, int32_t u1,
                       strip_hit_t *hit)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int32_t uc = (u0 + u1) / 2;
    row_stat_t st;
    int32_t v;
    int32_t sup_start = -1; /* range of the first ground row, -1: none */
    int32_t supported = 0;
    int32_t sup_v = -1;     /* row where the support became long enough */
    int32_t last_g_v = -1;
    int32_t last_g_r = 0;
    int32_t last_g_dg = 0;
    int32_t gap = 0;
    int32_t run = 0;
    int32_t run_skip = 0;
    int64_t sdg = 0;
    int64_t sd = 0;
    int64_t sr = 0;
    int64_t stau = 0;
    int32_t miss_len = 0; /* invalid band beyond the last ground row */
    int32_t phase = 0;    /* 0 scan, 1 classify after a drop          */
    int32_t rho1 = 0;
    int32_t back = 0;
    int32_t deeper = 0;
    int32_t range = 0;
    int32_t settle = 0;  /* rows after the edge run, before classifying */
    int64_t s2dg = 0;
    int64_t s2d = 0;

    memset(hit, 0, sizeof *hit);
    hit->u0 = u0;
    hit->u1 = u1;
    for (v = cfg->cam.height - 1; v >= 0; v--) {
        enum row_class rc;
        int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
        if (dgc < s->d_min_q4 || dgc <= 0) {
            break;
        }
        if (phase == 0 && !in_corridor(s, uc, dgc)) {
            break;
        }
        model_point(s, uc, v, dgc, &range, NULL, NULL);
        rc = classify_row(s, u0, u1, v, range, (phase == 1) ? rho1 : 0, &st);

        if (phase == 1) {
            /* Classify the drop found: hole (ground or far wall again),
             * stairs (a second, deeper plateau) or plain drop. */
            hit->top_v = v;
            if (range - hit->range_mm > cfg->max_hole_mm + 500) {
                break;
            }
            if (settle < cfg->min_edge_rows) {
                /* The first deficit rows past an edge are blurred by the
                 * matcher's windows and DP, so the plateau they give is
                 * too shallow: a plain curb then looked "deeper" a few
                 * rows on (typed STAIRS) and its height read low (15 cm
                 * curbs at 9-11 cm). The next min_edge_rows rows measure
                 * it again; the deeper of the two plateaus is kept and
                 * classification starts after them. */
                settle++;
                if (rc == ROW_DEFICIT) {
                    s2dg += st.sum_dg_def;
                    s2d += st.sum_d_def;
                }
                if (settle == cfg->min_edge_rows && s2d > 0 && s2dg > s2d) {
                    int32_t rho2 = (int32_t)(((s2dg - s2d) * 32768) / s2dg);
                    if (rho2 > rho1) {
                        rho1 = rho2;
                        hit->rho1_q15 = rho1;
                        hit->drop_mm = (int32_t)geom_clamp_s64(
                            ((int64_t)s->frame->height_mm * (s2dg - s2d)) /
                                s2d,
                            0, 100000);
                    }
                }
                if (settle == cfg->min_edge_rows) {
                    /* With the settled plateau (the first run's is too
                     * shallow, so ground rows read nearer to it): move the
                     * edge to the change point. */
                    int32_t ev = edge_change_point(s, u0, u1, hit->edge_v,
                                                   sup_v, rho1);
                    if (ev != hit->edge_v) {
                        hit->edge_v = ev;
                        model_point(s, uc, ev,
                                    negobs_ground_disp_q4(s->plane, uc, ev),
                                    &hit->range_mm, &hit->lateral_mm,
                                    &hit->depth_mm);
                    }
                }
                continue;
            }
            if ((rc == ROW_GROUND || rc == ROW_POSITIVE) &&
                st.n_up * 2 > st.n) {
                /* Back up to the ground (closer to it than to the
                 * plateau): the far rim or far wall of a hole. */
                deeper = 0;
                if (++back >= cfg->min_edge_rows &&
                    range - hit->range_mm <= cfg->max_hole_mm) {
                    hit->type = NEGOBS_HAZARD_HOLE;
                    break;
                }
            } else if (rc == ROW_DEFICIT && st.n_deeper * 2 > st.n) {
                back = 0;
                if (++deeper >= cfg->min_edge_rows) {
                    hit->type = NEGOBS_HAZARD_STAIRS;
                    break;
                }
            } else if (rc == ROW_DEFICIT) {
                back = 0;
                deeper = 0;
            }
            continue;
        }

        switch (rc) {
        case ROW_GROUND:
            if (sup_start < 0) {
                sup_start = range;
            }
            last_g_v = v;
            last_g_r = range;
            last_g_dg = dgc;
            if (!supported && range - sup_start >= cfg->min_support_mm) {
                supported = 1;
                sup_v = v;
            }
            gap = 0;
            run = 0;
            run_skip = 0;
            miss_len = 0;
            break;
        case ROW_DEFICIT:
            gap = 0;
            if (!supported) {
                /* Lower surface before any supported ground. */
                sup_start = -1;
                run = 0;
                break;
            }
            if (run == 0) {
                sdg = sd = sr = stau = 0;
                run_skip = 0;
            }
            run++;
            sdg += st.sum_dg_def;
            sd += st.sum_d_def;
            sr += st.sum_r_def;
            stau += (int64_t)st.tau * st.n_def;
            if (run >= cfg->min_edge_rows) {
                hit->found = 1;
                hit->type = NEGOBS_HAZARD_DROP;
                hit->edge_v = last_g_v;
                hit->top_v = v;
                model_point(s, uc, last_g_v, last_g_dg, &hit->range_mm,
                            &hit->lateral_mm, &hit->depth_mm);
                /* Same-ray relation h = H * (d_g / d_far - 1). */
                if (sd > 0) {
                    hit->drop_mm = (int32_t)geom_clamp_s64(
                        ((int64_t)s->frame->height_mm * (sdg - sd)) / sd, 0,
                        100000);
                } else {
                    hit->drop_mm = 100000;
                    hit->h_lower = 1;
                }
                hit->margin_q8 = (stau > 0)
                                     ? (int32_t)geom_clamp_s64(
                                           (-sr * 256) / stau, 0, 1 << 20)
                                     : 0;
                rho1 = (sdg > 0) ? (int32_t)(((sdg - sd) * 32768) / sdg) : 0;
                hit->rho1_q15 = rho1;
                phase = 1;
                back = 0;
                deeper = 0;
            }
            break;
        case ROW_POSITIVE:
            if (supported && miss_len >= cfg->min_gap_mm) {
                goto missing;
            }
            return; /* wall or up-step: nothing beyond is visible */
        case ROW_INVALID:
        case ROW_MIXED:
        default:
            if (run > 0) {
                if (++run_skip > 2) {
                    run = 0;
                    run_skip = 0;
                }
            }
            if (!supported) {
                if (++gap > 2) {
                    sup_start = -1;
                }
                break;
            }
            if (rc == ROW_INVALID && run == 0) {
                miss_len = range - last_g_r;
            }
            break;
        }
    }
    if (hit->found) {
        return;
    }
    if (!(supported && miss_len >= cfg->min_gap_mm)) {
        return;
    }
missing:
    /* Missing ground: supported ground, then no data for min_gap_mm up to
     * the end of the scan (or up to a far wall). The occlusion shadow of
     * a drop h at range R is about R*h/H long, so h >= H*L/R. */
    hit->found = 1;
    hit->type = NEGOBS_HAZARD_UNKNOWN;
    hit->edge_v = last_g_v;
    hit->top_v = geom_max_s32(v, 0);
    model_point(s, uc, last_g_v, last_g_dg, &hit->range_mm, &hit->lateral_mm,
                &hit->depth_mm);
    hit->drop_mm = (hit->range_mm > 0)
                       ? (int32_t)(((int64_t)s->frame->height_mm * miss_len) /
                                   hit->range_mm)
                       : 0;
    hit->h_lower = 1;
    hit->margin_q8 = 256;
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
            hit->margin_q8 = 384;
        } else {
            hit->margin_q8 = 128;
        }
    }
}

/* Median of n (1..MAX_STRIP_PX) values, times 2 (the two middle values
 * summed for even n), so no precision is lost. Sorts x in place. */
static int32_t median2_s32(int32_t *x, int32_t n)
{
    int32_t i;
    for (i = 1; i < n; i++) {
        int32_t t = x[i];
        int32_t j = i - 1;
        while (j >= 0 && x[j] > t) {
            x[j + 1] = x[j];
            j--;
        }
        x[j + 1] = t;
    }
    return (n & 1) ? 2 * x[n / 2] : x[n / 2 - 1] + x[n / 2];
}

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
    *spread_q8 = (int32_t)geom_clamp_s64((mad_x256 * 759 + 8192) / 16384, 1,
                                         1 << 20);
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
 * measured; see strip_sigma_at.
 *
 * Scaling: d and d_g are q4; 2 * median is in q5 (1/32 px); e goes to a
 * 128-bin histogram of 1/32 px centred on 0 (beyond +-2 px in the end
 * bins: such a band is NOISY whatever the interpolation). Counts are
 * uint16: a band holds at most height/8 rows x width/4 strips.
 */
/* Strip-median residual e (1/32 px) of strip si on row v, against the
 * nearer of the ground and a reported drop's plateau past its edge; 0
 * when the row is outside the corridor or has too few voting pixels. */
static int strip_row_e(const scan_ctx_t *s, const detect_priv_t *p,
                       int32_t v, int32_t si, int32_t *rr, int32_t *e_out)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const strip_hit_t *hit = &p->hits[si];
    const int16_t *row = negobs_image_s16_row(s->disp, v);
    const uint8_t *crow =
        (s->conf != NULL) ? negobs_image_u8_row(s->conf, v) : NULL;
    int32_t u0 = strip_u0(cfg, p->n_strips, si);
    int32_t u1 = u0 + cfg->strip_px;
    int32_t uc = (u0 + u1) / 2;
    int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
    int64_t acc = (int64_t)s->plane->b_q20 * v + s->plane->c_q20 +
                  (int64_t)s->plane->a_q20 * u0;
    int32_t n = 0;
    int32_t e;
    int32_t u;
    if (dgc <= 0 || !in_corridor(s, uc, dgc)) {
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
    e = median2_s32(rr, n);
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

static void strip_noise(scan_ctx_t *s, detect_priv_t *p, uint16_t *hist)
{
    const int32_t h = s->cfg->cam.height;
    int32_t rr[MAX_STRIP_PX];
    int32_t b;
    int32_t v;
    int32_t si;

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
        for (v = h - 1; v >= s->band_v0 && hs->blocked_v < 0; v--) {
            int32_t e;
            int32_t thr = geom_max_s32(BLOCK_MIN_Q5, 6 * sigma_at(s, v));
            if (!strip_row_e(s, p, v, si, rr, &e)) {
                continue;
            }
            strip_hist_add(s, hist, v, e);
            if (e * 4 < thr) {
                foot = v - 1;
            }
            if (e >= thr) {
                if (++hs->pos_run >= BLOCK_ROWS) {
                    hs->blocked_v = (foot >= 0) ? foot : v;
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
            if (v <= p->hits[si].blocked_v ||
                !strip_row_e(s, p, v, si, rr, &e)) {
                continue; /* beyond a wall: nothing to vouch for there */
            }
            strip_hist_add(s, hist, v, e);
        }
    }
    for (b = 0; b < NOISE_BANDS; b++) {
        hist_median_spread_q8(
            hist + (size_t)b * STRIP_BINS,
            (b + 1 < NOISE_BANDS) ? hist + (size_t)(b + 1) * STRIP_BINS
                                  : NULL,
            &s->band_bias_q8[b], &s->band_strip_q8[b]);
    }
}

/* Measured spread of the strip median at row v (1/256 px), and in
 * *offset_q8 the median itself (the ground model's offset there). Where
 * too few strip rows could be measured, the independent-pixel value
 * 1.25 * sigma / sqrt(strip_px) stands in, with offset 0: with so little
 * data in the band the rule itself reads those rows as INVALID, not as
 * ground. */
static int32_t strip_sigma_at(const scan_ctx_t *s, int32_t v,
                              int32_t *offset_q8)
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
    return (int32_t)(((int64_t)sigma_at(s, v) * 320) /
                     (int64_t)negobs_isqrt_u32(
                         (uint32_t)s->cfg->strip_px * 256u));
}

static void fill_no_info(negobs_detect_result_t *res, uint32_t reasons)
{
    memset(res, 0, sizeof *res);
    res->state = NEGOBS_DETECT_NO_INFO;
    res->reasons = reasons;
    res->level = NEGOBS_LEVEL_NONE;
    res->nearest_range_mm = -1;
}

/* Merge adjacent strips into hazards; nearest kept when over the bound. */
static void merge_strips(const scan_ctx_t *s, detect_priv_t *p,
                         negobs_detect_result_t *res)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t i = 0;
    while (i < p->n_strips) {
        int32_t j;
        int32_t k;
        int32_t cnt;
        int32_t nearest;
        int64_t drop_sum = 0;
        int32_t types[4] = {0, 0, 0, 0};
        int32_t margin = 0;
        int32_t n_textured = 0;
        negobs_hazard_t h;
        if (!p->hits[i].found) {
            i++;
            continue;
        }
        j = i + 1;
        while (j < p->n_strips && p->hits[j].found &&
               negobs_abs_s32(p->hits[j].range_mm - p->hits[j - 1].range_mm) <=
                   cfg->merge_range_mm &&
               (p->hits[j].type == NEGOBS_HAZARD_UNKNOWN) ==
                   (p->hits[j - 1].type == NEGOBS_HAZARD_UNKNOWN)) {
            j++;
        }
        cnt = j - i;
        if (cnt < cfg->min_strips) {
            i = j;
            continue;
        }
        memset(&h, 0, sizeof h);
        nearest = i;
        h.u0 = (int16_t)p->hits[i].u0;
        h.u1 = (int16_t)(p->hits[j - 1].u1 - 1);
        h.v0 = (int16_t)p->hits[i].top_v;
        h.v1 = (int16_t)p->hits[i].edge_v;
        for (k = i; k < j; k++) {
            if (p->hits[k].range_mm < p->hits[nearest].range_mm) {
                nearest = k;
            }
        }
        /* Among strips within 50 mm of the nearest, report the one most
         * ahead (a straight curb across the path is "straight ahead"). */
        {
            int32_t rmin = p->hits[nearest].range_mm;
            for (k = i; k < j; k++) {
                if (p->hits[k].range_mm <= rmin + 50 &&
                    negobs_abs_s32(p->hits[k].lateral_mm) <
                        negobs_abs_s32(p->hits[nearest].lateral_mm)) {
                    nearest = k;
                }
            }
        }
        for (k = i; k < j; k++) {
            const strip_hit_t *sh = &p->hits[k];
            drop_sum += sh->drop_mm;
            types[sh->type]++;
            margin += sh->margin_q8;
            h.v0 = (int16_t)geom_min_s32(h.v0, sh->top_v);
            h.v1 = (int16_t)geom_max_s32(h.v1, sh->edge_v);
            if (sh->h_lower) {
                h.flags |= NEGOBS_HAZARD_F_H_LOWER;
            }
            n_textured += sh->textured;
        }
        if (2 * n_textured > cnt) {
            h.flags |= NEGOBS_HAZARD_F_TEXTURED;
        }
        h.type = NEGOBS_HAZARD_DROP;
        if (types[NEGOBS_HAZARD_UNKNOWN] == cnt) {
            h.type = NEGOBS_HAZARD_UNKNOWN;
        } else if (types[NEGOBS_HAZARD_STAIRS] * 2 >= cnt) {
            h.type = NEGOBS_HAZARD_STAIRS;
        } else if (types[NEGOBS_HAZARD_HOLE] * 2 >= cnt) {
            h.type = NEGOBS_HAZARD_HOLE;
        }
        h.range_mm = p->hits[nearest].range_mm;
        h.lateral_mm = p->hits[nearest].lateral_mm;
        h.depth_mm = p->hits[nearest].depth_mm;
        h.bearing_mdeg = negobs_bearing_mdeg(h.lateral_mm, h.range_mm);
        h.drop_mm = (int32_t)(drop_sum / cnt);
        h.strips = (int16_t)cnt;
        /* Edge orientation: least-squares line range = m * lateral + q
         * through the strips' edge points; angle = atan(m). */
        {
            int64_t n = 0;
            int64_t sx = 0;
            int64_t sy = 0;
            int64_t sxx = 0;
            int64_t sxy = 0;
            for (k = i; k < j; k++) {
                int64_t x = p->hits[k].lateral_mm;
                int64_t y = p->hits[k].range_mm;
                n++;
                sx += x;
                sy += y;
                sxx += x * x;
                sxy += x * y;
            }
            if (n >= 2 && n * sxx - sx * sx > 0) {
                h.edge_angle_mdeg =
                    negobs_atan2_mdeg(n * sxy - sx * sy, n * sxx - sx * sx);
            }
        }
        /* Confidence: agreement across strips (4 strips = full) times the
         * mean threshold margin (2x tau = full). Canny adds support. */
        {
            int64_t a = (int64_t)geom_min_s32(cnt, 4) * 8192;
            int64_t m = geom_clamp_s64((int64_t)(margin / cnt), 0, 512);
            h.conf_q15 = (int16_t)geom_clamp_s64((a * m) / 512, 0, 32767);
        }
        for (k = i; k < j; k++) {
            p->hits[k].reported = 1;
        }
        if (res->n_candidates < NEGOBS_DETECT_MAX_HAZARDS) {
            res->candidates[res->n_candidates++] = h;
        } else {
            /* Replace the farthest when this one is nearer. */
            uint32_t far = 0;
            uint32_t q;
            for (q = 1; q < res->n_candidates; q++) {
                if (res->candidates[q].range_mm >
                    res->candidates[far].range_mm) {
                    far = q;
                }
            }
            if (res->candidates[far].range_mm > h.range_mm) {
                res->candidates[far] = h;
            }
            res->candidates_dropped++;
        }
        i = j;
    }
}

/* 1 when at least a quarter of the corridor pixels within 4 rows of v_w
 * (the strips whose centre is in the corridor there) carry a matched
 * disparity: valid and, with a confidence map, not filled or
 * textureless. */
static int warn_rows_measured(const scan_ctx_t *s, const detect_priv_t *p,
                              int32_t v_w)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t h = cfg->cam.height;
    int32_t v0 = geom_max_s32(v_w - 4, 0);
    int32_t v1 = geom_min_s32(v_w + 4, h - 1);
    int32_t total = 0;
    int32_t good = 0;
    int32_t si;
    for (si = 0; si < p->n_strips; si++) {
        int32_t u0 = strip_u0(cfg, p->n_strips, si);
        int32_t v;
        if (!strip_in_corridor(s, p->n_strips, si, v_w)) {
            continue;
        }
        for (v = v0; v <= v1; v++) {
            const int16_t *row = negobs_image_s16_row(s->disp, v);
            const uint8_t *crow = (s->conf != NULL)
                                      ? negobs_image_u8_row(s->conf, v)
                                      : NULL;
            int32_t u;
            for (u = u0; u < u0 + cfg->strip_px; u++) {
                total++;
                if (row[u] != NEGOBS_DISP_INVALID &&
                    (crow == NULL ||
                     crow[u] >= NEGOBS_STEREO_CONF_MATCHED_MIN)) {
                    good++;
                }
            }
        }
    }
    return total == 0 || 4 * good >= total;
}

/*
 * Ground-drop cue. The rule above needs the edge in view with ground
 * before it; a drop first seen within ~1.6 m (after a corner) leaves the
 * bottom of the image before k of n frames
 * confirm it, and the ground fit then takes the lower surface as the
 * ground: the estimated camera height rises by the drop (+150 mm on a
 * 15 cm curb) and every later frame looked CLEAR until the user stepped
 * off. So the camera height over the ground under the feet is kept as a
 * reference, followed on clean frames only; a rise of ground_drop_mm or
 * more at a steady pitch makes a DROP candidate at the nearest visible
 * ground (the edge is nearer still), which the temporal logic confirms
 * and holds like any other. After ground_drop_max_ms of a continuous cue
 * the lower ground becomes the reference (the camera was raised, not
 * walked to an edge).
 *
 * The reference is the first clean frame's ground model that lies less
 * than ground_verify_mm above the configured height. A device switched on
 * within ~1.4 m of an edge has the lower surface in its fit rows and sees
 * a camera about the drop too high; so does one whose cam_height_mm is set
 * too low. The view cannot tell these apart, so such frames are NO_INFO
 * (*unverified), never CLEAR, until a frame agrees with the configured
 * height or ground_drop_max_ms have passed; then the view is taken as it
 * is. The start check is tighter than the cue (50 against 100 mm): a
 * 10 cm drop at switch-on reads 98-103 mm high, just under the cue's
 * threshold, and the configured height is the only reference there is.
 */
/* The view's camera height and pitch become the reference. */
static inline void ground_ref_take(detect_priv_t *p, const gfit_out_t *g)
{
    p->ref_ok = 1;
    p->ref_height_mm = g->pose.height_mm;
    p->ref_pitch_mdeg = g->pose.pitch_mdeg;
    p->drop_on = 0;
}

static int ground_unverified(detect_priv_t *p,
                             const negobs_detect_config_t *cfg,
                             const gfit_out_t *g, uint32_t now_ms)
{
    if (g->pose.height_mm - cfg->cam_height_mm < cfg->ground_verify_mm) {
        p->unverified_on = 0;
        return 0;
    }
    if (!p->unverified_on) {
        p->unverified_on = 1;
        p->unverified_since_ms = now_ms;
    }
    return (int32_t)(now_ms - p->unverified_since_ms) <=
           cfg->ground_drop_max_ms;
}

/* The rise that makes a ground-drop candidate: ground_drop_mm, or the
 * smaller ground_drop_corroborated_mm for hold_ms after a clean frame
 * whose rule found a drop within h_near_range_mm. A 10 cm drop first seen
 * at ~1.5 m is found by the rule on a frame or two, leaves the view
 * before k of n confirm it, and then raises the fitted height by only
 * 73-122 mm, across the plain threshold; the two cues together vouch for
 * the smaller rise, which alone would also fire on posture changes. */
static inline int32_t ground_drop_threshold(const detect_priv_t *p,
                                            const negobs_detect_config_t *cfg,
                                            uint32_t now_ms)
{
    int32_t t = cfg->ground_drop_mm;
    if (p->near_cand_on && cfg->ground_drop_corroborated_mm > 0 &&
        cfg->ground_drop_corroborated_mm < t &&
        (int32_t)(now_ms - p->near_cand_ms) <= cfg->hold_ms) {
        t = cfg->ground_drop_corroborated_mm;
    }
    return t;
}

/* Remember a clean frame whose rule (not the cue) found a drop, stairs
 * or hole within h_near_range_mm. */
static void near_candidate_note(detect_priv_t *p,
                                const negobs_detect_config_t *cfg,
                                const negobs_detect_result_t *res,
                                uint32_t now_ms)
{
    uint32_t i;
    for (i = 0; i < res->n_candidates; i++) {
        const negobs_hazard_t *c = &res->candidates[i];
        if (c->type != NEGOBS_HAZARD_UNKNOWN &&
            (c->flags & NEGOBS_HAZARD_F_GROUND_DROP) == 0u &&
            c->range_mm <= cfg->h_near_range_mm) {
            p->near_cand_on = 1;
            p->near_cand_ms = now_ms;
            return;
        }
    }
}

static int ground_drop(detect_priv_t *p, const negobs_detect_config_t *cfg,
                       const scan_ctx_t *s, const gfit_out_t *g,
                       uint32_t now_ms, negobs_hazard_t *hz,
                       int *unverified)
{
    int32_t dh;
    int32_t dp;
    int32_t vb = cfg->cam.height - 1;
    int32_t dg;
    int32_t range = 0;
    int32_t depth = 0;
    if (cfg->ground_drop_mm <= 0) {
        return 0;
    }
    if (!p->ref_ok) {
        /* the reference itself is taken on a clean frame
         * (ground_ref_follow) */
        *unverified = ground_unverified(p, cfg, g, now_ms);
        return 0;
    }
    dh = g->pose.height_mm - p->ref_height_mm;
    dp = negobs_abs_s32(g->pose.pitch_mdeg - p->ref_pitch_mdeg);
    if (dh < ground_drop_threshold(p, cfg, now_ms) ||
        dp > GROUND_DROP_PITCH_MDEG) {
        p->drop_on = 0;
        return 0;
    }
    if (!p->drop_on) {
        p->drop_on = 1;
        p->drop_since_ms = now_ms;
    } else if ((int32_t)(now_ms - p->drop_since_ms) >
               cfg->ground_drop_max_ms) {
        ground_ref_take(p, g);
        return 0;
    }
    dg = negobs_ground_disp_q4(&g->plane, cfg->cam.width / 2, vb);
    model_point(s, cfg->cam.width / 2, vb, dg, &range, NULL, &depth);
    memset(hz, 0, sizeof *hz);
    hz->type = NEGOBS_HAZARD_DROP;
    hz->level = NEGOBS_LEVEL_NONE;
    hz->flags = NEGOBS_HAZARD_F_GROUND_DROP;
    hz->range_mm = range;
    hz->depth_mm = depth;
    hz->drop_mm = dh;
    hz->u0 = 0;
    hz->u1 = (int16_t)(cfg->cam.width - 1);
    hz->v0 = (int16_t)geom_max_s32(vb - cfg->hold_bottom_rows, 0);
    hz->v1 = (int16_t)vb;
    hz->conf_q15 = 16384;
    return 1;
}

/* Set the reference of the ground-drop cue on the first clean frame that
 * ground_drop() did not find unverified, then follow it on clean frames
 * whose height is near it (slow changes: posture, bobbing); a jump either
 * way is a different surface in view, not the ground under the feet. Only
 * clean frames: the model of a NOISY frame can be far off (945 mm for a
 * 1.2 m camera in test_detect_start_near_drop_is_not_clear), and as the
 * reference it hid the drop. */
static void ground_ref_follow(detect_priv_t *p,
                              const negobs_detect_config_t *cfg,
                              const gfit_out_t *g, int unverified)
{
    int32_t dh = g->pose.height_mm - p->ref_height_mm;
    if (!p->ref_ok) {
        if (cfg->ground_drop_mm > 0 && !unverified) {
            ground_ref_take(p, g);
        }
        return;
    }
    if (p->drop_on ||
        2 * negobs_abs_s32(dh) >= cfg->ground_drop_mm) {
        return;
    }
    p->ref_height_mm += dh / 4;
    p->ref_pitch_mdeg += (g->pose.pitch_mdeg - p->ref_pitch_mdeg) / 4;
}

negobs_status_t negobs_detect_process(negobs_detect_t *ctx,
                                      const negobs_detect_frame_t *frame,
                                      negobs_detect_result_t *res)
{
    detect_priv_t *p;
    const negobs_detect_config_t *cfg;
    uint32_t reasons = 0;
    int32_t pending_noisy = 0; /* unconfirmed candidate, near bands noisy */
    int unverified = 0;        /* no reference yet, ground lower than set */
    int32_t pending_sparse = 0; /* unconfirmed candidate, warning rows empty */
    negobs_photo_stats_t ls;
    gfit_out_t g;
    uint32_t i;
    int32_t hold_range = 0;

    if (res == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (ctx == NULL || ctx->priv == NULL ||
        ((detect_priv_t *)ctx->priv)->magic != DETECT_MAGIC) {
        fill_no_info(res, NEGOBS_DEGRADED_BAD_INPUT);
        return NEGOBS_ERR_STATE;
    }
    p = (detect_priv_t *)ctx->priv;
    cfg = &ctx->cfg;
    if (frame == NULL || frame->disp_q4 == NULL ||
        negobs_image_s16_check(frame->disp_q4) != NEGOBS_OK ||
        frame->disp_q4->width != cfg->cam.width ||
        frame->disp_q4->height != cfg->cam.height ||
        (frame->confidence != NULL &&
         (negobs_image_u8_check(frame->confidence) != NEGOBS_OK ||
          frame->confidence->width != cfg->cam.width ||
          frame->confidence->height != cfg->cam.height)) ||
        (frame->left != NULL &&
         negobs_image_u8_check(frame->left) != NEGOBS_OK)) {
        fill_no_info(res, NEGOBS_DEGRADED_BAD_INPUT);
        if (frame != NULL) {
            /* Evidence cannot clear tracks, but held ones keep ageing. */
            temporal_update(&p->temporal, NULL, 0, 0, 0, frame->now_ms);
            res->n_hazards = temporal_report(&p->temporal, res->hazards,
                                             NEGOBS_DETECT_MAX_HAZARDS,
                                             frame->now_ms);
        }
        return NEGOBS_ERR_INVAL;
    }
    memset(res, 0, sizeof *res);
    res->nearest_range_mm = -1;

    /* Step 0: validity gating. */
    if (negobs_abs_s32((int32_t)(frame->t_left_ms - frame->t_right_ms)) >
        cfg->sync_tol_ms) {
        reasons |= NEGOBS_DEGRADED_UNSYNCED;
    }
    if ((int32_t)(frame->now_ms - frame->t_left_ms) > cfg->max_frame_age_ms ||
        (int32_t)(frame->now_ms - frame->t_left_ms) < -cfg->max_frame_age_ms) {
        reasons |= NEGOBS_DEGRADED_STALE;
    }
    memset(&ls, 0, sizeof ls);
    if (frame->left_stats != NULL) {
        ls = *frame->left_stats;
        reasons |= photo_reasons(cfg, &ls);
    } else if (frame->left != NULL) {
        (void)negobs_detect_photo_stats(frame->left, &ls);
        reasons |= photo_reasons(cfg, &ls);
    }
    if (frame->right_stats != NULL) {
        reasons |= photo_reasons(cfg, frame->right_stats);
    }
    res->stats = ls;

    /* Step 1: ground model. */
    gfit_process(&p->gfit, frame->disp_q4, frame->confidence, &g);
    reasons |= g.reasons;
    res->ground_valid_permille = g.valid_permille;
    res->ground_inliers = g.inliers;

    if (g.ok) {
        scan_ctx_t s;
        int32_t s_i;
        int32_t d_w;
        int32_t h;
        res->ground_valid = 1;
        res->plane = g.plane;
        res->pose = g.pose;
        res->sigma_q4 = g.sigma_q4;

        memset(&s, 0, sizeof s); /* every field defined before use */
        s.cfg = cfg;
        s.disp = frame->disp_q4;
        s.conf = frame->confidence;
        s.left = (frame->left != NULL &&
                  frame->left->width == cfg->cam.width &&
                  frame->left->height == cfg->cam.height)
                     ? frame->left
                     : NULL;
        s.plane = &p->gfit.plane;
        s.frame = &g.frame;
        s.sigma_q4 = g.sigma_q4;
        s.d_min_q4 = negobs_disp_q4_from_depth_mm(&cfg->cam, cfg->range_max_mm);

        /* Noise per band of rows over the scanned part of the image (from
         * the row where the ground reaches range_max down to the bottom). */
        {
            int32_t v_top = cfg->cam.height - 1;
            while (v_top > 0 &&
                   negobs_ground_disp_q4(&g.plane, cfg->cam.width / 2,
                                         v_top - 1) >= s.d_min_q4) {
                v_top--;
            }
            band_noise(&s, p->band_hist, v_top);
        }

        /* Step 2-3: per-strip scan, merge. */
        for (s_i = 0; s_i < p->n_strips; s_i++) {
            int32_t u0 = strip_u0(cfg, p->n_strips, s_i);
            scan_strip(&s, u0, u0 + cfg->strip_px, &p->hits[s_i]);
        }
        merge_strips(&s, p, res);
        {
            negobs_hazard_t hz;
            /* A hazard already confirmed or held nearer than the view's
             * bottom is this drop: the cue's range (an upper bound) would
             * only pull its dead-reckoned range back. */
            if (ground_drop(p, cfg, &s, &g, frame->now_ms, &hz,
                            &unverified) &&
                !temporal_covers(&p->temporal, hz.range_mm, frame->now_ms) &&
                res->n_candidates < NEGOBS_DETECT_MAX_HAZARDS) {
                res->candidates[res->n_candidates++] = hz;
            }
        }
        /* Step 6 (self-check): can h_min_far still be seen at the warning
         * range? The rule tests the median residual of a strip row, so the
         * drop's deficit d_w * h / (H + h) must exceed k times the
         * *measured* spread of that median (strip_noise), not a value
         * derived from per-pixel noise under an independence assumption,
         * plus the ground model's offset there when it is positive (the
         * ground reads above the model, which shrinks every deficit). The
         * per-pixel sigma is still capped by sigma_max. Measured after the
         * scan, so that rows beyond a drop found this frame are compared
         * with its plateau. */
        strip_noise(&s, p, p->strip_hist);
        d_w = negobs_disp_q4_from_depth_mm(&cfg->cam, cfg->range_warn_mm);
        h = cfg->h_min_far_mm;
        {
            int32_t v_w = cfg->cam.height - 1;
            int32_t sw;
            int32_t sm;
            int32_t bias;
            int32_t blocked_path = 0;
            while (v_w > 0 && negobs_ground_disp_q4(&g.plane,
                                                    cfg->cam.width / 2,
                                                    v_w) > d_w) {
                v_w--;
            }
            /* The matcher may have been told to skip the rows above
             * first_row (the pipeline's crop to the rows the scan reads,
             * placed from the previous frame's ground). If the warning
             * range lies up there now (the camera pitched down faster
             * than the crop's margin), this frame did not look that far:
             * it must not say CLEAR, nor count as a clean frame that
             * clears tracks. The crop's first rows carry no value either
             * (the matcher's window does not fit). */
            if (frame->first_row > 0 && v_w < frame->first_row + 2) {
                reasons |= NEGOBS_DEGRADED_FEW_GROUND;
            }
            sw = sigma_at(&s, v_w);
            sm = strip_sigma_at(&s, v_w, &bias);
            res->sigma_warn_q4 = sw;
            res->sigma_strip_warn_q8 = sm;
            res->offset_strip_warn_q8 = bias;
            /* A wall or up-step across most of the corridor nearer than
             * the warning range: the walk ends there, so the range that
             * must be vouched for ends there too (the near bands below
             * are still tested). Without this, 55 of 96 frames before a
             * wall or up-step within 4 m were NO_INFO on the synthetic
             * suite. */
            {
                int32_t closed = 0;
                int32_t seen = 0;
                for (i = 0; i < (uint32_t)p->n_strips; i++) {
                    /* s.plane is the model gfit_process returned as
                     * g.plane */
                    if (!strip_in_corridor(&s, p->n_strips, (int32_t)i,
                                           v_w)) {
                        continue;
                    }
                    seen++;
                    closed += p->hits[i].blocked_v > v_w;
                }
                blocked_path = seen > 0 && 4 * closed >= 3 * seen;
            }
            /* Was the warning range measured at all? The noise test below
             * reads a band of rows and falls back to the independent-
             * pixel formula where the band has too few strip rows, so a
             * frame whose matcher gave (almost) nothing around the
             * warning row (textureless or dark far ground) could pass it
             * and say CLEAR without having looked there. Fewer than a
             * quarter of the corridor pixels within +-4 rows of the
             * warning row with a matched value: FEW_GROUND. With a
             * candidate in the frame (a drop's shadow can cover those
             * rows) it only keeps the frame from saying CLEAR, as the
             * near-band check does. */
            if (!blocked_path &&
                !warn_rows_measured(&s, p, v_w)) {
                if (res->n_candidates == 0u) {
                    reasons |= NEGOBS_DEGRADED_FEW_GROUND;
                } else {
                    pending_sparse = 1;
                }
            }
            /* k_q4/16 * sm/256 + max(bias, 0)/256 > d_w/16 * h/(H + h). */
            if (sw > cfg->sigma_max_q4 ||
                (!blocked_path &&
                 ((int64_t)cfg->k_sigma_q4 * sm +
                  16 * (int64_t)geom_max_s32(bias, 0)) *
                         (g.frame.height_mm + h) >
                     (int64_t)d_w * h * 256)) {
                reasons |= NEGOBS_DEGRADED_NOISY;
            }
            /* The same test for every measured band nearer than the
             * warning range, each with its own h_min (h_min_near inside
             * h_near_range): seeing 100 mm at range_warn says nothing
             * about the rows under the feet. On SurDis with a 1.5 m
             * warning range the rows near the user spread more than
             * those at 1.5 m, and 5 frames were CLEAR with the steps in
             * view. It guards the absence of evidence only: a frame with
             * a candidate is not made NOISY by it, because a drop's own
             * lower surface fills the near bands once the edge is within
             * 1-3 m (applied to every frame it cut the synthetic
             * detection rate at 1.5-3 m from 98.6 % to 90 %), and such a
             * frame is not CLEAR anyway. */
            {
                int32_t near_noisy = 0;
                int32_t b;
                for (b = 0; b < NOISE_BANDS; b++) {
                    int32_t vb = s.band_v0 + b * s.band_rows +
                                 s.band_rows / 2;
                    int32_t dgb;
                    int32_t rb = 0;
                    int32_t hb;
                    if (vb <= v_w || vb > cfg->cam.height - 1 ||
                        s.band_strip_q8[b] <= 0) {
                        continue;
                    }
                    dgb = negobs_ground_disp_q4(&g.plane, cfg->cam.width / 2,
                                                vb);
                    model_point(&s, cfg->cam.width / 2, vb, dgb, &rb, NULL,
                                NULL);
                    hb = h_min_at(cfg, rb);
                    if (((int64_t)cfg->k_sigma_q4 * s.band_strip_q8[b] +
                         16 * (int64_t)geom_max_s32(s.band_bias_q8[b], 0)) *
                            (g.frame.height_mm + hb) >
                        (int64_t)dgb * hb * 256) {
                        near_noisy = 1;
                    }
                }
                if (near_noisy && res->n_candidates == 0u) {
                    reasons |= NEGOBS_DEGRADED_NOISY;
                } else if (near_noisy) {
                    /* A candidate that is not confirmed yet: the frame
                     * still feeds the tracker as a clean one (else a drop
                     * filling the near bands could never confirm), but
                     * unless a hazard is confirmed the user is not told
                     * CLEAR (below). On SurDis with a 1.5 m warning range
                     * frame 89 was CLEAR with a HOLE candidate on the
                     * steps. */
                    pending_noisy = 1;
                }
            }
        }
        if (res->n_candidates > 0) {
            int32_t vtop = cfg->cam.height;
            int32_t gmax;
            for (i = 0; i < res->n_candidates; i++) {
                vtop = geom_min_s32(vtop, res->candidates[i].v0);
            }
            gmax = dcanny_band_max(frame->disp_q4, vtop);
            for (i = 0; i < res->n_candidates; i++) {
                negobs_hazard_t *hz = &res->candidates[i];
                int32_t need = (hz->u1 - hz->u0 + 1) / 4;
                if (dcanny_support(frame->disp_q4, gmax,
                                   cfg->canny_thresh_permille,
                                   cfg->canny_low_permille, hz->u0, hz->u1,
                                   hz->v1, &p->canny) >= need) {
                    hz->flags |= NEGOBS_HAZARD_F_CANNY;
                    hz->conf_q15 = (int16_t)geom_min_s32(
                        32767, hz->conf_q15 + 4096);
                }
            }
        }

        /* Hold zone: an edge lost within the bottom rows, or so near that
         * the support requirement can no longer be met below it. */
        {
            int32_t vb = geom_max_s32(cfg->cam.height - 1 -
                                          cfg->hold_bottom_rows,
                                      0);
            int32_t dgb = negobs_ground_disp_q4(&g.plane, cfg->cam.width / 2,
                                                vb);
            int32_t rb = 0;
            int32_t rn = 0;
            model_point(&s, cfg->cam.width / 2, vb, dgb, &rb, NULL, NULL);
            model_point(&s, cfg->cam.width / 2, cfg->cam.height - 1,
                        negobs_ground_disp_q4(&g.plane, cfg->cam.width / 2,
                                              cfg->cam.height - 1),
                        &rn, NULL, NULL);
            hold_range = geom_max_s32(rb, rn + cfg->min_support_mm +
                                              cfg->assoc_range_mm);
        }
    } else {
        /* No ground model: use the nominal geometry for the hold zone. */
        hold_range = cfg->range_imminent_mm + cfg->assoc_range_mm;
    }

    /* Steps 4-5: temporal confirmation, clearing and hold. */
    temporal_update(&p->temporal, res->candidates, res->n_candidates,
                    reasons == 0u, hold_range, frame->now_ms);
    res->n_hazards = temporal_report(&p->temporal, res->hazards,
                                     NEGOBS_DETECT_MAX_HAZARDS,
                                     frame->now_ms);
    for (i = 0; i < res->n_hazards; i++) {
        if (res->hazards[i].level > res->level ||
            (res->hazards[i].level == res->level &&
             res->level != NEGOBS_LEVEL_NONE &&
             res->hazards[i].range_mm < res->nearest_range_mm)) {
            res->level = res->hazards[i].level;
            res->nearest_range_mm = res->hazards[i].range_mm;
        }
    }
    if (pending_sparse && res->n_hazards == 0u) {
        reasons |= NEGOBS_DEGRADED_FEW_GROUND;
    }
    if (pending_noisy && res->n_hazards == 0u) {
        reasons |= NEGOBS_DEGRADED_NOISY;
    }
    /* like the pending reasons: the frame still feeds the tracker, a
     * hazard found by the rule is reported, but "clear" is not said */
    if (unverified && res->n_hazards == 0u) {
        reasons |= NEGOBS_DEGRADED_GROUND_UNVERIFIED;
    }
    res->reasons = reasons;
    if (g.ok && reasons == 0u) {
        ground_ref_follow(p, cfg, &g, unverified);
        near_candidate_note(p, cfg, res, frame->now_ms);
    }
    if (reasons != 0u) {
        res->state = NEGOBS_DETECT_NO_INFO;
    } else if (res->n_hazards > 0u) {
        res->state = NEGOBS_DETECT_HAZARD;
    } else {
        res->state = NEGOBS_DETECT_CLEAR;
    }
    return NEGOBS_OK;
}
