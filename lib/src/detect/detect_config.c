/* Detector configuration: defaults, presets, validation, workspace and
 * init (docs/DETECTION.md section 9). */
#include "detect_internal.h"

void negobs_detect_config_default(negobs_detect_config_t *cfg, int32_t width,
                                  int32_t height)
{
    memset(cfg, 0, sizeof *cfg);
    negobs_rig_default(&cfg->rig, width, height);
    mount_config_default(cfg);
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
    /* Walking at 1.0-1.4 m/s, a det_verdict needs ~0.3 s (3 of 5 frames at
     * 10 Hz) and the wearer ~0.7 s to react and stop: 1.0-1.4 m are gone
     * before a warning helps. The cane covers about the first metre, so
     * a frame must vouch for at least 1.5 m to be of any use
     * (docs/DETECTION.md, "Verdicts and the vouched range"). */
    cfg->near_min_mm = 1500;
    cfg->ttc_imminent_ms = 1200;
    /* Half-width of the walking corridor (docs/DETECTION.md 10.2, "The
     * corridor"). At the feet: 250 mm, half the shoulder width of a broad
     * adult; a straight walker's feet land within +-0.15 m of the body's
     * line, so that covers them with 0.1 m for sway and foot placement. It
     * widens by tan 20 deg per mm of range (the path's heading off the
     * camera's axis) up to 600 mm (reached at 0.96 m): 250 mm + 350 mm of
     * heading, 13 deg at the near-zone minimum (1.5 m); a path bending more
     * than that is a turn, and floor that far ahead is in view again, in the
     * new heading's corridor, before it is reached. */
    cfg->corridor_half_width_mm = 600;
    cfg->corridor_near_half_mm = 250;
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
    /* The rate every frame count here was set and evaluated at. */
    cfg->frame_interval_ms = 100;
    cfg->pool_frames = 4;
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
    default: return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

static int in_range(int32_t x, int32_t lo, int32_t hi)
{
    return x >= lo && x <= hi;
}

static negobs_status_t config_check(const negobs_detect_config_t *c)
{
    if (c == NULL || negobs_rig_check(&c->rig) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    if (mount_config_check(c) != NEGOBS_OK ||
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
        !in_range(c->near_min_mm, 0, c->range_max_mm) ||
        !in_range(c->ttc_imminent_ms, 0, 10000) ||
        !in_range(c->corridor_half_width_mm, 100, 5000) ||
        !in_range(c->corridor_near_half_mm, 100, 5000) ||
        !in_range(c->strip_px, 4, MAX_STRIP_PX) ||
        c->strip_px > c->rig.width || !in_range(c->h_min_far_mm, 10, 2000) ||
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
        !in_range(c->frame_interval_ms, 0, 1000) ||
        !in_range(c->hold_speed_mm_s, 0, 5000) ||
        !in_range(c->pool_frames, 1, 4) ||
        !in_range(c->max_speed_mm_s, 0, 10000) ||
        !in_range(c->assoc_range_mm, 0, 5000) ||
        !in_range(c->assoc_lateral_mm, 0, 5000) ||
        !in_range(c->hold_bottom_rows, 0, c->rig.height) ||
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
    p->n_strips = cfg->rig.width / cfg->strip_px;
    p->hits = negobs_arena_take(ar, (size_t)p->n_strips * sizeof(strip_hit_t));
    p->band_hist = negobs_arena_take(ar, (size_t)NOISE_BANDS * NOISE_BINS *
                                             sizeof(uint32_t));
    p->strip_hist = negobs_arena_take(ar, (size_t)NOISE_BANDS * STRIP_BINS *
                                              sizeof(uint16_t));
    p->cells = negobs_arena_take(ar, (size_t)p->n_strips * NOISE_BANDS *
                                         sizeof(vouch_cell_t));
    p->reach_v = negobs_arena_take(ar, (size_t)p->n_strips * sizeof(int32_t));
    p->row_e = negobs_arena_take(
        ar, (size_t)p->n_strips * (size_t)cfg->rig.height * sizeof(int16_t));
    p->canny.mag = negobs_arena_take(ar, dcanny_mag_bytes(cfg->rig.width));
    p->canny.label = negobs_arena_take(ar, dcanny_label_bytes(cfg->rig.width));
    p->canny.width = cfg->rig.width;
    p->view_l_u0 = negobs_arena_take(ar, (size_t)cfg->rig.height *
                                             sizeof(int16_t));
    p->view_l_u1 = negobs_arena_take(ar, (size_t)cfg->rig.height *
                                             sizeof(int16_t));
    p->view_r_u0 = negobs_arena_take(ar, (size_t)cfg->rig.height *
                                             sizeof(int16_t));
    p->view_r_u1 = negobs_arena_take(ar, (size_t)cfg->rig.height *
                                             sizeof(int16_t));
    p->fill_u0 = negobs_arena_take(ar,
                                   (size_t)cfg->rig.height * sizeof(int16_t));
    p->fill_u1 = negobs_arena_take(ar,
                                   (size_t)cfg->rig.height * sizeof(int16_t));
    p->travel = negobs_arena_take(ar, TRAVEL_TRACKS * sizeof(travel_track_t));
    p->row_prof = negobs_arena_take(ar,
                                    (size_t)cfg->rig.height * sizeof(int32_t));
    p->row_prof_cur = negobs_arena_take(ar, (size_t)cfg->rig.height *
                                                sizeof(int32_t));
    if (cfg->pool_frames > 1) {
        const size_t px = (size_t)cfg->rig.width * (size_t)cfg->rig.height;
        p->pool_hist[0] = negobs_arena_take(ar, px * sizeof(int16_t));
        p->pool_hist[1] = negobs_arena_take(ar, px * sizeof(int16_t));
        p->pool_out = negobs_arena_take(ar, px * sizeof(int16_t));
        p->pool_node = negobs_arena_take(
            ar, (size_t)NEGOBS_DETECT_POOL_BANDS *
                    (size_t)det_pool_nodes(cfg->rig.width) * 2 *
                    sizeof(int32_t));
    }
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
    mount_reset(&p->mount);
    travel_reset(p->travel); /* carved memory is not zeroed */
    memset(&p->exec, 0, sizeof p->exec);
    p->magic = DETECT_MAGIC;
    ctx->priv = p;
    return NEGOBS_OK;
}

negobs_status_t negobs_detect_set_executor(negobs_detect_t *ctx,
                                           const negobs_executor_t *exec)
{
    detect_priv_t *p;
    if (ctx == NULL || ctx->priv == NULL) {
        return NEGOBS_ERR_STATE;
    }
    p = (detect_priv_t *)ctx->priv;
    if (p->magic != DETECT_MAGIC) {
        return NEGOBS_ERR_STATE;
    }
    if (exec == NULL) {
        memset(&p->exec, 0, sizeof p->exec);
        return NEGOBS_OK;
    }
    if (exec->run == NULL || exec->workers < 1) {
        return NEGOBS_ERR_INVAL;
    }
    p->exec = *exec;
    return NEGOBS_OK;
}

/* The drop the rule is set for at a floor range (detect_int.h). */
int32_t det_h_t_at(const negobs_detect_config_t *cfg, int32_t range_mm)
{
    int32_t h_min = (range_mm <= cfg->h_near_range_mm) ? cfg->h_min_near_mm
                                                       : cfg->h_min_far_mm;
    return (h_min * cfg->h_thresh_pct) / 100;
}
