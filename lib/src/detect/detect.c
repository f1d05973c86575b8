/*
 * Negative-obstacle detector, one frame: gating, ground model, per-strip
 * scan, hazard merging, local noise and the vouched range, disparity-edge
 * support and temporal logic (docs/DETECTION.md). The steps live in the
 * detect_*.c files named in detect_internal.h.
 */
#include "detect_internal.h"

static void fill_no_info(negobs_detect_result_t *res, uint32_t reasons)
{
    memset(res, 0, sizeof *res);
    res->state = NEGOBS_DETECT_NO_INFO;
    res->reasons = reasons;
    res->level = NEGOBS_LEVEL_NONE;
    res->nearest_range_mm = -1;
}

negobs_status_t negobs_detect_process(negobs_detect_t *ctx,
                                      const negobs_detect_frame_t *frame,
                                      negobs_detect_result_t *res)
{
    detect_priv_t *p;
    const negobs_detect_config_t *cfg;
    uint32_t reasons = 0;
    int unverified = 0;        /* no reference yet, ground lower than set */
    int32_t walk_to = 0;       /* vouched by this frame's noise (mm)      */
    uint32_t walk_cause = NEGOBS_DEGRADED_FEW_GROUND; /* why it stopped  */
    uint8_t trusted[NEGOBS_DETECT_MAX_HAZARDS];
    int32_t n_trusted = 0;
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
        reasons |= det_photo_reasons(cfg, &ls);
    } else if (frame->left != NULL) {
        (void)negobs_detect_photo_stats(frame->left, &ls);
        reasons |= det_photo_reasons(cfg, &ls);
    }
    if (frame->right_stats != NULL) {
        reasons |= det_photo_reasons(cfg, frame->right_stats);
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
            det_band_noise(&s, p->band_hist, v_top);
        }

        /* Step 2-3: per-strip scan, merge. */
        for (s_i = 0; s_i < p->n_strips; s_i++) {
            int32_t u0 = det_strip_u0(cfg, p->n_strips, s_i);
            det_scan_strip(&s, u0, u0 + cfg->strip_px, &p->hits[s_i]);
        }
        det_merge_strips(&s, p, res);
        {
            negobs_hazard_t hz;
            /* A hazard already confirmed or held nearer than the view's
             * bottom is this drop: the cue's range (an upper bound) would
             * only pull its dead-reckoned range back. */
            if (det_ground_drop(p, cfg, &s, &g, frame->now_ms, &hz,
                                &unverified) &&
                !temporal_covers(&p->temporal, hz.range_mm, frame->now_ms) &&
                res->n_candidates < NEGOBS_DETECT_MAX_HAZARDS) {
                res->candidates[res->n_candidates++] = hz;
            }
        }
        /* Step 6 (self-check), local: how far does this frame's measured
         * noise, support and texture vouch for the corridor (det_vouch_walk)?
         * Measured after the scan, so that rows beyond a drop found this
         * frame are compared with its plateau. */
        det_strip_noise(&s, p, p->strip_hist);
        det_vouch_collect(&s, p);
        walk_to = det_vouch_walk(&s, p, frame->first_row,
                                 res->n_candidates > 0u, &walk_cause);
        /* Diagnostics: the noise at the warning-range row. */
        {
            int32_t d_w =
                negobs_disp_q4_from_depth_mm(&cfg->cam, cfg->range_warn_mm);
            int32_t v_w = cfg->cam.height - 1;
            while (v_w > 0 && negobs_ground_disp_q4(&g.plane,
                                                    cfg->cam.width / 2,
                                                    v_w) > d_w) {
                v_w--;
            }
            res->sigma_warn_q4 = det_sigma_at(&s, v_w);
            res->sigma_strip_warn_q8 =
                det_strip_sigma_at(&s, v_w, &res->offset_strip_warn_q8);
        }
        /* A candidate is trusted (may start and confirm a track) when the
         * frame vouches for the warning range, as every clean frame did,
         * or when its own strips pass the local check: a drop in clean
         * strips is reported whatever the noise elsewhere. A candidate in
         * strips that fail it is as likely matching noise: it only
         * refreshes a confirmed track (section 6). The ground-drop cue has
         * no strips: it needs the whole frame. */
        for (i = 0; i < res->n_candidates && i < NEGOBS_DETECT_MAX_HAZARDS;
             i++) {
            const negobs_hazard_t *c = &res->candidates[i];
            trusted[i] = (uint8_t)(walk_to >= cfg->range_warn_mm ||
                                   ((c->flags & NEGOBS_HAZARD_F_GROUND_DROP) ==
                                        0u &&
                                    det_vouch_candidate(&s, p, c)));
            n_trusted += trusted[i];
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
            det_model_point(&s, cfg->cam.width / 2, vb, dgb, &rb, NULL, NULL);
            det_model_point(&s, cfg->cam.width / 2, cfg->cam.height - 1,
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

    /* Steps 4-5: temporal confirmation, clearing and hold. A frame without
     * a gating or ground reason is observed; tracks beyond the vouched
     * range are not counted as missed by it. */
    temporal_update_vouched(&p->temporal, res->candidates, trusted,
                            res->n_candidates, reasons == 0u, walk_to,
                            hold_range, frame->now_ms);
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
    /* like a noisy frame: the frame still feeds the tracker, a hazard
     * found by the rule is reported, but "clear" is not said */
    if (unverified && res->n_hazards == 0u) {
        reasons |= NEGOBS_DEGRADED_GROUND_UNVERIFIED;
    }
    if (g.ok && reasons == 0u &&
        (walk_to >= cfg->range_warn_mm || n_trusted > 0)) {
        /* the ground under the feet is followed on frames that vouch for
         * the warning range or carry a trusted drop, as clean frames did */
        det_ground_ref_follow(p, cfg, &g, unverified);
        det_near_candidate_note(p, cfg, res, frame->now_ms);
    }
    det_verdict(cfg, res, reasons, walk_to, walk_cause);
    return NEGOBS_OK;
}
