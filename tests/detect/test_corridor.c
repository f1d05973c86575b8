/*
 * The walking corridor near the feet (docs/DETECTION.md 10.2, "The
 * corridor"): its half-width is corridor_near_half_mm (250 mm) plus range x
 * tan 20 deg, capped at corridor_half_width_mm (600 mm). Analytic maps
 * (tests/support/scene_disp.h) of a low wide-angle camera (0.6 m, 20 deg,
 * f = 160 px at 320x240, B = 120 mm), whose bottom rows see the floor
 * 0.5-0.9 m ahead across more than the old +-0.6 m.
 */
#include <math.h>

#include "cmocka_all.h"
#include "scene_util.h"
#include "detect/detect_int.h"

static rig_t rig;

#define WIDE_F_PX 160
#define NEAR_HALF_MM 250.0
#define HEADING_TAN 0.364 /* tan 20 deg */

enum spoil { SPOIL_OUTSIDE, SPOIL_INSIDE };

/* Floor distance (m) seen by image row v (flat floor, roll 0). */
static double row_floor_m(const synth_scene_t *s, int32_t v)
{
    const double d2r = 3.14159265358979323846 / 180.0;
    double f = rig.cfg.rig.focal_q4 / 16.0;
    double cy = rig.cfg.rig.cy_q4 / 16.0;
    return s->h_m / tan(s->pitch_deg * d2r + atan((v - cy) / f));
}

/* Spoils whole strip rows of the rendered map the way the dark parquet of
 * a real low camera looked (1 px lower than the floor, +-1.5 px per strip
 * row, +-1 px per pixel): SPOIL_OUTSIDE where the strip centre lies more than
 * 40 mm outside the narrowed corridor but inside +-0.6 m (the old
 * corridor), SPOIL_INSIDE on the right-hand half of the narrowed corridor
 * (centres 40 mm or more inside it), both only on floor nearer than
 * 0.9 m. */
static void spoil(const synth_scene_t *s, enum spoil where, uint32_t seed)
{
    const double cx = rig.cfg.rig.cx_q4 / 16.0;
    const double b_mm = rig.cfg.rig.baseline_um / 1000.0;
    const int32_t sp = rig.cfg.strip_px;
    uint32_t st = seed;
    int32_t v;
    for (v = 0; v < RIG_H; v++) {
        double r_m = row_floor_m(s, v);
        double w_mm = fmin(600.0, NEAR_HALF_MM + HEADING_TAN * r_m * 1000.0);
        int32_t u0;
        if (r_m <= 0.0 || r_m > 0.9) {
            continue;
        }
        for (u0 = 0; u0 + sp <= RIG_W; u0 += sp) {
            int32_t uc = u0 + sp / 2;
            int16_t dc = rig.disp[v * RIG_W + uc];
            double x_mm;
            int hit;
            int32_t off;
            int32_t u;
            if (dc == NEGOBS_DISP_INVALID || dc <= 0) {
                continue;
            }
            x_mm = (uc + 0.5 - cx) * b_mm / (dc / 16.0);
            hit = (where == SPOIL_OUTSIDE)
                      ? fabs(x_mm) > w_mm + 40.0 && fabs(x_mm) <= 600.0
                      : x_mm > 80.0 && x_mm < 250.0;
            if (!hit) {
                continue;
            }
            off = (int32_t)((test_lcg_next(&st) >> 16) % 49u) - 40;
            for (u = u0; u < u0 + sp; u++) {
                int16_t *d = &rig.disp[v * RIG_W + u];
                if (*d != NEGOBS_DISP_INVALID) {
                    int32_t px = (int32_t)((test_lcg_next(&st) >> 16) % 33u);
                    *d = (int16_t)(*d + off + px - 16);
                }
            }
        }
    }
}

/* The low wide-angle camera told its mounting, fed n frames of the scene
 * with the near floor spoiled as given (n >= 1); the last result stays in
 * rig.res. */
