/*
 * Row bands: the frame's stages 2-4 as independent jobs for the caller's
 * executor (negobs/executor.h). The library creates no thread.
 *
 * A band is a run of whole strips; its layout depends on cfg.bands and the
 * frame's rows only (negobs_stereo_band_rows), never on the executor, and
 * the growth never crosses a band border (gcs.c: seed_carry). Each band is
 * therefore the same computation whichever worker runs it, in whatever
 * order: the output is bit-identical for every thread count.
 *
 * Each worker owns one scratch area (the strip buffers, the queue, the
 * score cache, the memo and a DP row): worker 0 is the context itself, the
 * others are copies of the context (s->wk) with their own scratch and
 * statistics, merged after each parallel pass. Pass 0 (window sums, Canny,
 * GCS, DP stage 1) keeps every row's stage-1 end scores in s->yend when
 * several workers exist; the second DP stage then takes the rows in order
 * on the caller's thread (h x ndisp steps, about 1 % of the frame). Pass 1
 * (the back-track with sub-pixel refinement) is row-independent.
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
    memset(&x->st, 0, sizeof x->st);
    if (x->clock != NULL) {
        x->lap = x->clock(x->clock_user);
    }
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
} band_job_t;

static stx_t *worker_state(stx_t *s, int32_t worker)
{
    return (worker == 0) ? s : &s->wk[worker - 1];
}

/* Window sums, Canny, GCS and DP stage 1 of band `band`. */
static void pass0_job(void *arg, int32_t band, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    stx_t *x = worker_state(j->s, worker);
    int32_t yb0;
    int32_t yb1;
    int32_t y0;
    if (negobs_stereo_band_rows(&x->cfg, x->h, band, &yb0, &yb1) !=
        NEGOBS_OK) {
        return;
    }
    x->band_y0 = yb0;
    for (y0 = yb0; y0 < yb1; y0 += x->sh) {
        int32_t y1 = (y0 + x->sh < yb1) ? y0 + x->sh : yb1;
        int32_t y;
        stx_strip_stats(x, y0, y1);
        stx_lap(x, NEGOBS_STEREO_STAGE_WINDOWS);
        x->st.edges += stx_canny_strip(x, y0, y1);
        stx_lap(x, NEGOBS_STEREO_STAGE_CANNY);
        stx_gcs_strip(x, j->disp);
        stx_lap(x, NEGOBS_STEREO_STAGE_GCS);
        for (y = y0; y < y1; y++) {
            stx_dp_row(x, y, negobs_image_s16_row(j->disp, y), 0, NULL, NULL);
        }
        stx_lap(x, NEGOBS_STEREO_STAGE_DP);
    }
}

/* Back-track, sub-pixel and confidence of the rows of band `band`. */
static void pass1_job(void *arg, int32_t band, int32_t worker)
{
    band_job_t *j = (band_job_t *)arg;
    stx_t *x = worker_state(j->s, worker);
    int32_t yb0;
    int32_t yb1;
    int32_t y0;
    if (negobs_stereo_band_rows(&x->cfg, x->h, band, &yb0, &yb1) !=
        NEGOBS_OK) {
        return;
    }
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
}

/* Every band through fn: on the executor when one is set (and there is
 * more than one worker), else here, in order. The wait for the slowest
 * band goes to `wait_stage`. */
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
    s->exec.run(s->exec.user, nb, fn, job);
    for (k = 1; k < s->exec.workers; k++) {
        stats_merge(&s->st, &s->wk[k - 1].st);
    }
    stx_lap(s, wait_stage);
}

void stx_bands_pass0(stx_t *s, negobs_image_s16_t *disp_q4)
{
    band_job_t job;
    job.s = s;
    job.disp = disp_q4;
    job.conf = NULL;
    stx_dp_stage2_reset(s);
    run_bands(s, pass0_job, &job, NEGOBS_STEREO_STAGE_GCS);
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
    job.s = s;
    job.disp = disp_q4;
    job.conf = confidence;
    run_bands(s, pass1_job, &job, NEGOBS_STEREO_STAGE_DP);
}
