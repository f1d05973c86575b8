/*
 * The library's whole pipeline behind negobs_run (see the header). The
 * photometric gate is the detector's, on both images (the pipeline passes
 * it the right image's statistics); this file only maps its reasons to
 * the app's and adds the left/right brightness check.
 */
#include <stddef.h>
#include <string.h>

#include "app_pipeline.h"
#include "negobs/pipeline.h"
#include "negobs_port/pool.h"

/*
 * The library pipeline lives in static memory: its workspace at the
 * largest supported frame (752x480, the DUO camera) with debug guards is
 * about 3.2 MB with one matcher thread, the half-resolution pass for weak
 * texture included (docs/DETECTION.md); each further thread adds a band
 * scratch area of about 1.3 MB there (1.05 MB at 640x480, 0.6 MB at
 * 320x240: the full-size and the half-size matcher's), so 7 MiB hold 4
 * threads at 752x480 and 640x480 (fewer are used where fewer fit: same
 * output). Untouched pages of a static buffer cost no RAM.
 * NEGOBS_RUN_MAX sizes beyond that are refused with a no-information
 * verdict rather than a crash.
 */
#define APP_WS_BYTES (7168u * 1024u)
static uint8_t lib_ws[APP_WS_BYTES] __attribute__((aligned(16)));
static negobs_pipeline_t lib_pipe;
static int32_t lib_w;
static int32_t lib_h;
static int lib_ready;
static negobs_pool_t *lib_pool; /* band threads (threads > 1)  */
static int32_t lib_pool_threads;
static int32_t lib_workers; /* matcher threads of this frame size */
static int32_t lib_profile; /* its NEGOBS_STEREO_PROFILE_*         */

void app_pipeline_config_default(app_pipeline_config_t *cfg)
{
    negobs_detect_config_t d;
    /* The photometric thresholds have one home, the detector's defaults
     * (the size does not matter for them). */
    negobs_detect_config_default(&d, 320, 240);
    cfg->dark_mean_min = d.dark_mean_min;
    cfg->sat_permille_max = d.saturated_max_permille;
    cfg->texture_min_q4 = d.texture_min_q4;
    /* Left and right see the same scene through the same kind of sensor:
     * 60 grey levels apart (a quarter of the range) is a covered lens, a
     * lens in the sun or a broken exposure control, not a scene. */
    cfg->lr_mean_diff_max = 60;
    cfg->focal_px = 250;
    cfg->baseline_mm = 120;
    cfg->cam_height_mm = 1200;
    cfg->cam_pitch_mdeg = 20000;
    cfg->max_disp = 63;
    cfg->vertical_align = 0;
    cfg->row_crop = 1;
    cfg->focal_q4 = 0;
    cfg->baseline_um = 0;
    cfg->cx_q4 = -1;
    cfg->cy_q4 = -1;
    cfg->sync_tol_ms = 10;
    cfg->max_frame_age_ms = 150;
    cfg->latency_budget_ms = 250;
    cfg->threads = 1;
}

negobs_status_t app_pipeline_init(app_pipeline_t *p,
                                  const app_pipeline_config_t *cfg)
{
    if (p == NULL || cfg == NULL || cfg->dark_mean_min < 0 ||
        cfg->dark_mean_min > 255 || cfg->sat_permille_max < 0 ||
        cfg->sat_permille_max > 1000 || cfg->texture_min_q4 < 0 ||
        cfg->texture_min_q4 > 4096 || cfg->lr_mean_diff_max < 0 ||
        cfg->lr_mean_diff_max > 255 || cfg->focal_px < 50 ||
        cfg->focal_px > 4000 || cfg->baseline_mm < 10 ||
        cfg->baseline_mm > 1000 ||
        (cfg->cam_height_mm != 0 && cfg->cam_height_mm < 300) ||
        cfg->cam_height_mm > 3000 || cfg->cam_pitch_mdeg < 0 ||
        cfg->cam_pitch_mdeg > 60000 || cfg->max_disp < 8 ||
        cfg->max_disp > 255 || cfg->sync_tol_ms < 0 ||
        cfg->vertical_align < 0 || cfg->vertical_align > 1 ||
        cfg->row_crop < 0 || cfg->row_crop > 1 || cfg->sync_tol_ms > 1000 ||
        cfg->max_frame_age_ms < 1 || cfg->max_frame_age_ms > 60000 ||
        cfg->latency_budget_ms < 0 || cfg->latency_budget_ms > 60000 ||
        cfg->focal_q4 < 0 || cfg->focal_q4 > 4000 * 16 ||
        cfg->baseline_um < 0 || cfg->baseline_um > 1000000 ||
        cfg->cx_q4 < -1 || cfg->cy_q4 < -1 || cfg->threads < 1 ||
        cfg->threads > NEGOBS_POOL_MAX_THREADS) {
        return NEGOBS_ERR_INVAL;
    }
    memset(p, 0, sizeof *p);
    lib_ready = 0; /* a new configuration sets the library up again */
    p->cfg = *cfg;
    return NEGOBS_OK;
}

