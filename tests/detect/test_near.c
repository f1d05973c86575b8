/*
 * The floor nearer than the view (detect/detect_near.c): a frame may vouch
 * from the feet only when the floor it cannot see was vouched while it was
 * in view, or has been walked over since. Each case feeds the tracker the
 * nearest floor in view, the vouched range and the measured travel of a
 * walk at 10 frames a second, as negobs_detect_process does.
 */
#include "cmocka_all.h"
#include "detect/detect_internal.h"

#define SEEN_MM 1200 /* nearest floor in view: 1.2 m / 20 deg, f = 250 */
#define STEP_MM 120  /* 1.2 m/s at 10 fps */

typedef struct near_walk {
    negobs_detect_config_t cfg;
    detect_priv_t p;
    uint32_t now_ms;
} near_walk_t;

static void walk_setup(near_walk_t *w)
{
    memset(w, 0, sizeof *w);
    negobs_detect_config_default(&w->cfg, 320, 240);
    w->now_ms = 1000u;
}

/* One frame; start_ok says its ground passed the start check,
 * vouched_5cm_mm how far the frame vouched for 5 cm drops, and pending_mm
 * what a frame whose usable ground awaits the start check would vouch
 * once it passes (-1: not such a frame). */
static int frame_pending(near_walk_t *w, int32_t seen_mm, int32_t vouched_mm,
                         int32_t vouched_5cm_mm, int32_t pending_mm,
                         int32_t travel_mm, int start_ok)
{
    w->now_ms += 100u;
    return det_near_follow(&w->p, &w->cfg, seen_mm, vouched_mm, vouched_5cm_mm,
                           pending_mm, travel_mm, start_ok, w->now_ms);
}

static int frame_5cm(near_walk_t *w, int32_t seen_mm, int32_t vouched_mm,
                     int32_t vouched_5cm_mm, int32_t travel_mm, int start_ok)
{
    return frame_pending(w, seen_mm, vouched_mm, vouched_5cm_mm, -1, travel_mm,
                         start_ok);
}

/* A frame whose whole vouched range holds for 5 cm drops too (the cases
 * below that are about the following itself, not the drop it vouches
 * for). */
static int frame_start(near_walk_t *w, int32_t seen_mm, int32_t vouched_mm,
                       int32_t travel_mm, int start_ok)
{
    return frame_5cm(w, seen_mm, vouched_mm, vouched_mm, travel_mm, start_ok);
}

static int frame(near_walk_t *w, int32_t seen_mm, int32_t vouched_mm,
                 int32_t travel_mm)
{
    return frame_start(w, seen_mm, vouched_mm, travel_mm, 1);
}

/* A vouched frame, then 25 frames (2.5 s) that vouch nothing, with
 * travel_mm measured on each: the floor vouched first has aged below the
 * view, a gap is open. */
static void open_gap(near_walk_t *w, int32_t travel_mm)
{
    int i;
    assert_true(frame(w, SEEN_MM, 4000, travel_mm));
    for (i = 0; i < 25; i++) {
        (void)frame(w, SEEN_MM, 0, travel_mm);
    }
    assert_true(det_near_gap(&w->p));
}

/* With a gap open, frames that vouch vouched_mm beyond the view while the
 * walker goes on at STEP_MM a frame: the first does not vouch from the
 * feet, and each later one does exactly once the walk has passed the
 * unvouched floor (the view's nearest floor) and half a stride more.
 * Returns the distance walked when it first does. */
static int32_t walk_over_gap(near_walk_t *w, int32_t vouched_mm)
{
    int32_t walked_mm = 0;
    int i;
    assert_false(frame(w, SEEN_MM, vouched_mm, STEP_MM));
    for (i = 0; i < 40; i++) {
        int ok;
        walked_mm += STEP_MM;
        ok = frame(w, SEEN_MM, vouched_mm, STEP_MM);
        print_message("walked %d mm: %s\n", (int)walked_mm,
                      ok ? "vouched" : "unseen");
        assert_int_equal(ok, walked_mm >= SEEN_MM + 500);
        if (ok) {
            break;
        }
    }
    return walked_mm;
}

