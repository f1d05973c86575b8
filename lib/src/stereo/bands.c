/*
 * Row bands: the frame's stages (all but the seam rule's check, the second
 * DP stage and the output count) as independent jobs for the caller's
 * executor (negobs/executor.h). The library creates no thread.
 *
 * A band is a run of whole strips; its layout depends on cfg.bands and the
 * frame's rows only (negobs_stereo_band_rows), never on the executor, and
 * the growth crosses a band border only by the seam rule (gcs.c:
 * seed_carry; seam_pass below). Each band is therefore the same
 * computation whichever worker runs it, in whatever order: the output is
 * bit-identical for every thread count. With several workers job 0 of a
 * run is the band expected to cost most (stx_bands_order), so an executor
 * that starts jobs in index order balances best. An executor that skips a
 * job or names a worker or job it does not have fails the frame
 * (NEGOBS_ERR_STATE).
 *
 * Each worker owns one scratch area (the strip buffers, the queue, the
 * score cache or the memo, a DP row and the speckle flood lists): worker 0
 * is the context itself, the others are copies of the context (s->wk)
 * with their own scratch and statistics, merged after each parallel
 * pass.
 *
 * Per frame: (0) the vertical offset search and the 1/4-scale map, each
 * band taking its share of the sampling grid's rows or of the low-res
 * rows, their integer partial sums added in band order on the caller's
 * thread (stx_bands_vertical_range); (a) every band grows on its own
 * (window sums, Canny, GCS);
 * (b) the seam rule (seam_pass) grows a band again, on the caller's
 * thread, with the matches above its border as seeds where it lacks them;
 * (c) DP stage 1 of every row, band by band, keeping each row's end scores
 * in s->yend when several workers exist, and its pointers where the
 * store lent to the DP has room (dp.c; each band in its own part of it,
 * in proportion to its rows); (d) the second DP stage takes the rows in
 * order on the caller's thread (h x ndisp steps, about 1 % of the frame);
 * (e) the back-track with sub-pixel refinement, band by band, after which
 * the store is given back;
 * (f) the LR check, the gap fill and the mean's rows by bands, the mean's
 * columns by as many column slices (each line is independent); the
 * speckle filter in two runs, marks then clears (refine.c:
 * speckle_flood_band says why that is the sequential result).
 */
#include <string.h>

#include "negobs/stereo.h"
#include "stereo/stereo_int.h"

int32_t negobs_stereo_band_count(const negobs_stereo_config_t *cfg,
                                 int32_t rows)
{
    int32_t strips;
    if (cfg == NULL || rows < 1 || cfg->strip_rows < 1 || cfg->bands < 1) {
        return 0;
    }
    strips = (rows + cfg->strip_rows - 1) / cfg->strip_rows;
    return (cfg->bands < strips) ? cfg->bands : strips;
}