void app_pipeline_set_clock(app_pipeline_t *p, negobs_stereo_clock_fn now_ns,
                            void *user)
{
    if (p != NULL) {
        p->clock_ns = now_ns;
        p->clock_user = user;
    }
}

/* The band threads: a pool of `threads` (kept across re-initialisations of
 * the same count) handed to the pipeline; none for one thread. */
static negobs_status_t pool_setup(int32_t threads)
{
    negobs_executor_t e;
    if (lib_pool != NULL && lib_pool_threads != threads) {
        negobs_pool_destroy(lib_pool);
        lib_pool = NULL;
        lib_pool_threads = 0;
    }
    if (threads < 2) {
        return negobs_pipeline_set_executor(&lib_pipe, NULL);
    }
    if (lib_pool == NULL) {
        negobs_status_t st = negobs_pool_create(&lib_pool, threads);
        if (st != NEGOBS_OK) {
            /* no thread to be had: the same output on this one */
            return negobs_pipeline_set_executor(&lib_pipe, NULL);
        }
        lib_pool_threads = threads;
    }
    e = negobs_pool_executor(lib_pool);
    return negobs_pipeline_set_executor(&lib_pipe, &e);
}

/* The workspace of pc with the fast memory profile where lib_ws holds it,
 * else with the compact one: NEGOBS_ERR_NOSPACE when neither fits. The
 * fast profile's memo saves the growth's repeated correlations (about a
 * tenth of the matcher's instructions) and changes no output
 * (docs/DISPARITY.md, "Memory profiles"). */
static negobs_status_t ws_fit(negobs_pipeline_config_t *pc, size_t *bytes)
{
    static const int32_t profiles[2] = {NEGOBS_STEREO_PROFILE_FAST,
                                        NEGOBS_STEREO_PROFILE_COMPACT};
    int i;
    for (i = 0; i < 2; i++) {
        negobs_status_t st;
        pc->stereo.memory_profile = profiles[i];
        st = negobs_pipeline_workspace_size(pc, bytes);
        if (st != NEGOBS_OK) {
            return st;
        }
        if (*bytes <= sizeof lib_ws) {
            return NEGOBS_OK;
        }
    }
    return NEGOBS_ERR_NOSPACE;
}

/* (Re)initialise the library pipeline for this frame size. */
static negobs_status_t lib_setup(const app_pipeline_config_t *c, int32_t w,
                                 int32_t h)
{
    negobs_pipeline_config_t pc;
    size_t bytes = 0;
    negobs_status_t st;

    if (lib_ready && lib_w == w && lib_h == h) {
        return NEGOBS_OK;
    }
    lib_ready = 0;
    negobs_pipeline_config_default(&pc, w, h);
    /* The matcher refuses a range wider than half the frame. */
    pc.stereo.max_disp = (c->max_disp < w / 2) ? c->max_disp : w / 2 - 1;
    pc.detect.max_disp_q4 = (pc.stereo.max_disp + 1) * NEGOBS_DISP_ONE;
    pc.valign.enable = c->vertical_align;
    pc.stereo_roi = c->row_crop;
    pc.valign.max_disp = pc.stereo.max_disp;
    /* The focal length is given for the frame the camera delivers. */
    pc.detect.rig.focal_q4 = c->focal_q4 > 0 ? c->focal_q4
                                             : c->focal_px * NEGOBS_DISP_ONE;
    pc.detect.rig.baseline_um = c->baseline_um > 0 ? c->baseline_um
                                                   : c->baseline_mm * 1000;
    if (c->cx_q4 >= 0) {
        pc.detect.rig.cx_q4 = c->cx_q4;
    }
    if (c->cy_q4 >= 0) {
        pc.detect.rig.cy_q4 = c->cy_q4;
    }
    pc.detect.cam_height_mm = c->cam_height_mm;
    pc.detect.cam_pitch_mdeg = c->cam_pitch_mdeg;
    /* One limit for "a pair": what the capture pairs, the detector takes. */
    pc.detect.sync_tol_ms = c->sync_tol_ms;
    pc.detect.max_frame_age_ms = c->max_frame_age_ms;
    pc.detect.dark_mean_min = c->dark_mean_min;
    pc.detect.saturated_max_permille = c->sat_permille_max;
    pc.detect.texture_min_q4 = c->texture_min_q4;
    /* One scratch area per thread; fewer threads where the workspace
     * cannot hold them all, and the memo only where it fits beside them
     * (threads cut the latency more than the memo does). The disparities
     * depend on neither. */
    for (pc.stereo.band_workers = c->threads;; pc.stereo.band_workers--) {
        st = ws_fit(&pc, &bytes);
        if (st == NEGOBS_OK) {
            break;
        }
        if (st != NEGOBS_ERR_NOSPACE || pc.stereo.band_workers == 1) {
            return st;
        }
    }
    st = negobs_pipeline_init(&lib_pipe, &pc, lib_ws, bytes);
    if (st != NEGOBS_OK) {
        return st;
    }
    st = pool_setup(pc.stereo.band_workers);
    if (st != NEGOBS_OK) {
        return st;
    }
    lib_w = w;
    lib_h = h;
    lib_workers = pc.stereo.band_workers;
    lib_profile = pc.stereo.memory_profile;
    lib_ready = 1;
    return NEGOBS_OK;
}