/* A walk over vouched floor, with single frames that vouch nothing (noise)
 * or only the first metres: the floor vouched earlier still covers the
 * view's near edge, so the frames keep their verdicts. */
static void test_near_vouched_walk_stays_vouched(void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    for (i = 0; i < 30; i++) {
        int32_t vouched = (i % 7 == 3) ? 0 : (i % 5 == 2) ? 1600 : 4000;
        assert_true(frame(&w, SEEN_MM, vouched, STEP_MM));
        assert_false(det_near_gap(&w.p));
    }
}

/* Standing before an obstacle that bars the path at 1.4 m: each frame
 * vouches 1.2-1.4 m; with no travel the vouched floor ahead is renewed
 * before the walker could have come 200 mm nearer. */
static void test_near_standing_short_view_stays_vouched(void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    for (i = 0; i < 20; i++) {
        assert_true(frame(&w, SEEN_MM, 1400, 0));
    }
}

/* Walking up to a drop the detector never confirms (a pit with a dark
 * bottom): the frames vouch up to its near edge, then nothing while it
 * crosses the near rows, then the floor beyond it once it is below the
 * view. Those frames must not vouch from the feet until the walker has
 * measurably passed the unvouched floor and half a stride more; pit_mm
 * is where the unvouched floor ended on the first frame that vouched
 * again (its nearest floor in view). */
static void test_near_unvouched_floor_until_walked_over(void **state)
{
    near_walk_t w;
    int32_t edge_mm = 3000;
    int i;
    (void)state;
    walk_setup(&w);
    assert_true(frame(&w, SEEN_MM, 4000, STEP_MM));
    while (edge_mm > SEEN_MM + STEP_MM) {
        edge_mm -= STEP_MM;
        assert_true(frame(&w, SEEN_MM, edge_mm, STEP_MM));
    }
    for (i = 0; i < 8; i++) { /* the pit fills the near rows */
        edge_mm -= STEP_MM;
        (void)frame(&w, SEEN_MM, 0, STEP_MM);
    }
    assert_true(det_near_gap(&w.p));
    /* below the view: every frame vouches 1.2-4.5 m */
    (void)walk_over_gap(&w, 4500);
    assert_false(det_near_gap(&w.p));
}

/* The same without a measured travel (a floor the travel cannot read, or
 * standing still): the unvouched floor may still be just ahead, so no
 * frame vouches from the feet, however long. */
static void test_near_unmeasured_travel_never_passes(void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    open_gap(&w, 0);
    for (i = 0; i < 50; i++) {
        assert_false(frame(&w, SEEN_MM, 4500, 0));
    }
}

/* Unvouched floor that reaches a later view extends the gap: a second
 * noisy stretch after the first re-opens it to that view's near edge. */
static void test_near_second_gap_extends_the_first(void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    open_gap(&w, STEP_MM);
    assert_false(frame(&w, SEEN_MM, 1500, STEP_MM));
    /* 1.5 m vouched, then 3 frames of nothing: the floor vouched beyond
     * the gap no longer reaches the view, so the gap grows to it */
    for (i = 0; i < 3; i++) {
        assert_false(frame(&w, SEEN_MM, 0, STEP_MM));
    }
    for (i = 0; i < 5; i++) {
        assert_false(frame(&w, SEEN_MM, 4000, STEP_MM));
    }
    assert_int_equal(w.p.near_any.gap_mm, SEEN_MM - 4 * STEP_MM);
}

/* A frame gap longer than hold_ms: the camera may be anywhere, and the
 * floor under the view is the start check's business again. */
static void test_near_long_frame_gap_restarts(void **state)
{
    near_walk_t w;
    (void)state;
    walk_setup(&w);
    open_gap(&w, 0);
    assert_false(frame(&w, SEEN_MM, 4000, 0));
    w.now_ms += (uint32_t)w.cfg.hold_ms + 1u;
    assert_true(frame(&w, SEEN_MM, 4000, 0));
    assert_true(frame(&w, SEEN_MM, 4000, 0));
}

/* Switched on over noisy floor: the start check passes on the first
 * frame, but no frame vouches for 2 s of walking (a 10 cm curb on smooth
 * concrete, never confirmed, came under the view meanwhile). The first
 * frame that vouches must not speak for the floor it did not see: the
 * floor under the first view was the start check's, the floor walked
 * towards since was in view and never vouched. It vouches from the feet
 * once that floor is walked over, as after any gap. */
