/* Ground-drop cue: a drop first seen near (docs/DETECTION.md 6.1). */
#include "detect_internal.h"

/* The cue needs a steady pitch: a pitch change of more than this between
 * the reference and the frame also moves the estimated height. */
#define GROUND_DROP_PITCH_MDEG 3000

/*
 * Ground-drop cue. The rule above needs the edge in view with ground
 * before it; a drop first seen within ~1.6 m (after a corner) leaves the
 * bottom of the image before k of n frames
 * confirm it, and the ground fit then takes the lower surface as the
 * ground: the estimated camera height rises by the drop (+150 mm on a
 * 15 cm curb) and every later frame looked CLEAR until the user stepped
 * off. So the camera height over the ground under the feet is kept as a
 * reference, followed on clean frames only; a rise of ground_drop_mm or
 * more at a steady pitch makes a DROP candidate at the nearest visible
 * ground (the edge is nearer still), which the temporal logic confirms
 * and holds like any other. After ground_drop_max_ms of a continuous cue
 * the lower ground becomes the reference (the camera was raised, not
 * walked to an edge).
 *
 * The reference is the first clean frame's ground model that is verified:
 * its height lies within ground_verify_mm of the height hint, or its view
 * reaches the floor within mount_verify_near_mm of the feet (the wearer
 * looked down; mount.c) and the fitted height did not just rise
 * (ground_risen). A device switched on within ~1.4 m of an edge
 * has the lower surface in its fit rows and sees a camera about the drop
 * too high; so does one whose hint is too low, and a hint too high would
 * take the lower floor for the right one. The view cannot tell these
 * apart, so unverified frames are NO_INFO (*unverified), never CLEAR,
 * until a frame is verified or ground_drop_max_ms have passed; then the
 * view is taken as it is. The start check is tighter than the cue (50
 * against 100 mm): a 10 cm drop at switch-on reads 98-103 mm high, just
 * under the cue's threshold, and the hint is the only reference there is.
 */
/* The view's camera height and pitch become the reference, established
 * by `by` (negobs_ground_ref_by_t). */
static inline void ground_ref_take(detect_priv_t *p, const gfit_out_t *g,
                                   int32_t by)
{
    p->ref_ok = 1;
    p->ref_by = by;
    p->ref_height_mm = g->pose.height_mm;
    p->ref_pitch_mdeg = g->pose.pitch_mdeg;
    p->drop_on = 0;
}

/* A fit ground_drop_mm or more above the lowest fit of the last
 * ground_drop_max_ms: no posture raises a worn camera by 10 cm in a few
 * frames, but walking (or being switched on) over an edge does, and the
 * lower floor that then fills the view may lie within mount_verify_near_mm
 * of the feet. It is the rise the cue reads against the reference, read
 * before there is one; every fit counts, a noisy one too (the frames that
 * still see the edge are often noisy). */
static int ground_risen(detect_priv_t *p, const negobs_detect_config_t *cfg,
                        const gfit_out_t *g, uint32_t now_ms)
{
    const int32_t h = g->pose.height_mm;
    if (!p->low_on || h <= p->low_height_mm ||
        (int32_t)(now_ms - p->low_ms) > cfg->ground_drop_max_ms) {
        p->low_on = 1;
        p->low_height_mm = h;
        p->low_ms = now_ms;
    }
    if (h - p->low_height_mm >= cfg->ground_drop_mm) {
        p->risen_on = 1;
        p->risen_ms = now_ms;
    }
    return p->risen_on &&
           (int32_t)(now_ms - p->risen_ms) <= cfg->ground_drop_max_ms;
}

/* The travel that verifies a start beyond the nearest floor in view: half
 * a stride (about 350 mm), for the trailing foot still on the ground of
 * the start, and 150 mm for the travel's own error (its candidates are
 * 1/24 of 2 m/s apart: 8 mm a frame at 10 fps, over the 10-20 frames of
 * the walk). */
#define WALK_MARGIN_MM 500

