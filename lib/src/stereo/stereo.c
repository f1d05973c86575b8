/*
 * Public entry points of the disparity engine: config defaults and checks,
 * workspace carving (one function for the size query and for init), and the
 * per-frame driver that runs the stages strip by strip.
 */
#include <string.h>

#include "negobs/stereo.h"
#include "stereo/stereo_int.h"

void negobs_stereo_config_default(negobs_stereo_config_t *cfg, int32_t width,
                                  int32_t height)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->width = width;
    cfg->height = height;
    cfg->min_disp = 0;
    cfg->max_disp = 63;
    cfg->auto_range = 1;
    cfg->range_margin = 4;
    cfg->tile_size = 32;
    cfg->vertical_search = 4;
    cfg->vertical_offset = 0;
    cfg->canny_low = 60;
    cfg->canny_high = 120;
    cfg->canny_top_permille = 3;
    cfg->seed_step = 4;
    cfg->seed_tau_q14 = 13107;  /* 0.8 */
    cfg->seed_margin_q14 = 819; /* 0.05 */
    cfg->ncc_tau_q14 = 8192;    /* 0.5 */
    cfg->ncc_mu_q14 = 1638;     /* 0.1 */
    cfg->ssk_beta_q8 = 0;       /* plain stable matching; DP fills */
    cfg->zonegap = 1;
    cfg->texture_min = 100;
    cfg->queue_capacity = 8192;
    cfg->strip_rows = 32;
    cfg->band = 2;
    cfg->dp_neutral_q14 = 0;
    cfg->dp_jump_q14 = 8192; /* 0.5 */
    cfg->dp_rescore = 0;
    cfg->subpixel_halfshift = 0;
    cfg->lr_check = 1;
    cfg->speckle_size = 100;
    cfg->speckle_diff_q4 = 12;
    cfg->adaptive_mean = 1;
    cfg->gap_fill = 64;
    cfg->keep_out_of_view = 1; /* dense: docs/DISPARITY.md, out-of-view */
    cfg->memory_profile = NEGOBS_STEREO_PROFILE_DEFAULT;
    cfg->bands = NEGOBS_STEREO_BANDS_DEFAULT;
    cfg->band_workers = 1;
}

static negobs_status_t check_config(const negobs_stereo_config_t *c)
{
    if (c == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->width < NEGOBS_STEREO_MIN_WIDTH || c->width > NEGOBS_MAX_DIM ||
        c->height < NEGOBS_STEREO_MIN_HEIGHT || c->height > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->min_disp < 0 || c->max_disp < c->min_disp ||
        c->max_disp - c->min_disp + 1 > NEGOBS_STEREO_MAX_RANGE ||
        c->max_disp > c->width - 2 * STX_WIN_R - 2 || c->max_disp > 2000) {
        return NEGOBS_ERR_INVAL; /* range wider than the image */
    }
    if (c->range_margin < 0 || c->range_margin > 64 || c->tile_size < 8 ||
        c->tile_size > 1024 || (c->tile_size % 4) != 0) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->vertical_search < 0 || c->vertical_search > 4 ||
        c->vertical_offset < -4 || c->vertical_offset > 4) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->canny_low < 0 || c->canny_high < c->canny_low ||
        c->canny_high > 4096 || c->canny_top_permille < 0 ||
        c->canny_top_permille > 1000 || c->seed_step < 1 ||
        c->seed_step > 64) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->seed_tau_q14 < 0 || c->seed_tau_q14 > STX_ONE_Q14 ||
        c->seed_margin_q14 < 0 || c->seed_margin_q14 > STX_ONE_Q14 ||
        c->ncc_tau_q14 < 0 || c->ncc_tau_q14 > STX_ONE_Q14 ||
        c->ncc_mu_q14 < 0 || c->ncc_mu_q14 > STX_ONE_Q14 ||
        c->ssk_beta_q8 < 0 || c->ssk_beta_q8 > 255 || c->zonegap < 0 ||
        c->zonegap > 16 || c->texture_min < 0) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->queue_capacity < 16 || c->queue_capacity > (1 << 22) ||
        c->strip_rows < 8 || c->strip_rows > 255) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->band < 1 || c->band > NEGOBS_STEREO_MAX_BAND ||
        c->dp_neutral_q14 < -STX_ONE_Q14 || c->dp_neutral_q14 > STX_ONE_Q14 ||
        c->dp_jump_q14 < 0 || c->dp_jump_q14 > 2 * STX_ONE_Q14 ||
        c->dp_rescore < 0 || c->dp_rescore > 1 || c->subpixel_halfshift < 0 ||
        c->subpixel_halfshift > 1) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->speckle_size < 0 || c->speckle_size > 65536 ||
        c->speckle_diff_q4 < 0 || c->speckle_diff_q4 > 4096 ||
        c->gap_fill < 0 || c->gap_fill > 1024 || c->keep_out_of_view < 0 ||
        c->keep_out_of_view > 1) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->bands < 1 || c->bands > NEGOBS_STEREO_MAX_BANDS ||
        c->band_workers < 1 || c->band_workers > NEGOBS_STEREO_MAX_BANDS) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->memory_profile != NEGOBS_STEREO_PROFILE_COMPACT &&
        c->memory_profile != NEGOBS_STEREO_PROFILE_FAST) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

