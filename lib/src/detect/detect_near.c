/* The floor nearer than the view: vouched by earlier frames, or not
 * (docs/DETECTION.md, "Verdicts and the vouched range": "The floor under
 * the view"). */
#include "detect_internal.h"

/*
 * A frame vouches for the floor it sees, from its nearest floor row
 * (seen_mm) to its vouched range (vouched_mm). The floor between the feet
 * and seen_mm is out of view; clear_to_mm speaks for it too, so it must
 * have been vouched by earlier frames while it was in view. This follows
 * that floor along the walk, in distances ahead of the feet:
 *
 *  - NEAR_OK: the floor is vouched from the feet to ahead_mm, a lower
 *    bound: each frame it shrinks by the farthest the walker can have
 *    come (hold_speed_mm_s x the time since the last frame) and grows to
 *    the frame's vouched range when the frame's view starts inside it.
 *  - NEAR_GAP: ahead_mm fell short of the view's nearest floor, so some
 *    floor that is now out of view was never vouched (an unconfirmed drop
 *    with a dark or untextured bottom, a noisy stretch). gap_mm, an upper
 *    bound of the distance to the far end of that floor, shrinks only by
 *    the travel the images show (travel_step: 0 when unmeasured); the
 *    floor vouched beyond it, from gap_mm to beyond_mm, is followed like
 *    ahead_mm. Once gap_mm + NEAR_MARGIN_MM has been walked, the walker
 *    has stepped over that floor with both feet and NEAR_OK resumes with
 *    ahead_mm = beyond_mm. Until then no frame vouches from the feet.
 *  - NEAR_START: nothing followed yet (switch-on, or a frame gap longer
 *    than hold_ms, after which the camera may be anywhere). The floor
 *    nearer than the first view is the start check's business
 *    (GROUND_UNVERIFIED, docs/DETECTION.md 6.1-6.2), so the first frame
 *    whose ground passed it (start_ok) starts NEAR_OK with its own view:
 *    ahead_mm is its vouched range, or its nearest floor when it vouches
 *    nothing. Not the first frame that vouches: the wearer may walk far
 *    over noisy floor before one does, and the floor walked towards in
 *    between was in view but never vouched (a 10 cm curb on smooth
 *    concrete, never confirmed, was left under the view and the next
 *    vouching frame said CLEAR to 1.5 m, 0.3 m beyond it).
 *
 * The start check itself may take many frames (a start verified by
 * walking: the nearest floor in view plus half a metre), and the floor
 * walked towards meanwhile leaves the view before the check passes. The
 * check covers only the floor that was nearer than its first view, so
 * the frames awaiting it are followed too (pend_any, pend_5cm), with the
 * range each would vouch once its ground is verified: the check verifies
 * the same plane they vouched from (a fit that rose restarts both,
 * det_near_pending_restart). The frame that ends NEAR_START takes that
 * following over instead of starting afresh with its own view; where the
 * awaiting frames vouched nothing, a gap is open. Before, the floor under
 * the view of such a frame was taken as vouched: a 5 cm drop that passed
 * below the view while the start was being walked, unchecked, read CLEAR
 * to 2.7-3.0 m with it 0.6-1.4 m ahead (docs/DETECTION.md 10.2).
 *
 * The floor is followed twice with these rules (near_track): for the
 * minimum drop of the range it was vouched at (near_any, needed up to the
 * view), and for 5 cm drops (near_5cm, needed up to the nearer of the
 * view and VOUCH_NEAR_RANGE_MM): the floor within 1.5 m of the feet must
 * be clear of 5 cm drops, and floor seen beyond 1.5 m was checked for 10 cm
 * only unless det_vouch_walk_5cm checked it (a 5 cm curb under a camera
 * whose view started at 1.52 m passed below it unchecked, and the next
 * frames said CLEAR to 1.5-2 m over it).
 *
 * The walk is one-dimensional, along the heading, as the tracks' hold is.
 */
