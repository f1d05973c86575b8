/*
 * Near occluders at the view's bottom edge (docs/DETECTION.md 10.2, "Near
 * occluders"): hands, a held phone, a sleeve covering the bottom rows of
 * part of the corridor, with floor above them. Analytic maps
 * (tests/support/scene_disp.h) of the default rig (1.2 m / 20 deg,
 * f = 250 px, B = 120 mm at 320x240), the "hands" painted into the
 * rendered map as blobs of near disparity.
 */
#include <math.h>

#include "cmocka_all.h"
#include "scene_util.h"

static rig_t rig;
/* frames run_hands saw CLEAR, and the largest clear_to_mm it saw */
static int n_clear;
static int32_t max_clear_to;

enum blob { BLOB_MATCHED, BLOB_INVALID, BLOB_NONE };

/* Image row of the level floor at forward distance d_m (roll 0). */
static int32_t floor_row(const synth_scene_t *s, double d_m)
{
    const double d2r = 3.14159265358979323846 / 180.0;
    double f = rig.cfg.rig.focal_q4 / 16.0;
    double cy = rig.cfg.rig.cy_q4 / 16.0;
    return (int32_t)lround(cy +
                           f * tan(atan(s->h_m / d_m) - s->pitch_deg * d2r));
}

/*
 * Two hands 0.55 m in front of the camera (54.5 px, 0.76 m above the floor
 * at the bottom row) in columns 96-151 and 168-223, from the bottom row up
 * to top_v (their top rises by 6 rows towards their middle, like
 * fingers), their upper 4 rows read 0.4 px high as a real matcher bleeds a
 * near disparity past its edge. BLOB_INVALID leaves the same pixels
 * unmatched instead (a hand nearer than the search range, or a
 * textureless one).
 */
static void paint_hands(int32_t top_v, enum blob kind, uint32_t seed)
{
    static const int32_t u0s[2] = {96, 168};
    uint32_t st = seed;
    int h;
    for (h = 0; h < 2; h++) {
        int32_t u;
        for (u = u0s[h]; u < u0s[h] + 56; u++) {
            int32_t mid = negobs_abs_s32(u - (u0s[h] + 28));
            int32_t top = top_v + (mid * 6) / 28;
            int32_t v;
            for (v = top; v < RIG_H; v++) {
                int16_t *d = &rig.disp[v * RIG_W + u];
                int32_t n = (int32_t)((test_lcg_next(&st) >> 16) % 9u) - 4;
                if (kind == BLOB_INVALID) {
                    *d = NEGOBS_DISP_INVALID;
                } else {
                    *d = (int16_t)(872 + n);
                }
            }
            if (kind == BLOB_MATCHED) {
                for (v = top - 4; v < top; v++) {
                    int16_t *d = &rig.disp[v * RIG_W + u];
                    if (*d != NEGOBS_DISP_INVALID) {
                        *d = (int16_t)(*d + 6);
                    }
                }
            }
        }
    }
}

/* n frames of the scene with the hands painted; the last result stays in
 * rig.res. */
