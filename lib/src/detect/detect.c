/*
 * Negative-obstacle detector, one frame: gating, ground model, per-strip
 * scan, hazard merging, local noise and the vouched range, disparity-edge
 * support and temporal logic (docs/DETECTION.md). The steps live in the
 * detect_*.c files named in detect_internal.h.
 */
#include "detect_internal.h"

/* What the steps of one frame hand to the temporal logic and the verdict. */
typedef struct frame_work {
    int unverified;      /* no reference yet, ground lower than set     */
    int32_t walk_to;     /* vouched by this frame's noise (mm)          */
    int32_t walk_5cm_to; /* of it, vouched for 5 cm drops (mm)          */
    uint32_t walk_cause; /* why the walk stopped                        */
    int32_t barred;      /* the walk ended at obstacles barring the lanes */
    uint8_t trusted[NEGOBS_DETECT_MAX_HAZARDS];
    int32_t n_trusted;
    int32_t hold_range;
    int32_t seen_from; /* floor distance of the nearest row in view (mm) */
} frame_work_t;

static void fill_no_info(negobs_detect_result_t *res, uint32_t reasons)
{
    memset(res, 0, sizeof *res);
    res->state = NEGOBS_DETECT_NO_INFO;
    res->reasons = reasons;
    res->level = NEGOBS_LEVEL_NONE;
    res->nearest_range_mm = -1;
}

/* 1 when the frame is malformed: no or wrong-sized disparity, a
 * confidence map or left image that does not fit. */
static int frame_malformed(const negobs_detect_config_t *cfg,
                           const negobs_detect_frame_t *frame)
{
    return frame == NULL || frame->disp_q4 == NULL ||
           negobs_image_s16_check(frame->disp_q4) != NEGOBS_OK ||
           frame->disp_q4->width != cfg->rig.width ||
           frame->disp_q4->height != cfg->rig.height ||
           (frame->confidence != NULL &&
            (negobs_image_u8_check(frame->confidence) != NEGOBS_OK ||
             frame->confidence->width != cfg->rig.width ||
             frame->confidence->height != cfg->rig.height)) ||
           (frame->left != NULL &&
            negobs_image_u8_check(frame->left) != NEGOBS_OK) ||
           (frame->right != NULL &&
            negobs_image_u8_check(frame->right) != NEGOBS_OK) ||
           (frame->left_half != NULL &&
            (negobs_image_u8_check(frame->left_half) != NEGOBS_OK ||
             frame->left_half->width != cfg->rig.width / 2 ||
             frame->left_half->height != cfg->rig.height / 2)) ||
           (frame->disp_half_q4 != NULL &&
            (negobs_image_s16_check(frame->disp_half_q4) != NEGOBS_OK ||
             frame->disp_half_q4->width != cfg->rig.width / 2 ||
             frame->disp_half_q4->height != cfg->rig.height / 2));
}

static int same_size(const negobs_detect_config_t *cfg,
                     const negobs_image_u8_t *img)
{
    return img != NULL && img->width == cfg->rig.width &&
           img->height == cfg->rig.height;
}

/* A side's out-of-view part grows by at most this per frame (px). The
 * fill is fixed by the calibration, so it is accepted within a few frames
 * (a 30 px fill in 4, at 10 fps in 0.4 s); a clipped object entering at
 * the border is taken for fill no faster, and one that leaves is back in
 * view on the next frame. */
#define FILL_GROW_PX 8

/* Reasons that keep a frame's ground from starting the following of the
 * floor nearer than the view (det_near_follow's start_ok): an image gated
 * as unusable (dark, blown out, blank: a covered lens), or a fit that is
 * not, or not yet, the floor under the feet. A noisy frame with a
 * verified fit starts it: it vouches nothing, so the floor walked towards
 * is followed from its view and must be vouched before it leaves the
 * view. */
static const uint32_t NEAR_START_BLOCKING = NEGOBS_DEGRADED_TOO_DARK |
                                            NEGOBS_DEGRADED_SATURATED |
                                            NEGOBS_DEGRADED_LOW_TEXTURE |
                                            NEGOBS_DEGRADED_FEW_GROUND |
                                            NEGOBS_DEGRADED_GROUND_REJECTED |
                                            NEGOBS_DEGRADED_STALE |
                                            NEGOBS_DEGRADED_UNSYNCED |
                                            NEGOBS_DEGRADED_BAD_INPUT |
                                            NEGOBS_DEGRADED_GROUND_UNVERIFIED;