#define TAKE(ptr, type, count)                                                \
    do {                                                                      \
        void *p_ = negobs_arena_take(a, (size_t)(count) * sizeof(type));      \
        if (s != NULL) {                                                      \
            (ptr) = (type *)p_;                                               \
        }                                                                     \
    } while (0)

/* Offset of the next `bytes` in a block laid out as the arena would lay
 * out separate blocks (without guards), and the block's end in *end. */
static size_t slot(size_t *end, size_t bytes)
{
    size_t at = *end;
    *end += (bytes + (NEGOBS_ARENA_ALIGN - 1u)) &
            ~(size_t)(NEGOBS_ARENA_ALIGN - 1u);
    return at;
}

/*
 * The growth's strip scratch (Canny, the matching table and its bitset,
 * the queue, and without a memo the score cache) as one block: canny.c
 * and gcs.c set all of it up again at every strip, so it is idle from the
 * end of the growth to the next frame, and the DP keeps its pointers in
 * it between its passes (dp_store.c) unless carve() lends the memo, where
 * that is larger. A worker with a memo reads its scores from the memo
 * alone (gcs.c: member_memo), so it has no cache. In a release build the
 * block takes what the separate blocks took; with debug guards it has one
 * guard pair.
 */
static void carve_growth(negobs_arena_t *a, stx_t *x,
                         const negobs_stereo_config_t *c, size_t spx,
                         int32_t memo_k)
{
    size_t w = (size_t)c->width;
    size_t nd = (size_t)c->max_disp - (size_t)c->min_disp + 1u;
    size_t q = (size_t)c->queue_capacity;
    size_t end = 0;
    size_t mag = slot(&end, (spx + 2u * w) * sizeof(uint16_t));
    size_t edge = slot(&end, spx);
    size_t ld = slot(&end, spx);
    size_t lc = slot(&end, spx);
    size_t lc2 = slot(&end, spx);
    size_t rd = slot(&end, spx);
    size_t rc = slot(&end, spx);
    size_t rc2 = slot(&end, spx);
    size_t tbits = slot(&end, (spx * nd + 7u) / 8u);
    size_t item = slot(&end, q * sizeof(uint32_t));
    size_t next = slot(&end, q * sizeof(int32_t));
    size_t head = slot(&end, STX_NBUCKET * sizeof(int32_t));
    size_t cache = (memo_k > 0) ? 0u
                                : slot(&end, sizeof(stx_cache_entry_t)
                                                 << STX_CACHE_BITS);
    uint8_t *g = (uint8_t *)negobs_arena_take(a, end);
    if (x == NULL || g == NULL) {
        return;
    }
    x->mag = (uint16_t *)(void *)(g + mag);
    x->edge = g + edge;
    x->ld = g + ld;
    x->lc = g + lc;
    x->lc2 = g + lc2;
    x->rd = g + rd;
    x->rc = g + rc;
    x->rc2 = g + rc2;
    x->tbits = g + tbits;
    x->q.item = (uint32_t *)(void *)(g + item);
    x->q.next = (int32_t *)(void *)(g + next);
    x->q.head = (int32_t *)(void *)(g + head);
    x->cache = (memo_k > 0) ? NULL : (stx_cache_entry_t *)(void *)(g + cache);
    x->dps = g; /* carve() prefers the memo where there is one */
    x->dps_cap = end;
}