/* The statistics the detector's gate judged, for logs and the pair check. */
static void photo_of(const negobs_pipeline_result_t *r, app_frame_stats_t *st)
{
    const negobs_photo_stats_t *ph[2];
    int i;
    ph[0] = &r->detect.stats;
    ph[1] = &r->right_stats;
    for (i = 0; i < 2; i++) {
        st->mean[i] = ph[i]->mean;
        st->sat_permille[i] = ph[i]->saturated_permille;
        st->texture_q4[i] = ph[i]->texture_q4;
    }
}

/* The detector's photometric reasons, named as the app's; DETECTOR for
 * none of them. */
static app_reason_t reason_of(uint32_t detect_reasons)
{
    if ((detect_reasons & NEGOBS_DEGRADED_TOO_DARK) != 0) {
        return APP_REASON_DARK;
    }
    if ((detect_reasons & NEGOBS_DEGRADED_SATURATED) != 0) {
        return APP_REASON_SATURATED;
    }
    if ((detect_reasons & NEGOBS_DEGRADED_LOW_TEXTURE) != 0) {
        return APP_REASON_TEXTURELESS;
    }
    return APP_REASON_DETECTOR;
}

/* Detector verdict -> app verdict; "clear" only when it really looked. */
static app_verdict_t verdict_of(const app_pipeline_t *p,
                                const negobs_pipeline_result_t *r,
                                app_frame_stats_t *st)
{
    const negobs_detect_result_t *d = &r->detect;
    int32_t lr = st->mean[0] - st->mean[1];
    st->detect_reasons = d->reasons;
    st->nearest_range_mm = d->nearest_range_mm;
    st->clear_to_mm = d->clear_to_mm;
    st->short_sight = d->short_sight;
    st->hazards = d->n_hazards;
    st->mount = d->mount;
    st->ground_ref_by = d->ground_ref_by;
    st->ground_ref_height_mm = d->ground_ref_height_mm;
    st->ground_ref_pitch_mdeg = d->ground_ref_pitch_mdeg;
    /* An image the gate refused names the reason; else two images that
     * each passed but disagree: no match between them can be trusted,
     * whatever the detector made of it. */
    st->reason = reason_of(d->reasons);
    if (st->reason == APP_REASON_DETECTOR &&
        (lr < 0 ? -lr : lr) > p->cfg.lr_mean_diff_max) {
        st->reason = APP_REASON_MISMATCH;
        return APP_VERDICT_NO_INFO;
    }
    if (d->state == NEGOBS_DETECT_NO_INFO) {
        return APP_VERDICT_NO_INFO;
    }
    st->reason = APP_REASON_NONE;
    if (d->level == NEGOBS_LEVEL_IMMINENT) {
        return APP_VERDICT_IMMINENT;
    }
    if (d->level == NEGOBS_LEVEL_CAUTION) {
        return APP_VERDICT_CAUTION;
    }
    return APP_VERDICT_CLEAR;
}