/* A start verified by walking takes as its reference the mean of the fits
 * of the walk, not the last frame's: one fit on a narrow rig spreads by
 * +-40-50 mm (3 cm rig at 1.7 m / 15 deg: 1653-1739 mm over six frames),
 * which a single-frame reference hands on to the ground-drop cue as a
 * rise of 70-100 mm. The mean of the first 64 fits (6.4 s at 10 fps, more
 * than any walk to verification) is enough. */
#define WALK_FITS_MAX 64

/* Forward distance along the floor to the nearest floor in view: the
 * bottom row's middle column on the fitted plane, or the nearest row within
 * the matcher's range (v_near; 0: none). */
static int32_t nearest_floor_mm(const negobs_detect_config_t *cfg,
                                const gfit_out_t *g)
{
    int32_t fwd = 0;
    if (!mount_floor_point(&cfg->rig, &g->plane, &g->frame, cfg->rig.width / 2,
                           g->v_near, &fwd, NULL)) {
        return 0;
    }
    return geom_max_s32(fwd, 0);
}

/* The mean fitted height of the walk so far (walk_fits > 0). */
static inline int32_t walk_mean_height_mm(const detect_priv_t *p)
{
    return (int32_t)(p->walk_height_sum / p->walk_fits);
}

/*
 * The hint verifies a start when this frame's fit agrees with it and so
 * does the mean of the fits since the start (since the fit last rose):
 * the hint is a claim about the camera's height over the floor the
 * wearer stands on, and the floor seen on the way is the evidence for
 * it. A single later fit that agrees is none: walking towards an edge,
 * the lower floor comes to fill the fit rows and reads the camera the
 * drop higher, which a hint set that much too high takes for the right
 * floor, and the floor nearer than the view, the edge on it, was never
 * vouched. The caller also wants no rise (ground_risen, 100 mm: a fit
 * that dipped onto a blend of both levels first, then rose onto the
 * lower one); the mean catches a rise smaller than that
 * (docs/DETECTION.md 6.1, "The hint").
 */
static int hint_agrees(const detect_priv_t *p,
                       const negobs_detect_config_t *cfg, const gfit_out_t *g)
{
    if (mount_height_unverified(cfg, g->pose.height_mm)) {
        return 0;
    }
    return p->walk_fits == 0 ||
           !mount_height_unverified(cfg, walk_mean_height_mm(p));
}

/* The walk starts over: nothing walked, no fits taken. */
static void walk_restart(detect_priv_t *p)
{
    p->walked_mm = 0;
    p->walk_fits = 0;
    p->walk_height_sum = 0;
    p->walk_pitch_sum = 0;
    det_near_pending_restart(p);
}

static int ground_unverified(detect_priv_t *p,
                             const negobs_detect_config_t *cfg,
                             const gfit_out_t *g, uint32_t now_ms)
{
    /* looking at the feet verifies the start unless the floor in view
     * rose meanwhile; so does agreeing with the hint, when the floor seen
     * since the start agrees with it too (hint_agrees). A fit of the
     * wide band (ground_fit.c) never sees the feet: it exists because the
     * bottom rows showed no floor, so its plane there is extrapolated,
     * and the floor it rests on may lie beyond an edge. */
    const int risen = ground_risen(p, cfg, g, now_ms);
    p->fit_risen = risen;
    /* So does walking over the floor that was nearer than the view on
     * the first unverified frame (docs/DETECTION.md 6.2): a drop there
     * has been stepped down by then, and the fit would have risen. Only
     * a fit of the bottom band is walked on (det_travel_follow). */
    const int32_t walked = p->travel_mm;
    if (!p->walk_on) {
        p->walk_on = 1;
        p->walk_need_mm = nearest_floor_mm(cfg, g) + WALK_MARGIN_MM;
        walk_restart(p);
    } else if (risen) {
        walk_restart(p);
    } else {
        p->walked_mm += walked;
    }
    if (!g->wide && p->walk_fits < WALK_FITS_MAX) {
        p->walk_height_sum += g->pose.height_mm;
        p->walk_pitch_sum += g->pose.pitch_mdeg;
        p->walk_fits++;
    }
    p->walk_verified = 0;
    if (!risen && hint_agrees(p, cfg, g)) {
        p->unverified_on = 0;
        p->verify_by = NEGOBS_GROUND_REF_HINT;
        return 0;
    }
    if (!risen && !g->wide &&
        mount_sees_feet(cfg, &g->plane, &g->frame, g->v_near)) {
        p->unverified_on = 0;
        p->verify_by = NEGOBS_GROUND_REF_FEET;
        return 0;
    }
    if (!risen && p->walked_mm >= p->walk_need_mm) {
        p->walk_verified = 1;
        p->unverified_on = 0;
        p->verify_by = NEGOBS_GROUND_REF_WALK;
        return 0;
    }
    if (!p->unverified_on) {
        p->unverified_on = 1;
        p->unverified_since_ms = now_ms;
    }
    p->verify_by = NEGOBS_GROUND_REF_TIME;
    return (int32_t)(now_ms - p->unverified_since_ms) <=
           cfg->ground_drop_max_ms;
}

