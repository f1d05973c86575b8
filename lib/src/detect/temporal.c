/*
 * Hazard tracks.
 *
 * Association is greedy, nearest range first, inside a gate that follows
 * the walking geometry: a real edge can only come closer, by at most
 * max_speed * dt (plus the association tolerance), and may look up to
 * assoc_range_mm, and no more than 20 % of its range, farther because of
 * noise (farther_tol_mm). Lateral offsets must agree
 * within assoc_lateral_mm.
 *
 * A track is confirmed when it was seen in confirm_k of the last confirm_n
 * frames and one of its sightings' drops reached h_t (sighting_reaches),
 * missing ground only once it came nearer as the wearer walked
 * (track_approaches), and then stays confirmed until clear_m consecutive
 * clean ticks (frames at least 3/4 of frame_interval_ms apart:
 * temporal_clock()).
 * Frames that are not "observed" (degraded) never count as clean, and
 * their candidates only refresh tracks that are already confirmed. When a
 * confirmed track is lost close to the bottom of the image it is held: its
 * range is dead-reckoned at hold_speed_mm_s and it keeps alerting for
 * hold_ms, or until the floor patches measured the wearer walking
 * HOLD_PAST_MM past its last range (track_unseen).
 */
#include "temporal.h"

#include <string.h>

#include "detect_int.h"
#include "geom_internal.h"

static uint32_t popcount32(uint32_t x)
{
    uint32_t c = 0;
    while (x != 0u) {
        x &= x - 1u;
        c++;
    }
    return c;
}

static int32_t elapsed_ms(uint32_t now, uint32_t then)
{
    /* Wrap-safe difference; negative if the clock went backwards. */
    return (int32_t)(now - then);
}

void temporal_reset(temporal_t *t, const negobs_detect_config_t *cfg)
{
    memset(t, 0, sizeof *t);
    t->cfg = cfg;
    t->next_id = 1;
}

static uint32_t window_mask(const negobs_detect_config_t *cfg)
{
    return (cfg->confirm_n >= 32) ? 0xFFFFFFFFu
                                  : (((uint32_t)1 << cfg->confirm_n) - 1u);
}

void temporal_clock(temporal_t *t, uint32_t now_ms)
{
    const int32_t iv = t->cfg->frame_interval_ms;
    const int32_t dt = elapsed_ms(now_ms, t->tick_ms);
    /* 3/4 of the interval: a 10 fps camera's jitter never skips a tick,
     * 30 fps ticks on every third frame, 15 fps on every other one */
    t->tick = iv <= 0 || !t->tick_have || dt < 0 || 4 * dt >= 3 * iv;
    if (t->tick) {
        t->tick_ms = now_ms;
        t->tick_have = 1;
    }
    t->clocked = 1;
}

static int32_t held_range(const negobs_detect_config_t *cfg,
                          const tmp_track_t *tr, uint32_t now_ms)
{
    int64_t dt = elapsed_ms(now_ms, tr->last_seen_ms);
    int64_t r;
    if (dt < 0) {
        dt = 0;
    }
    r = tr->hz.range_mm - ((int64_t)cfg->hold_speed_mm_s * dt) / 1000;
    return (int32_t)((r < 0) ? 0 : r);
}

void temporal_walked(temporal_t *t, int32_t travel_mm)
{
    if (travel_mm > 0) {
        t->odo_mm += (uint32_t)travel_mm;
    }
}

int temporal_needs_travel(const temporal_t *t)
{
    int32_t k;
    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        const tmp_track_t *tr = &t->tracks[k];
        if (tr->active &&
            (tr->confirmed || tr->hz.type == NEGOBS_HAZARD_UNKNOWN)) {
            return 1;
        }
    }
    return 0;
}