app_verdict_t app_process_pair(app_pipeline_t *p,
                               const negobs_image_u8_t *left,
                               const negobs_image_u8_t *right)
{
    return app_process_pair_at(p, left, right, 0, 0, 0);
}

app_verdict_t app_process_pair_at(app_pipeline_t *p,
                                  const negobs_image_u8_t *left,
                                  const negobs_image_u8_t *right,
                                  uint32_t t_left_ms, uint32_t t_right_ms,
                                  uint32_t now_ms)
{
    app_frame_stats_t *st = &p->last;
    negobs_pipeline_frame_t fr;
    negobs_pipeline_result_t res;
    memset(st, 0, sizeof *st);
    st->latency_ms = -1;
    p->res_valid = 0;
    if (left == NULL || right == NULL || left->width != right->width ||
        left->height != right->height ||
        negobs_image_u8_check(left) != NEGOBS_OK ||
        negobs_image_u8_check(right) != NEGOBS_OK) {
        st->reason = APP_REASON_BAD_INPUT;
        return APP_VERDICT_NO_INFO;
    }
    if (lib_setup(&p->cfg, left->width, left->height) != NEGOBS_OK) {
        st->reason = APP_REASON_BAD_INPUT;
        return APP_VERDICT_NO_INFO;
    }
    memset(&fr, 0, sizeof fr);
    fr.left = left;
    fr.right = right;
    fr.t_left_ms = t_left_ms;
    fr.t_right_ms = t_right_ms;
    fr.now_ms = now_ms;
    /* set on every pair: lib_setup may have initialised it again */
    (void)negobs_pipeline_set_clock(&lib_pipe, p->clock_ns, p->clock_user);
    if (negobs_pipeline_process(&lib_pipe, &fr, &res) != NEGOBS_OK) {
        st->reason = APP_REASON_BAD_INPUT;
        return APP_VERDICT_NO_INFO;
    }
    p->res = res;
    p->res_valid = 1;
    if (res.stereo_status != NEGOBS_OK) {
        st->reason = APP_REASON_BAD_INPUT;
        return APP_VERDICT_NO_INFO;
    }
    photo_of(&res, st);
    st->valid_permille = (int32_t)((uint64_t)res.stereo.valid * 1000u /
                                   ((uint64_t)left->width *
                                    (uint64_t)left->height));
    st->first_row = res.stereo.first_row;
    st->matcher_threads = lib_workers;
    st->memory_profile = lib_profile;
    {
        int k;
        uint64_t sum = 0;
        for (k = 0; k < NEGOBS_STEREO_STAGE_COUNT; k++) {
            uint64_t us = res.stereo.stage_ticks[k] / 1000u;
            st->stage_us[k] = (uint32_t)((us > UINT32_MAX) ? UINT32_MAX : us);
            sum += us;
        }
        st->stereo_us = (uint32_t)((sum > UINT32_MAX) ? UINT32_MAX : sum);
    }
    return verdict_of(p, &res, st);
}

app_verdict_t app_pipeline_latency_gate(app_pipeline_t *p, app_verdict_t v,
                                        int32_t latency_ms)
{
    if (p == NULL) {
        return APP_VERDICT_NO_INFO;
    }
    if (latency_ms < 0) {
        latency_ms = 0;
    }
    p->last.latency_ms = latency_ms;
    if (v == APP_VERDICT_CLEAR && p->cfg.latency_budget_ms > 0 &&
        latency_ms > p->cfg.latency_budget_ms) {
        p->last.reason = APP_REASON_LATE;
        return APP_VERDICT_NO_INFO;
    }
    return v;
}

const char *app_verdict_name(app_verdict_t v)
{
    switch (v) {
    case APP_VERDICT_NO_INFO: return "no-info";
    case APP_VERDICT_CLEAR: return "clear";
    case APP_VERDICT_CAUTION: return "caution";
    case APP_VERDICT_IMMINENT: return "imminent";
    default: return "?";
    }
}

const char *app_reason_name(app_reason_t r)
{
    switch (r) {
    case APP_REASON_NONE: return "-";
    case APP_REASON_BAD_INPUT: return "bad-input";
    case APP_REASON_DARK: return "dark";
    case APP_REASON_SATURATED: return "saturated";
    case APP_REASON_TEXTURELESS: return "textureless";
    case APP_REASON_DETECTOR: return "detector";
    case APP_REASON_MISMATCH: return "lr-mismatch";
    case APP_REASON_LATE: return "late";
    default: return "?";
    }
}