/* The rise that makes a ground-drop candidate: ground_drop_mm, or the
 * smaller ground_drop_corroborated_mm for hold_ms after a clean frame
 * whose rule found a drop within h_near_range_mm. A 10 cm drop first seen
 * at ~1.5 m is found by the rule on a frame or two, leaves the view
 * before k of n confirm it, and then raises the fitted height by only
 * 73-122 mm, across the plain threshold; the two cues together vouch for
 * the smaller rise, which alone would also fire on posture changes. */
static inline int32_t ground_drop_threshold(const detect_priv_t *p,
                                            const negobs_detect_config_t *cfg,
                                            uint32_t now_ms)
{
    int32_t t = cfg->ground_drop_mm;
    if (p->near_cand_on && cfg->ground_drop_corroborated_mm > 0 &&
        cfg->ground_drop_corroborated_mm < t &&
        (int32_t)(now_ms - p->near_cand_ms) <= cfg->hold_ms) {
        t = cfg->ground_drop_corroborated_mm;
    }
    return t;
}

/* Remember a clean frame whose rule (not the cue) found a drop, stairs
 * or hole within h_near_range_mm. */
void det_near_candidate_note(detect_priv_t *p,
                             const negobs_detect_config_t *cfg,
                             const negobs_detect_result_t *res,
                             uint32_t now_ms)
{
    uint32_t i;
    for (i = 0; i < res->n_candidates; i++) {
        const negobs_hazard_t *c = &res->candidates[i];
        if (c->type != NEGOBS_HAZARD_UNKNOWN &&
            (c->flags & NEGOBS_HAZARD_F_GROUND_DROP) == 0u &&
            c->range_mm <= cfg->h_near_range_mm) {
            p->near_cand_on = 1;
            p->near_cand_ms = now_ms;
            return;
        }
    }
}

void det_travel_follow(detect_priv_t *p, const negobs_detect_config_t *cfg,
                       const gfit_out_t *g, const negobs_image_u8_t *left,
                       uint32_t now_ms)
{
    /* Only a start to verify, a confirmed track (its hold), unvouched
     * floor ahead (detect_near.c) and pooled frames (detect_pool.c) use
     * the travel: on other frames it costs 0.8 M instructions for
     * nothing. */
    const int needed = !(p->ref_ok && !temporal_needs_travel(&p->temporal) &&
                         !det_near_gap(p));
    int32_t walked = 0;
    if (g->wide || (!needed && cfg->pool_frames <= 1)) {
        travel_reset(p->travel);
        p->pool_travel_mm = 0;
    } else if (!p->temporal.tick) {
        /* measured from tick to tick, over the interval it was set for:
         * a faster camera's floor moves less than the patches resolve */
        p->pool_travel_mm = 0;
    } else {
        walked = travel_step(p->travel, &cfg->rig, &g->plane, &g->frame, left,
                             now_ms, &p->exec, &p->pool_travel_mm);
    }
    /* the start, the tracks and the floor under the view count the travel
     * only while they need it, as without pooling */
    p->travel_mm = (needed && !g->wide) ? walked : 0;
    temporal_walked(&p->temporal, p->travel_mm);
}