/* Follow one image's columns in view [u0, u1) per row: this frame's fill
 * (fill_u0 / fill_u1), its growth limited to FILL_GROW_PX per frame. */
static void view_follow(detect_priv_t *p, const negobs_detect_config_t *cfg,
                        const negobs_image_u8_t *img, int16_t *u0, int16_t *u1,
                        int32_t *held)
{
    int32_t v;
    if (!same_size(cfg, img) ||
        negobs_detect_fill_extent(img, p->fill_u0, p->fill_u1) != NEGOBS_OK) {
        *held = 0;
        return; /* not known: every column in view (det_in_view) */
    }
    for (v = 0; v < cfg->rig.height; v++) {
        int32_t a = *held ? u0[v] : 0;
        int32_t b = *held ? u1[v] : cfg->rig.width;
        u0[v] = (int16_t)geom_min_s32(p->fill_u0[v], a + FILL_GROW_PX);
        u1[v] = (int16_t)geom_max_s32(p->fill_u1[v], b - FILL_GROW_PX);
    }
    *held = 1;
}

/* Step 0: validity gating (timestamps, photometry). */
static uint32_t gate(const negobs_detect_config_t *cfg,
                     const negobs_detect_frame_t *frame,
                     negobs_detect_result_t *res)
{
    uint32_t reasons = 0;
    negobs_photo_stats_t ls;
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
    return reasons;
}

/*
 * Confidence a candidate gains from Canny support, Q15: 1/8 of full. Canny
 * is a supporting cue only: it has no sign and no metric height, and it
 * supports 90 % of the false candidates of the suite as well as 99 % of
 * the true ones (docs/DETECTION.md, "Canny support"), so it nudges the
 * confidence and never decides a hazard.
 */
enum { CANNY_CONF_BONUS_Q15 = 4096 };

/* Disparity Canny support of each candidate's edge. */
static void canny_support(detect_priv_t *p, const negobs_detect_config_t *cfg,
                          const negobs_detect_frame_t *frame,
                          negobs_detect_result_t *res)
{
    int32_t vtop = cfg->rig.height;
    int32_t gmax;
    uint32_t i;
    if (res->n_candidates == 0) {
        return;
    }
    for (i = 0; i < res->n_candidates; i++) {
        vtop = geom_min_s32(vtop, res->candidates[i].v0);
    }
    gmax = dcanny_band_max(frame->disp_q4, vtop);
    for (i = 0; i < res->n_candidates; i++) {
        negobs_hazard_t *hz = &res->candidates[i];
        int32_t need = (hz->u1 - hz->u0 + 1) / 4;
        if (dcanny_support(frame->disp_q4, gmax, cfg->canny_thresh_permille,
                           cfg->canny_low_permille, hz->u0, hz->u1, hz->v1,
                           &p->canny) >= need) {
            hz->flags |= NEGOBS_HAZARD_F_CANNY;
            hz->conf_q15 = (int16_t)geom_min_s32(
                32767, hz->conf_q15 + CANNY_CONF_BONUS_Q15);
        }
    }
}

/* Diagnostics: the noise at the warning-range row. */
static void warn_diagnostics(const scan_ctx_t *s, negobs_detect_result_t *res)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t d_w = negobs_disp_q4_from_depth_mm(&cfg->rig, cfg->range_warn_mm);
    int32_t v_w = cfg->rig.height - 1;
    while (v_w > 0 &&
           negobs_ground_disp_q4(s->plane, cfg->rig.width / 2, v_w) > d_w) {
        v_w--;
    }
    res->sigma_warn_q4 = det_sigma_at(s, v_w);
    res->sigma_strip_warn_q8 = det_strip_sigma_at(s, v_w,
                                                  &res->offset_strip_warn_q8);
}

/* Hold zone: an edge lost within the bottom rows in view (v_near: above
 * the floor beyond the matcher's range; rn_mm its floor distance), or so
 * near that the support requirement can no longer be met below it. */
static int32_t hold_zone(const scan_ctx_t *s, int32_t v_near, int32_t rn_mm)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t uc = cfg->rig.width / 2;
    int32_t vb = geom_max_s32(v_near - cfg->hold_bottom_rows, 0);
    int32_t rb = 0;
    det_model_point(s, uc, vb, negobs_ground_disp_q4(s->plane, uc, vb), &rb,
                    NULL, NULL);
    return geom_max_s32(rb, rn_mm + cfg->min_support_mm + cfg->assoc_range_mm);
}

