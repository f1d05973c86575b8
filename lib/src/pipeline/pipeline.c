#include "negobs/pipeline.h"

#include <string.h>

#include "arena.h"
#include "coarse.h"
#include "detect/detect_int.h"
#include "pipeline_private.h"

#define PIPELINE_MAGIC 0x4E50494Cu /* "NPIL" */

/* The public storage must hold the private layout (C99: no static_assert;
 * a negative array size stops the build). Same members, so the alignment
 * is the same too. */
typedef char negobs_pipeline_storage_fits
    [(sizeof(negobs_pipeline_priv_t) <= sizeof(negobs_pipeline_t)) ? 1 : -1];

void negobs_pipeline_config_default(negobs_pipeline_config_t *cfg,
                                    int32_t width, int32_t height)
{
    memset(cfg, 0, sizeof *cfg);
    negobs_stereo_config_default(&cfg->stereo, width, height);
    negobs_valign_config_default(&cfg->valign, width, height);
    cfg->valign.min_disp = cfg->stereo.min_disp;
    cfg->valign.max_disp = cfg->stereo.max_disp;
    negobs_detect_config_default(&cfg->detect, width, height);
    negobs_alert_config_default(&cfg->alert);
    cfg->detect.max_disp_q4 = (cfg->stereo.max_disp + 1) * NEGOBS_DISP_ONE;
    /* For drop detection a missing match is safer than a carried one: the
     * matcher's defaults (floor 100, tau 0.5) are tuned for dense maps and
     * let weak windows grow across bland paint into false holes. Measured
     * reasons: docs/decisions/0001-pipeline-strict-matcher.md. */
    cfg->stereo.texture_min = 2500;
    cfg->stereo.ncc_tau_q14 = 9830; /* 0.6 */
    cfg->stereo_roi = 1;
    cfg->roi_margin_rows = height / 8;
    cfg->vertical_every_frames = 10;
    cfg->coarse_pass = 1;
    /* The pass pays when the detector would discard a sizeable part of
     * the rows it reads. On textured floors a median of 3-4 % of those
     * pixels are weak (occlusions beside obstacles, the drop's own face,
     * hard shadows), on smooth concrete half or more: an eighth lies
     * between (figures in docs/DETECTION.md). */
    cfg->coarse_weak_permille = 125;
}

/*
 * negobs_pipeline_roi_first_row: roi_margin_rows above the highest
 * row (over both image edges, so roll is covered) where the ground model
 * is still nearer than range_max, the detector's scan limit; never below
 * the top of the ground fit's rows. 0 when the plane does not descend
 * towards the bottom of the image (no usable model).
 */
int32_t negobs_pipeline_roi_first_row(const negobs_pipeline_config_t *cfg,
                                      const negobs_detect_result_t *det)
{
    const negobs_detect_config_t *d;
    const negobs_ground_plane_t *plane;
    int32_t h;
    int32_t w;
    int32_t d_far;
    int32_t fit_top;
    int32_t v;
    int32_t top;
    if (cfg == NULL || det == NULL || !cfg->stereo_roi || !det->ground_valid) {
        return 0;
    }
    d = &cfg->detect;
    plane = &det->plane;
    h = d->rig.height;
    w = d->rig.width;
    d_far = negobs_disp_q4_from_depth_mm(&d->rig, d->range_max_mm);
    fit_top = h - (h * d->fit_rows_pct) / 100;
    v = h - 1;
    if (plane->b_q20 <= 0 || d_far <= 0) {
        return 0;
    }
    while (v > 0 && (negobs_ground_disp_q4(plane, 0, v - 1) >= d_far ||
                     negobs_ground_disp_q4(plane, w - 1, v - 1) >= d_far)) {
        v--;
    }
    top = v - cfg->roi_margin_rows;
    if (top > fit_top - cfg->roi_margin_rows) {
        top = fit_top - cfg->roi_margin_rows;
    }
    if (top > h - NEGOBS_STEREO_MIN_HEIGHT) {
        top = h - NEGOBS_STEREO_MIN_HEIGHT;
    }
    return (top > 0) ? top : 0;
}