/*
 * Missing ground must come nearer as the wearer walks before it confirms.
 *
 * A band without matches from some row to the end of the scan is what a
 * drop whose lower level lies beyond the camera's sight looks like, but
 * also what any floor looks like where its texture fades into the
 * sensor's noise with distance (the pixel's footprint grows with range
 * and averages the grain away): there the band's near end is the sight
 * limit, tied to the camera, and stays the same distance ahead while the
 * wearer walks. Confirmed, it was a caution that walked along with the
 * wearer on every frame of a flat walk (docs/DETECTION.md, "Missing
 * ground"). A drop is a place: its distance falls by what the wearer
 * walks.
 *
 * So a track that only missing ground has seen confirms once the floor
 * patches measured at least APPROACH_WALK_MM of travel between its first
 * and its last sighting (section 6.2), and its place along the walk,
 * range plus odometer, moved by at most half that travel: about 0 for an
 * edge, all of it for a sight limit. The median of three sightings at
 * each end (six sightings at least, so the two ends are apart), because
 * the band's near end scatters by 100-300 mm from frame to frame; 500 mm
 * walked (about four ticks at 1.2 m/s) puts the half-way mark, 250 mm,
 * beyond that scatter of a median of three. A measured drop (a deficit)
 * confirms as before, and a track a measured sighting joined is a drop
 * (track_refresh keeps its type). Travel that is not measured (a
 * standing wearer, a bland floor) confirms nothing: the band still ends
 * the vouched range, so the verdict never says clear past it.
 */
enum { APPROACH_WALK_MM = 500 };

static int32_t median3_s32(int32_t a, int32_t b, int32_t c)
{
    return geom_max_s32(geom_min_s32(a, b),
                        geom_min_s32(geom_max_s32(a, b), c));
}

static void track_place(temporal_t *t, tmp_track_t *tr, int32_t range_mm)
{
    const uint32_t place = t->odo_mm + (uint32_t)geom_max_s32(range_mm, 0);
    if (tr->n_places < TMP_PLACES) {
        if (tr->n_places == 0) {
            tr->first_odo_mm = t->odo_mm;
        }
        tr->first_place_mm[tr->n_places] = place;
    }
    if (tr->n_places < 2 * TMP_PLACES) {
        tr->n_places++;
    }
    tr->last_place_mm[0] = tr->last_place_mm[1];
    tr->last_place_mm[1] = tr->last_place_mm[2];
    tr->last_place_mm[2] = place;
}

static int track_approaches(const tmp_track_t *tr)
{
    int32_t walked;
    int32_t start;
    int32_t end;
    uint32_t base;
    if (tr->hz.type != NEGOBS_HAZARD_UNKNOWN) {
        return 1;
    }
    if (tr->n_places < 2 * TMP_PLACES) {
        return 0; /* the first three and the last three are apart */
    }
    /* wrap-safe: every place and odometer reading relative to the first */
    walked = (int32_t)(tr->seen_odo_mm - tr->first_odo_mm);
    if (walked < APPROACH_WALK_MM) {
        return 0;
    }
    base = tr->first_place_mm[0];
    start = median3_s32(0, (int32_t)(tr->first_place_mm[1] - base),
                        (int32_t)(tr->first_place_mm[2] - base));
    end = median3_s32((int32_t)(tr->last_place_mm[0] - base),
                      (int32_t)(tr->last_place_mm[1] - base),
                      (int32_t)(tr->last_place_mm[2] - base));
    return end - start <= walked / 2;
}

void temporal_update(temporal_t *t, const negobs_hazard_t *cands, uint32_t n,
                     int observed, int32_t hold_range_mm, uint32_t now_ms)
{
    temporal_update_vouched(t, cands, NULL, n, observed, 0, INT32_MAX,
                            hold_range_mm, now_ms);
}

/* Candidates nearest first (insertion sort, n <= 8): the nearest edge is
 * the most urgent, so it gets first pick of the tracks. */
static void sort_nearest_first(const negobs_hazard_t *cands, uint32_t n,
                               uint32_t *order)
{
    uint32_t i;
    uint32_t j;
    for (i = 0; i < n; i++) {
        order[i] = i;
    }
    for (i = 1; i < n; i++) {
        uint32_t x = order[i];
        j = i;
        while (j > 0 && cands[order[j - 1]].range_mm > cands[x].range_mm) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = x;
    }
}