/*
 * Steps 2-3 and 6 on a frame with a ground model: per-strip scan, merge,
 * the ground-drop cue, the measured noise and the vouched range, which
 * candidates are trusted, disparity-edge support and the hold zone.
 */
/* The strips' scans of one frame as executor jobs (job = strip): each
 * reads the frame and writes its own hit, so they may run at once in any
 * order and give the same hits. */
typedef struct scan_pass {
    const scan_ctx_t *s;
    detect_priv_t *p;
} scan_pass_t;

/* Marks a hit whose strip no job has scanned yet: det_scan_strip clears
 * the hit first, so any scan overwrites it. */
#define SCAN_NOT_RUN (-1)

static void scan_job(void *arg, int32_t job, int32_t worker)
{
    const scan_pass_t *sp = (const scan_pass_t *)arg;
    const negobs_detect_config_t *cfg = sp->s->cfg;
    int32_t u0;
    (void)worker;
    if (job < 0 || job >= sp->p->n_strips) {
        return;
    }
    u0 = det_strip_u0(cfg, sp->p->n_strips, job);
    det_scan_strip(sp->s, u0, u0 + cfg->strip_px, &sp->p->hits[job]);
}

/* Out of line: the call through the caller's executor stays here, where
 * the stack bound's check (tools/negobs, stack_bound) allows it. */
static __attribute__((noinline)) void scan_strips(detect_priv_t *p,
                                                  const scan_ctx_t *s)
{
    scan_pass_t sp;
    int32_t i;
    sp.s = s;
    sp.p = p;
    for (i = 0; i < p->n_strips; i++) {
        p->hits[i].found = SCAN_NOT_RUN;
    }
    if (p->exec.run != NULL) {
        p->exec.run(p->exec.user, p->n_strips, scan_job, &sp);
    }
    /* without an executor, and any strip a faulty executor skipped */
    for (i = 0; i < p->n_strips; i++) {
        if (p->hits[i].found == SCAN_NOT_RUN) {
            scan_job(&sp, i, 0);
        }
    }
}

/* Is candidate c's box textured? At full size; where a half-resolution
 * pass supplied the box's values, also at its scale: its 5x5 windows span
 * 10x10 pixels of a pair with half the noise (pipeline/coarse.c). Values
 * the full-size matcher kept are judged at full size only. noise_half is
 * measured once, on the first box that needs it. */
static int det_box_textured_at(const negobs_detect_frame_t *frame,
                               const negobs_image_u8_t *left,
                               const int32_t *noise_med, int32_t *noise_half,
                               const negobs_hazard_t *c)
{
    if (det_box_textured(left, *noise_med, c->u0, c->v0, c->u1, c->v1)) {
        return 1;
    }
    if (frame->left_half == NULL || frame->disp_half_q4 == NULL ||
        !det_box_from_half(frame->disp_q4, frame->disp_half_q4, c->u0, c->v0,
                           c->u1, c->v1)) {
        return 0;
    }
    if (*noise_half < 0) {
        *noise_half = det_noise_median(frame->left_half);
    }
    return det_box_textured(frame->left_half, *noise_half, c->u0 / 2,
                            c->v0 / 2, c->u1 / 2, c->v1 / 2);
}

/* A deficit of at least this (Q4, 1 px) stands out of the wander of a
 * weakly textured match: below a texture-to-noise power of 3 a 5x5
 * window's match wanders by tenths of a pixel (det_box_textured), so a
 * whole pixel is several times that wander. */
enum { WEAK_TEXTURE_DEFICIT_Q4 = 16 };

/* Do at least min_strips of the strips hits[k0..k1-1] read a first
 * plateau a whole pixel or more below the ground at their edge? */