int det_ground_drop(detect_priv_t *p, const negobs_detect_config_t *cfg,
                    const scan_ctx_t *s, const gfit_out_t *g, uint32_t now_ms,
                    negobs_hazard_t *hz, int *unverified)
{
    int32_t dh;
    int32_t dp;
    int32_t vb = g->v_near; /* the nearest floor in view */
    int32_t dg;
    int32_t range = 0;
    int32_t depth = 0;
    p->fit_risen = 0;
    if (cfg->ground_drop_mm <= 0) {
        return 0;
    }
    if (!p->ref_ok) {
        /* the reference itself is taken on a clean frame
         * (det_ground_ref_follow) */
        *unverified = ground_unverified(p, cfg, g, now_ms);
        return 0;
    }
    dh = g->pose.height_mm - p->ref_height_mm;
    dp = negobs_abs_s32(g->pose.pitch_mdeg - p->ref_pitch_mdeg);
    if (dh < ground_drop_threshold(p, cfg, now_ms) ||
        dp > GROUND_DROP_PITCH_MDEG) {
        p->drop_on = 0;
        return 0;
    }
    if (!p->drop_on) {
        p->drop_on = 1;
        p->drop_since_ms = now_ms;
    } else if ((int32_t)(now_ms - p->drop_since_ms) >
               cfg->ground_drop_max_ms) {
        /* a raised camera, or a lower floor stood before that long:
         * accepted, but not evidence */
        ground_ref_take(p, g, NEGOBS_GROUND_REF_TIME);
        return 0;
    }
    dg = negobs_ground_disp_q4(&g->plane, cfg->rig.width / 2, vb);
    det_model_point(s, cfg->rig.width / 2, vb, dg, &range, NULL, &depth);
    memset(hz, 0, sizeof *hz);
    hz->type = NEGOBS_HAZARD_DROP;
    hz->level = NEGOBS_LEVEL_NONE;
    hz->flags = NEGOBS_HAZARD_F_GROUND_DROP;
    hz->range_mm = range;
    hz->depth_mm = depth;
    hz->drop_mm = dh;
    hz->u0 = 0;
    hz->u1 = (int16_t)(cfg->rig.width - 1);
    hz->v0 = (int16_t)geom_max_s32(vb - cfg->hold_bottom_rows, 0);
    hz->v1 = (int16_t)vb;
    hz->conf_q15 = 16384;
    return 1;
}

/* Set the reference of the ground-drop cue on the first clean frame that
 * det_ground_drop() did not find unverified, then follow it on clean frames
 * whose height is near it (slow changes: posture, bobbing); a jump either
 * way is a different surface in view, not the ground under the feet. Only
 * clean frames: the model of a NOISY frame can be far off (945 mm for a
 * 1.2 m camera in test_detect_start_near_drop_is_not_clear), and as the
 * reference it hid the drop. */
void det_ground_ref_follow(detect_priv_t *p, const negobs_detect_config_t *cfg,
                           const gfit_out_t *g, int unverified)
{
    int32_t dh = g->pose.height_mm - p->ref_height_mm;
    if (!p->ref_ok) {
        if (cfg->ground_drop_mm > 0 && !unverified) {
            ground_ref_take(p, g, p->verify_by);
            if (p->walk_verified && p->walk_fits > 0) {
                /* verified by walking: the walk's mean fit, not one
                 * frame's, is the floor under the feet (detect_travel.c) */
                p->ref_height_mm = walk_mean_height_mm(p);
                p->ref_pitch_mdeg = (int32_t)(p->walk_pitch_sum /
                                              p->walk_fits);
            }
        }
        return;
    }
    if (p->drop_on || 2 * negobs_abs_s32(dh) >= cfg->ground_drop_mm) {
        return;
    }
    if (p->temporal.tick) {
        p->ref_height_mm += dh / 4;
        p->ref_pitch_mdeg += (g->pose.pitch_mdeg - p->ref_pitch_mdeg) / 4;
    }
}