/*
 * How much farther than a track's last range a sighting may lie:
 * assoc_range_mm, but no more than ASSOC_FARTHER_PCT of that range. A
 * sighting's range error grows with the range (the disparity error and
 * the edge's row both weigh more far off), and the suite's p95 is 7-12 %
 * of the true range (docs/DETECTION.md section 12), so two sightings of
 * one edge differ by up to about 17 %; a fixed 400 mm is that at 2.3 m
 * and 33 % at 1.2 m, where it let matching noise on a bland floor hop
 * from 1.20 m to 1.59 m and confirm a track held IMMINENT to the feet.
 * Real edges do jump farther now and then (up to 29 % on a 6 cm rig over
 * paving), but rarely: 2 of 7 939 consecutive trusted sightings of real
 * drops in the suite and generic draws 11-21 lay more than 20 % and
 * less than 400 mm farther; such a sighting starts a track of its own.
 * Never below ASSOC_FARTHER_MIN_MM, a shoe's width. A held track's range
 * is dead-reckoned at hold_speed_mm_s, a guess at the walking speed,
 * so its gate keeps the full assoc_range_mm (assoc_best).
 */
#define ASSOC_FARTHER_PCT 20
#define ASSOC_FARTHER_MIN_MM 100

static int32_t farther_tol_mm(const negobs_detect_config_t *cfg,
                              int32_t range_mm)
{
    int32_t rel = geom_max_s32(
        (int32_t)(((int64_t)geom_max_s32(range_mm, 0) * ASSOC_FARTHER_PCT) /
                  100),
        ASSOC_FARTHER_MIN_MM);
    return geom_min_s32(cfg->assoc_range_mm, rel);
}

/*
 * 1 when a sighting's own drop estimate reaches h_t, the drop the rule is
 * set for at its range (h_thresh_pct of h_min_near within h_near_range,
 * of h_min_far beyond). The rule counts a pixel whose deficit reaches h_t's,
 * rounded down to whole 1/16 px; at the 4-8 px of the floor 1.5-3 m ahead
 * of a 6 cm rig one such step is 13-30 % of it, so noise alone passes rows
 * with a plateau of 28-35 mm where h_t is 40. A track none of whose
 * sightings reached h_t has only that rounding to show: it is not
 * confirmed (30-34 mm "holes" on a textured flat walk, B = 6 cm, pitch
 * 35 deg, were held IMMINENT to its end). One sighting is enough: a real
 * 5 cm drop at B = 6 cm reads 36 mm or more a sighting, median 55-76 mm
 * (the suite and fresh draws), so among three sightings one reaches 40.
 * Missing ground and the ground-drop cue measure no plateau: they always
 * reach.
 */
static int sighting_reaches(const negobs_detect_config_t *cfg,
                            const negobs_hazard_t *c)
{
    if (c->type == NEGOBS_HAZARD_UNKNOWN ||
        (c->flags & NEGOBS_HAZARD_F_GROUND_DROP) != 0u) {
        return 1;
    }
    return c->drop_mm >= det_h_t_at(cfg, c->range_mm) &&
           (c->flags & NEGOBS_HAZARD_F_UNIT_SHALLOW) == 0u;
}

/* The unassociated track whose gate (the walking geometry of the file
 * comment) holds the candidate, nearest predicted range first; -1 if none. */
static int32_t assoc_best(const temporal_t *t, const negobs_hazard_t *c,
                          const int32_t *used, uint32_t now_ms)
{
    const negobs_detect_config_t *cfg = t->cfg;
    int32_t best = -1;
    int32_t best_err = INT32_MAX;
    int32_t k;
    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        const tmp_track_t *tr = &t->tracks[k];
        int32_t pred;
        int32_t lo;
        int32_t hi;
        int32_t err;
        int32_t age;
        if (!tr->active || used[k]) {
            continue;
        }
        age = elapsed_ms(now_ms, tr->last_seen_ms);
        if (age < 0) {
            age = 0;
        }
        pred = tr->held ? held_range(cfg, tr, now_ms) : tr->hz.range_mm;
        hi = pred +
             (tr->held ? cfg->assoc_range_mm : farther_tol_mm(cfg, pred));
        lo = pred - cfg->assoc_range_mm -
             (int32_t)(((int64_t)cfg->max_speed_mm_s * age) / 1000);
        if (c->range_mm > hi || c->range_mm < lo) {
            continue;
        }
        if (negobs_abs_s32(c->lateral_mm - tr->hz.lateral_mm) >
            cfg->assoc_lateral_mm) {
            continue;
        }
        err = negobs_abs_s32(c->range_mm - pred);
        if (err < best_err) {
            best_err = err;
            best = k;
        }
    }
    return best;
}