static int cand_deep(const scan_ctx_t *s, const detect_priv_t *p,
                     const negobs_detect_config_t *cfg, int32_t k0, int32_t k1)
{
    int32_t deep = 0;
    int32_t k;
    for (k = k0; k < k1; k++) {
        const strip_hit_t *sh = &p->hits[k];
        int32_t dg_q4 = negobs_ground_disp_q4(s->plane, (sh->u0 + sh->u1) / 2,
                                              sh->edge_v);
        /* dg_q4 < 2^15, rho1_q15 <= 2^15: the product needs 64 bits */
        deep += sh->rho1_q15 > 0 && ((int64_t)dg_q4 * sh->rho1_q15 >> 15) >=
                                        WEAK_TEXTURE_DEFICIT_Q4;
    }
    return deep >= cfg->min_strips;
}

/* Is candidate c's deficit read on texture? Its box by
 * det_box_textured_at, or else some min_strips adjacent strips of it,
 * each over its own rows (det_run_textured): the strips it was merged
 * from, found by their columns. Or, for a deficit of a whole pixel or more
 * on min_strips strips (cand_deep), weak grain (det_box_weak_textured):
 * sensor noise as strong as the floor's grain makes a window's match
 * wander by tenths of a pixel, not by pixels. */
static int cand_textured(const scan_ctx_t *s, const detect_priv_t *p,
                         const negobs_detect_config_t *cfg,
                         const negobs_detect_frame_t *frame,
                         const negobs_image_u8_t *left,
                         const int32_t *noise_med, int32_t *noise_half,
                         const negobs_hazard_t *c)
{
    int32_t k0 = 0;
    int32_t k1;
    if (det_box_textured_at(frame, left, noise_med, noise_half, c)) {
        return 1;
    }
    while (k0 < p->n_strips &&
           !(p->hits[k0].found && p->hits[k0].u0 >= c->u0)) {
        k0++;
    }
    k1 = k0;
    while (k1 < p->n_strips && p->hits[k1].found &&
           p->hits[k1].u1 - 1 <= c->u1) {
        k1++;
    }
    return det_run_textured(left, *noise_med, p->hits, k0, k1,
                            cfg->min_strips) ||
           (cand_deep(s, p, cfg, k0, k1) &&
            det_box_weak_textured(left, *noise_med, c->u0, c->v0, c->u1,
                                  c->v1));
}

/* Missing ground (type UNKNOWN) whose band holds no texture above the
 * image's noise, by the test of a candidate's box: the matcher had
 * nothing there it could match (a floor whose grain has faded into the
 * sensor's noise with distance, a bland or dark patch), so the absent
 * matches are no evidence of a drop, and the band is not TEXTURED
 * whatever its gradient next to the ground's (detect_scan.c's split,
 * which sensor noise alone passes where the ground before the band is
 * itself near the noise). It is unknown there: the vouched range ends
 * before it. Under the default policy (CAUTION) such a candidate only
 * refreshes a confirmed track; it neither starts nor confirms one.
 * TEXTURED and DANGER keep reporting bland bands, as their names say
 * (docs/DETECTION.md, "Missing ground"). */
static void missing_texture(const negobs_detect_config_t *cfg,
                            const negobs_detect_frame_t *frame,
                            const negobs_image_u8_t *left,
                            const int32_t *noise_med, int32_t *noise_half,
                            negobs_hazard_t *c, uint8_t *trusted)
{
    if (det_box_textured_at(frame, left, noise_med, noise_half, c)) {
        return;
    }
    c->flags &= ~(uint32_t)NEGOBS_HAZARD_F_TEXTURED;
    if (cfg->missing_policy == NEGOBS_MISSING_CAUTION) {
        *trusted = (uint8_t)TMP_UNTRUSTED;
    }
}

