/*
 * Ground model estimation (internal): v-disparity histogram, constrained
 * Hough line search, IRLS refinement to a disparity-space plane, tracking
 * and online noise estimate.
 */
#ifndef NEGOBS_DETECT_GROUND_FIT_H
#define NEGOBS_DETECT_GROUND_FIT_H

#include <stdint.h>

#include "arena.h"
#include "negobs/image.h"
#include "negobs/detect.h"
#include "negobs/ground.h"

#define GFIT_N_SLOPES 32
#define GFIT_N_K 128
#define GFIT_ABS_BINS 64
/* Column strips of the fit rows whose support is judged one by one
 * (ground_fit.c, "Support"). */
#define GFIT_COLS 16

typedef struct gfit {
    const negobs_detect_config_t *cfg;
    uint16_t *vhist;  /* rows x nbins v-disparity histogram           */
    uint32_t *acc;    /* GFIT_N_SLOPES x GFIT_N_K Hough accumulator   */
    uint32_t *absres; /* GFIT_ABS_BINS |residual| histogram (q4)      */
    int32_t v_lo;     /* first fit row of the band being fitted       */
    int32_t rows;     /* fit rows (v_lo .. height-1)                  */
    /* Nearest fit row read: height-1, or a row above the floor that lies
     * beyond the matcher's disparity range (gfit_process, "Beyond the
     * matcher's range"). */
    int32_t v_hi;
    int32_t d_top_q4;  /* the largest disparity measured: max_disp - 1 px */
    int32_t band_v_lo; /* the bottom band: fit_rows_pct              */
    int32_t band_step;
    int32_t wide_v_lo; /* the wide band: up to the lowest horizon    */
    int32_t wide_step;
    int32_t wide;      /* 1 while the wide band is fitted            */
    int32_t v_bot;     /* nearest sampled row with support (-1: none) */
    int32_t near_rows; /* rows v_lo .. v_bot: the fractions' base    */
    int32_t nbins;     /* disparity bins                               */
    int32_t bin_q4;    /* bin width (q4)                               */
    int32_t step;      /* sampling step of the band being fitted (px)  */
    int32_t s_q12[GFIT_N_SLOPES]; /* candidate slopes, px/row Q12    */
    int64_t k_lo_q12[GFIT_N_SLOPES];
    int64_t k_bin_q12[GFIT_N_SLOPES];
    int32_t n_slopes;
    /* Support: column strips of width col_w; col_ok[i] when strip i's own
     * valid share reaches ground_min_valid_pct this frame; support_cols:
     * the sampled columns per row inside those strips. */
    int32_t col_w;
    uint8_t col_ok[GFIT_COLS];
    int32_t support_cols;
    /* Track. */
    int32_t tracked;
    int32_t jumps;
    int32_t fails;
    negobs_ground_plane_t plane;
    int32_t sigma_q4;
} gfit_t;

typedef struct gfit_out {
    int32_t ok;       /* plane usable for detection this frame    */
    uint32_t reasons; /* NEGOBS_DEGRADED_FEW_GROUND / _REJECTED   */
    negobs_ground_plane_t plane;
    negobs_ground_pose_t pose;
    negobs_ground_frame_t frame;
    int32_t sigma_q4;
    int32_t valid_permille;   /* valid share of the fit rows in view   */
    int32_t support_permille; /* share of them in the support strips */
    int32_t wide;             /* 1: fitted on the wide band           */
    int32_t inliers;
    /* Nearest row of floor the matcher can measure: height-1, or the row
     * above where the plane's disparity passes d_top_q4. */
    int32_t v_near;
} gfit_out_t;

/* A sample with a disparity the fit may read: valid and, with a
 * confidence map, at least min_conf confident. */
static inline int gfit_sample_valid(const negobs_image_u8_t *conf,
                                    int32_t min_conf, int32_t u, int32_t v,
                                    int32_t d)
{
    if (d == NEGOBS_DISP_INVALID || d < 0) {
        return 0;
    }
    return conf == NULL ||
           (int32_t)negobs_image_u8_row(conf, v)[u] >= min_conf;
}

/* A sample the fit may use: valid, and in a column strip of the support
 * (gfit_support). */
