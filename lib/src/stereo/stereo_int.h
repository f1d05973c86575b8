/*
 * Disparity engine internals (not installed): the stage functions the
 * driver (stereo.c) calls, plus the headers per concern:
 *   stereo_state.h  private state stx_t, shared constants, memo layout
 *   stereo_queue.h  bounded bucket queue of the growth
 *   stereo_ncc.h    window statistics and the MNCC kernels (C + SIMD)
 *
 * One private state block is carved from the caller's workspace by
 * carve() (stereo.c), which runs twice: once in measuring
 * mode for negobs_stereo_workspace_size() and once for real in init, so the
 * size query cannot drift from what init consumes.
 */
#ifndef NEGOBS_STEREO_INT_H
#define NEGOBS_STEREO_INT_H

#include <stddef.h>
#include <stdint.h>

#include "stereo/stereo_ncc.h"
#include "stereo/stereo_queue.h"
#include "stereo/stereo_state.h"

/* Attribute the clock ticks since the last lap to `stage`. */
static inline void stx_lap(stx_t *s, negobs_stereo_stage_t stage)
{
    if (s->clock != NULL) {
        uint32_t now = s->clock(s->clock_user);
        s->st.stage_ticks[stage] += (uint32_t)(now - s->lap);
        s->lap = now;
    }
}

/* ---- bands.c ---------------------------------------------------------- */
/* Init: give every extra worker the context's geometry, empty its memo. */
void stx_bands_init(stx_t *s);
/* The frame's band dispatch order, costliest band first (output-neutral:
 * it only decides which band a job index names). Before the first job. */
void stx_bands_order(stx_t *s);
/* Stages 2-4 up to the end of the second DP stage, band by band (on the
 * executor when one is set): disp_q4 gets the GCS disparities (px). */
void stx_bands_pass0(stx_t *s, negobs_image_s16_t *disp_q4);
/* Back-track, sub-pixel and confidence of every row, band by band. */
void stx_bands_pass1(stx_t *s, negobs_image_s16_t *disp_q4,
                     negobs_image_u8_t *confidence);
/* Stages 6 and 1 (vertical offset, 1/4-scale map and ranges) as band
 * jobs when an executor with several workers is set, else in place. */
void stx_bands_vertical_range(stx_t *s);
/* A line filter of refine.c over the frame, band by band (rows) or in as
 * many column slices (the mean's vertical pass). */
typedef enum stx_line_filter {
    STX_FILTER_LR,
    STX_FILTER_GAP_FILL,
    STX_FILTER_MEAN,      /* rows, then columns                       */
    STX_FILTER_MEAN_ROWS, /* (the two passes of the mean, bands.c)    */
    STX_FILTER_MEAN_COLS,
    STX_FILTER_SPECKLE,      /* mark by bands, then clear by bands       */
    STX_FILTER_SPECKLE_MARK, /* (the two passes of the speckle filter)   */
    STX_FILTER_SPECKLE_CLEAR
} stx_line_filter_t;
void stx_bands_filter(stx_t *s, stx_line_filter_t f,
                      negobs_image_s16_t *disp_q4, uint8_t *conf,
                      int32_t conf_stride);

/* ---- canny.c ---------------------------------------------------------- */
/* Edge map of strip rows [y0, y1) into s->edge (1 = edge). Returns count. */
uint32_t stx_canny_strip(stx_t *s, int32_t y0, int32_t y1);

/* ---- lowres.c --------------------------------------------------------- */
/* Elementary 1/4-scale disparity and search ranges (global + per tile). */
void stx_lowres_range(stx_t *s);
/* Estimate the vertical offset in [-n, n]; returns the chosen offset. */
int32_t stx_vertical_estimate(stx_t *s, int32_t n);
/* The same in steps, for band jobs (bands.c): begin (configured range;
 * 1 when the map is to be made), the 4x4 means of low-res rows
 * [y4a, y4b), their matches (kept count returned, histogram of
 * stx_lowres_levels() + 1 bins written), then the ranges from the summed
 * histogram in s->hist. */
int stx_lowres_begin(stx_t *s);
int32_t stx_lowres_levels(const stx_t *s);
void stx_lowres_downsample_rows(stx_t *s, int32_t y4a, int32_t y4b);
uint32_t stx_lowres_match_rows(stx_t *s, int32_t y4a, int32_t y4b,
                               uint32_t *hist);
void stx_lowres_finish(stx_t *s, uint32_t kept);
/* The vertical search in steps: its grid rows, the score sums of every
 * offset (2n + 1, order 0, -1, +1, ...) over grid rows [g0, g1), and the
 * pick from the summed scores (integer sums: any split gives the same). */
int32_t stx_vertical_grid_rows(const stx_t *s);
void stx_vertical_scores(stx_t *s, int32_t n, int32_t g0, int32_t g1,
                         int64_t *score);
int32_t stx_vertical_pick(const int64_t *score, int32_t n);
/* Tile range for pixel (x, y). */
void stx_tile_range(const stx_t *s, int32_t x, int32_t y, int32_t *lo,
                    int32_t *hi);