/* New track: an unused slot, else the weakest unconfirmed one, so a
 * confirmed hazard is never displaced by a new sighting; -1 if all slots
 * hold confirmed hazards. */
static int32_t new_track_slot(const temporal_t *t, const int32_t *used)
{
    const negobs_detect_config_t *cfg = t->cfg;
    uint32_t weakest = 0xFFFFFFFFu;
    int32_t best = -1;
    int32_t k;
    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        if (!t->tracks[k].active) {
            return k;
        }
    }
    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        const tmp_track_t *tr = &t->tracks[k];
        uint32_t hits = popcount32(tr->hist & window_mask(cfg));
        if (!tr->confirmed && !used[k] && hits < weakest) {
            weakest = hits;
            best = k;
        }
    }
    return best;
}

/* Does weak sighting c lie where track tr's edge can be now? Its last
 * trusted range, nearer by at most the walk since (hold_speed_mm_s, the
 * fastest wearer, as the hold) and a shoe's width (ASSOC_FARTHER_MIN_MM,
 * the measurement's slack), farther by at most the farther gate. The
 * association's own gate lets a sighting come nearer at max_speed_mm_s
 * and assoc_range_mm more: right for a trusted sighting, which moves the
 * track, too loose for a noisy one that only counts (a noise hole
 * 0.53 m nearer than a 10 cm curb it joined confirmed, at its own range,
 * on a 3 cm rig). */
static int weak_fits(const negobs_detect_config_t *cfg, const tmp_track_t *tr,
                     const negobs_hazard_t *c, uint32_t now_ms)
{
    const int32_t age = geom_max_s32(elapsed_ms(now_ms, tr->last_seen_ms), 0);
    const int32_t pred = tr->hz.range_mm;
    const int32_t lo = pred - ASSOC_FARTHER_MIN_MM -
                       (int32_t)(((int64_t)cfg->hold_speed_mm_s * age) / 1000);
    return c->range_mm >= lo &&
           c->range_mm <= pred + farther_tol_mm(cfg, pred);
}

/* The window moves on by a frame: trusted / weak say what this frame saw
 * of the track, tick whether the frame is a tick. */
static void track_shift(tmp_track_t *tr, int trusted, int weak, int tick)
{
    tr->hist = (tr->hist << 1) | (trusted ? 1u : 0u);
    tr->weak = (tr->weak << 1) | (weak ? 1u : 0u);
    tr->ticks = (tr->ticks << 1) | (tick ? 1u : 0u);
}

/* confirm_k trusted sightings in the window, or confirm_k - 1 and a weak
 * one: a noisy sighting may fill the gap between trusted ones (a 10 cm
 * curb on smooth concrete seen by a 6 cm rig: trusted, too noisy,
 * trusted, three frames running), but never stand in for more than one
 * of them, so noise alone still confirms nothing. */
static int confirms(const negobs_detect_config_t *cfg, const tmp_track_t *tr)
{
    const uint32_t m = window_mask(cfg);
    const uint32_t k = (uint32_t)cfg->confirm_k;
    if (popcount32(tr->hist & m) >= k) {
        return 1;
    }
    /* with a weak sighting (on a tick), the trusted ones count on ticks
     * only: every look then is a tick apart, a fresh view of the place
     * (at 30 fps a window of five frames holds two ticks, so a weak
     * sighting never confirms there) */
    return (tr->weak & m) != 0u &&
           popcount32(tr->hist & tr->ticks & m) + 1u >= k;
}

static void track_start(temporal_t *t, tmp_track_t *tr,
                        const negobs_hazard_t *c, uint32_t now_ms)
{
    memset(tr, 0, sizeof *tr);
    tr->active = 1;
    tr->hz = *c;
    tr->hz.track_id = t->next_id++;
    tr->near_mm = c->range_mm;
    tr->last_seen_ms = now_ms;
    tr->hist = 0;
}

/* A sighting of an existing track: its range, approach speed and near
 * bound follow the sighting, its identity and drop type persist. */
