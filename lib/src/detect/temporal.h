/*
 * Temporal logic for hazards (internal): k-of-n confirmation, clearing
 * after m clean ticks, and the hold when a confirmed edge leaves the
 * bottom of the image (it is then closer, not gone). Confirmation
 * counts frames (every sighting is evidence); clearing counts ticks,
 * frames at least 3/4 of cfg->frame_interval_ms apart, so that a clean
 * stretch means the same time at any frame rate.
 */
#ifndef NEGOBS_DETECT_TEMPORAL_H
#define NEGOBS_DETECT_TEMPORAL_H

#include <stdint.h>

#include "negobs/detect.h"

/* Sightings kept at each end of a missing-ground track's approach. */
#define TMP_PLACES 3

typedef struct tmp_track {
    int32_t active;
    int32_t confirmed;
    int32_t held;
    uint32_t hist;  /* bit 0 = this frame, 1 = seen            */
    uint32_t weak;  /* as hist: seen by a weak sighting only   */
    uint32_t ticks; /* as hist: the frame was a tick           */
    int32_t misses; /* consecutive observed frames without it  */
    uint32_t last_seen_ms;
    uint32_t hold_start_ms;
    int32_t speed_mm_s;   /* approach speed estimate, >= 0           */
    int32_t near_mm;      /* nearer of the last sighting and the
                           track's prediction for it (vouch bound)  */
    int32_t reached;      /* a sighting's drop reached h_t (temporal.c,
                           sighting_reaches)                        */
    uint32_t seen_odo_mm; /* the odometer at the last sighting     */
    /* Where the track's trusted sightings lay along the walk: range plus
     * odometer (mm, wraps like it) of the first and of the last
     * TMP_PLACES, the odometer at the first (at the last: seen_odo_mm),
     * and how many (up to twice TMP_PLACES): temporal.c,
     * track_approaches (missing ground). */
    uint32_t first_place_mm[TMP_PLACES];
    uint32_t last_place_mm[TMP_PLACES];
    uint32_t first_odo_mm;
    int32_t n_places;
    negobs_hazard_t hz; /* latest observation (range as observed)  */
} tmp_track_t;

typedef struct temporal {
    const negobs_detect_config_t *cfg;
    tmp_track_t tracks[NEGOBS_DETECT_MAX_TRACKS];
    uint32_t next_id;
    uint32_t last_ms;
    int32_t have_last;
    uint32_t odo_mm; /* measured travel along the floor, summed (wraps) */
    /* Ticks (cfg->frame_interval_ms): what clearing counts */
    uint32_t tick_ms; /* the last tick                              */
    int32_t tick_have;
    int32_t tick;    /* this frame is one                          */
    int32_t clocked; /* temporal_clock() ran for this frame        */
} temporal_t;

void temporal_reset(temporal_t *t, const negobs_detect_config_t *cfg);

/*
 * Is the frame at now_ms a tick (t->tick)? Once per frame, before anything
 * reads t->tick; temporal_update*() calls it when the frame was not
 * clocked yet.
 */
void temporal_clock(temporal_t *t, uint32_t now_ms);

/*
 * Feed one frame's candidates (any order). observed != 0 means the frame
 * was fully usable, so a missing track counts as a clean frame; otherwise
 * nothing is cleared and candidates only refresh confirmed tracks (they
 * never start or confirm one). A confirmed track
 * lost with range <= hold_range_mm is held (dead-reckoned) for hold_ms.
 */
void temporal_update(temporal_t *t, const negobs_hazard_t *cands, uint32_t n,
                     int observed, int32_t hold_range_mm, uint32_t now_ms);

/* How far a candidate may count (temporal_update_vouched's trusted[]). */
enum {
    TMP_UNTRUSTED = 0, /* refresh-only, as on a degraded frame          */
    TMP_TRUSTED = 1,   /* may start and confirm a track                 */
    TMP_WEAK = 2       /* textured, but its strips failed the noise
                          check: on an observed frame that is a tick, and
                          where the track's edge can be by now, it counts
                          for a track that trusted sightings started,
                          without moving it; confirm_k - 1 of the
                          window's sightings must still be trusted, on
                          ticks                                         */
};

/*
 * temporal_update with a vouched range: trusted[i] (TMP_*; trusted may be
 * NULL: all trusted) says how far candidate i counts: TMP_UNTRUSTED makes
 * it refresh-only, as on a degraded frame (its own strips failed the
 * local noise check, or its box has no texture); TMP_WEAK lets it count
 * as a sighting of an unconfirmed track it associates with on a tick,
 * where the track's edge can be by now, but not start or move one, and a
 * track confirms only with confirm_k sightings of which at
 * least confirm_k - 1 are trusted; a track farther
 * than seen_to_mm that this frame did not see is not counted as a clean
 * miss (the frame did not vouch for its place), unless it is confirmed
 * within hold_range_mm (then it is held as usual). A confirmed track
 * whose dead-reckoned range lies nearer than seen_from_mm, the nearest
 * floor in view (0: all of it in view), is held on an observed frame. An unconfirmed track's
 * confirm_n window moves on every frame, seen or not (on degraded frames
 * too): confirmation is confirm_k sightings within confirm_n frames.
 */
void temporal_update_vouched(temporal_t *t, const negobs_hazard_t *cands,
                             const uint8_t *trusted, uint32_t n, int observed,
                             int32_t seen_from_mm, int32_t seen_to_mm,
                             int32_t hold_range_mm, uint32_t now_ms);

/*
 * The wearer's forward travel along the floor since the last frame, as the
 * floor patches measured it (detect_travel.c; 0: not measured). Call once
 * per frame before temporal_update*: the sightings of that update are
 * placed at the summed travel.
 */
void temporal_walked(temporal_t *t, int32_t travel_mm);

/* 1 when a track would use the travel: a confirmed or held one (the
 * hold), or missing ground waiting to show that it comes nearer as the
 * wearer walks (its confirmation). */
int temporal_needs_travel(const temporal_t *t);

/*
 * Confirmed and held tracks as hazards, nearest first, with level and
 * flags; returns the count (<= max). Held ranges are dead-reckoned to
 * now_ms. Missing-ground (UNKNOWN) tracks follow cfg->missing_policy.
 */
uint32_t temporal_report(const temporal_t *t, negobs_hazard_t *out,
                         uint32_t max, uint32_t now_ms);

/*
 * The farthest a frame may vouch with confirmed or held tracks in view:
 * the least, over them, of the nearer of each one's last sighting and the
 * range its own motion predicted for that sighting, dead-reckoned to
 * now_ms like a held range. INT32_MAX without such a track.
 */
int32_t temporal_vouch_bound(const temporal_t *t, uint32_t now_ms);

/* 1 when a confirmed or held track is reported at range_mm or nearer. */
int temporal_covers(const temporal_t *t, int32_t range_mm, uint32_t now_ms);

#endif