static void scan_frame(detect_priv_t *p, const negobs_detect_config_t *cfg,
                       const negobs_detect_frame_t *frame, const gfit_out_t *g,
                       negobs_detect_result_t *res, frame_work_t *fw)
{
    scan_ctx_t s;
    negobs_hazard_t hz;
    int32_t v_top = cfg->rig.height - 1;
    int32_t noise_med = -1;  /* det_noise_median, measured when needed */
    int32_t noise_half = -1; /* the same, of frame->left_half */
    int32_t fit_far_mm = 0;  /* floor distance of the top fit row */
    uint32_t i;

    memset(&s, 0, sizeof s); /* every field defined before use */
    s.cfg = cfg;
    s.left = same_size(cfg, frame->left) ? frame->left : NULL;
    det_travel_follow(p, cfg, g, s.left, frame->now_ms);
    s.disp = det_pool_frame(p, cfg, frame->disp_q4, g, p->temporal.tick,
                            p->pool_travel_mm, frame->now_ms,
                            &res->pooled_permille);
    s.conf = frame->confidence;
    if (p->view_l_held) {
        s.view_l_u0 = p->view_l_u0;
        s.view_l_u1 = p->view_l_u1;
    }
    if (p->view_r_held) {
        s.view_r_u0 = p->view_r_u0;
        s.view_r_u1 = p->view_r_u1;
    }
    s.plane = &p->gfit.plane;
    s.frame = &g->frame;
    s.sigma_q4 = g->sigma_q4;
    s.d_min_q4 = negobs_disp_q4_from_depth_mm(&cfg->rig, cfg->range_max_mm);
    s.d_top_q4 = gfit_range_top_q4(cfg);

    /* Noise per band of rows over the scanned part of the image (from the
     * row where the ground reaches range_max down to the bottom). */
    while (v_top > 0 && negobs_ground_disp_q4(&g->plane, cfg->rig.width / 2,
                                              v_top - 1) >= s.d_min_q4) {
        v_top--;
    }
    det_band_noise(&s, p->band_hist, v_top, g->v_near + 1);

    /* Step 2-3: per-strip scan (on the executor), merge. */
    scan_strips(p, &s);
    det_merge_strips(&s, p, res);
    /* A hazard already confirmed or held nearer than the view's bottom is
     * this drop: the cue's range (an upper bound) would only pull its
     * dead-reckoned range back. */
    if (det_ground_drop(p, cfg, &s, g, frame->now_ms, &hz, &fw->unverified) &&
        !temporal_covers(&p->temporal, hz.range_mm, frame->now_ms) &&
        res->n_candidates < NEGOBS_DETECT_MAX_HAZARDS) {
        res->candidates[res->n_candidates++] = hz;
    }
    /* Step 6 (self-check), local: how far does this frame's measured
     * noise, support and texture vouch for the corridor (det_vouch_walk)?
     * Measured after the scan, so that rows beyond a drop found this frame
     * are compared with its plateau. */
    det_strip_noise(&s, p, p->strip_hist);
    det_vouch_collect(&s, p);
    fw->walk_to = det_vouch_walk(&s, p, frame->first_row,
                                 res->n_candidates > 0u, &fw->walk_cause,
                                 &fw->barred);
    fw->walk_5cm_to = det_vouch_walk_5cm(&s, p, frame->first_row,
                                         res->n_candidates > 0u, fw->walk_to);
    res->blocked_at_mm = fw->barred ? fw->walk_to : 0;
    warn_diagnostics(&s, res);
    /* A candidate is trusted (may start and confirm a track) when the
     * frame vouches for the warning range, as every clean frame did, or
     * when its own strips pass the local check: a drop in clean strips is
     * reported whatever the noise elsewhere. A candidate in strips that
     * fail it is as likely matching noise: alone it only refreshes a
     * confirmed track (section 6), and in a textured box it may fill one
     * gap between trusted sightings of the same place (TMP_WEAK). The
     * ground-drop cue has no strips: it comes from
     * the plane of the fit rows, so it needs the frame to vouch for the
     * near zone and for the fit rows' floor: a plane those rows do not
     * follow as a floor is not a lower level (a wall standing in the fit
     * rows of a camera pitched 7 deg tilted the fit up by 3 deg and
     * 150 mm). */
    det_model_point(
        &s, cfg->rig.width / 2, p->gfit.v_lo,
        negobs_ground_disp_q4(s.plane, cfg->rig.width / 2, p->gfit.v_lo),
        &fit_far_mm, NULL, NULL);
    for (i = 0; i < res->n_candidates && i < NEGOBS_DETECT_MAX_HAZARDS; i++) {
        negobs_hazard_t *c = &res->candidates[i];
        int quiet;
        if ((c->flags & NEGOBS_HAZARD_F_GROUND_DROP) != 0u) {
            fw->trusted[i] = (uint8_t)(fw->walk_to >=
                                               geom_max_s32(cfg->near_min_mm,
                                                            fit_far_mm)
                                           ? TMP_TRUSTED
                                           : TMP_UNTRUSTED);
            fw->n_trusted += fw->trusted[i] == TMP_TRUSTED;
            continue;
        }
        quiet = fw->walk_to >= cfg->range_warn_mm ||
                det_vouch_candidate(&s, p, c);
        fw->trusted[i] = (uint8_t)(quiet ? TMP_TRUSTED : TMP_UNTRUSTED);
        /* A deficit read in a box without texture (flat paint, a smooth
         * slab) is the matcher wandering, not a drop: it may refresh a
         * confirmed track but not count towards one. Missing ground
         * (type UNKNOWN) is about matches that are absent, not wrong, and
         * has its own texture policy (missing_policy). A textured box
         * whose strips failed the noise check is a weak sighting
         * (temporal.h, TMP_WEAK). The noise is measured once, on the
         * first candidate that needs it. */
        if (s.left != NULL) {
            if (noise_med < 0) {
                noise_med = det_noise_median(s.left);
            }
            if (c->type == NEGOBS_HAZARD_UNKNOWN) {
                missing_texture(cfg, frame, s.left, &noise_med, &noise_half, c,
                                &fw->trusted[i]);
            } else {
                fw->trusted[i] =
                    (uint8_t)(cand_textured(&s, p, cfg, frame, s.left,
                                            &noise_med, &noise_half, c)
                                  ? (quiet ? TMP_TRUSTED : TMP_WEAK)
                                  : TMP_UNTRUSTED);
            }
        }
        /* While the start is checked, a fit that stands ground_drop_mm
         * above the lowest of the last ground_drop_max_ms is no floor to
         * measure deficits against: either the wearer stepped down (the
         * check restarts) or its rows hold something else, a riser or the
         * lower floor of an edge, which tilts the plane (docs/DETECTION.md
         * 6.1, "A fit that rose"). */
        if (fw->unverified && p->fit_risen) {
            fw->trusted[i] = (uint8_t)TMP_UNTRUSTED;
        }
        fw->n_trusted += fw->trusted[i] == TMP_TRUSTED;
    }
    canny_support(p, cfg, frame, res);
    det_model_point(
        &s, cfg->rig.width / 2, g->v_near,
        negobs_ground_disp_q4(s.plane, cfg->rig.width / 2, g->v_near),
        &fw->seen_from, NULL, NULL);
    fw->hold_range = hold_zone(&s, g->v_near, fw->seen_from);
    if (g->v_near < cfg->rig.height - 1) {
        /* the nearer floor lies beyond the matcher's range */
        res->range_near_mm = fw->seen_from;
    }
}