/* The walking pitch sway of a worn camera is 1-3 deg either way; a fit
 * 5 deg flatter than the recent ones is not gait. Looking up that fast
 * costs about a second without a vouch (the track follows a flattening by
 * a sixteenth per frame), never an alarm. */
#define FIT_PITCH_FALL_MDEG 5000

/* Does this frame's ground fit lie ground_drop_mm or more below the
 * recent fits (a slow track of them)? Updates the track.
 *
 * The fall is the mirror of the cue's rise, with the opposite reading.
 * Walking up to a drop, the fit rows may come to hold the lower level
 * beyond the edge: the fitted plane then tilts onto it, the camera reads
 * lower and flatter than it is (on a 3 cm rig, a 17 cm stair edge at
 * 1.96 m: 1566 -> 1356 mm and 10.8 -> 3.8 deg in one frame, against a
 * true 1692 mm / 14.1 deg), and the walk read through that plane vouches
 * past the edge. On a narrow baseline a minimum drop near the fit rows
 * moves the floor disparity by less than the fit's pixel gates, so the
 * fit cannot see the edge itself. ground_drop_mm (100 mm) is four times
 * the whole amplitude of the walking bob (about 25 mm): a fit that far
 * below the recent ones is more likely tilted onto a lower level than the
 * floor under the feet, and the frame vouches nothing.
 *
 * The reference is a track, not the previous frame: the fit can stay on
 * the lower level for several frames while the edge is in the fit rows,
 * and the second of two such fits agreed with the first (a 3 cm rig at
 * 1.7 m, a 15 cm curb at 1.92 m: fits 1450 then 1420 mm against a true
 * 1705 mm, the second vouched 2.14 m). The track follows a rise by a
 * quarter of it per frame (a wearer standing up, a mount moved up) and a
 * fall by a sixteenth: a persistent 250 mm fall stays beyond
 * ground_drop_mm for about 15 frames (1.5 s at 10 fps), longer than a fit
 * sits on a lower level while walking past its edge; a wearer who
 * crouches gets that long of "no information". A rise is left to the cue
 * (det_ground_drop).
 *
 * On a steep camera the same tilt shows in the pitch alone: the lower
 * level fills the far part of the fit rows and the plane flattens about a
 * height that barely moves (6 cm rig at 1.26 m / 41 deg, a 5 cm curb at
 * 0.72 m: 1230 -> 1225 mm but 39.5 -> 31.7 deg in one frame, and the walk
 * vouched 833 mm). So a fit FIT_PITCH_FALL_MDEG or more flatter than a
 * slow track of the fitted pitch (the same quarter / sixteenth) vouches
 * nothing either. */
/* Row profile of the left image: per row, the mean grey of the middle
 * half of the columns, x 16. */
static void row_profile(const negobs_image_u8_t *left, int32_t *prof)
{
    const int32_t u0 = left->width / 4;
    const int32_t u1 = left->width - left->width / 4;
    int32_t v;
    for (v = 0; v < left->height; v++) {
        const uint8_t *row = negobs_image_u8_row(left, v);
        int32_t sum = 0;
        int32_t u;
        for (u = u0; u < u1; u++) {
            sum += row[u];
        }
        prof[v] = sum * 16 / (u1 - u0);
    }
}

/* Mean |a[v] - b[v + shift]| over the rows both hold (x 16 grey). */
static int32_t profile_sad(const int32_t *a, const int32_t *b, int32_t h,
                           int32_t shift)
{
    int64_t sum = 0;
    int32_t n = 0;
    int32_t v;
    for (v = 0; v < h; v++) {
        const int32_t w = v + shift;
        if (w >= 0 && w < h) {
            sum += negobs_abs_s32(a[v] - b[w]);
            n++;
        }
    }
    return (n > 0) ? (int32_t)(sum / n) : INT32_MAX;
}