enum { NEAR_START = 0, NEAR_OK = 1, NEAR_GAP = 2 };

/* Walked beyond the far end of unvouched floor before it is behind both
 * feet: half a stride (about 350 mm) for the trailing foot, and 150 mm
 * for the travel's own error, as for a start verified by walking
 * (detect_cue.c). */
#define NEAR_MARGIN_MM 500
/* Unvouched floor narrower than this between the vouched floor and the
 * view is let pass, as the walk lets a shorter unseen run pass
 * (detect_vouch.c, VOUCH_GAP_MM): it cannot take a foot. Without it the
 * ageing at the fastest walk, faster than most wearers go, opened gaps of
 * a few centimetres whenever frames vouched little beyond their view. */
#define NEAR_SLIVER_MM 100
#define NEAR_NONE (-1)

/* Does floor vouched up to to_mm reach a view that starts at seen_mm? */
static inline int near_reaches(int32_t to_mm, int32_t seen_mm)
{
    return to_mm + NEAR_SLIVER_MM >= seen_mm;
}

/* Grow a vouched stretch that reaches the view: 1 when it did. */
static inline int near_extend(int32_t *to_mm, int32_t seen_mm,
                              int32_t vouched_mm)
{
    if (!near_reaches(*to_mm, seen_mm)) {
        return 0;
    }
    *to_mm = geom_max_s32(*to_mm, vouched_mm);
    return 1;
}

/* A frame vouches only a stretch that starts at its nearest floor. */
static inline int near_vouches(int32_t seen_mm, int32_t vouched_mm)
{
    return seen_mm > 0 && vouched_mm > seen_mm;
}

/* Does this frame end NEAR_START: it vouches, or its ground passed the
 * start check with a floor in view? */
static inline int near_starts(int32_t seen_mm, int32_t vouched_mm,
                              int start_ok)
{
    return near_vouches(seen_mm, vouched_mm) || (start_ok && seen_mm > 0);
}

/* One following (the comment above) of the floor that must be vouched
 * from the feet to need_mm: seen_mm for the minimum drop of each range,
 * the nearer of seen_mm and VOUCH_NEAR_RANGE_MM for 5 cm. came_mm: the
 * farthest the walker can have come since the last frame. */
static int near_track(near_track_t *n, int32_t seen_mm, int32_t need_mm,
                      int32_t vouched_mm, int32_t came_mm, int32_t travel_mm,
                      int start_ok)
{
    const int vouched = near_vouches(seen_mm, vouched_mm);
    if (n->state == NEAR_START) {
        if (near_starts(seen_mm, vouched_mm, start_ok)) {
            n->state = NEAR_OK;
            n->ahead_mm = vouched ? vouched_mm : seen_mm;
        }
        return 1;
    }
    if (n->state == NEAR_GAP) {
        if (n->beyond_mm == NEAR_NONE) {
            /* nothing vouched since the gap opened: it reaches the first
             * view that vouches again */
            if (vouched) {
                n->gap_mm = seen_mm;
                n->beyond_mm = vouched_mm;
            }
            return 0;
        }
        n->gap_mm -= geom_max_s32(travel_mm, 0);
        n->beyond_mm = geom_max_s32(n->beyond_mm - came_mm, 0);
        if (n->gap_mm + NEAR_MARGIN_MM > 0) {
            if (vouched && !near_extend(&n->beyond_mm, seen_mm, vouched_mm)) {
                /* the unvouched floor reaches this frame's view */
                n->gap_mm = geom_max_s32(n->gap_mm, seen_mm);
                n->beyond_mm = vouched_mm;
            }
            return 0;
        }
        /* stepped over: the floor behind the gap was vouched up to
         * beyond_mm (0 if nothing was) */
        n->state = NEAR_OK;
        n->ahead_mm = geom_max_s32(n->beyond_mm, 0);
        came_mm = 0; /* beyond_mm has aged this frame already */
    }
    n->ahead_mm = geom_max_s32(n->ahead_mm - came_mm, 0);
    if (vouched) {
        (void)near_extend(&n->ahead_mm, seen_mm, vouched_mm);
    }
    /* a frame that vouches nothing says NO_INFO on its own; the floor
     * vouched earlier keeps shrinking until a frame does */
    if (seen_mm <= 0 || near_reaches(n->ahead_mm, need_mm)) {
        return 1;
    }
    /* all of the floor up to the view is out of view by the time it is
     * walked: it is the gap's far end */
    n->state = NEAR_GAP;
    n->gap_mm = seen_mm;
    n->beyond_mm = vouched ? vouched_mm : NEAR_NONE;
    return 0;
}