/* The scratch of one band worker (the context itself is worker 0): the
 * strip buffers of stages 2-4 and one DP row. bands.c: worker_sync()
 * lists the same fields. */
static void carve_scratch(negobs_arena_t *a, stx_t *x,
                          const negobs_stereo_config_t *c, int32_t memo_k)
{
    stx_t *s = x; /* TAKE stores only when not measuring */
    int32_t w = c->width;
    int32_t nd = c->max_disp - c->min_disp + 1;
    size_t spx = (size_t)c->strip_rows * (size_t)w;
    int32_t maxwh = (w > c->height) ? w : c->height;
    if (memo_k > 0) {
        if (x != NULL) {
            x->memo_k = memo_k;
        }
        TAKE(x->memo, uint32_t, spx * (size_t)memo_k);
        TAKE(x->memo_base, uint8_t, spx);
    }
    TAKE(x->sl, uint16_t, spx);
    TAKE(x->sr, uint16_t, spx);
    TAKE(x->vl, uint32_t, spx);
    TAKE(x->vr, uint32_t, spx);
    carve_growth(a, x, c, spx, memo_k);
    TAKE(x->yprev, int32_t, nd + 2);
    TAKE(x->ycur, int32_t, nd + 2);
    TAKE(x->p1, uint8_t, (size_t)w * (size_t)nd);
    TAKE(x->cost, int16_t, (size_t)w * (size_t)nd);
    TAKE(x->jump_to, int16_t, w);
    TAKE(x->blo, int16_t, w);
    TAKE(x->bhi, int16_t, w);
    TAKE(x->bscored, uint8_t, w);
    TAKE(x->rowd, int16_t, w);
    TAKE(x->line, int16_t, maxwh + 16);
    TAKE(x->line2, int16_t, maxwh + 16);
    TAKE(x->flood, uint32_t, c->speckle_size + 2);
    if (c->band_workers > 1) {
        TAKE(x->flood_out, uint32_t, c->speckle_size + 2);
    }
    if (x != NULL) {
        x->q.cap = c->queue_capacity;
    }
}

/*
 * The only place that decides the workspace layout. In measuring mode
 * (NULL base) `s` stays NULL and only the sizes are summed.
 */
static stx_t *carve(negobs_arena_t *a, const negobs_stereo_config_t *c,
                    int32_t memo_k)
{
    stx_t *s = (stx_t *)negobs_arena_take(a, sizeof(stx_t));
    int32_t w = c->width;
    int32_t h = c->height;
    int32_t nd = c->max_disp - c->min_disp + 1;
    int32_t sh = c->strip_rows;
    int32_t lw = w / STX_LOWRES;
    int32_t lh = h / STX_LOWRES;
    int32_t tw = (w + c->tile_size - 1) / c->tile_size;
    int32_t th = (h + c->tile_size - 1) / c->tile_size;
    int32_t nd4 = (c->max_disp + 3) / 4 - c->min_disp / 4 + 1;

    if (s != NULL) {
        memset(s, 0, sizeof *s);
        s->cfg = *c;
        s->w = w;
        s->h = h;
        s->dmin = c->min_disp;
        s->ndisp = nd;
        s->sh = sh;
        s->lw = lw;
        s->lh = lh;
        s->tile = c->tile_size;
        s->tw = tw;
        s->th = th;
        s->q.cap = c->queue_capacity;
    }
    carve_scratch(a, s, c, memo_k);
    if (s != NULL && s->memo != NULL &&
        (size_t)sh * (size_t)w * (size_t)memo_k * sizeof *s->memo >
            s->dps_cap) {
        /* the growth is over when the DP runs: worker 0's memo (the
         * bands' DP rows share one store), where larger than its strip
         * scratch, holds the DP's pointers between its two passes
         * (dp_store.c) and is zeroed after them */
        s->dps = (uint8_t *)s->memo;
        s->dps_cap = (size_t)sh * (size_t)w * (size_t)memo_k * sizeof *s->memo;
        s->dps_memo = 1;
    }
    TAKE(s->lo_l, uint8_t, (size_t)lw * (size_t)lh);
    TAKE(s->lo_r, uint8_t, (size_t)lw * (size_t)lh);
    TAKE(s->lo_d, uint8_t, (size_t)lw * (size_t)lh);
    TAKE(s->tile_lo, int16_t, 2 * tw * th);
    TAKE(s->tile_hi, int16_t, 2 * tw * th);
    TAKE(s->hist, uint32_t, nd4 + 2);
    TAKE(s->zprev, int64_t, nd);
    TAKE(s->zcur, int64_t, nd);
    TAKE(s->p2, uint8_t, (size_t)h * (size_t)nd);
    TAKE(s->dend, int16_t, h);
    TAKE(s->zarg, int16_t, h);
    TAKE(s->vis, uint8_t, (size_t)h * (((size_t)w + 7u) / 8u));
    TAKE(s->keep, uint8_t, (size_t)h * (((size_t)w + 7u) / 8u));
    if (c->band_workers > 1) {
        int32_t k;
        TAKE(s->wk, stx_t, c->band_workers - 1);
        for (k = 0; k < c->band_workers - 1; k++) {
            stx_t *x = (s != NULL) ? &s->wk[k] : NULL;
            if (x != NULL) {
                memset(x, 0, sizeof *x);
            }
            carve_scratch(a, x, c, memo_k);
        }
        TAKE(s->yend, int32_t, (size_t)h * (size_t)nd);
        TAKE(s->yhave, uint8_t, h);
        TAKE(s->vscore, int64_t,
             (size_t)c->bands * (2u * STX_VSEARCH_MAX + 1u));
        TAKE(s->lhist, uint32_t, (size_t)c->bands * ((size_t)nd4 + 2u));
        TAKE(s->lkept, uint32_t, c->bands);
    }
    return s;
}