/* Did the camera turn up by dpitch_mdeg since the profiled frame? A turn
 * moves the whole image by about f tan(dpitch) rows; a fit that flattened
 * onto a lower level moves nothing but the sway. The shift that explains
 * the turn must match at most 3/4 as badly as no shift (both signs are
 * tried: the image's row order is the caller's). */
static int image_turned(const detect_priv_t *p,
                        const negobs_detect_config_t *cfg, const int32_t *prof,
                        int32_t dpitch_mdeg)
{
    const int32_t h = cfg->rig.height;
    /* tan(x) ~ x (1 + x^2 / 3) for the few tens of degrees a head turns:
     * x in rad = mdeg * pi / 180000 */
    const int64_t x_q16 = (int64_t)dpitch_mdeg * 205887 / 180000; /* pi Q16 */
    const int64_t tan_q16 = x_q16 + x_q16 * x_q16 / 65536 * x_q16 / 65536 / 3;
    const int32_t shift =
        (int32_t)((tan_q16 * cfg->rig.focal_q4 / 16 + 32768) / 65536);
    int32_t c0;
    int32_t c1;
    if (shift < 2 || shift > h / 2) {
        return 0;
    }
    c0 = profile_sad(prof, p->row_prof, h, 0);
    c1 = geom_min_s32(profile_sad(prof, p->row_prof, h, shift),
                      profile_sad(prof, p->row_prof, h, -shift));
    return 4 * (int64_t)c1 <= 3 * (int64_t)c0;
}

int det_fit_fell(detect_priv_t *p, const negobs_detect_config_t *cfg,
                 const gfit_out_t *g, const negobs_image_u8_t *left)
{
    const int32_t ref = p->slow_fit_height_mm;
    int32_t h;
    int32_t pitch;
    int pitch_fell;
    int32_t *prof = p->row_prof_cur;
    const int have_image = left != NULL && left->width == cfg->rig.width &&
                           left->height == cfg->rig.height;
    if (!g->ok) {
        return 0; /* no fit: nothing vouched through one anyway */
    }
    h = g->pose.height_mm;
    pitch = g->pose.pitch_mdeg;
    if (have_image) {
        row_profile(left, prof);
    }
    if (ref <= 0) {
        p->slow_fit_height_mm = h;
        p->slow_fit_pitch_mdeg = pitch;
        pitch_fell = 0;
    } else {
        const int32_t ref_p = p->slow_fit_pitch_mdeg;
        /* followed on ticks (temporal.h): the same time at any rate */
        if (p->temporal.tick) {
            p->slow_fit_height_mm = ref + ((h > ref) ? (h - ref) / 4
                                                     : (h - ref) / 16);
            p->slow_fit_pitch_mdeg = ref_p + ((pitch > ref_p)
                                                  ? (pitch - ref_p) / 4
                                                  : (pitch - ref_p) / 16);
        }
        /* Without an image (or a profile to compare) a turn cannot be told
         * from a tilted fit, and the pitch is not judged. */
        pitch_fell = have_image && p->row_prof_ok &&
                     ref_p - pitch >= FIT_PITCH_FALL_MDEG;
        if (pitch_fell &&
            image_turned(p, cfg, prof, p->row_prof_pitch_mdeg - pitch)) {
            /* the camera turned up: the new pitch is the floor's */
            p->slow_fit_pitch_mdeg = pitch;
            pitch_fell = 0;
        }
        if (cfg->ground_drop_mm <= 0) {
            return 0;
        }
        if (ref - h >= cfg->ground_drop_mm) {
            pitch_fell = 1;
        }
    }
    if (have_image) {
        /* the profile of the last frame with a fit, and its pitch */
        p->row_prof_cur = p->row_prof;
        p->row_prof = prof;
        p->row_prof_ok = 1;
        p->row_prof_pitch_mdeg = pitch;
    }
    return pitch_fell;
}