static void run_spoiled(const synth_scene_t *s0, enum spoil where, int n)
{
    negobs_detect_config_t cfg;
    synth_scene_t s = *s0;
    int i;
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    cfg.rig.focal_q4 = WIDE_F_PX * 16;
    cfg.cam_height_mm = (int32_t)lround(s.h_m * 1000.0);
    cfg.cam_pitch_mdeg = (int32_t)lround(s.pitch_deg * 1000.0);
    rig_setup(&rig, &cfg);
    for (i = 0; i < n; i++) {
        s.seed = s0->seed + (uint32_t)i;
        synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
        spoil(&s, where, 1000u + (uint32_t)i);
        assert_int_equal(rig_run(&rig), NEGOBS_OK);
        print_message("  frame %d: state %d, clear_to %d, reasons %u\n", i,
                      (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.reasons);
    }
}

/* Noise in the image-edge strips near the feet, 0.5-0.9 m ahead and 0.4-
 * 0.6 m to the side: floor a straight walker does not step on (outside
 * its body's lane and 20 deg of heading), in the cane's reach, and in view
 * again when the walker turns to it. The rest of the floor is clean, so
 * the frame is CLEAR beyond the near-zone minimum. The old fixed +-0.6 m
 * corridor held those strips: the walk ended at the bottom row, NO_INFO
 * with clear_to_mm 0. */
static void test_corridor_noise_outside_the_feet_lane_is_not_walked(
    void **state)
{
    synth_scene_t s;
    (void)state;
    synth_flat(&s, 0.6, 20.0);
    s.noise_px = 0.2;
    s.seed = 131u;
    run_spoiled(&s, SPOIL_OUTSIDE, 3);
    print_message("edge strips spoiled: state %d, clear_to %d, reasons %u\n",
                  (int)rig.res.state, rig.res.clear_to_mm, rig.res.reasons);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
    assert_true(rig.res.clear_to_mm >= rig.cfg.near_min_mm);
    rig_teardown(&rig);
}

/* The same noise inside the narrowed corridor (right of the camera's axis,
 * within the lane a straight walker's feet may take) is what the feet may
 * step on: NO_INFO, nothing vouched up to the near-zone minimum. */
static void test_corridor_noise_in_the_feet_lane_is_no_info(void **state)
{
    synth_scene_t s;
    (void)state;
    synth_flat(&s, 0.6, 20.0);
    s.noise_px = 0.2;
    s.seed = 141u;
    run_spoiled(&s, SPOIL_INSIDE, 2);
    assert_true((rig.res.reasons & NEGOBS_DEGRADED_NOISY) != 0u);
    print_message("lane spoiled: state %d, clear_to %d, reasons %u\n",
                  (int)rig.res.state, rig.res.clear_to_mm, rig.res.reasons);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
    assert_true(rig.res.clear_to_mm < rig.cfg.near_min_mm);
    rig_teardown(&rig);
}

/* An object in the corridor that leaves lanes open (a 1 m post 0.3 m wide,
 * 1.0 m ahead, in the middle): the floor up to its foot is vouched, its
 * shadow (the floor behind it, in the corridor, unseen) is not, and a
 * walker passing it reaches floor beside and behind it. So clear_to_mm
 * stops at the post's foot and the frame is NO_INFO there (below the
 * near-zone minimum), not CLEAR past it. With the edge strips spoiled as
 * in the first test, the old corridor ended the walk at the bottom row
 * (clear_to_mm 0). */
static void test_corridor_object_with_open_lanes_stops_at_its_foot(
    void **state)
{
    synth_scene_t s;
    (void)state;
    synth_flat(&s, 0.6, 20.0);
    s.noise_px = 0.2;
    s.seed = 151u;
    synth_step(&s, 1.0, 1.0);
    s.lat_half_m = 0.15;
    run_spoiled(&s, SPOIL_OUTSIDE, 3);
    print_message("post at 1.0 m: state %d, clear_to %d, blocked_at %d, "
                  "reasons %u\n",
                  (int)rig.res.state, rig.res.clear_to_mm,
                  rig.res.blocked_at_mm, rig.res.reasons);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
    assert_int_equal(rig.res.blocked_at_mm, 0);
    assert_true(rig.res.clear_to_mm >= 800);
    assert_true(rig.res.clear_to_mm <= 1000 + 1000 / 10);
    rig_teardown(&rig);
}

/* The corridor's half-width: 250 mm at the feet, + tan 20 deg x range,
 * 600 mm from 0.96 m on (far behaviour unchanged); a near half-width equal
 * to the cap (a head-worn camera) does not narrow it, and one above the
 * cap is held to it. */
static void test_corridor_half_width(void **state)
{
    negobs_detect_config_t cfg;
    (void)state;
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    assert_int_equal(cfg.corridor_near_half_mm, 250);
    assert_int_equal(negobs_detect_corridor_half_mm(&cfg, 0), 250);
    assert_int_equal(negobs_detect_corridor_half_mm(&cfg, 500), 250 + 182);
    assert_int_equal(negobs_detect_corridor_half_mm(&cfg, 961), 599);
    assert_int_equal(negobs_detect_corridor_half_mm(&cfg, 962), 600);
    assert_int_equal(negobs_detect_corridor_half_mm(&cfg, 5000), 600);
    cfg.corridor_near_half_mm = 600;
    assert_int_equal(negobs_detect_corridor_half_mm(&cfg, 0), 600);
    cfg.corridor_near_half_mm = 900;
    assert_int_equal(negobs_detect_corridor_half_mm(&cfg, 0), 600);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corridor_half_width),
        cmocka_unit_test(
            test_corridor_noise_outside_the_feet_lane_is_not_walked),
        cmocka_unit_test(test_corridor_noise_in_the_feet_lane_is_no_info),
        cmocka_unit_test(
            test_corridor_object_with_open_lanes_stops_at_its_foot),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
