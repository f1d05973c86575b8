/*
 * The nearest noise band (docs/DETECTION.md 10.2, "The walk"): the scanned
 * rows are cut into bands of rows rounded up, so the nearest band holds
 * what is left, and the image's last two rows carry no disparity (the
 * matcher's 5x5 window). On a camera pitched nearly level that band can
 * be a sliver of one matched row; it must not end the vouched walk at
 * the bottom row. Analytic maps (tests/support/scene_disp.h) of the
 * default rig (f = 250 px, B = 120 mm at 320x240) at 1.2 m, pitch 2-4
 * deg, the detector told 1.2 m (the start verified by the hint).
 */
#include <math.h>

#include "cmocka_all.h"
#include "scene_util.h"

static rig_t rig;

/* Flat floor at each pitch from 2 to 4 deg in quarter degrees, 3 frames
 * each: every frame CLEAR and vouched past the near-zone minimum. At
 * these pitches the bottom row sees the floor 2.0-2.4 m ahead and the
 * scan reaches range_max; for some of them the nearest band is three
 * rows, two unmatched. Before, those frames ended the walk at the bottom
 * row: NO_INFO (FEW_GROUND), clear_to_mm 0. */
static void test_near_band_sliver_does_not_end_the_walk(void **state)
{
    int n_frames = 0;
    int n_clear = 0;
    int k;
    (void)state;
    for (k = 0; k <= 8; k++) {
        synth_scene_t s;
        int i;
        synth_flat(&s, 1.2, 2.0 + 0.25 * k);
        s.noise_px = 0.1;
        rig_setup(&rig, NULL);
        for (i = 0; i < 3; i++) {
            int32_t u;
            int32_t v;
            s.seed = 61u + (uint32_t)(10 * k + i);
            synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
            for (v = RIG_H - 2; v < RIG_H; v++) {
                for (u = 0; u < RIG_W; u++) {
                    rig.disp[v * RIG_W + u] = NEGOBS_DISP_INVALID;
                }
            }
            assert_int_equal(rig_run(&rig), NEGOBS_OK);
            n_frames++;
            if (rig.res.state == NEGOBS_DETECT_CLEAR &&
                rig.res.clear_to_mm >= rig.cfg.near_min_mm) {
                n_clear++;
            } else {
                print_message("  pitch %.2f frame %d: state %d, reasons %u, "
                              "clear_to %d\n",
                              s.pitch_deg, i, (int)rig.res.state,
                              rig.res.reasons, rig.res.clear_to_mm);
            }
        }
        rig_teardown(&rig);
    }
    assert_int_equal(n_clear, n_frames);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_near_band_sliver_does_not_end_the_walk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