static void track_refresh(const negobs_detect_config_t *cfg, tmp_track_t *tr,
                          const negobs_hazard_t *c, uint32_t now_ms)
{
    int32_t age = elapsed_ms(now_ms, tr->last_seen_ms);
    uint32_t id = tr->hz.track_id;
    negobs_hazard_type_t old_type = tr->hz.type;
    /* Where the track's own approach put this sighting: a real
     * edge only comes nearer while the wearer walks on, so a
     * sighting farther than that is as likely a range error of
     * this frame (a ground model tilted by the drop itself read
     * 15-19 % too far) as a wearer who turned back. Vouching
     * takes the nearer (temporal_vouch_bound). */
    int32_t pred = (tr->held ? held_range(cfg, tr, now_ms) : tr->hz.range_mm) -
                   (int32_t)(((int64_t)tr->speed_mm_s * geom_max_s32(age, 0)) /
                             1000);
    tr->near_mm = geom_min_s32(c->range_mm, geom_max_s32(pred, 0));
    if (age > 0) {
        int32_t inst =
            (int32_t)(((int64_t)(tr->hz.range_mm - c->range_mm) * 1000) / age);
        inst = negobs_clamp_s32(inst, 0, cfg->max_speed_mm_s);
        tr->speed_mm_s += (inst - tr->speed_mm_s) / 4;
    }
    tr->hz = *c;
    tr->hz.track_id = id;
    /* Missing ground never downgrades a measured drop. */
    if (c->type == NEGOBS_HAZARD_UNKNOWN) {
        tr->hz.type = old_type;
    }
    tr->last_seen_ms = now_ms;
}

/*
 * A held track ends once the measured travel since its last sighting
 * passed that range by HOLD_PAST_MM: the wearer stands beyond the edge,
 * on a floor whose patches tracked the walk. Half a metre covers a last
 * range read up to 15 % short at the hold's 1-1.5 m (p95 range error 7-12
 * %, docs/DETECTION.md section 12) together with a travel read 14 % long
 * (patches on a 15 cm step above the floor model, at 1.2 m). Patches
 * beyond a drop lie below the model and read the travel short: the hold
 * only lasts longer. Travel that was not measured (a standing wearer, a
 * bland floor) counts nothing, and hold_ms ends the hold as before.
 */
#define HOLD_PAST_MM 500

/* A track without a sighting this frame: held tracks time out, confirmed
 * ones whose edge has gone below the view are held, tracks the frame
 * could not vouch for wait, the others count a miss (confirmed ones close
 * by are held instead, since the camera loses them underfoot). */
static void track_unseen(const temporal_t *t, tmp_track_t *tr, int observed,
                         int32_t seen_from_mm, int32_t seen_to_mm,
                         int32_t hold_range_mm, uint32_t now_ms)
{
    const negobs_detect_config_t *cfg = t->cfg;
    if (tr->held) {
        const int32_t walked = (int32_t)(t->odo_mm - tr->seen_odo_mm);
        if (elapsed_ms(now_ms, tr->hold_start_ms) > cfg->hold_ms ||
            (int64_t)walked >= (int64_t)tr->hz.range_mm + HOLD_PAST_MM) {
            tr->active = 0;
        }
        return;
    }
    if (observed && tr->confirmed &&
        held_range(cfg, tr, now_ms) < seen_from_mm) {
        /* The edge, dead-reckoned from its last sighting as the report
         * places it, now lies nearer than the view's nearest floor: the
         * camera has lost it underfoot, so it is held, whatever its last
         * range. (Counted as missed at that range by frames that vouched
         * from the view's nearest floor on, a 15 cm curb confirmed 3.6 m
         * ahead of a camera pitched 5 deg, whose view starts 2.3 m ahead,
         * was dropped 1.6 m before the edge: CLEAR.) */
        tr->held = 1;
        tr->hold_start_ms = now_ms;
        return;
    }
    if (!observed || (tr->hz.range_mm > seen_to_mm &&
                      !(tr->confirmed && tr->hz.range_mm <= hold_range_mm))) {
        /* No evidence either way (the frame did not vouch for the
         * track's place): it is not a miss, and only time can retire
         * a confirmed track. An unconfirmed track's window still
         * moves on: confirmation is confirm_k sightings within the
         * last confirm_n frames, i.e. persistence in time. Were the
         * window frozen, sightings scattered over frames that could
         * not look between them (frames vouching 0 mm, trusting a
         * candidate on its own strips only) would add up to a
         * "3 of 5" over any number of frames: matching noise that
         * recurs now and then would confirm. */
        if (!tr->confirmed) {
            track_shift(tr, 0, 0, t->tick);
            if ((tr->hist & window_mask(cfg)) == 0u) {
                tr->active = 0;
                return;
            }
        }
        if (elapsed_ms(now_ms, tr->last_seen_ms) > cfg->hold_ms) {
            tr->active = 0;
        }
        return;
    }
    track_shift(tr, 0, 0, t->tick);
    if (t->tick) {
        tr->misses++; /* clean time, counted in ticks */
    }
    if (tr->confirmed) {
        if (tr->hz.range_mm <= hold_range_mm) {
            tr->held = 1;
            tr->hold_start_ms = now_ms;
        } else if (tr->misses >= cfg->clear_m) {
            tr->active = 0;
        }
    } else if ((tr->hist & window_mask(cfg)) == 0u) {
        tr->active = 0;
    }
}