static inline int gfit_sample_ok(const gfit_t *g,
                                 const negobs_image_u8_t *conf, int32_t u,
                                 int32_t v, int32_t d)
{
    return g->col_ok[u / g->col_w] &&
           gfit_sample_valid(conf, g->cfg->ground_min_confidence, u, v, d);
}

/* The fit rows' samples per column strip (ground_support.c). */
typedef struct gfit_support {
    uint32_t col_n[GFIT_COLS];     /* samples in view                  */
    uint32_t col_valid[GFIT_COLS]; /* of them valid                    */
    uint32_t samples;              /* all in view                      */
    uint32_t valid;                /* all valid                        */
    uint32_t support;              /* in view, in the support strips   */
    uint32_t support_valid;        /* valid, in the support strips     */
} gfit_support_t;

/* The support of the current band (g->v_lo, g->step): per column strip the
 * samples in view and valid; col_ok, support_cols; the v-disparity
 * histogram of the support's samples; v_bot and near_rows. view_u0 /
 * view_u1 as in gfit_process. */
void gfit_support(gfit_t *g, const negobs_image_s16_t *disp,
                  const negobs_image_u8_t *conf, const int16_t *view_u0,
                  const int16_t *view_u1, gfit_support_t *sup);

/* After the seed step: strips whose near samples mostly lie outside the
 * seed's gate of plane leave the support (col_ok, support_cols). Returns
 * the samples in view of the strips kept; *valid_out their valid ones. */
uint32_t gfit_line_support(gfit_t *g, const negobs_image_s16_t *disp,
                           const negobs_image_u8_t *conf,
                           const negobs_ground_plane_t *plane,
                           const gfit_support_t *sup, uint32_t *valid_out);

/* The largest ground disparity the matcher measures: a floor point
 * nearer than 1 px below its last disparity (max_disp_q4 is one past it)
 * has no disparity above it to make a sub-pixel peak. */
static inline int32_t gfit_range_top_q4(const negobs_detect_config_t *cfg)
{
    return cfg->max_disp_q4 - 2 * NEGOBS_DISP_ONE;
}

/* The nearest row at or above v whose floor on plane pl, at column u,
 * lies within the matcher's range (ground disparity below d_top_q4);
 * -1 when none down to row 0. */
static inline int32_t gfit_row_in_range(const negobs_ground_plane_t *pl,
                                        int32_t u, int32_t v, int32_t d_top_q4)
{
    while (v >= 0 && negobs_ground_disp_q4(pl, u, v) >= d_top_q4) {
        v--;
    }
    return v;
}

/* The matcher's range (ground_range.c). The fit row just above the
 * topmost row of the band (g->v_lo ..) where a quarter of the usable
 * samples, 4 at least, lie at the range's top; height-1 when none. */
int32_t gfit_range_rows_hi(const gfit_t *g, const negobs_image_s16_t *disp,
                           const negobs_image_u8_t *conf);
/* The nearest fit row at or above hi whose floor on plane pl lies within
 * the range at both image borders. */
int32_t gfit_plane_rows_hi(const gfit_t *g, const negobs_ground_plane_t *pl,
                           int32_t hi);
/* Read rows up to hi; the bottom band moves up by the rows cut. */
void gfit_range_cut(gfit_t *g, int32_t hi);
/* The nearest row (<= g->v_hi) whose floor on pl the matcher measures at
 * the centre column. */
int32_t gfit_near_row(const gfit_t *g, const negobs_ground_plane_t *pl);

/* Carve buffers (measure mode when the arena has no base) and precompute
 * the Hough grid. cfg must be valid and outlive g. */
negobs_status_t gfit_carve(gfit_t *g, negobs_arena_t *ar,
                           const negobs_detect_config_t *cfg);

/* Forget the track. */
void gfit_reset(gfit_t *g);

/* Fit the ground for one disparity map (valid size checked by caller).
 * view_u0 / view_u1 (per row, may be NULL: all in view): the columns in
 * the left image's field of view; samples outside it are not counted in
 * the valid share (out of view, not unmatched floor). */
void gfit_process(gfit_t *g, const negobs_image_s16_t *disp,
                  const negobs_image_u8_t *conf, const int16_t *view_u0,
                  const int16_t *view_u1, gfit_out_t *out);

/* One-shot fit without tracking, for tests: same as gfit_process on a
 * fresh track. */

#endif