void det_near_pending_restart(detect_priv_t *p)
{
    p->pend_any.state = NEAR_START;
    p->pend_5cm.state = NEAR_START;
}

/* While the start check is pending: follow the awaiting frames with what
 * they would vouch (a frame without usable ground vouches nothing and
 * starts nothing), and hand that following over on the frame that starts
 * the following proper (before it is followed with this frame). */
static void near_pending(detect_priv_t *p, int32_t seen_mm, int32_t vouched_mm,
                         int32_t vouched_5cm_mm, int32_t pending_mm,
                         int32_t came_mm, int32_t travel_mm, int start_ok)
{
    const int usable = pending_mm >= 0;
    if (p->near_any.state != NEAR_START && p->near_5cm.state != NEAR_START) {
        return;
    }
    if (near_starts(seen_mm, vouched_mm, start_ok)) {
        if (p->pend_any.state != NEAR_START) {
            p->near_any = p->pend_any;
            p->near_5cm = p->pend_5cm;
        }
        det_near_pending_restart(p);
        return;
    }
    if (!usable && p->pend_any.state == NEAR_START) {
        return;
    }
    (void)near_track(&p->pend_any, seen_mm, seen_mm, usable ? pending_mm : 0,
                     came_mm, travel_mm, usable);
    (void)near_track(&p->pend_5cm, seen_mm,
                     geom_min_s32(seen_mm, VOUCH_NEAR_RANGE_MM),
                     usable ? geom_min_s32(vouched_5cm_mm, pending_mm) : 0,
                     came_mm, travel_mm, usable);
}

int det_near_follow(detect_priv_t *p, const negobs_detect_config_t *cfg,
                    int32_t seen_mm, int32_t vouched_mm,
                    int32_t vouched_5cm_mm, int32_t pending_mm,
                    int32_t travel_mm, int start_ok, uint32_t now_ms)
{
    const int32_t dt = (int32_t)(now_ms - p->near_ms);
    /* dt <= hold_ms <= 60 s and hold_speed <= 5 m/s: at most 3e5 mm */
    const int32_t came_mm = (int32_t)(((int64_t)cfg->hold_speed_mm_s *
                                       geom_max_s32(dt, 0)) /
                                      1000);
    int ok_any;
    int ok_5cm;
    if (!p->near_on || dt < 0 || dt > cfg->hold_ms) {
        p->near_any.state = NEAR_START;
        p->near_5cm.state = NEAR_START;
        det_near_pending_restart(p);
    }
    p->near_on = 1;
    p->near_ms = now_ms;
    near_pending(p, seen_mm, vouched_mm, vouched_5cm_mm, pending_mm, came_mm,
                 travel_mm, start_ok);
    ok_any = near_track(&p->near_any, seen_mm, seen_mm, vouched_mm, came_mm,
                        travel_mm, start_ok);
    ok_5cm = near_track(&p->near_5cm, seen_mm,
                        geom_min_s32(seen_mm, VOUCH_NEAR_RANGE_MM),
                        geom_min_s32(vouched_5cm_mm, vouched_mm), came_mm,
                        travel_mm, start_ok);
    return ok_any && ok_5cm;
}

int det_near_gap(const detect_priv_t *p)
{
    return p->near_any.state == NEAR_GAP || p->near_5cm.state == NEAR_GAP;
}