void temporal_update_vouched(temporal_t *t, const negobs_hazard_t *cands,
                             const uint8_t *trusted, uint32_t n, int observed,
                             int32_t seen_from_mm, int32_t seen_to_mm,
                             int32_t hold_range_mm, uint32_t now_ms)
{
    const negobs_detect_config_t *cfg = t->cfg;
    int32_t used[NEGOBS_DETECT_MAX_TRACKS];
    uint32_t order[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t i;
    int32_t k;

    if (!t->clocked) {
        temporal_clock(t, now_ms);
    }
    t->clocked = 0; /* the next frame is clocked afresh */
    if (n > NEGOBS_DETECT_MAX_HAZARDS) {
        n = NEGOBS_DETECT_MAX_HAZARDS;
    }
    memset(used, 0, sizeof used);
    sort_nearest_first(cands, n, order);

    for (i = 0; i < n; i++) {
        const negobs_hazard_t *c = &cands[order[i]];
        int32_t best = assoc_best(t, c, used, now_ms);
        const uint8_t trust = (trusted != NULL) ? trusted[order[i]]
                                                : (uint8_t)TMP_TRUSTED;
        /* A weak sighting of an unconfirmed track on an observed frame:
         * the same place again, a step too noisy to vouch by itself. Only
         * on ticks: frames closer than that see nearly the same images,
         * whose matching noise is not a fresh look (at 30 fps a phantom
         * read on three frames within 0.1 s confirmed on a flat walk). */
        const int weak = observed && trust == TMP_WEAK && best >= 0 &&
                         !t->tracks[best].confirmed && t->tick &&
                         weak_fits(cfg, &t->tracks[best], c, now_ms);
        if ((!observed || trust != TMP_TRUSTED) && !weak &&
            (best < 0 || !t->tracks[best].confirmed)) {
            /* A degraded frame's candidate may refresh a hazard that clean
             * frames confirmed, but never starts or confirms one: on such
             * frames the deficits are as likely to be matching noise. */
            continue;
        }
        if (best < 0) {
            best = new_track_slot(t, used);
            if (best < 0) {
                continue; /* every slot holds a confirmed hazard */
            }
            track_start(t, &t->tracks[best], c, now_ms);
        } else if (!weak) {
            track_refresh(cfg, &t->tracks[best], c, now_ms);
        }
        used[best] = 1;
        if (!weak) {
            /* a weak sighting says the place is still there, not where
             * it is nor how deep: the track keeps its trusted range,
             * speed and depth */
            t->tracks[best].seen_odo_mm = t->odo_mm;
            t->tracks[best].reached |= sighting_reaches(cfg, c);
            track_place(t, &t->tracks[best], c->range_mm);
        }
        track_shift(&t->tracks[best], !weak, weak, t->tick);
        t->tracks[best].misses = 0;
        t->tracks[best].held = 0;
        if (t->tracks[best].reached && confirms(cfg, &t->tracks[best]) &&
            track_approaches(&t->tracks[best])) {
            t->tracks[best].confirmed = 1;
        }
    }

    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        tmp_track_t *tr = &t->tracks[k];
        if (!tr->active || used[k]) {
            continue;
        }
        track_unseen(t, tr, observed, seen_from_mm, seen_to_mm, hold_range_mm,
                     now_ms);
    }
    t->last_ms = now_ms;
    t->have_last = 1;
}