static void test_near_noisy_start_does_not_vouch_the_floor_walked_to(
    void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    assert_true(frame(&w, SEEN_MM, 0, STEP_MM)); /* the start's own view */
    for (i = 0; i < 20; i++) {
        (void)frame(&w, SEEN_MM, 0, STEP_MM);
    }
    assert_true(det_near_gap(&w.p));
    /* 1.7 m and the last 120 mm step */
    assert_int_equal(walk_over_gap(&w, 1600), 1800);
}

/* Frames without a usable ground at switch-on leave the floor under the
 * view to the start check: the first verified frame starts the following
 * with its own view, and a walk that vouches from then on stays
 * vouched. */
static void test_near_unverified_frames_leave_the_start_open(void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    for (i = 0; i < 20; i++) {
        assert_true(frame_start(&w, SEEN_MM, 0, STEP_MM, 0));
        assert_false(det_near_gap(&w.p));
    }
    assert_true(frame_start(&w, SEEN_MM, 4000, STEP_MM, 1));
    for (i = 0; i < 10; i++) {
        assert_true(frame(&w, SEEN_MM, 4000, STEP_MM));
    }
    assert_false(det_near_gap(&w.p));
}

/* The start verified by walking, 20 frames (2.4 m) after switch-on: the
 * frames that awaited the check would each have vouched 4 m from a view
 * at 1.2 m, so the floor walked towards meanwhile was vouched, by the
 * plane the check has now verified. The first verified frame vouches from
 * the feet, and so does the walk after it. */
static void test_near_awaited_frames_that_vouch_carry_over(void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    for (i = 0; i < 20; i++) {
        assert_true(frame_pending(&w, SEEN_MM, 0, 4000, 4000, STEP_MM, 0));
    }
    assert_true(frame(&w, SEEN_MM, 4000, STEP_MM));
    for (i = 0; i < 10; i++) {
        assert_true(frame(&w, SEEN_MM, 4000, STEP_MM));
    }
    assert_false(det_near_gap(&w.p));
}

/* The same walk, but the awaiting frames would have vouched nothing (a
 * noisy floor, a drop never confirmed): the floor walked towards left the
 * view unvouched before the check passed. The first verified frame must
 * not speak for it, although its own view is clean: it vouches from the
 * feet once that floor is walked over, as after any gap. Before the
 * awaiting frames were followed it did at once (a 5 cm drop that passed
 * below the view while the start was walked read CLEAR to 2.8 m with it
 * 0.6-1.4 m ahead). */
static void test_near_awaited_frames_that_vouch_nothing_leave_a_gap(
    void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    for (i = 0; i < 20; i++) {
        assert_true(frame_pending(&w, SEEN_MM, 0, 0, 0, STEP_MM, 0));
    }
    assert_int_equal(walk_over_gap(&w, 4000), SEEN_MM + 600);
}

/* A fit that rose while the check was awaited starts its following anew
 * (det_near_pending_restart): the floor behind the rise is the restarted
 * check's business, as at switch-on, and the frames after it vouch. */
static void test_near_awaited_following_restarts_with_the_check(void **state)
{
    near_walk_t w;
    int i;
    (void)state;
    walk_setup(&w);
    for (i = 0; i < 10; i++) {
        assert_true(frame_pending(&w, SEEN_MM, 0, 0, 0, STEP_MM, 0));
    }
    det_near_pending_restart(&w.p);
    for (i = 0; i < 10; i++) {
        assert_true(frame_pending(&w, SEEN_MM, 0, 4000, 4000, STEP_MM, 0));
    }
    assert_true(frame(&w, SEEN_MM, 4000, STEP_MM));
    assert_false(det_near_gap(&w.p));
}

/* A camera whose view starts beyond 1.5 m (1.7 m here: a head-worn
 * camera looking ahead). Every frame vouches 4.5 m for the minimum drop
 * of each range, i.e. for 10 cm from its view on; the floor within 1.5 m
 * of the feet is never in view, so only the floor checked for 5 cm while
 * it lay at 1.7-2 m can be vouched from the feet. vouched_5cm_mm: how far
 * each frame checked it (0: nowhere). Returns the frames vouched from the
 * feet out of 40, and asserts that once one is not, none is after it. */