/* ---- gcs.c ------------------------------------------------------------ */
/* Seeds + growth + stable selection for the current strip; writes integer
 * disparities (or NEGOBS_DISP_INVALID) into rows [y0, y1) of out. */
void stx_gcs_strip(stx_t *s, negobs_image_s16_t *out);
/* Fast profile: empty the memo (init) so stamps start afresh. */
void stx_memo_clear(stx_t *s);

/* ---- dp.c ------------------------------------------------------------- */
/* Stage 1 of one row (needs the strip statistics of row y). With
 * pass == 0 the end column feeds stage 2 (and the pointers go to the store
 * when they fit); with pass == 1 the row is back-tracked from s->dend[y]
 * (stage 1 runs again unless its pointers were stored) and written
 * (integer px) to out, costs kept in s->cost for sub-pixel refinement.
 * `gcsrow` holds the GCS result; rows of a band come in the same order in
 * both passes. */
void stx_dp_row(stx_t *s, int32_t y, const int16_t *gcsrow, int pass,
                int16_t *outrow, uint8_t *confrow);

/* ---- subpix.c --------------------------------------------------------- */
/* Sub-pixel offset (Q4) of the integer disparity d at (x, y) whose scores
 * at d - 1, d, d + 1 are cm, c0, cp (Q14, none STX_FLAT): the mean of the
 * parabola's vertex and the vertex on the right image shifted by half a
 * pixel (subpixel_halfshift). Returns off_q4 (the parabola's rounded
 * offset) where either is no peak or a window leaves an image. */
int32_t stx_subpix_halfshift_q4(const stx_t *s, int32_t x, int32_t y,
                                int32_t d, int32_t cm, int32_t c0, int32_t cp,
                                int32_t off_q4);

/* ---- dp_store.c ------------------------------------------------------- */
/* The pointer store: rows [y0, y1) take records from their part of it,
 * at most `limit` bytes (pass 0: all of it; pass 1: what pass 0 used,
 * stx_dp_store_used() after its rows). After pass 1, release gives the
 * part's used bytes back to their owner. */
void stx_dp_store_begin(stx_t *s, int32_t y0, int32_t y1, size_t limit);
size_t stx_dp_store_used(const stx_t *s);
void stx_dp_store_release(stx_t *s, int32_t y0, int32_t y1, size_t used);
/* (the records' layout and the taking of one: stereo/dp_store.h) */

/* ---- dp_stage2.c ------------------------------------------------------ */
/* Stage-1 scores at or below this are outside the band ("-inf"); real
 * ones stay above it (dp.c: |Y| < 2^28). */
#define STX_DP_NEG32 (INT32_MIN / 2)
void stx_dp_stage2_reset(stx_t *s);
/* Row y's stage-1 end scores ye (ndisp; unread unless `have`) into the
 * second stage; rows must come in order 0, 1, ... */
void stx_dp_stage2_feed(stx_t *s, int32_t y, int have, const int32_t *ye);
/* With several band workers (s->yend): feed the stored rows 0 .. h-1. */
void stx_dp_stage2_feed_stored(stx_t *s);
void stx_dp_stage2_finish(stx_t *s);

/* ---- refine.c --------------------------------------------------------- */
void stx_lr_check(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                  int32_t conf_stride);
void stx_speckle(stx_t *s, negobs_image_s16_t *disp);
/* Filled pixels get NEGOBS_STEREO_CONF_FILLED (negobs/stereo.h). */
void stx_gap_fill(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                  int32_t conf_stride);
void stx_adaptive_mean(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                       int32_t conf_stride);
/* The same on rows [y0, y1) (LR check, gap fill, the mean's horizontal
 * pass) or columns [x0, x1) (the mean's vertical pass): each line reads
 * and writes only itself, so ranges can run at once (bands.c). */
void stx_lr_check_rows(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                       int32_t conf_stride, int32_t y0, int32_t y1);
void stx_gap_fill_rows(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                       int32_t conf_stride, int32_t y0, int32_t y1);
void stx_amean_rows(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                    int32_t conf_stride, int32_t y0, int32_t y1);
void stx_amean_cols(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                    int32_t conf_stride, int32_t x0, int32_t x1);
/* The speckle filter by bands: mark rows [y0, y1) (floods may read other
 * rows, write only their own bitmap bits), then, once every band is
 * marked, clear the band's pixels of small regions. */
void stx_speckle_mark_rows(stx_t *s, const negobs_image_s16_t *disp,
                           int32_t y0, int32_t y1);
void stx_speckle_clear_rows(stx_t *s, negobs_image_s16_t *disp, int32_t y0,
                            int32_t y1);
/* keep_out_of_view == 0: drop values whose match lies left of the right
 * image (x - d < 0); the final pass then clears their confidence. */
void stx_out_of_view(stx_t *s, negobs_image_s16_t *disp);

#endif /* NEGOBS_STEREO_INT_H */
