/* Recent sightings bound the vouched range (docs/DETECTION.md, "Verdicts
 * and the vouched range": "Recent sightings"). */
#include "detect_internal.h"

/*
 * The vouched range of this frame, as far as the candidates of the last
 * confirm_n - 1 frame intervals (frame_interval_ms; frames when it is 0)
 * allow: each sighting at range r, t ms ago, bounds
 * it at r - hold_speed_mm_s * t (the walker may have come that much
 * nearer), at least 0. INT32_MAX when there is none.
 *
 * Why: a candidate cuts its own frame's vouch whether or not it is
 * trusted or confirmed, but the next frame may not see it at all. On a
 * narrow-baseline or low camera the edge of a small drop leaves the fit
 * rows' view within a frame or two of being first seen, and the ground
 * fit can settle on the level below, one drop higher (below
 * ground_drop_mm, so det_fit_fell does not see it). Read through that
 * plane the floor beyond the edge is flat and the walk vouches past the
 * edge. A sighting is evidence for as long as the tracker would weigh it,
 * the confirmation window of confirm_n frames; within it the vouch never
 * passes a place where a drop was seen. A frame gap longer than hold_ms
 * ends every sighting: the camera may have moved anywhere.
 */
int32_t det_sight_bound(const detect_priv_t *p,
                        const negobs_detect_config_t *cfg, uint32_t now_ms)
{
    int32_t bound = INT32_MAX;
    int32_t i;
    /* the window in time at the configured frame interval (to its middle
     * beyond the last one), else in frames */
    const int32_t iv = cfg->frame_interval_ms;
    const int64_t span_ms = (iv > 0)
                                ? (int64_t)(cfg->confirm_n - 1) * iv + iv / 2
                                : (int64_t)cfg->hold_ms;
    int32_t n = (iv > 0) ? p->sight_n
                         : geom_min_s32(p->sight_n, cfg->confirm_n - 1);
    for (i = 0; i < n; i++) {
        int32_t k = (p->sight_head - 1 - i + SIGHT_FRAMES) % SIGHT_FRAMES;
        int64_t dt = (int64_t)(int32_t)(now_ms - p->sight_ms[k]);
        int64_t r;
        if (dt < 0 || dt > cfg->hold_ms || dt > span_ms) {
            break; /* older entries are older still */
        }
        if (p->sight_range_mm[k] == INT32_MAX) {
            continue;
        }
        r = p->sight_range_mm[k] - (cfg->hold_speed_mm_s * dt) / 1000;
        bound = geom_min_s32(bound, (int32_t)((r < 0) ? 0 : r));
    }
    return bound;
}

/* Note this frame's nearest candidate (INT32_MAX: none) for the next
 * frames' det_sight_bound. */
void det_sight_note(detect_priv_t *p, const negobs_detect_result_t *res,
                    uint32_t now_ms)
{
    int32_t r = INT32_MAX;
    uint32_t i;
    for (i = 0; i < res->n_candidates; i++) {
        r = geom_min_s32(r, geom_max_s32(res->candidates[i].range_mm, 0));
    }
    p->sight_range_mm[p->sight_head] = r;
    p->sight_ms[p->sight_head] = now_ms;
    p->sight_head = (p->sight_head + 1) % SIGHT_FRAMES;
    p->sight_n = geom_min_s32(p->sight_n + 1, SIGHT_FRAMES);
}