static int shallow_view_walk(int32_t vouched_5cm_mm)
{
    near_walk_t w;
    int n_ok = 0;
    int lost = 0;
    int i;
    walk_setup(&w);
    for (i = 0; i < 40; i++) {
        const int ok = frame_5cm(&w, 1700, 4500, vouched_5cm_mm, STEP_MM, 1);
        assert_false(ok && lost);
        lost |= !ok;
        n_ok += ok;
    }
    return n_ok;
}

static void test_near_shallow_view_needs_the_floor_checked_for_5cm(
    void **state)
{
    (void)state;
    /* never checked for 5 cm: vouched only while the start's floor (the
     * start check's) still covers 1.5 m, then never again */
    assert_int_equal(shallow_view_walk(0), 3);
    /* checked for 5 cm out to 2 m (the rule's 5 cm reach): every frame */
    assert_int_equal(shallow_view_walk(2000), 40);
    /* one following for both, as before the 5 cm following: every frame,
     * over floor within 1.5 m that was only checked for 10 cm */
    assert_int_equal(shallow_view_walk(4500), 40);
}

/* A camera whose view starts at 1.2 m, walking over floor it vouches to
 * 4 m (for 5 cm to 2 m), then 7 frames (0.7 s) that vouch nothing: the
 * floor that passed through the near rows meanwhile was checked for 10 cm
 * only, beyond 2 m. Not vouched from the feet until that floor has been
 * walked over; the single following vouched straight on. */
static void test_near_noisy_run_needs_the_floor_checked_for_5cm(void **state)
{
    near_walk_t w;
    near_walk_t w1; /* the same walk, one following for both */
    int i;
    (void)state;
    walk_setup(&w);
    walk_setup(&w1);
    for (i = 0; i < 10; i++) {
        assert_true(frame_5cm(&w, SEEN_MM, 4000, 2000, STEP_MM, 1));
        assert_true(frame(&w1, SEEN_MM, 4000, STEP_MM));
    }
    for (i = 0; i < 7; i++) {
        (void)frame_5cm(&w, SEEN_MM, 0, 0, STEP_MM, 1);
        assert_true(frame(&w1, SEEN_MM, 0, STEP_MM));
    }
    assert_true(det_near_gap(&w.p));
    assert_false(det_near_gap(&w1.p));
    assert_true(frame(&w1, SEEN_MM, 4000, STEP_MM));
    /* the view's nearest floor and half a stride, as after any gap */
    {
        int32_t walked_mm = 0;
        assert_false(frame_5cm(&w, SEEN_MM, 4000, 2000, STEP_MM, 1));
        while (!frame_5cm(&w, SEEN_MM, 4000, 2000, STEP_MM, 1)) {
            walked_mm += STEP_MM;
            assert_true(walked_mm < SEEN_MM + 500);
        }
        assert_true(walked_mm + STEP_MM >= SEEN_MM + 500);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_near_vouched_walk_stays_vouched),
        cmocka_unit_test(test_near_standing_short_view_stays_vouched),
        cmocka_unit_test(test_near_unvouched_floor_until_walked_over),
        cmocka_unit_test(test_near_unmeasured_travel_never_passes),
        cmocka_unit_test(test_near_second_gap_extends_the_first),
        cmocka_unit_test(test_near_long_frame_gap_restarts),
        cmocka_unit_test(
            test_near_noisy_start_does_not_vouch_the_floor_walked_to),
        cmocka_unit_test(test_near_unverified_frames_leave_the_start_open),
        cmocka_unit_test(test_near_awaited_frames_that_vouch_carry_over),
        cmocka_unit_test(
            test_near_awaited_frames_that_vouch_nothing_leave_a_gap),
        cmocka_unit_test(test_near_awaited_following_restarts_with_the_check),
        cmocka_unit_test(
            test_near_shallow_view_needs_the_floor_checked_for_5cm),
        cmocka_unit_test(test_near_noisy_run_needs_the_floor_checked_for_5cm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