typedef struct carve_out {
    void *valign_ws;
    size_t valign_bytes;
    uint8_t *aligned;
    void *stereo_ws;
    size_t stereo_bytes;
    void *detect_ws;
    size_t detect_bytes;
    int16_t *disp;
    uint8_t *conf;
    int coarse; /* the half-resolution pass is carved     */
    negobs_stereo_config_t half_cfg;
    void *half_ws;
    size_t half_bytes;
    uint8_t *half_left;
    uint8_t *half_right;
    int16_t *half_disp;
    uint8_t *half_conf;
} carve_out_t;

/*
 * The sizes of the stage workspaces come from the stages themselves; the
 * pipeline only adds the two intermediate images. Same code measures and
 * carves (see arena.h).
 */
static negobs_status_t carve(negobs_arena_t *a,
                             const negobs_pipeline_config_t *cfg,
                             carve_out_t *out)
{
    negobs_status_t st;
    size_t npix;

    st = negobs_stereo_workspace_size(&cfg->stereo, &out->stereo_bytes);
    if (st != NEGOBS_OK) {
        return st;
    }
    st = negobs_detect_workspace_size(&cfg->detect, &out->detect_bytes);
    if (st != NEGOBS_OK) {
        return st;
    }
    npix = (size_t)cfg->stereo.width * (size_t)cfg->stereo.height;
    out->valign_bytes = 0;
    out->valign_ws = NULL;
    out->aligned = NULL;
    if (cfg->valign.enable) {
        st = negobs_valign_workspace_size(&cfg->valign, &out->valign_bytes);
        if (st != NEGOBS_OK) {
            return st;
        }
        out->valign_ws = negobs_arena_take(a, out->valign_bytes);
        out->aligned = (uint8_t *)negobs_arena_take(a, npix);
    }
    out->stereo_ws = negobs_arena_take(a, out->stereo_bytes);
    out->detect_ws = negobs_arena_take(a, out->detect_bytes);
    out->disp = (int16_t *)negobs_arena_take(a, npix * sizeof(int16_t));
    out->conf = (uint8_t *)negobs_arena_take(a, npix);
    out->coarse = pl_coarse_config(cfg, &out->half_cfg);
    if (out->coarse) {
        size_t nhalf = (size_t)out->half_cfg.width *
                       (size_t)out->half_cfg.height;
        st = negobs_stereo_workspace_size(&out->half_cfg, &out->half_bytes);
        if (st != NEGOBS_OK) {
            return st;
        }
        out->half_ws = negobs_arena_take(a, out->half_bytes);
        out->half_left = (uint8_t *)negobs_arena_take(a, nhalf);
        out->half_right = (uint8_t *)negobs_arena_take(a, nhalf);
        out->half_disp = (int16_t *)negobs_arena_take(a,
                                                      nhalf * sizeof(int16_t));
        out->half_conf = (uint8_t *)negobs_arena_take(a, nhalf);
    }
    return negobs_arena_status(a);
}