static size_t carve_bytes(const negobs_stereo_config_t *c, int32_t memo_k)
{
    negobs_arena_t a;
    negobs_arena_init(&a, NULL, 0);
    (void)carve(&a, c, memo_k);
    return negobs_arena_used(&a);
}

/*
 * The fast profile's memo levels per worker: NEGOBS_STEREO_MEMO_LEVELS (or
 * the whole range when narrower) for one worker. Every worker needs its own
 * memo, so with several the band narrows until the workspace fits
 * NEGOBS_STEREO_FAST_BUDGET (or one worker's workspace, when that is
 * larger); below NEGOBS_STEREO_MEMO_MIN_LEVELS there is no memo. The
 * memo never changes the output, only the instructions.
 */
static int32_t memo_levels(const negobs_stereo_config_t *c)
{
    int32_t nd = c->max_disp - c->min_disp + 1;
    int32_t k = (nd < NEGOBS_STEREO_MEMO_LEVELS) ? nd
                                                 : NEGOBS_STEREO_MEMO_LEVELS;
    negobs_stereo_config_t one;
    size_t budget;
    if (c->memory_profile != NEGOBS_STEREO_PROFILE_FAST) {
        return 0;
    }
    if (c->band_workers < 2) {
        return k;
    }
    one = *c;
    one.band_workers = 1;
    budget = carve_bytes(&one, k);
    if (budget < NEGOBS_STEREO_FAST_BUDGET) {
        budget = NEGOBS_STEREO_FAST_BUDGET;
    }
    while (k >= NEGOBS_STEREO_MEMO_MIN_LEVELS && carve_bytes(c, k) > budget) {
        k--;
    }
    return (k >= NEGOBS_STEREO_MEMO_MIN_LEVELS || k == nd) ? k : 0;
}