static void run_hands(const synth_scene_t *s0, double top_m, enum blob kind,
                      int n)
{
    synth_scene_t s = *s0;
    int i;
    for (i = 0; i < n; i++) {
        s.seed = s0->seed + (uint32_t)i;
        synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
        if (kind != BLOB_NONE) {
            paint_hands(floor_row(&s, top_m), kind, 500u + (uint32_t)i);
        }
        assert_int_equal(rig_run(&rig), NEGOBS_OK);
        n_clear += rig.res.state == NEGOBS_DETECT_CLEAR;
        if (rig.res.clear_to_mm > max_clear_to) {
            max_clear_to = rig.res.clear_to_mm;
        }
        print_message("  frame %d: state %d, clear_to %d, noise_vouch %d, "
                      "reasons %u, candidates %u, hazards %u\n",
                      i, (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.noise_vouch_mm, rig.res.reasons,
                      rig.res.n_candidates, rig.res.n_hazards);
    }
}

/* Hands over the bottom rows of most of the corridor, clean floor above:
 * the walk starts above them and vouches as far as the noise allows, as
 * it would above the image's bottom row (CLEAR to 4.5 m). The old walk
 * counted the hands' rows as unseen floor: it ended at their top, NO_INFO
 * (FEW_GROUND) at 1.19 m. */
static void test_occl_hands_start_the_walk_above_them(void **state)
{
    synth_scene_t s;
    (void)state;
    synth_flat(&s, 1.2, 20.0);
    s.noise_px = 0.1;
    s.seed = 31u;
    rig_setup(&rig, NULL);
    run_hands(&s, 1.5, BLOB_MATCHED, 3);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
    assert_int_equal(rig.res.reasons, 0);
    assert_true(rig.res.clear_to_mm >= rig.cfg.range_warn_mm);
    assert_int_equal(rig.res.clear_to_mm, rig.res.noise_vouch_mm);
    rig_teardown(&rig);
}

/* A drop in view above the hands at the near-zone minimum (10 cm, then
 * 5 cm, at 1.5 m across the width; the hands reach 1.25 m), after flat
 * frames with the hands (the floor verified): never CLEAR, clear_to_mm
 * within 1.1x its distance, a confirmed HAZARD, as without the hands
 * (BLOB_NONE, the same frames). */
static void test_occl_drop_above_the_hands_is_not_vouched(void **state)
{
    synth_scene_t s;
    int i;
    (void)state;
    for (i = 0; i < 4; i++) {
        synth_flat(&s, 1.2, 20.0);
        s.noise_px = 0.1;
        s.seed = 41u + (uint32_t)i;
        rig_setup(&rig, NULL);
        /* flat frames first: the floor under the feet verified */
        run_hands(&s, 1.25, i < 2 ? BLOB_MATCHED : BLOB_NONE, 4);
        synth_step(&s, 1.5, (i & 1) == 0 ? -0.10 : -0.05);
        n_clear = 0;
        max_clear_to = 0;
        run_hands(&s, 1.25, i < 2 ? BLOB_MATCHED : BLOB_NONE, 5);
        assert_int_equal(n_clear, 0);
        assert_true(max_clear_to <= 1500 + 1500 / 10);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_HAZARD);
        rig_teardown(&rig);
    }
}

/* The same blobs unmatched: nothing says they are not floor (a textureless
 * floor, a hole's lower surface look the same), so they stay unseen floor
 * and the walk stops at the bottom row, as before. */
static void test_occl_unmatched_blobs_stay_unseen_floor(void **state)
{
    synth_scene_t s;
    (void)state;
    synth_flat(&s, 1.2, 20.0);
    s.noise_px = 0.1;
    s.seed = 51u;
    rig_setup(&rig, NULL);
    run_hands(&s, 1.5, BLOB_INVALID, 3);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
    assert_true(rig.res.clear_to_mm < rig.cfg.near_min_mm);
    rig_teardown(&rig);
}

/* Low things near the feet are floor-standing obstacles, not occluders:
 * a 15 cm up-step 1.25 m ahead, just above the bottom row (1.18 m; below
 * BAR_H_MM), and a 10 cm drop there (a lower surface): the verdict is the
 * old one, never CLEAR past them. */
static void test_occl_low_step_near_the_feet_is_unchanged(void **state)
{
    synth_scene_t s;
    int i;
    (void)state;
    for (i = 0; i < 2; i++) {
        int k;
        synth_flat(&s, 1.2, 20.0);
        s.noise_px = 0.1;
        s.seed = 61u + (uint32_t)i;
        synth_step(&s, 1.25, i == 0 ? 0.15 : -0.10);
        s.lat_half_m = 0.3;
        rig_setup(&rig, NULL);
        for (k = 0; k < 3; k++) {
            s.seed += 1u;
            assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
            print_message("  step %d frame %d: state %d, clear_to %d, "
                          "reasons %u\n",
                          i, k, (int)rig.res.state, rig.res.clear_to_mm,
                          rig.res.reasons);
        }
        if (i == 1) {
            assert_true(rig.res.state != NEGOBS_DETECT_CLEAR);
            assert_true(rig.res.clear_to_mm <= 1250 + 1250 / 10);
        } else {
            assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
        }
        rig_teardown(&rig);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_occl_hands_start_the_walk_above_them),
        cmocka_unit_test(test_occl_drop_above_the_hands_is_not_vouched),
        cmocka_unit_test(test_occl_unmatched_blobs_stay_unseen_floor),
        cmocka_unit_test(test_occl_low_step_near_the_feet_is_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