static negobs_status_t check_config(const negobs_pipeline_config_t *cfg)
{
    if (cfg == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    /* The detector must describe the same frames the matcher produces. */
    if (cfg->detect.rig.width != cfg->stereo.width ||
        cfg->detect.rig.height != cfg->stereo.height) {
        return NEGOBS_ERR_INVAL;
    }
    if (cfg->valign.enable && (cfg->valign.width != cfg->stereo.width ||
                               cfg->valign.height != cfg->stereo.height)) {
        return NEGOBS_ERR_INVAL;
    }
    if (cfg->stereo_roi < 0 || cfg->stereo_roi > 1 ||
        cfg->roi_margin_rows < 0 ||
        cfg->roi_margin_rows > cfg->stereo.height ||
        cfg->vertical_every_frames < 1 || cfg->vertical_every_frames > 1000 ||
        cfg->coarse_pass < 0 || cfg->coarse_pass > 1 ||
        cfg->coarse_weak_permille < 0 || cfg->coarse_weak_permille > 1000) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

negobs_status_t negobs_pipeline_workspace_size(
    const negobs_pipeline_config_t *cfg, size_t *bytes_out)
{
    negobs_arena_t a;
    carve_out_t c;
    negobs_status_t st;

    if (bytes_out == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    st = check_config(cfg);
    if (st != NEGOBS_OK) {
        return st;
    }
    negobs_arena_init(&a, NULL, 0);
    st = carve(&a, cfg, &c);
    if (st != NEGOBS_OK) {
        return st;
    }
    *bytes_out = negobs_arena_used(&a);
    return NEGOBS_OK;
}

static void half_image(negobs_image_u8_t *img, uint8_t *data,
                       const negobs_stereo_config_t *c)
{
    img->data = data;
    img->width = c->width;
    img->height = c->height;
    img->stride = c->width;
}

static negobs_status_t half_init(negobs_pipeline_priv_t *p,
                                 const carve_out_t *c)
{
    negobs_stereo_config_t h = c->half_cfg;
    if (p->cfg.stereo.vertical_search == 0) {
        /* aligned rows (valign) or a fixed offset: no search here either */
        h.vertical_search = 0;
        if (p->cfg.valign.enable) {
            h.vertical_offset = 0;
        }
    }
    half_image(&p->left_half, c->half_left, &h);
    half_image(&p->right_half, c->half_right, &h);
    half_image(&p->conf_half, c->half_conf, &h);
    p->disp_half.data = c->half_disp;
    p->disp_half.width = h.width;
    p->disp_half.height = h.height;
    p->disp_half.stride = h.width;
    return negobs_stereo_init(&p->stereo_half, &h, c->half_ws, c->half_bytes);
}

negobs_status_t negobs_pipeline_init(negobs_pipeline_t *ctx,
                                     const negobs_pipeline_config_t *cfg,
                                     void *workspace, size_t workspace_bytes)
{
    negobs_arena_t a;
    carve_out_t c;
    negobs_status_t st;
    negobs_pipeline_priv_t *p;

    if (ctx == NULL || workspace == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(ctx, 0, sizeof *ctx);
    p = negobs_pipeline_priv(ctx);
    st = check_config(cfg);
    if (st != NEGOBS_OK) {
        return st;
    }
    negobs_arena_init(&a, workspace, workspace_bytes);
    if (negobs_arena_status(&a) != NEGOBS_OK) {
        return negobs_arena_status(&a);
    }
    st = carve(&a, cfg, &c);
    if (st != NEGOBS_OK) {
        return st;
    }
    p->cfg = *cfg;
    if (cfg->valign.enable) {
        /* the rows are aligned before matching: an integer search on top
         * would only add noise to an already sub-pixel alignment */
        p->cfg.stereo.vertical_search = 0;
        p->cfg.stereo.vertical_offset = 0;
        st = negobs_valign_init(&p->valign, &p->cfg.valign, c.valign_ws,
                                c.valign_bytes);
        if (st != NEGOBS_OK) {
            return st;
        }
        p->right_aligned.data = c.aligned;
        p->right_aligned.width = cfg->stereo.width;
        p->right_aligned.height = cfg->stereo.height;
        p->right_aligned.stride = cfg->stereo.width;
    }
    st = negobs_stereo_init(&p->stereo, &p->cfg.stereo, c.stereo_ws,
                            c.stereo_bytes);
    if (st != NEGOBS_OK) {
        return st;
    }
    st = negobs_detect_init(&p->detect, &p->cfg.detect, c.detect_ws,
                            c.detect_bytes);
    if (st != NEGOBS_OK) {
        return st;
    }
    st = negobs_alert_init(&p->alert, &p->cfg.alert, NULL, 0);
    if (st != NEGOBS_OK) {
        return st;
    }
    p->disp_q4.data = c.disp;
    p->disp_q4.width = cfg->stereo.width;
    p->disp_q4.height = cfg->stereo.height;
    p->disp_q4.stride = cfg->stereo.width;
    p->confidence.data = c.conf;
    p->confidence.width = cfg->stereo.width;
    p->confidence.height = cfg->stereo.height;
    p->confidence.stride = cfg->stereo.width;
    p->coarse = c.coarse;
    if (c.coarse) {
        st = half_init(p, &c);
        if (st != NEGOBS_OK) {
            return st;
        }
    }
    /* no offset found yet: the first frame searches */
    p->vframes = (uint32_t)cfg->vertical_every_frames;
    p->voff = 0;
    p->magic = PIPELINE_MAGIC;
    return NEGOBS_OK;
}

/*
 * A frame without a usable disparity map still has to reach the user: the
 * verdict is "no information" with the reason, never "clear".
 */
static void no_info_result(negobs_detect_result_t *res)
{
    memset(res, 0, sizeof *res);
    res->state = NEGOBS_DETECT_NO_INFO;
    res->reasons = NEGOBS_DEGRADED_BAD_INPUT;
    res->level = NEGOBS_LEVEL_NONE;
    res->nearest_range_mm = -1;
}

/* 1 when this frame matches with the offset the last search found
 * (vertical_every_frames); 0 when it searches: the first frame, every
 * vertical_every_frames-th one, and every frame until one search has
 * succeeded (vframes stays at the period until then). */
static int vertical_hold(negobs_pipeline_priv_t *p)
{
    if (p->cfg.stereo.vertical_search <= 0 ||
        p->vframes + 1u >= (uint32_t)p->cfg.vertical_every_frames) {
        return 0;
    }
    p->vframes++;
    return negobs_stereo_hold_vertical_offset(&p->stereo, p->voff) ==
           NEGOBS_OK;
}

/*
 * The half-resolution pass (coarse.c) on the pair the full-size matcher
 * just matched, when the weak share of its map is above
 * coarse_weak_permille. Same rows (from the full-size first row), the
 * full-size vertical offset halved. A refused half frame leaves the
 * full-size map as it is.
 */
static void half_pass(negobs_pipeline_priv_t *p, const negobs_image_u8_t *left,
                      const negobs_image_u8_t *right,
                      negobs_pipeline_result_t *result)
{
    const negobs_detect_config_t *d = &p->cfg.detect;
    int32_t y0 = result->stereo.first_row;
    int32_t hy0 = y0 / 2;
    negobs_stereo_stats_t hs;

    result->weak_permille = pl_weak_permille(
        &p->confidence, y0, p->cfg.stereo.max_disp, d->min_confidence);
    if (result->weak_permille <= p->cfg.coarse_weak_permille) {
        return;
    }
    pl_bin2_u8(left, &p->left_half);
    pl_bin2_u8(right, &p->right_half);
    if (p->cfg.stereo.vertical_search > 0) {
        int32_t v = result->stereo.vertical_offset;
        /* half a row rounds away from zero: either way it is half a
         * half-size row off, and a row is the search's own step */
        v = (v >= 0) ? (v + 1) / 2 : -((1 - v) / 2);
        (void)negobs_stereo_hold_vertical_offset(&p->stereo_half, v);
    }
    if (hy0 > p->disp_half.height - NEGOBS_STEREO_MIN_HEIGHT) {
        hy0 = p->disp_half.height - NEGOBS_STEREO_MIN_HEIGHT;
    }
    (void)negobs_stereo_set_first_row(&p->stereo_half, hy0 > 0 ? hy0 : 0);
    if (negobs_stereo_process(&p->stereo_half, &p->left_half, &p->right_half,
                              &p->disp_half, &p->conf_half,
                              &hs) != NEGOBS_OK) {
        return;
    }
    result->coarse_ran = 1;
    result->coarse_replaced = pl_coarse_fuse(
        left, &p->disp_q4, &p->confidence, &p->disp_half, &p->conf_half, y0,
        d->min_confidence, p->cfg.stereo.min_disp * NEGOBS_DISP_ONE,
        d->max_disp_q4);
}

/* Ticks since *t0 go to stage k; *t0 moves on. No clock: nothing. */
static void lap(negobs_pipeline_priv_t *p, uint32_t *t0,
                negobs_pipeline_result_t *result, negobs_pipeline_stage_t k)
{
    uint32_t t;
    if (p->clock == NULL) {
        return;
    }
    t = p->clock(p->clock_user);
    result->stage_ticks[k] += (uint32_t)(t - *t0);
    *t0 = t;
}

negobs_status_t negobs_pipeline_process(negobs_pipeline_t *ctx,
                                        const negobs_pipeline_frame_t *frame,
                                        negobs_pipeline_result_t *result)
{
    negobs_pipeline_priv_t *p;
    negobs_detect_frame_t df;
    const negobs_image_u8_t *right = NULL; /* the right image matched */
    negobs_alert_input_t in;
    negobs_status_t st;
    uint32_t t0 = 0;

    if (ctx == NULL || frame == NULL || result == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    p = negobs_pipeline_priv(ctx);
    if (p->magic != PIPELINE_MAGIC) {
        return NEGOBS_ERR_STATE;
    }
    memset(result, 0, sizeof *result);
    if (p->clock != NULL) {
        t0 = p->clock(p->clock_user);
    }
    if (frame->left == NULL || frame->right == NULL) {
        st = NEGOBS_ERR_INVAL;
    } else {
        right = frame->right;
        st = NEGOBS_OK;
        if (p->cfg.valign.enable) {
            st = negobs_valign_process(&p->valign, frame->left, right,
                                       &p->right_aligned, &result->valign);
            right = &p->right_aligned;
            lap(p, &t0, result, NEGOBS_PIPELINE_STAGE_VALIGN);
        }
        if (st == NEGOBS_OK) {
            int held = vertical_hold(p);
            st = negobs_stereo_process(&p->stereo, frame->left, right,
                                       &p->disp_q4, &p->confidence,
                                       &result->stereo);
            if (st == NEGOBS_OK && !held) {
                p->voff = result->stereo.vertical_offset;
                p->vframes = 0;
            }
            if (st == NEGOBS_OK && p->coarse) {
                half_pass(p, frame->left, right, result);
            }
        }
        if (st == NEGOBS_OK && p->cfg.valign.enable) {
            /* the next estimate searches the range the matcher used */
            (void)negobs_valign_set_disp_range(&p->valign,
                                               result->stereo.range_min,
                                               result->stereo.range_max);
        }
    }
    lap(p, &t0, result, NEGOBS_PIPELINE_STAGE_STEREO);
    result->stereo_status = st;
    if (st == NEGOBS_OK) {
        memset(&df, 0, sizeof df);
        df.disp_q4 = &p->disp_q4;
        df.confidence = &p->confidence;
        df.left = frame->left;
        /* the one photometric gate judges both images */
        if (negobs_detect_photo_stats(frame->right, &result->right_stats) ==
            NEGOBS_OK) {
            df.right_stats = &result->right_stats;
        }
        df.right = right;
        df.t_left_ms = frame->t_left_ms;
        df.t_right_ms = frame->t_right_ms;
        df.now_ms = frame->now_ms;
        df.first_row = result->stereo.first_row;
        df.left_half = result->coarse_ran ? &p->left_half : NULL;
        df.disp_half_q4 = result->coarse_ran ? &p->disp_half : NULL;
        st = negobs_detect_process(&p->detect, &df, &result->detect);
    }
    if (st != NEGOBS_OK) {
        no_info_result(&result->detect);
    }
    lap(p, &t0, result, NEGOBS_PIPELINE_STAGE_DETECT);
    /* next frame: only the rows the detector will read, as far as this
     * frame's ground model says; every row without one */
    (void)negobs_stereo_set_first_row(
        &p->stereo, (st == NEGOBS_OK) ? negobs_pipeline_roi_first_row(
                                            &p->cfg, &result->detect)
                                      : 0);
    lap(p, &t0, result, NEGOBS_PIPELINE_STAGE_STEREO);
    negobs_alert_input_from_result(&result->detect, frame->battery_low,
                                   frame->now_ms, &in);
    st = negobs_alert_update(&p->alert, frame->now_ms, &in, &result->motor);
    lap(p, &t0, result, NEGOBS_PIPELINE_STAGE_ALERT);
    return st;
}

negobs_status_t negobs_pipeline_set_clock(negobs_pipeline_t *ctx,
                                          negobs_pipeline_clock_fn clock,
                                          void *user)
{
    negobs_pipeline_priv_t *p;
    if (ctx == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    p = negobs_pipeline_priv(ctx);
    if (p->magic != PIPELINE_MAGIC) {
        return NEGOBS_ERR_STATE;
    }
    p->clock = clock;
    p->clock_user = (clock != NULL) ? user : NULL;
    return negobs_stereo_set_clock(&p->stereo, clock, p->clock_user);
}

negobs_status_t negobs_pipeline_set_executor(negobs_pipeline_t *ctx,
                                             const negobs_executor_t *exec)
{
    negobs_pipeline_priv_t *p;
    if (ctx == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    p = negobs_pipeline_priv(ctx);
    if (p->magic != PIPELINE_MAGIC) {
        return NEGOBS_ERR_STATE;
    }
    if (p->coarse) {
        negobs_status_t st = negobs_stereo_set_executor(&p->stereo_half, exec);
        if (st != NEGOBS_OK) {
            return st;
        }
    }
    {
        const negobs_status_t st = negobs_stereo_set_executor(&p->stereo,
                                                              exec);
        if (st != NEGOBS_OK) {
            return st;
        }
    }
    /* the detector's row bands (the pooled frames' pass) on the same
     * threads: its bands keep their own scratch, any worker count fits */
    return negobs_detect_set_executor(&p->detect, exec);
}

negobs_status_t negobs_pipeline_tick(negobs_pipeline_t *ctx, uint32_t now_ms,
                                     negobs_motor_cmd_t *motor)
{
    negobs_pipeline_priv_t *p;
    if (ctx == NULL || motor == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    p = negobs_pipeline_priv(ctx);
    if (p->magic != PIPELINE_MAGIC) {
        return NEGOBS_ERR_STATE;
    }
    return negobs_alert_update(&p->alert, now_ms, NULL, motor);
}

/* The initialised private view, or NULL. */
static const negobs_pipeline_priv_t *ready(const negobs_pipeline_t *ctx)
{
    const negobs_pipeline_priv_t *p;
    if (ctx == NULL) {
        return NULL;
    }
    p = negobs_pipeline_priv_const(ctx);
    return (p->magic == PIPELINE_MAGIC) ? p : NULL;
}

const negobs_image_s16_t *negobs_pipeline_disparity(
    const negobs_pipeline_t *ctx)
{
    const negobs_pipeline_priv_t *p = ready(ctx);
    return (p != NULL) ? &p->disp_q4 : NULL;
}

const negobs_image_u8_t *negobs_pipeline_confidence(
    const negobs_pipeline_t *ctx)
{
    const negobs_pipeline_priv_t *p = ready(ctx);
    return (p != NULL) ? &p->confidence : NULL;
}

const negobs_image_u8_t *negobs_pipeline_aligned_right(
    const negobs_pipeline_t *ctx)
{
    const negobs_pipeline_priv_t *p = ready(ctx);
    return (p != NULL && p->cfg.valign.enable) ? &p->right_aligned : NULL;
}