/*
 * A track not seen this frame is where its last sighting put it,
 * dead-reckoned, and that sighting's range error stays with it in
 * millimetres while the range shrinks: a stair edge last read 8 % far at
 * 1.64 m, held below the view, was still 130 mm far at 0.65 m, 20 %. The
 * vouch stops short of such a track by the detector's range error at
 * p95 (7-12 % on the suite, docs/DETECTION.md section 12) of that last
 * range. A track seen this frame is bounded by its own range, measured
 * now.
 */
enum { UNSEEN_RANGE_ERR_PCT = 12 };

int32_t temporal_vouch_bound(const temporal_t *t, uint32_t now_ms)
{
    int32_t bound = INT32_MAX;
    int32_t k;
    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        const tmp_track_t *tr = &t->tracks[k];
        int64_t dt;
        int64_t r;
        if (!tr->active || !(tr->confirmed || tr->held)) {
            continue;
        }
        dt = geom_max_s32(elapsed_ms(now_ms, tr->last_seen_ms), 0);
        r = geom_min_s32(tr->near_mm, tr->hz.range_mm) -
            ((int64_t)t->cfg->hold_speed_mm_s * dt) / 1000;
        if (dt > 0) {
            r -= ((int64_t)tr->hz.range_mm * UNSEEN_RANGE_ERR_PCT) / 100;
        }
        bound = geom_min_s32(bound, (int32_t)((r < 0) ? 0 : r));
    }
    return bound;
}

int temporal_covers(const temporal_t *t, int32_t range_mm, uint32_t now_ms)
{
    int32_t k;
    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        const tmp_track_t *tr = &t->tracks[k];
        if (tr->active && (tr->confirmed || tr->held) &&
            held_range(t->cfg, tr, now_ms) <= range_mm) {
            return 1;
        }
    }
    return 0;
}

uint32_t temporal_report(const temporal_t *t, negobs_hazard_t *out,
                         uint32_t max, uint32_t now_ms)
{
    const negobs_detect_config_t *cfg = t->cfg;
    uint32_t n = 0;
    uint32_t i;
    int32_t k;

    for (k = 0; k < NEGOBS_DETECT_MAX_TRACKS; k++) {
        const tmp_track_t *tr = &t->tracks[k];
        negobs_hazard_t h;
        negobs_alert_level_t lv = NEGOBS_LEVEL_NONE;
        if (!tr->active || !(tr->confirmed || tr->held)) {
            continue;
        }
        if (tr->hz.type == NEGOBS_HAZARD_UNKNOWN &&
            cfg->missing_policy == NEGOBS_MISSING_IGNORE) {
            continue;
        }
        h = tr->hz;
        h.flags |= NEGOBS_HAZARD_F_CONFIRMED;
        if (tr->held) {
            h.flags |= NEGOBS_HAZARD_F_HELD;
        }
        /* Not seen this frame (missed, degraded or held): the walker may
         * have gone on, so report it where it would be by now, never at
         * the last range seen. */
        h.range_mm = held_range(cfg, tr, now_ms);
        if (tr->held || h.range_mm <= cfg->range_imminent_mm ||
            (tr->speed_mm_s >= 300 &&
             ((int64_t)h.range_mm * 1000) / tr->speed_mm_s <
                 cfg->ttc_imminent_ms)) {
            /* At the edge, held below the image, or reached within the
             * time to contact at the walking speed. */
            lv = NEGOBS_LEVEL_IMMINENT;
        } else if (h.range_mm <= cfg->range_warn_mm) {
            lv = NEGOBS_LEVEL_CAUTION;
        }
        if (h.type == NEGOBS_HAZARD_UNKNOWN &&
            (cfg->missing_policy == NEGOBS_MISSING_CAUTION ||
             (cfg->missing_policy == NEGOBS_MISSING_TEXTURED &&
              !(h.flags & NEGOBS_HAZARD_F_TEXTURED))) &&
            lv == NEGOBS_LEVEL_IMMINENT) {
            lv = NEGOBS_LEVEL_CAUTION;
        }
        h.level = lv;
        if (n < max) {
            /* Insert sorted by range. */
            i = n;
            while (i > 0 && out[i - 1].range_mm > h.range_mm) {
                out[i] = out[i - 1];
                i--;
            }
            out[i] = h;
            n++;
        }
    }
    return n;
}
