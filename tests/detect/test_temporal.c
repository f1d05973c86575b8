/*
 * Temporal logic: k-of-n confirmation, clearing after m clean frames,
 * degraded frames that cannot clear, the hold below the image, and an
 * end-to-end approach on synthetic maps.
 */
#include "cmocka_all.h"
#include "detect/temporal.h"
#include "scene_util.h"

static negobs_detect_config_t cfg;
static temporal_t tp;

static negobs_hazard_t cand(int32_t range, int32_t lat)
{
    negobs_hazard_t h;
    memset(&h, 0, sizeof h);
    h.type = NEGOBS_HAZARD_DROP;
    h.range_mm = range;
    h.lateral_mm = lat;
    h.drop_mm = 150;
    return h;
}

static uint32_t report(negobs_hazard_t *out, uint32_t now)
{
    return temporal_report(&tp, out, NEGOBS_DETECT_MAX_HAZARDS, now);
}

static void setup_cfg(void)
{
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    temporal_reset(&tp, &cfg);
}

static void test_temporal_confirms_on_k_of_n(void **state)
{
    negobs_hazard_t c = cand(3000, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    (void)state;
    setup_cfg();
    temporal_update(&tp, &c, 1, 1, 2000, 100);
    temporal_update(&tp, NULL, 0, 1, 2000, 200);
    temporal_update(&tp, &c, 1, 1, 2000, 300);
    assert_int_equal(report(out, 300), 0); /* 2 of 3 */
    temporal_update(&tp, NULL, 0, 1, 2000, 400);
    c.range_mm = 2900;
    temporal_update(&tp, &c, 1, 1, 2000, 500); /* 3 of 5 */
    assert_int_equal(report(out, 500), 1);
    assert_true(out[0].flags & NEGOBS_HAZARD_F_CONFIRMED);
    assert_int_equal(out[0].range_mm, 2900);
    assert_int_equal(out[0].level, NEGOBS_LEVEL_CAUTION);
    assert_true(out[0].track_id > 0);
}

static void test_temporal_sparse_hits_never_confirm(void **state)
{
    negobs_hazard_t c = cand(3000, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    /* One hit every third frame: at most 2 in any 5. */
    for (t = 1; t <= 30; t++) {
        temporal_update(&tp, (t % 3u == 0u) ? &c : NULL,
                        (t % 3u == 0u) ? 1u : 0u, 1, 2000, t * 100u);
        assert_int_equal(report(out, t * 100u), 0);
    }
}

/* A confirmed edge, unseen, whose range dead-reckoned at hold_speed_mm_s
 * passes below the view's nearest floor: the camera lost it underfoot, so
 * it is held (IMMINENT) from that frame for hold_ms, whatever later frames
 * vouch. Here: confirmed at 3600 mm (0.3 s), the view starting at
 * 2300 mm, frames vouching nothing until 1.4 s, then 2.3-4.6 m; the hold
 * zone 3300 mm. Counted at its last range as a miss by the vouching
 * frames, it was dropped after clear_m of them (a 15 cm curb, CLEAR 1.6 m
 * before it). */
static void test_temporal_edge_below_the_view_is_held(void **state)
{
    negobs_hazard_t c = cand(3600, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 3; t++) {
        temporal_update_vouched(&tp, &c, NULL, 1, 1, 2300, 4600, 3300,
                                t * 100u);
    }
    assert_int_equal(report(out, 300), 1);
    for (t = 4; t <= 14; t++) { /* observed, vouching nothing: held at
                                   1.3 s (predicted 2200 mm) */
        temporal_update_vouched(&tp, NULL, NULL, 0, 1, 2300, 0, 3300,
                                t * 100u);
    }
    for (t = 15; t <= 43; t++) { /* vouching 2.3-4.6 m, nothing seen */
        temporal_update_vouched(&tp, NULL, NULL, 0, 1, 2300, 4600, 3300,
                                t * 100u);
        assert_int_equal(report(out, t * 100u), 1);
        assert_true(out[0].flags & NEGOBS_HAZARD_F_HELD);
        assert_int_equal(out[0].level, NEGOBS_LEVEL_IMMINENT);
    }
    /* more than hold_ms (3 s) after the hold began (1.3 s) it ends */
    temporal_update_vouched(&tp, NULL, NULL, 0, 1, 2300, 4600, 3300, 4400);
    assert_int_equal(report(out, 4400), 0);
}

/* Sightings spread over frames that could not look at the track's place
 * (observed frames vouching 0 mm, or degraded ones) are not 3 of 5: the
 * window moves with time. Frozen, one hit every third frame confirmed on
 * the third hit (false holes on flat suite walks). */
static void test_temporal_unseen_frames_move_the_window(void **state)
{
    negobs_hazard_t c = cand(3000, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 30; t++) {
        int hit = (t % 3u == 0u);
        temporal_update_vouched(&tp, hit ? &c : NULL, NULL, hit ? 1u : 0u, 1,
                                0, hit ? INT32_MAX : 0, 2000, t * 100u);
        assert_int_equal(report(out, t * 100u), 0);
    }
    setup_cfg();
    for (t = 1; t <= 30; t++) {
        int hit = (t % 3u == 0u);
        temporal_update_vouched(&tp, hit ? &c : NULL, NULL, hit ? 1u : 0u, hit,
                                0, INT32_MAX, 2000, t * 100u);
        assert_int_equal(report(out, t * 100u), 0);
    }
    /* Three sightings in five frames still confirm, looked at or not. */
    setup_cfg();
    for (t = 1; t <= 5; t++) {
        int hit = (t % 2u == 1u);
        temporal_update_vouched(&tp, hit ? &c : NULL, NULL, hit ? 1u : 0u, 1,
                                0, hit ? INT32_MAX : 0, 2000, t * 100u);
    }
    assert_int_equal(report(out, 500), 1);
}

static void test_temporal_clears_after_m_clean_frames(void **state)
{
    negobs_hazard_t c = cand(3500, 100);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 3; t++) {
        temporal_update(&tp, &c, 1, 1, 2000, t * 100u);
    }
    assert_int_equal(report(out, 300), 1);
    for (t = 4; t < 4 + 4; t++) {
        temporal_update(&tp, NULL, 0, 1, 2000, t * 100u);
        assert_int_equal(report(out, t * 100u), 1); /* < clear_m */
    }
    temporal_update(&tp, NULL, 0, 1, 2000, 800);
    assert_int_equal(report(out, 800), 0);
}

/* A 30 fps camera (frames 33-34 ms apart) against the 100 ms interval
 * the clearing is set for: every frame's sighting counts towards
 * confirmation (three in a row confirm), but once the hazard is seen no
 * more it stays until clear_m ticks (400 ms and more) have passed, not
 * five frames (167 ms). frame_interval_ms = 0 counts frames as given. */
static uint32_t ms_30fps(uint32_t i)
{
    return i * 100u / 3u;
}

static void test_temporal_clears_after_ticks_not_frames(void **state)
{
    negobs_hazard_t c = cand(3000, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t i;
    (void)state;
    setup_cfg();
    assert_int_equal(cfg.frame_interval_ms, 100);
    for (i = 0; i < 3; i++) {
        temporal_update(&tp, &c, 1, 1, 2000, ms_30fps(i));
    }
    assert_int_equal(report(out, ms_30fps(2)), 1);
    /* unseen from 100 ms on: ticks at 100, 200, 300, 400 and 500 ms */
    for (; ms_30fps(i) < 500; i++) {
        temporal_update(&tp, NULL, 0, 1, 2000, ms_30fps(i));
        assert_int_equal(report(out, ms_30fps(i)), 1);
    }
    temporal_update(&tp, NULL, 0, 1, 2000, ms_30fps(i));
    assert_int_equal(ms_30fps(i), 500);
    assert_int_equal(report(out, 500), 0);

    /* counted as frames: five unseen frames clear it */
    setup_cfg();
    cfg.frame_interval_ms = 0;
    for (i = 0; i < 3; i++) {
        temporal_update(&tp, &c, 1, 1, 2000, ms_30fps(i));
    }
    for (; i < 7; i++) {
        temporal_update(&tp, NULL, 0, 1, 2000, ms_30fps(i));
        assert_int_equal(report(out, ms_30fps(i)), 1);
    }
    temporal_update(&tp, NULL, 0, 1, 2000, ms_30fps(i));
    assert_int_equal(report(out, ms_30fps(i)), 0);
}

static void test_temporal_degraded_frames_do_not_clear(void **state)
{
    negobs_hazard_t c = cand(3500, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 3; t++) {
        temporal_update(&tp, &c, 1, 1, 2000, t * 100u);
    }
    for (t = 4; t < 20; t++) {
        temporal_update(&tp, NULL, 0, 0, 2000, t * 100u);
    }
    assert_int_equal(report(out, 1900), 1);
    /* ...but not for ever: hold_ms after the last sighting it expires. */
    temporal_update(&tp, NULL, 0, 0, 2000, 3400);
    assert_int_equal(report(out, 3400), 0);
}

static void test_temporal_degraded_frames_never_confirm(void **state)
{
    negobs_hazard_t c = cand(3000, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    /* The same deficit on every degraded frame: still no hazard. */
    for (t = 1; t <= 20; t++) {
        temporal_update(&tp, &c, 1, 0, 2000, t * 100u);
        assert_int_equal(report(out, t * 100u), 0);
    }
    /* Two clean sightings are not three: the degraded ones did not count. */
    temporal_update(&tp, &c, 1, 1, 2000, 2100);
    temporal_update(&tp, &c, 1, 1, 2000, 2200);
    assert_int_equal(report(out, 2200), 0);
    temporal_update(&tp, &c, 1, 1, 2000, 2300);
    assert_int_equal(report(out, 2300), 1);
}

/* Feed one sighting a frame at ranges r[0..n), trust t[0..n) (TMP_*;
 * 'T' trusted, 'W' weak, 'U' untrusted, '-' none), on observed frames; the
 * number of the first frame that reports a confirmed hazard, 0 if none. */
static int first_confirmed_dt(const char *t, int32_t r0, int32_t step,
                              uint32_t dt_ms)
{
    negobs_hazard_t c;
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    int i;
    setup_cfg();
    for (i = 0; t[i] != '\0'; i++) {
        uint8_t trust = (t[i] == 'T')   ? (uint8_t)TMP_TRUSTED
                        : (t[i] == 'W') ? (uint8_t)TMP_WEAK
                                        : (uint8_t)TMP_UNTRUSTED;
        const uint32_t now = dt_ms * (uint32_t)(i + 1);
        c = cand(r0 - step * i, 0);
        temporal_update_vouched(&tp, &c, &trust, t[i] == '-' ? 0u : 1u, 1, 0,
                                INT32_MAX, 1000, now);
        if (report(out, now) > 0u) {
            return i + 1;
        }
    }
    return 0;
}

/* first_confirmed_dt at 10 fps, where every frame is a tick */
static int first_confirmed(const char *t, int32_t r0, int32_t step)
{
    return first_confirmed_dt(t, r0, step, 100u);
}

/* A weak sighting (a textured box whose strips failed the noise check)
 * fills one gap between trusted sightings of the same approaching edge,
 * as on smooth concrete seen by a 6 cm rig; an untrusted one does not,
 * weak ones never start a track, and one trusted sighting with any
 * number of weak ones never confirms. */
static void test_temporal_weak_sighting_fills_one_gap(void **state)
{
    (void)state;
    assert_int_equal(first_confirmed("TWT", 2455, 120), 3);
    assert_int_equal(first_confirmed("TTW", 2455, 120), 3);
    assert_int_equal(first_confirmed("TUT", 2455, 120), 0);
    assert_int_equal(first_confirmed("TUTT", 2455, 120), 4);
    assert_int_equal(first_confirmed("WWWWWWWW", 2455, 120), 0);
    assert_int_equal(first_confirmed("TWWWWWWW", 2455, 120), 0);
    assert_int_equal(first_confirmed("WWTWWT", 2455, 120), 6);
    /* the window still moves: T and T four frames apart, W between */
    assert_int_equal(first_confirmed("T-W--T", 2455, 120), 0);
    assert_int_equal(first_confirmed("TTT", 2455, 120), 3);
}

/* A weak sighting confirms only with looks a tick apart (frame_interval_ms
 * 100: at 33 ms frames 1, 4, 7, ... are ticks): the frames between see
 * nearly the same images, so their noise is no fresh look. A window of
 * five frames at 30 fps holds two ticks, so there a weak sighting never
 * confirms, while three trusted ones still do. */
static void test_temporal_weak_sighting_only_on_ticks(void **state)
{
    (void)state;
    assert_int_equal(first_confirmed_dt("TWT", 2455, 40, 33u), 0);
    assert_int_equal(first_confirmed_dt("T-TW", 2455, 40, 33u), 0);
    assert_int_equal(first_confirmed_dt("TT-W", 2455, 40, 33u), 0);
    assert_int_equal(first_confirmed_dt("TTT", 2455, 40, 33u), 3);
    /* 10 fps: every frame a tick */
    assert_int_equal(first_confirmed_dt("TT-W", 2455, 120, 100u), 4);
}

/* A weak sighting counts only where the track's edge can be by now (its
 * last trusted range, nearer by at most the walk since at
 * hold_speed_mm_s), and it does not move the track: a noise hole 0.53 m
 * nearer than a curb seen at 1.97 and 1.83 m confirmed it at 1.31 m. */
static void test_temporal_weak_sighting_must_fit_the_track(void **state)
{
    const int32_t near[2] = {1307, 1700};
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    const uint8_t trusted = TMP_TRUSTED;
    const uint8_t weak = TMP_WEAK;
    int j;
    (void)state;
    for (j = 0; j < 2; j++) {
        negobs_hazard_t c = cand(1969, 0);
        setup_cfg();
        temporal_update_vouched(&tp, &c, &trusted, 1, 1, 0, INT32_MAX, 1000,
                                100);
        c.range_mm = 1833;
        temporal_update_vouched(&tp, &c, &trusted, 1, 1, 0, INT32_MAX, 1000,
                                200);
        temporal_update_vouched(&tp, NULL, NULL, 0, 1, 0, INT32_MAX, 1000,
                                300);
        c.range_mm = near[j];
        temporal_update_vouched(&tp, &c, &weak, 1, 1, 0, INT32_MAX, 1000, 400);
        if (j == 0) {
            assert_int_equal(report(out, 400), 0);
        } else {
            /* within 1833 - 100 - 1.4 m/s x 0.2 s: confirmed, at the
             * trusted range (dead-reckoned as an unseen track's) */
            assert_int_equal(report(out, 400), 1);
            assert_true(out[0].range_mm >= 1833 - 300);
            assert_true(out[0].range_mm <= 1833);
            assert_true(out[0].range_mm != 1700);
        }
    }
}

/* On a degraded frame a weak sighting counts no more than an untrusted
 * one: it may not confirm a track. */
static void test_temporal_weak_sighting_on_degraded_frame(void **state)
{
    negobs_hazard_t c = cand(3000, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    const uint8_t trusted = TMP_TRUSTED;
    const uint8_t weak = TMP_WEAK;
    (void)state;
    setup_cfg();
    temporal_update_vouched(&tp, &c, &trusted, 1, 1, 0, INT32_MAX, 1000, 100);
    temporal_update_vouched(&tp, &c, &weak, 1, 0, 0, INT32_MAX, 1000, 200);
    temporal_update_vouched(&tp, &c, &trusted, 1, 1, 0, INT32_MAX, 1000, 300);
    assert_int_equal(report(out, 300), 0);
    temporal_update_vouched(&tp, &c, &weak, 1, 1, 0, INT32_MAX, 1000, 400);
    assert_int_equal(report(out, 400), 1);
}

static void test_temporal_degraded_frames_refresh_confirmed(void **state)
{
    negobs_hazard_t c = cand(3500, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 3; t++) {
        temporal_update(&tp, &c, 1, 1, 2000, t * 100u);
    }
    /* Degraded frames that still see it keep it alive past hold_ms and
     * update its range. */
    for (t = 4; t <= 40; t++) {
        c.range_mm = 3500 - (int32_t)(t - 3u) * 20;
        temporal_update(&tp, &c, 1, 0, 2000, t * 100u);
    }
    assert_int_equal(report(out, 4000), 1);
    assert_int_equal(out[0].range_mm, c.range_mm);
}

static void test_temporal_unseen_track_is_dead_reckoned(void **state)
{
    negobs_hazard_t c = cand(3500, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 3; t++) {
        temporal_update(&tp, &c, 1, 1, 2000, t * 100u);
    }
    /* One second without evidence (degraded): it is reported where the
     * walker would have brought it, not at the old 3.5 m. */
    for (t = 4; t <= 13; t++) {
        temporal_update(&tp, NULL, 0, 0, 2000, t * 100u);
    }
    assert_int_equal(report(out, 1300), 1);
    assert_int_equal(out[0].range_mm,
                     3500 - cfg.hold_speed_mm_s * 1000 / 1000);
}

static void test_temporal_hold_when_edge_leaves_image(void **state)
{
    negobs_hazard_t c = cand(2200, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    int32_t prev;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 5; t++) {
        c.range_mm = 2200 - (int32_t)t * 140;
        temporal_update(&tp, &c, 1, 1, 2000, t * 100u);
    }
    assert_int_equal(report(out, 500), 1);
    assert_int_equal(out[0].level, NEGOBS_LEVEL_IMMINENT); /* 1500 mm */
    prev = out[0].range_mm;
    /* The edge is gone from the image: held, closer every frame. */
    for (t = 6; t <= 30; t++) {
        temporal_update(&tp, NULL, 0, 1, 2000, t * 100u);
        assert_int_equal(report(out, t * 100u), 1);
        assert_true(out[0].flags & NEGOBS_HAZARD_F_HELD);
        assert_int_equal(out[0].level, NEGOBS_LEVEL_IMMINENT);
        assert_true(out[0].range_mm <= prev);
        prev = out[0].range_mm;
    }
    assert_int_equal(prev, 0);
    /* hold_ms = 3000 after the hold began (600): gone at 3700. */
    temporal_update(&tp, NULL, 0, 1, 2000, 3600);
    assert_int_equal(report(out, 3600), 1);
    temporal_update(&tp, NULL, 0, 1, 2000, 3700);
    assert_int_equal(report(out, 3700), 0);
}

/* The hold ends once the floor patches measured the wearer walking half a
 * metre past the edge's last range (they stand beyond it); without
 * measured travel (standing at the edge, a bland floor) it lasts hold_ms
 * as in the test above. */
static void test_temporal_hold_ends_when_walked_past(void **state)
{
    negobs_hazard_t c = cand(2200, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 5; t++) {
        c.range_mm = 2200 - (int32_t)t * 140; /* last seen at 1500 mm */
        temporal_walked(&tp, 140);
        temporal_update(&tp, &c, 1, 1, 2000, t * 100u);
    }
    /* 14 frames of 140 mm: 1960 mm walked since, still on hold */
    for (t = 6; t <= 19; t++) {
        temporal_walked(&tp, 140);
        temporal_update(&tp, NULL, 0, 1, 2000, t * 100u);
        assert_int_equal(report(out, t * 100u), 1);
        assert_true(out[0].flags & NEGOBS_HAZARD_F_HELD);
    }
    /* 2100 mm >= 1500 + 500: past the edge */
    temporal_walked(&tp, 140);
    temporal_update(&tp, NULL, 0, 1, 2000, 2000);
    assert_int_equal(report(out, 2000), 0);
}

static void test_temporal_far_track_lost_is_not_held(void **state)
{
    negobs_hazard_t c = cand(3800, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    for (t = 1; t <= 3; t++) {
        temporal_update(&tp, &c, 1, 1, 2000, t * 100u);
    }
    temporal_update(&tp, NULL, 0, 1, 2000, 400);
    assert_int_equal(report(out, 400), 1);
    assert_false(out[0].flags & NEGOBS_HAZARD_F_HELD);
}

static void test_temporal_association_follows_walking(void **state)
{
    negobs_hazard_t c[2];
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    /* Two edges: one ahead approaching at 1.4 m/s, one to the side. */
    for (t = 1; t <= 6; t++) {
        c[0] = cand(4000 - (int32_t)t * 140, 0);
        c[1] = cand(3000 - (int32_t)t * 140, 1500);
        temporal_update(&tp, c, 2, 1, 1500, t * 100u);
    }
    assert_int_equal(report(out, 600), 2);
    assert_true(out[0].track_id != out[1].track_id);
    assert_int_equal(out[0].range_mm, 3000 - 6 * 140);
    /* A candidate 1 m farther than the track is a different hazard. */
    c[0] = cand(4160 + 1000, 0);
    temporal_update(&tp, c, 1, 1, 1500, 700);
    assert_int_equal(report(out, 700), 2);
}

/* Feed ranges r[0..n) as one trusted sighting a frame, with drops h[0..n)
 * (NULL: cand()'s 150 mm); 1 if confirmed. */
static int confirms(const int32_t *r, const int32_t *h, int n)
{
    negobs_hazard_t c;
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    int i;
    setup_cfg();
    for (i = 0; i < n; i++) {
        c = cand(r[i], 0);
        if (h != NULL) {
            c.drop_mm = h[i];
        }
        temporal_update(&tp, &c, 1, 1, 6000, 100u * (uint32_t)(i + 1));
    }
    return report(out, 100u * (uint32_t)n) > 0u;
}

/* A sighting may lie farther than the track by assoc_range_mm, but by no
 * more than 20 % of its range: near, 400 mm let matching noise hop from
 * 1.20 m to 1.59 m and confirm (temporal.c, farther_tol_mm). */
static void test_temporal_near_sightings_may_not_hop_far(void **state)
{
    const int32_t hop[3] = {1400, 1200, 1590};
    const int32_t near_noise[3] = {1400, 1200, 1420};
    const int32_t far_noise[3] = {3000, 2900, 3280};
    (void)state;
    assert_false(confirms(hop, NULL, 3));
    assert_true(confirms(near_noise, NULL, 3));
    assert_true(confirms(far_noise, NULL, 3));
}

/* A track confirms only when one of its sightings' drops reached h_t:
 * below it there is only the rule's rounding to show (temporal.c,
 * sighting_reaches). */
static void test_temporal_confirm_needs_a_sighting_at_h_t(void **state)
{
    const int32_t ranges[3] = {1800, 1700, 1600}; /* h_t 40 mm there */
    const int32_t low[3] = {34, 30, 38};
    const int32_t one[3] = {34, 45, 30};
    (void)state;
    assert_false(confirms(ranges, low, 3));
    assert_true(confirms(ranges, one, 3));
}

static void test_temporal_missing_ground_policy(void **state)
{
    negobs_hazard_t c = cand(1200, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    c.type = NEGOBS_HAZARD_UNKNOWN;
    /* six sightings coming nearer by the 120 mm walked each (the approach
     * test below) */
    for (t = 1; t <= 6; t++) {
        c.range_mm = 1800 - (int32_t)t * 120;
        temporal_walked(&tp, 120);
        temporal_update(&tp, &c, 1, 1, 1000, t * 100u);
    }
    assert_int_equal(report(out, 600), 1);
    assert_int_equal(out[0].level, NEGOBS_LEVEL_CAUTION); /* capped */
    cfg.missing_policy = NEGOBS_MISSING_DANGER;
    assert_int_equal(report(out, 600), 1);
    assert_int_equal(out[0].level, NEGOBS_LEVEL_IMMINENT);
    cfg.missing_policy = NEGOBS_MISSING_IGNORE;
    assert_int_equal(report(out, 600), 0);
}

/* NEGOBS_MISSING_TEXTURED: a textured band may reach IMMINENT like a drop,
 * a bland one stays at CAUTION; the default policy caps both. */
static void test_temporal_missing_policy_textured(void **state)
{
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    int textured;
    int policy;
    (void)state;
    for (policy = 0; policy < 2; policy++) {
        for (textured = 0; textured < 2; textured++) {
            negobs_hazard_t c = cand(1200, 0);
            uint32_t t;
            setup_cfg();
            cfg.missing_policy = policy ? NEGOBS_MISSING_TEXTURED
                                        : NEGOBS_MISSING_CAUTION;
            c.type = NEGOBS_HAZARD_UNKNOWN;
            c.flags = textured ? NEGOBS_HAZARD_F_TEXTURED : 0u;
            for (t = 1; t <= 6; t++) {
                c.range_mm = 1800 - (int32_t)t * 120;
                temporal_walked(&tp, 120);
                temporal_update(&tp, &c, 1, 1, 1000, t * 100u);
            }
            assert_int_equal(report(out, 600), 1);
            assert_int_equal(out[0].level, (policy && textured)
                                               ? NEGOBS_LEVEL_IMMINENT
                                               : NEGOBS_LEVEL_CAUTION);
        }
    }
}

/* Missing ground confirms only once it comes nearer by what the wearer
 * walks (temporal.c, track_approaches). A band whose near end stays the
 * same distance ahead, a sight limit where a floor's texture fades into
 * the noise, never confirms however often it is seen; nor does one seen
 * without measured travel; an approaching one does, on its sixth
 * sighting (the first three and the last three apart) once 500 mm are
 * walked between them; and a measured drop is not held to it. The
 * ranges scatter by +-150 mm like a sight limit's do. */
static void test_temporal_missing_ground_must_approach(void **state)
{
    static const int32_t jitter[8] = {0, 150, -120, 90, -150, 60, 130, -80};
    negobs_hazard_t c = cand(3600, 0);
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    (void)state;
    setup_cfg();
    c.type = NEGOBS_HAZARD_UNKNOWN;
    for (t = 1; t <= 30; t++) { /* walks with the wearer */
        c.range_mm = 3600 + jitter[t % 8u];
        temporal_walked(&tp, 120);
        temporal_update(&tp, &c, 1, 1, 1000, t * 100u);
        assert_int_equal(report(out, t * 100u), 0);
    }
    setup_cfg();
    for (t = 1; t <= 30; t++) { /* a place, but no travel measured */
        c.range_mm = 3600 + jitter[t % 8u];
        temporal_update(&tp, &c, 1, 1, 1000, t * 100u);
        assert_int_equal(report(out, t * 100u), 0);
    }
    setup_cfg();
    for (t = 1; t <= 6; t++) { /* a place, walked towards */
        c.range_mm = 3600 - (int32_t)t * 120 + jitter[t % 8u];
        temporal_walked(&tp, 120);
        temporal_update(&tp, &c, 1, 1, 1000, t * 100u);
        assert_int_equal(report(out, t * 100u), (t == 6u) ? 1 : 0);
    }
    assert_int_equal(out[0].type, NEGOBS_HAZARD_UNKNOWN);
    setup_cfg();
    c = cand(3600, 0); /* a measured drop, standing still */
    for (t = 1; t <= 3; t++) {
        temporal_update(&tp, &c, 1, 1, 1000, t * 100u);
    }
    assert_int_equal(report(out, 300), 1);
}

static void test_temporal_bounded_tracks(void **state)
{
    negobs_hazard_t c[NEGOBS_DETECT_MAX_HAZARDS];
    negobs_hazard_t out[NEGOBS_DETECT_MAX_HAZARDS];
    uint32_t t;
    int i;
    (void)state;
    setup_cfg();
    /* Far more distinct candidates than tracks over time: no overflow,
     * and confirmed tracks are never evicted by new ones. */
    for (t = 1; t <= 3; t++) {
        c[0] = cand(3000, 0);
        temporal_update(&tp, c, 1, 1, 1000, t * 100u);
    }
    for (t = 4; t <= 40; t++) {
        for (i = 0; i < NEGOBS_DETECT_MAX_HAZARDS; i++) {
            c[i] = cand(3000, 0);
            c[i].lateral_mm = 2000 + (int32_t)(t * 8u + (uint32_t)i) * 700;
        }
        c[0] = cand(3000, 0);
        temporal_update(&tp, c, NEGOBS_DETECT_MAX_HAZARDS, 1, 1000, t * 100u);
        assert_true(report(out, t * 100u) >= 1);
    }
}

/* End to end: walk at 1.4 m/s towards a 150 mm drop; CAUTION early,
 * then IMMINENT, and still IMMINENT (held) when the edge is below the
 * image. */
static void test_temporal_approach_sequence_end_to_end(void **state)
{
    static rig_t r;
    synth_scene_t s;
    double edge = 4.0;
    int i;
    int first_caution_mm = -1;
    int first_imminent_mm = -1;
    int held_seen = 0;
    (void)state;
    rig_setup(&r, NULL);
    for (i = 0; i < 40 && edge > 0.3; i++) {
        synth_flat(&s, 1.2, 20.0);
        s.noise_px = 0.25;
        s.seed = (uint32_t)i + 1u;
        synth_step(&s, edge, -0.15);
        assert_int_equal(rig_frame(&r, &s), NEGOBS_OK);
        if (r.res.level == NEGOBS_LEVEL_CAUTION && first_caution_mm < 0) {
            first_caution_mm = (int)(edge * 1000);
        }
        if (r.res.level == NEGOBS_LEVEL_IMMINENT && first_imminent_mm < 0) {
            first_imminent_mm = (int)(edge * 1000);
        }
        if (edge < 1.6) {
            /* From here on the alert must not stop. */
            assert_int_equal(r.res.level, NEGOBS_LEVEL_IMMINENT);
        }
        if (r.res.n_hazards > 0 &&
            (r.res.hazards[0].flags & NEGOBS_HAZARD_F_HELD)) {
            held_seen = 1;
        }
        edge -= 0.14; /* 1.4 m/s at 10 frames/s */
    }
    print_message("approach: CAUTION from %d mm, IMMINENT from %d mm\n",
                  first_caution_mm, first_imminent_mm);
    assert_true(first_caution_mm >= 3500);
    assert_true(first_imminent_mm >= 1500);
    assert_true(held_seen);
    rig_teardown(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_temporal_confirms_on_k_of_n),
        cmocka_unit_test(test_temporal_sparse_hits_never_confirm),
        cmocka_unit_test(test_temporal_unseen_frames_move_the_window),
        cmocka_unit_test(test_temporal_edge_below_the_view_is_held),
        cmocka_unit_test(test_temporal_clears_after_m_clean_frames),
        cmocka_unit_test(test_temporal_degraded_frames_do_not_clear),
        cmocka_unit_test(test_temporal_degraded_frames_never_confirm),
        cmocka_unit_test(test_temporal_degraded_frames_refresh_confirmed),
        cmocka_unit_test(test_temporal_weak_sighting_fills_one_gap),
        cmocka_unit_test(test_temporal_weak_sighting_on_degraded_frame),
        cmocka_unit_test(test_temporal_weak_sighting_only_on_ticks),
        cmocka_unit_test(test_temporal_weak_sighting_must_fit_the_track),
        cmocka_unit_test(test_temporal_unseen_track_is_dead_reckoned),
        cmocka_unit_test(test_temporal_hold_when_edge_leaves_image),
        cmocka_unit_test(test_temporal_hold_ends_when_walked_past),
        cmocka_unit_test(test_temporal_far_track_lost_is_not_held),
        cmocka_unit_test(test_temporal_association_follows_walking),
        cmocka_unit_test(test_temporal_near_sightings_may_not_hop_far),
        cmocka_unit_test(test_temporal_confirm_needs_a_sighting_at_h_t),
        cmocka_unit_test(test_temporal_missing_ground_policy),
        cmocka_unit_test(test_temporal_missing_ground_must_approach),
        cmocka_unit_test(test_temporal_missing_policy_textured),
        cmocka_unit_test(test_temporal_bounded_tracks),
        cmocka_unit_test(test_temporal_clears_after_ticks_not_frames),
        cmocka_unit_test(test_temporal_approach_sequence_end_to_end),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