negobs_status_t negobs_detect_process(negobs_detect_t *ctx,
                                      const negobs_detect_frame_t *frame,
                                      negobs_detect_result_t *res)
{
    detect_priv_t *p;
    const negobs_detect_config_t *cfg;
    uint32_t reasons;
    frame_work_t fw;
    gfit_out_t g;
    int32_t sight_mm;
    int32_t vouch_bound;
    int32_t pending_mm = -1; /* det_near_follow's */
    uint32_t i;

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
    if (frame != NULL) {
        /* is it a tick: do clearing, the slow tracks and the travel
         * count this frame (temporal.h) */
        temporal_clock(&p->temporal, frame->now_ms);
    }
    if (frame_malformed(cfg, frame)) {
        fill_no_info(res, NEGOBS_DEGRADED_BAD_INPUT);
        mount_report(&p->mount, cfg, &res->mount);
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
    memset(&fw, 0, sizeof fw);
    fw.walk_cause = NEGOBS_DEGRADED_FEW_GROUND;

    reasons = gate(cfg, frame, res);

    /* Step 1: ground model. */
    view_follow(p, cfg, frame->left, p->view_l_u0, p->view_l_u1,
                &p->view_l_held);
    view_follow(p, cfg, frame->right, p->view_r_u0, p->view_r_u1,
                &p->view_r_held);
    gfit_process(&p->gfit, frame->disp_q4, frame->confidence,
                 p->view_l_held ? p->view_l_u0 : NULL,
                 p->view_l_held ? p->view_l_u1 : NULL, &g);
    reasons |= g.reasons;
    res->ground_valid_permille = g.valid_permille;
    res->ground_inliers = g.inliers;

    if (g.ok) {
        res->ground_valid = 1;
        res->plane = g.plane;
        res->pose = g.pose;
        res->sigma_q4 = g.sigma_q4;
        scan_frame(p, cfg, frame, &g, res, &fw);
    } else {
        /* No ground model: use the nominal geometry for the hold zone. */
        fw.hold_range = cfg->range_imminent_mm + cfg->assoc_range_mm;
        det_pool_distrust(p);
    }

    /* Steps 4-5: temporal confirmation, clearing and hold. A frame without
     * a gating or ground reason is observed; tracks beyond the vouched
     * range are not counted as missed by it. */
    temporal_update_vouched(&p->temporal, res->candidates, fw.trusted,
                            res->n_candidates, reasons == 0u, fw.seen_from,
                            fw.walk_to, fw.hold_range, frame->now_ms);
    res->n_hazards = temporal_report(&p->temporal, res->hazards,
                                     NEGOBS_DETECT_MAX_HAZARDS, frame->now_ms);
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
    if (fw.unverified && res->n_hazards == 0u) {
        reasons |= NEGOBS_DEGRADED_GROUND_UNVERIFIED;
    }
    if (g.ok && reasons == 0u &&
        (fw.walk_to >= cfg->near_min_mm || fw.n_trusted > 0)) {
        /* the ground under the feet is followed on frames that vouch for
         * the near zone (the fit rows agree with the model) or carry a
         * trusted drop: a frame short-sighted by far noise or a wall
         * measures the ground under the feet as well as any */
        det_ground_ref_follow(p, cfg, &g, fw.unverified);
        det_near_candidate_note(p, cfg, res, frame->now_ms);
    }
    /* height and roll follow only a view of the ground under the feet,
     * on ticks (temporal.h: a gain per tick keeps its time at any rate) */
    mount_update(&p->mount, cfg, g.ok ? &g.pose : NULL,
                 g.ok && !fw.unverified && !p->drop_on && p->temporal.tick,
                 frame->now_ms, &res->mount);
    if (p->ref_ok) {
        res->ground_ref_by = p->ref_by;
        res->ground_ref_height_mm = p->ref_height_mm;
        res->ground_ref_pitch_mdeg = p->ref_pitch_mdeg;
    }
    if (det_fit_fell(p, cfg, &g, frame->left)) {
        /* the fit dropped onto a lower level, not the camera: no vouch */
        fw.walk_to = 0;
        det_pool_distrust(p);
        fw.walk_cause = NEGOBS_DEGRADED_GROUND_REJECTED;
        res->blocked_at_mm = 0;
    }
    sight_mm = det_sight_bound(p, cfg, frame->now_ms);
    det_verdict(cfg, res, reasons, fw.walk_to, fw.walk_cause, sight_mm);
    det_sight_note(p, res, frame->now_ms);
    /* a hazard's range this frame may be too far (temporal.c): vouch
     * no farther than its track's own prediction either */
    vouch_bound = temporal_vouch_bound(&p->temporal, frame->now_ms);
    res->clear_to_mm = geom_min_s32(res->clear_to_mm, vouch_bound);
    /* what a frame whose usable ground awaits only the start check would
     * vouch once it passes (detect_near.c) */
    if (g.ok && fw.unverified &&
        (reasons & NEAR_START_BLOCKING &
         ~(uint32_t)NEGOBS_DEGRADED_GROUND_UNVERIFIED) == 0u) {
        pending_mm =
            ((reasons & ~(uint32_t)NEGOBS_DEGRADED_GROUND_UNVERIFIED) == 0u)
                ? geom_min_s32(det_vouch_cut(res, fw.walk_to, sight_mm),
                               vouch_bound)
                : 0;
    }
    /* the floor nearer than the view must have been vouched while it was
     * in view: else nothing is vouched from the feet (a hazard is still
     * reported) */
    if (!det_near_follow(p, cfg, fw.seen_from, res->clear_to_mm,
                         fw.walk_5cm_to, pending_mm, g.ok ? p->travel_mm : 0,
                         g.ok && !fw.unverified &&
                             (res->reasons & NEAR_START_BLOCKING) == 0u,
                         frame->now_ms)) {
        res->clear_to_mm = 0;
        res->short_sight = 0;
        res->blocked_at_mm = 0;
        if (res->state != NEGOBS_DETECT_HAZARD) {
            res->reasons = (res->state == NEGOBS_DETECT_CLEAR)
                               ? NEGOBS_DEGRADED_NEAR_UNSEEN
                               : res->reasons | NEGOBS_DEGRADED_NEAR_UNSEEN;
            res->state = NEGOBS_DETECT_NO_INFO;
        }
    }
    return NEGOBS_OK;
}