negobs_status_t negobs_stereo_workspace_size(const negobs_stereo_config_t *cfg,
                                             size_t *bytes_out)
{
    negobs_arena_t a;
    negobs_status_t st;
    if (bytes_out == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    st = check_config(cfg);
    if (st != NEGOBS_OK) {
        return st;
    }
    negobs_arena_init(&a, NULL, 0);
    (void)carve(&a, cfg, memo_levels(cfg));
    if (negobs_arena_status(&a) != NEGOBS_OK) {
        return negobs_arena_status(&a);
    }
    *bytes_out = negobs_arena_used(&a);
    return NEGOBS_OK;
}

negobs_status_t negobs_stereo_init(negobs_stereo_t *ctx,
                                   const negobs_stereo_config_t *cfg,
                                   void *workspace, size_t workspace_bytes)
{
    negobs_arena_t a;
    stx_t *s;
    negobs_status_t st;

    if (ctx == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    ctx->priv = NULL;
    st = check_config(cfg);
    if (st != NEGOBS_OK) {
        return st;
    }
    if (workspace == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    negobs_arena_init(&a, workspace, workspace_bytes);
    if (negobs_arena_status(&a) != NEGOBS_OK) {
        return negobs_arena_status(&a);
    }
    s = carve(&a, cfg, memo_levels(cfg));
    if (negobs_arena_status(&a) != NEGOBS_OK || s == NULL) {
        return (negobs_arena_status(&a) != NEGOBS_OK) ? negobs_arena_status(&a)
                                                      : NEGOBS_ERR_NOSPACE;
    }
    s->arena = a; /* kept for the guard check after each frame */
    stx_memo_clear(s);
    stx_bands_init(s);
    ctx->cfg = *cfg;
    ctx->priv = s;
    return NEGOBS_OK;
}

static negobs_status_t check_frame(const stx_t *s, const negobs_image_u8_t *l,
                                   const negobs_image_u8_t *r,
                                   const negobs_image_s16_t *d,
                                   const negobs_image_u8_t *c)
{
    if (negobs_image_u8_check(l) != NEGOBS_OK ||
        negobs_image_u8_check(r) != NEGOBS_OK ||
        negobs_image_s16_check(d) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    if (l->width != s->w || l->height != s->h || r->width != s->w ||
        r->height != s->h || d->width != s->w || d->height != s->h) {
        return NEGOBS_ERR_INVAL;
    }
    if (c != NULL && (negobs_image_u8_check(c) != NEGOBS_OK ||
                      c->width != s->w || c->height != s->h)) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

/* Show the map after `stage` to the observer; its time is not counted. */
static inline void stx_observe(stx_t *s, negobs_stereo_stage_t stage,
                               const negobs_image_s16_t *disp_q4)
{
    if (s->observer != NULL) {
        s->observer(s->observer_user, stage, disp_q4);
        if (s->clock != NULL) {
            s->lap = s->clock(s->clock_user);
        }
    }
}

negobs_status_t negobs_stereo_set_clock(negobs_stereo_t *ctx,
                                        negobs_stereo_clock_fn clock,
                                        void *user)
{
    stx_t *s;
    if (ctx == NULL || ctx->priv == NULL) {
        return NEGOBS_ERR_STATE;
    }
    s = (stx_t *)ctx->priv;
    s->clock = clock;
    s->clock_user = user;
    return NEGOBS_OK;
}

negobs_status_t negobs_stereo_set_observer(negobs_stereo_t *ctx,
                                           negobs_stereo_observer_fn observer,
                                           void *user)
{
    stx_t *s;
    if (ctx == NULL || ctx->priv == NULL) {
        return NEGOBS_ERR_STATE;
    }
    s = (stx_t *)ctx->priv;
    s->observer = observer;
    s->observer_user = user;
    return NEGOBS_OK;
}

negobs_status_t negobs_stereo_set_executor(negobs_stereo_t *ctx,
                                           const negobs_executor_t *exec)
{
    stx_t *s;
    if (ctx == NULL || ctx->priv == NULL) {
        return NEGOBS_ERR_STATE;
    }
    s = (stx_t *)ctx->priv;
    if (exec == NULL) {
        memset(&s->exec, 0, sizeof s->exec);
        return NEGOBS_OK;
    }
    if (exec->run == NULL || exec->workers < 1 ||
        exec->workers > s->cfg.band_workers) {
        return NEGOBS_ERR_INVAL;
    }
    s->exec = *exec;
    return NEGOBS_OK;
}

negobs_status_t negobs_stereo_set_first_row(negobs_stereo_t *ctx,
                                            int32_t first_row)
{
    stx_t *s;
    if (ctx == NULL || ctx->priv == NULL) {
        return NEGOBS_ERR_STATE;
    }
    s = (stx_t *)ctx->priv;
    if (first_row < 0 ||
        first_row > s->cfg.height - NEGOBS_STEREO_MIN_HEIGHT) {
        return NEGOBS_ERR_INVAL;
    }
    s->first_row = first_row;
    return NEGOBS_OK;
}

negobs_status_t negobs_stereo_hold_vertical_offset(negobs_stereo_t *ctx,
                                                   int32_t offset)
{
    stx_t *s;
    if (ctx == NULL || ctx->priv == NULL) {
        return NEGOBS_ERR_STATE;
    }
    s = (stx_t *)ctx->priv;
    if (offset < -s->cfg.vertical_search || offset > s->cfg.vertical_search) {
        return NEGOBS_ERR_INVAL;
    }
    s->vhold = offset;
    s->vhold_set = 1;
    return NEGOBS_OK;
}

/* Unless keep_out_of_view: drop the values whose match lies left of the
 * right image. Applied after the DP and after every refinement, so no stage
 * builds on such values and every map the observer sees is what a run
 * stopping at that stage returns. */
static void drop_out_of_view(stx_t *s, negobs_image_s16_t *disp_q4)
{
    if (!s->cfg.keep_out_of_view) {
        stx_out_of_view(s, disp_q4);
    }
}

/* Every stage on the frame as s describes it (s->h rows; the descriptors
 * may be a crop of the caller's images). */
static void process_frame(stx_t *s, const negobs_image_u8_t *left,
                          const negobs_image_u8_t *right,
                          negobs_image_s16_t *disp_q4,
                          negobs_image_u8_t *confidence)
{
    int32_t y;

    s->left = left;
    s->right = right;
    s->st.band = s->cfg.band;

    stx_bands_order(s);

    /* stage 6 then 1: vertical offset, range */
    s->voff = s->cfg.vertical_offset;
    s->gdmin = s->dmin;
    s->gdmax = s->dmin + s->ndisp - 1;
    if (s->vhold_set && s->cfg.vertical_search > 0) {
        /* a held offset: this frame skips the search */
        int32_t search = s->cfg.vertical_search;
        s->cfg.vertical_search = 0;
        s->voff = s->vhold;
        stx_bands_vertical_range(s);
        s->cfg.vertical_search = search;
    } else {
        stx_bands_vertical_range(s);
    }
    s->vhold_set = 0;
    s->st.vertical_offset = s->voff;
    s->st.range_min = s->gdmin;
    s->st.range_max = s->gdmax;

    /* stages 2-4 (first DP pass) band by band, then the second DP stage
     * and the back-track, sub-pixel and confidence (bands.c) */
    stx_bands_pass0(s, disp_q4);
    stx_observe(s, NEGOBS_STEREO_STAGE_GCS, disp_q4);
    stx_bands_pass1(s, disp_q4, confidence);
    /* (its few ticks go to the next stage: one clock read fewer) */
    drop_out_of_view(s, disp_q4);
    stx_observe(s, NEGOBS_STEREO_STAGE_DP, disp_q4);
    if (s->cfg.lr_check) {
        stx_bands_filter(s, STX_FILTER_LR, disp_q4,
                         confidence ? confidence->data : NULL,
                         confidence ? confidence->stride : 0);
        drop_out_of_view(s, disp_q4);
        stx_lap(s, NEGOBS_STEREO_STAGE_LR);
        stx_observe(s, NEGOBS_STEREO_STAGE_LR, disp_q4);
    }
    stx_bands_filter(s, STX_FILTER_SPECKLE, disp_q4, NULL, 0);
    drop_out_of_view(s, disp_q4);
    stx_lap(s, NEGOBS_STEREO_STAGE_SPECKLE);
    stx_observe(s, NEGOBS_STEREO_STAGE_SPECKLE, disp_q4);
    if (s->cfg.gap_fill > 0) {
        stx_bands_filter(s, STX_FILTER_GAP_FILL, disp_q4,
                         confidence ? confidence->data : NULL,
                         confidence ? confidence->stride : 0);
        drop_out_of_view(s, disp_q4);
        stx_lap(s, NEGOBS_STEREO_STAGE_GAP_FILL);
        stx_observe(s, NEGOBS_STEREO_STAGE_GAP_FILL, disp_q4);
    }
    if (s->cfg.adaptive_mean) {
        stx_bands_filter(s, STX_FILTER_MEAN, disp_q4,
                         confidence ? confidence->data : NULL,
                         confidence ? confidence->stride : 0);
        drop_out_of_view(s, disp_q4);
        stx_lap(s, NEGOBS_STEREO_STAGE_MEAN);
        stx_observe(s, NEGOBS_STEREO_STAGE_MEAN, disp_q4);
    }
    for (y = 0; y < s->h; y++) {
        const int16_t *row = negobs_image_s16_row(disp_q4, y);
        uint8_t *crow = confidence ? negobs_image_u8_row(confidence, y) : NULL;
        int32_t x;
        for (x = 0; x < s->w; x++) {
            if (row[x] != NEGOBS_DISP_INVALID) {
                s->st.valid++;
            } else if (crow != NULL) {
                crow[x] = 0;
            }
        }
    }
}

/* Views of rows [top, h) (no copy: descriptors carry stride). */
static negobs_image_u8_t crop_u8(const negobs_image_u8_t *img, int32_t top)
{
    negobs_image_u8_t c = *img;
    c.data = negobs_image_u8_row(img, top);
    c.height = img->height - top;
    return c;
}

static negobs_image_s16_t crop_s16(const negobs_image_s16_t *img, int32_t top)
{
    negobs_image_s16_t c = *img;
    c.data = negobs_image_s16_row(img, top);
    c.height = img->height - top;
    return c;
}

negobs_status_t negobs_stereo_process(negobs_stereo_t *ctx,
                                      const negobs_image_u8_t *left,
                                      const negobs_image_u8_t *right,
                                      negobs_image_s16_t *disp_q4,
                                      negobs_image_u8_t *confidence,
                                      negobs_stereo_stats_t *stats)
{
    stx_t *s;
    negobs_status_t st;
    int32_t top;

    if (ctx == NULL || ctx->priv == NULL) {
        return NEGOBS_ERR_STATE;
    }
    s = (stx_t *)ctx->priv;
    st = check_frame(s, left, right, disp_q4, confidence);
    if (st != NEGOBS_OK) {
        return st;
    }
    memset(&s->st, 0, sizeof s->st);
    if (s->clock != NULL) {
        s->lap = s->clock(s->clock_user);
    }
    top = s->first_row;
    if (top == 0) {
        process_frame(s, left, right, disp_q4, confidence);
    } else {
        /* Rows above first_row are not matched: the engine runs on a crop
         * of rows [top, h) with the geometry of that smaller frame (every
         * buffer sized for the full frame is large enough), then restores
         * its own. Rows above get no value and confidence 0. */
        const int32_t h_full = s->h;
        const int32_t lh_full = s->lh;
        const int32_t th_full = s->th;
        negobs_image_u8_t l2 = crop_u8(left, top);
        negobs_image_u8_t r2 = crop_u8(right, top);
        negobs_image_s16_t d2 = crop_s16(disp_q4, top);
        negobs_image_u8_t c2;
        negobs_image_u8_t *cp = NULL;
        int32_t y;
        if (confidence != NULL) {
            c2 = crop_u8(confidence, top);
            cp = &c2;
        }
        s->h = h_full - top;
        s->lh = s->h / STX_LOWRES;
        s->th = (s->h + s->tile - 1) / s->tile;
        process_frame(s, &l2, &r2, &d2, cp);
        s->h = h_full;
        s->lh = lh_full;
        s->th = th_full;
        for (y = 0; y < top; y++) {
            int16_t *row = negobs_image_s16_row(disp_q4, y);
            int32_t x;
            for (x = 0; x < s->w; x++) {
                row[x] = NEGOBS_DISP_INVALID;
            }
            if (confidence != NULL) {
                memset(negobs_image_u8_row(confidence, y), 0, (size_t)s->w);
            }
        }
    }
    s->st.first_row = top;
    stx_lap(s, NEGOBS_STEREO_STAGE_OUTPUT);
    if (s->exec_failed) {
        /* a broken executor: the map has holes of unknown content */
        s->exec_failed = 0;
        return NEGOBS_ERR_STATE;
    }
    if (stats != NULL) {
        *stats = s->st;
    }
    /* debug builds: a stage that wrote past a carved block shows here */
    if (negobs_arena_check(&s->arena) != NEGOBS_OK) {
        return NEGOBS_ERR_CORRUPT;
    }
    return NEGOBS_OK;
}