negobs_status_t negobs_stereo_band_rows(const negobs_stereo_config_t *cfg,
                                        int32_t rows, int32_t band,
                                        int32_t *y0, int32_t *y1)
{
    int32_t nb = negobs_stereo_band_count(cfg, rows);
    int32_t strips;
    int32_t a;
    int32_t b;
    if (nb < 1 || band < 0 || band >= nb || y0 == NULL || y1 == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    strips = (rows + cfg->strip_rows - 1) / cfg->strip_rows;
    /* strips spread as evenly as integers allow; the first bands get the
     * shorter share (strips * band / nb, rounded down) */
    a = (int32_t)((int64_t)strips * band / nb);
    b = (int32_t)((int64_t)strips * (band + 1) / nb);
    *y0 = a * cfg->strip_rows;
    *y1 = (b * cfg->strip_rows < rows) ? b * cfg->strip_rows : rows;
    return NEGOBS_OK;
}

/* Worker `k` (>= 1) takes the context's frame state and keeps its own
 * scratch (the fields carve_scratch() in stereo.c carves), with zero
 * statistics. */
static void worker_sync(const stx_t *s, stx_t *x)
{
    stx_t own = *x;
    *x = *s;
    x->wk = NULL;
    x->sl = own.sl;
    x->sr = own.sr;
    x->vl = own.vl;
    x->vr = own.vr;
    x->mag = own.mag;
    x->edge = own.edge;
    x->ld = own.ld;
    x->lc = own.lc;
    x->lc2 = own.lc2;
    x->rd = own.rd;
    x->rc = own.rc;
    x->rc2 = own.rc2;
    x->tbits = own.tbits;
    x->q = own.q;
    x->cache = own.cache;
    x->memo = own.memo;
    x->memo_base = own.memo_base;
    x->memo_k = own.memo_k;
    x->memo_gen = own.memo_gen;
    x->yprev = own.yprev;
    x->ycur = own.ycur;
    x->p1 = own.p1;
    x->cost = own.cost;
    x->jump_to = own.jump_to;
    x->blo = own.blo;
    x->bhi = own.bhi;
    x->bscored = own.bscored;
    x->rowd = own.rowd;
    x->line = own.line;
    x->line2 = own.line2;
    x->flood = own.flood;
    x->flood_out = own.flood_out;
    memset(&x->st, 0, sizeof x->st);
}

/* What a worker counted during a pass, into the context's statistics. */
static void stats_merge(negobs_stereo_stats_t *to,
                        const negobs_stereo_stats_t *from)
{
    int i;
    to->seeds += from->seeds;
    if (from->queue_peak > to->queue_peak) {
        to->queue_peak = from->queue_peak;
    }
    to->queue_overflows += from->queue_overflows;
    to->visited_cells += from->visited_cells;
    to->edges += from->edges;
    to->grown += from->grown;
    to->gcs_matched += from->gcs_matched;
    to->lr_rejected += from->lr_rejected;
    to->gap_filled += from->gap_filled;
    to->speckles_removed += from->speckles_removed;
    for (i = 0; i < NEGOBS_STEREO_STAGE_COUNT; i++) {
        to->stage_ticks[i] += from->stage_ticks[i];
    }
}

void stx_bands_init(stx_t *s)
{
    int32_t k;
    for (k = 0; k < s->cfg.band_workers - 1; k++) {
        worker_sync(s, &s->wk[k]);
        stx_memo_clear(&s->wk[k]);
    }
}

typedef struct band_job {
    stx_t *s;
    negobs_image_s16_t *disp;
    negobs_image_u8_t *conf;
    /* line filters (stx_bands_filter) */
    stx_line_filter_t filter;
    uint8_t *conf_data;
    int32_t conf_stride;
    int32_t step; /* stage 1: 0 the 4x4 means, 1 the matches */
} band_job_t;

/* The state of `worker`, or NULL for an index the executor must not
 * use (the job is then not done, and run_bands() notices). */
static stx_t *worker_state(stx_t *s, int32_t worker)
{
    if (worker == 0) {
        return s;
    }
    if (worker < 0 || s->exec.run == NULL || worker >= s->exec.workers) {
        return NULL;
    }
    return &s->wk[worker - 1];
}

/* GCS of band rows [yb0, yb1): window sums, Canny, seeds and growth,
 * strip by strip. With `carry` the first strip also takes the matches of
 * row yb0 - 1 as seeds, as every later strip does from the strip above. */
static void grow_band(stx_t *x, negobs_image_s16_t *disp, int32_t yb0,
                      int32_t yb1, int carry)
{
    int32_t y0;
    x->band_y0 = carry ? -1 : yb0;
    for (y0 = yb0; y0 < yb1; y0 += x->sh) {
        int32_t y1 = (y0 + x->sh < yb1) ? y0 + x->sh : yb1;
        stx_strip_stats(x, y0, y1);
        stx_lap(x, NEGOBS_STEREO_STAGE_WINDOWS);
        x->st.edges += stx_canny_strip(x, y0, y1);
        stx_lap(x, NEGOBS_STEREO_STAGE_CANNY);
        stx_gcs_strip(x, disp);
        stx_lap(x, NEGOBS_STEREO_STAGE_GCS);
    }
}

/* The result counts of one band's growth (kept per band, so a band grown
 * again at the seam counts once). */
static void band_result(const negobs_stereo_stats_t *after,
                        const negobs_stereo_stats_t *before,
                        stx_band_result_t *r)
{
    r->seeds = after->seeds - before->seeds;
    r->grown = after->grown - before->grown;
    r->gcs_matched = after->gcs_matched - before->gcs_matched;
    r->edges = after->edges - before->edges;
}

/* The start of every band job: the band that job index `job` names this
 * frame (stx_bands_order), the worker's state and the band's rows
 * [*y0, *y1), the band marked done; NULL when the executor named a worker
 * or job that does not exist (the frame then fails on the unmarked band). */
static stx_t *band_job_begin(band_job_t *j, int32_t job, int32_t worker,
                             int32_t *band, int32_t *y0, int32_t *y1)
{
    stx_t *x = worker_state(j->s, worker);
    if (x == NULL || job < 0 ||
        job >= negobs_stereo_band_count(&x->cfg, x->h)) {
        return NULL;
    }
    *band = j->s->band_order[job];
    if (negobs_stereo_band_rows(&x->cfg, x->h, *band, y0, y1) != NEGOBS_OK) {
        return NULL;
    }
    j->s->band_done[*band] = 1u;
    if (x != j->s && x->clock != NULL) {
        /* another worker's ticks start here, read on its own thread: a
         * per-thread clock (thread CPU time) read on the caller's thread
         * would not compare, and its wait for the job is no stage's */
        x->lap = x->clock(x->clock_user);
    }
    return x;
}

/* Rows of band `band` of a frame of h rows, as negobs_stereo_band_rows
 * gives them (0 when it does not exist). */
static int32_t band_rows(const stx_t *s, int32_t h, int32_t band)
{
    int32_t y0 = 0;
    int32_t y1 = 0;
    (void)negobs_stereo_band_rows(&s->cfg, h, band, &y0, &y1);
    return y1 - y0;
}

/*
 * Longest band first (LPT): a run lasts as long as its busiest worker, and
 * with fewer workers than bands the pool's first-come hand-out in index
 * order can leave the costliest band for last (4 bands of 1, 2, 1 and 2
 * strips on 2 workers: 1+1 against 2+2). The cost of a band is the
 * cells its growth and back-track scored in the last frame, scaled to
 * its rows now (a crop moves the borders), or its rows when no frame with
 * this band count ran yet. Counts, not clock time: the order is the same
 * on every run and needs no clock. Which band a job index names changes
 * no output: every band is the same computation whichever job runs it.
 */
void stx_bands_order(stx_t *s)
{
    uint64_t cost[NEGOBS_STEREO_MAX_BANDS];
    int32_t nb = negobs_stereo_band_count(&s->cfg, s->h);
    int parallel = s->exec.run != NULL && s->exec.workers > 1;
    int32_t k;
    for (k = 0; k < nb; k++) {
        int32_t rows = band_rows(s, s->h, k);
        int32_t last = band_rows(s, s->band_work_h, k);
        int32_t i;
        if (s->band_work_nb == nb && last > 0) {
            /* work per row of the last frame x rows now (< 2^32 x 2^15) */
            cost[k] = (uint64_t)s->band_work[k] * (uint64_t)rows /
                      (uint64_t)last;
        } else {
            cost[k] = (uint64_t)rows;
        }
        /* insertion by cost, ties in band order; on the caller's thread
         * alone the bands keep their order: with one worker DP stage 1
         * feeds each row to stage 2 as it ends, so rows must come top to
         * bottom (stx_dp_row) */
        for (i = k; i > 0 && parallel && cost[s->band_order[i - 1]] < cost[k];
             i--) {
            s->band_order[i] = s->band_order[i - 1];
        }
        s->band_order[i] = (uint8_t)k;
    }
    for (k = 0; k < nb; k++) {
        s->band_work[k] = 0;
    }
    s->band_work_h = s->h;
    s->band_work_nb = nb;
}

static void pass0_grow_job(void *arg, int32_t job, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    int32_t band;
    stx_t *x;
    negobs_stereo_stats_t before;
    int32_t yb0;
    int32_t yb1;
    x = band_job_begin(j, job, worker, &band, &yb0, &yb1);
    if (x == NULL) {
        return;
    }
    before = x->st;
    grow_band(x, j->disp, yb0, yb1, 0);
    band_result(&x->st, &before, &j->s->band_res[band]);
    j->s->band_work[band] += x->st.visited_cells - before.visited_cells;
}

/* DP stage 1 of the rows of band `band` (the window sums again only for
 * dp_rescore, the one case that correlates). */
static void pass0_dp_job(void *arg, int32_t job, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    int32_t band;
    stx_t *x;
    int32_t yb0;
    int32_t yb1;
    int32_t y0;
    x = band_job_begin(j, job, worker, &band, &yb0, &yb1);
    if (x == NULL) {
        return;
    }
    stx_dp_store_begin(x, yb0, yb1, SIZE_MAX);
    for (y0 = yb0; y0 < yb1; y0 += x->sh) {
        int32_t y1 = (y0 + x->sh < yb1) ? y0 + x->sh : yb1;
        int32_t y;
        if (x->cfg.dp_rescore) {
            stx_strip_stats(x, y0, y1);
            stx_lap(x, NEGOBS_STEREO_STAGE_WINDOWS);
        }
        for (y = y0; y < y1; y++) {
            stx_dp_row(x, y, negobs_image_s16_row(j->disp, y), 0, NULL, NULL);
        }
        stx_lap(x, NEGOBS_STEREO_STAGE_DP);
    }
    j->s->dps_used[band] = (uint32_t)stx_dp_store_used(x);
}

/*
 * Seam rule: pixels of the last row above a band border whose GCS match
 * the first row below lacks (no value, or one more than a level away).
 * Growth only flows down the image (each strip takes the last row of the
 * strip above as seeds), so a band without seeds of its own, a weakly
 * textured floor at the bottom of the frame, would otherwise stay empty
 * where the sequential growth filled it from above.
 */
static int32_t seam_missing(const stx_t *s, const negobs_image_s16_t *disp,
                            int32_t y0)
{
    const int16_t *above = negobs_image_s16_row(disp, y0 - 1);
    const int16_t *below = negobs_image_s16_row(disp, y0);
    int32_t n = 0;
    int32_t u;
    for (u = 0; u < s->w; u++) {
        int32_t dd;
        if (above[u] == NEGOBS_DISP_INVALID) {
            continue;
        }
        dd = (int32_t)below[u] - (int32_t)above[u];
        if (below[u] == NEGOBS_DISP_INVALID || dd > 1 || dd < -1) {
            n++;
        }
    }
    return n;
}

/* After the bands grew on their own: top to bottom, a band whose first row
 * lacks more than an eighth of a row of the matches just above its border
 * grows again here, with those matches as seeds, as the sequential growth
 * would have. Textured bands miss a few percent there; a quarter let
 * Flowerpots lose 0.5 point of bad1all, an eighth none (docs/DISPARITY.md,
 * "Row bands and threads"). The rule reads finished bands only, so the
 * result depends on the layout alone, not on the threads. */
static void seam_pass(stx_t *s, negobs_image_s16_t *disp, int32_t nb)
{
    int32_t b;
    for (b = 1; b < nb; b++) {
        int32_t yb0;
        int32_t yb1;
        negobs_stereo_stats_t before;
        stx_band_result_t *r = &s->band_res[b];
        if (negobs_stereo_band_rows(&s->cfg, s->h, b, &yb0, &yb1) !=
                NEGOBS_OK ||
            seam_missing(s, disp, yb0) * 8 <= s->w) {
            continue;
        }
        s->st.seeds -= r->seeds;
        s->st.grown -= r->grown;
        s->st.gcs_matched -= r->gcs_matched;
        s->st.edges -= r->edges;
        before = s->st;
        grow_band(s, disp, yb0, yb1, 1);
        band_result(&s->st, &before, r);
        s->st.seam_regrown++;
    }
}

/* Back-track, sub-pixel and confidence of the rows of band `band`. */
static void pass1_job(void *arg, int32_t job, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    int32_t band;
    stx_t *x;
    int32_t yb0;
    int32_t yb1;
    int32_t y0;
    uint32_t visited0;
    x = band_job_begin(j, job, worker, &band, &yb0, &yb1);
    if (x == NULL) {
        return;
    }
    visited0 = x->st.visited_cells;
    stx_dp_store_begin(x, yb0, yb1, j->s->dps_used[band]);
    for (y0 = yb0; y0 < yb1; y0 += x->sh) {
        int32_t y1 = (y0 + x->sh < yb1) ? y0 + x->sh : yb1;
        int32_t y;
        stx_strip_stats(x, y0, y1);
        stx_lap(x, NEGOBS_STEREO_STAGE_WINDOWS);
        for (y = y0; y < y1; y++) {
            int16_t *row = negobs_image_s16_row(j->disp, y);
            memcpy(x->rowd, row, (size_t)x->w * sizeof *row);
            stx_dp_row(x, y, x->rowd, 1, row,
                       j->conf ? negobs_image_u8_row(j->conf, y) : NULL);
        }
        stx_lap(x, NEGOBS_STEREO_STAGE_DP);
    }
    j->s->band_work[band] += x->st.visited_cells - visited0;
}

/* Every band through fn: on the executor when one is set (and there is
 * more than one worker), else here, in order. The wait for the slowest
 * band goes to `wait_stage` (NEGOBS_STEREO_STAGE_COUNT: to the caller's
 * next lap). */
static void run_bands(stx_t *s, negobs_job_fn fn, band_job_t *job,
                      negobs_stereo_stage_t wait_stage)
{
    int32_t nb = negobs_stereo_band_count(&s->cfg, s->h);
    int32_t k;
    if (s->exec.run == NULL || s->exec.workers < 2 || nb < 2) {
        for (k = 0; k < nb; k++) {
            fn(job, k, 0);
        }
        return;
    }
    for (k = 1; k < s->exec.workers; k++) {
        worker_sync(s, &s->wk[k - 1]);
    }
    memset(s->band_done, 0, sizeof s->band_done);
    s->exec.run(s->exec.user, nb, fn, job);
    for (k = 1; k < s->exec.workers; k++) {
        stats_merge(&s->st, &s->wk[k - 1].st);
    }
    for (k = 0; k < nb; k++) {
        if (!s->band_done[k]) {
            s->exec_failed = 1; /* the frame is not trustworthy */
        }
    }
    if (wait_stage < NEGOBS_STEREO_STAGE_COUNT) {
        stx_lap(s, wait_stage);
    }
}

void stx_bands_pass0(stx_t *s, negobs_image_s16_t *disp_q4)
{
    band_job_t job;
    job.s = s;
    job.disp = disp_q4;
    job.conf = NULL;
    run_bands(s, pass0_grow_job, &job, NEGOBS_STEREO_STAGE_GCS);
    seam_pass(s, disp_q4, negobs_stereo_band_count(&s->cfg, s->h));
    stx_lap(s, NEGOBS_STEREO_STAGE_GCS);
    stx_dp_stage2_reset(s);
    run_bands(s, pass0_dp_job, &job, NEGOBS_STEREO_STAGE_DP);
    if (s->yend != NULL) {
        stx_dp_stage2_feed_stored(s);
    }
    stx_dp_stage2_finish(s);
    stx_lap(s, NEGOBS_STEREO_STAGE_DP);
}

void stx_bands_pass1(stx_t *s, negobs_image_s16_t *disp_q4,
                     negobs_image_u8_t *confidence)
{
    band_job_t job;
    int32_t k;
    job.s = s;
    job.disp = disp_q4;
    job.conf = confidence;
    run_bands(s, pass1_job, &job, NEGOBS_STEREO_STAGE_DP);
    /* here, not in the jobs: also a band whose pass-1 job an executor
     * skipped gives its part back */
    for (k = 0; k < negobs_stereo_band_count(&s->cfg, s->h); k++) {
        int32_t y0 = 0;
        int32_t y1 = 0;
        (void)negobs_stereo_band_rows(&s->cfg, s->h, k, &y0, &y1);
        stx_dp_store_release(s, y0, y1, s->dps_used[k]);
        s->dps_used[k] = 0;
    }
}

/* Line filter over band `band`'s rows, or over the band-th of as many
 * column slices (the mean's vertical pass). */
static void filter_job(void *arg, int32_t job, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    int32_t band;
    stx_t *x;
    int32_t a;
    int32_t b;
    x = band_job_begin(j, job, worker, &band, &a, &b);
    if (x == NULL) {
        return;
    }
    switch (j->filter) {
    case STX_FILTER_LR:
        stx_lr_check_rows(x, j->disp, j->conf_data, j->conf_stride, a, b);
        break;
    case STX_FILTER_GAP_FILL:
        stx_gap_fill_rows(x, j->disp, j->conf_data, j->conf_stride, a, b);
        break;
    case STX_FILTER_MEAN_ROWS:
        stx_amean_rows(x, j->disp, j->conf_data, j->conf_stride, a, b);
        break;
    case STX_FILTER_SPECKLE_MARK:
        stx_speckle_mark_rows(x, j->disp, a, b);
        break;
    case STX_FILTER_SPECKLE_CLEAR:
        stx_speckle_clear_rows(x, j->disp, a, b);
        break;
    case STX_FILTER_MEAN_COLS:
    default: {
        int32_t nb = negobs_stereo_band_count(&x->cfg, x->h);
        if (nb < 1) {
            break; /* no band: the job cannot exist */
        }
        a = (int32_t)((int64_t)x->w * band / nb);
        b = (int32_t)((int64_t)x->w * (band + 1) / nb);
        stx_amean_cols(x, j->disp, j->conf_data, j->conf_stride, a, b);
        break;
    }
    }
}

void stx_bands_filter(stx_t *s, stx_line_filter_t f,
                      negobs_image_s16_t *disp_q4, uint8_t *conf,
                      int32_t conf_stride)
{
    band_job_t job;
    if (s->exec.run == NULL || s->exec.workers < 2) {
        /* one thread: the whole-frame filters, in their own order */
        if (f == STX_FILTER_LR) {
            stx_lr_check(s, disp_q4, conf, conf_stride);
        } else if (f == STX_FILTER_GAP_FILL) {
            stx_gap_fill(s, disp_q4, conf, conf_stride);
        } else if (f == STX_FILTER_SPECKLE) {
            stx_speckle(s, disp_q4);
        } else {
            stx_adaptive_mean(s, disp_q4, conf, conf_stride);
        }
        return;
    }
    job.s = s;
    job.disp = disp_q4;
    job.conf = NULL;
    job.filter = f;
    if (f == STX_FILTER_MEAN) {
        job.filter = STX_FILTER_MEAN_ROWS;
    } else if (f == STX_FILTER_SPECKLE) {
        job.filter = STX_FILTER_SPECKLE_MARK;
    }
    job.conf_data = conf;
    job.conf_stride = conf_stride;
    run_bands(s, filter_job, &job, NEGOBS_STEREO_STAGE_COUNT);
    if (f == STX_FILTER_MEAN) {
        job.filter = STX_FILTER_MEAN_COLS;
        run_bands(s, filter_job, &job, NEGOBS_STEREO_STAGE_COUNT);
    } else if (f == STX_FILTER_SPECKLE) {
        /* every band marked before any is cleared: a mark reads the
         * other bands' pixels as they were */
        job.filter = STX_FILTER_SPECKLE_CLEAR;
        run_bands(s, filter_job, &job, NEGOBS_STEREO_STAGE_COUNT);
    }
}

/* Part `k` of `n` of [0, len): the split the stage-6 and stage-1 jobs use
 * (any split gives the same sums; this one follows the band count). */
static void part(int32_t len, int32_t k, int32_t n, int32_t *a, int32_t *b)
{
    if (n < 1) {
        *a = 0; /* no bands (cannot happen inside a band job): nothing */
        *b = 0;
        return;
    }
    *a = (int32_t)((int64_t)len * k / n);
    *b = (int32_t)((int64_t)len * (k + 1) / n);
}

/* Stage 6 over the band-th part of the grid rows: its score per offset. */
static void vertical_job(void *arg, int32_t job, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    int32_t band;
    stx_t *x;
    int32_t a;
    int32_t b;
    int32_t nb;
    x = band_job_begin(j, job, worker, &band, &a, &b);
    if (x == NULL) {
        return;
    }
    nb = negobs_stereo_band_count(&x->cfg, x->h);
    part(stx_vertical_grid_rows(x), band, nb, &a, &b);
    stx_vertical_scores(x, x->cfg.vertical_search, a, b,
                        j->s->vscore +
                            (ptrdiff_t)band * (2 * STX_VSEARCH_MAX + 1));
}

/* Stage 1 over the band-th part of the low-res rows: the 4x4 means
 * (j->step 0) or the matches (1), the latter with the part's
 * histogram and kept count. */
static void lowres_job(void *arg, int32_t job, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    int32_t band;
    stx_t *x;
    int32_t a;
    int32_t b;
    int32_t nb;
    x = band_job_begin(j, job, worker, &band, &a, &b);
    if (x == NULL) {
        return;
    }
    nb = negobs_stereo_band_count(&x->cfg, x->h);
    part(x->lh, band, nb, &a, &b);
    if (j->step == 0) {
        stx_lowres_downsample_rows(x, a, b);
    } else {
        j->s->lkept[band] = stx_lowres_match_rows(
            x, a, b,
            j->s->lhist + (ptrdiff_t)band * (stx_lowres_levels(x) + 1));
    }
}

void stx_bands_vertical_range(stx_t *s)
{
    band_job_t job;
    int32_t nb = negobs_stereo_band_count(&s->cfg, s->h);
    int32_t k;
    int32_t i;
    if (s->exec.run == NULL || s->exec.workers < 2 || nb < 2 ||
        s->vscore == NULL) {
        if (s->cfg.vertical_search > 0) {
            s->voff = stx_vertical_estimate(s, s->cfg.vertical_search);
        }
        stx_lap(s, NEGOBS_STEREO_STAGE_VERTICAL);
        stx_lowres_range(s);
        stx_lap(s, NEGOBS_STEREO_STAGE_RANGE);
        return;
    }
    memset(&job, 0, sizeof job);
    job.s = s;
    if (s->cfg.vertical_search > 0) {
        int64_t sum[2 * STX_VSEARCH_MAX + 1];
        int32_t n = 2 * s->cfg.vertical_search + 1;
        run_bands(s, vertical_job, &job, NEGOBS_STEREO_STAGE_VERTICAL);
        /* the bands' partial sums in band order (integers: exact) */
        for (i = 0; i < n; i++) {
            sum[i] = 0;
            for (k = 0; k < nb; k++) {
                sum[i] += s->vscore[k * (2 * STX_VSEARCH_MAX + 1) + i];
            }
        }
        s->voff = stx_vertical_pick(sum, s->cfg.vertical_search);
    }
    stx_lap(s, NEGOBS_STEREO_STAGE_VERTICAL);
    if (stx_lowres_begin(s)) {
        int32_t bins = stx_lowres_levels(s) + 1;
        uint32_t kept = 0;
        job.step = 0;
        run_bands(s, lowres_job, &job, NEGOBS_STEREO_STAGE_RANGE);
        job.step = 1;
        run_bands(s, lowres_job, &job, NEGOBS_STEREO_STAGE_RANGE);
        for (i = 0; i < bins; i++) {
            s->hist[i] = 0;
            for (k = 0; k < nb; k++) {
                s->hist[i] += s->lhist[k * bins + i];
            }
        }
        for (k = 0; k < nb; k++) {
            kept += s->lkept[k];
        }
        stx_lowres_finish(s, kept);
    }
    stx_lap(s, NEGOBS_STEREO_STAGE_RANGE);
}
