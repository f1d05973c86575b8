/*
 * Floor beyond the matcher's disparity range (docs/DETECTION.md section 4,
 * "Beyond the matcher's range"): a camera whose near floor lies at more
 * disparity than the matcher searches. Analytic maps
 * (tests/support/scene_disp.h) of the default rig (1.2 m / 20 deg,
 * f = 250 px, B = 120 mm at 320x240: the floor reaches 19.8 px at the
 * bottom row), with the detector told a matcher that searches 0-15 px
 * (max_disp_q4 16 px). Where the floor's disparity passes 15 px the map
 * is overwritten as such a matcher leaves it: the first rows read the
 * range's top, the rest runs of arbitrary values below it, constant
 * along 40 px (what growth and the DP carry into rows they cannot match).
 */
#include <math.h>

#include "cmocka_all.h"
#include "scene_util.h"

#define RANGE_PX 16    /* detector's max_disp_q4 / 16                   */
#define TOP_ROWS 6     /* rows past the range that read its top         */
#define GARBAGE_RUN 40 /* columns of one arbitrary value in the garbage */

static rig_t rig;

/* Overwrite the rendered map where the true disparity passes the
 * matcher's last one (RANGE_PX - 1 px). */
static void beyond_range(uint32_t seed)
{
    const int32_t last_q4 = (RANGE_PX - 1) * NEGOBS_DISP_ONE;
    uint32_t st = seed;
    int32_t u;
    for (u = 0; u < RIG_W; u++) {
        int32_t past = 0;
        int32_t v;
        for (v = 0; v < RIG_H; v++) {
            int16_t *d = &rig.disp[v * RIG_W + u];
            if (*d == NEGOBS_DISP_INVALID || *d <= last_q4) {
                continue;
            }
            if (++past <= TOP_ROWS) {
                *d = (int16_t)last_q4;
            } else if (u % GARBAGE_RUN == 0 || u == 0) {
                *d = (int16_t)(2 * NEGOBS_DISP_ONE +
                               (int32_t)((test_lcg_next(&st) >> 8) %
                                         (uint32_t)(last_q4 -
                                                    2 * NEGOBS_DISP_ONE)));
            } else {
                *d = rig.disp[v * RIG_W + u - 1];
            }
        }
    }
}

static void setup_narrow_matcher(void)
{
    negobs_detect_config_t cfg;
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    cfg.max_disp_q4 = RANGE_PX * NEGOBS_DISP_ONE;
    rig_setup(&rig, &cfg);
}

/* n frames of the scene through the narrow matcher; counts hazards. */
static int run_frames(const synth_scene_t *s0, int n, int *n_clear)
{
    synth_scene_t s = *s0;
    int hazards = 0;
    int i;
    *n_clear = 0;
    for (i = 0; i < n; i++) {
        s.seed = s0->seed + (uint32_t)i;
        synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
        beyond_range(900u + (uint32_t)i);
        assert_int_equal(rig_run(&rig), NEGOBS_OK);
        hazards += rig.res.state == NEGOBS_DETECT_HAZARD;
        *n_clear += rig.res.state == NEGOBS_DETECT_CLEAR;
        print_message("  frame %d: state %d, clear_to %d, reasons %u, "
                      "H %d mm, pitch %d mdeg, hazards %u\n",
                      i, (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.reasons, rig.res.mount.height_mm,
                      rig.res.mount.pitch_mdeg, rig.res.n_hazards);
    }
    return hazards;
}

/* Flat floor: the fit rests on the rows within the range and measures the
 * mounting (the hint is the truth here, so the start is verified by it),
 * no hazard is reported, and the floor in range is vouched (CLEAR, at
 * least the near-zone minimum). Before, the rows of garbage took part in
 * the fit and the scan: a "drop" at the feet on every frame. */
static void test_range_flat_floor_beyond_the_range(void **state)
{
    synth_scene_t s;
    int n_clear = 0;
    (void)state;
    synth_flat(&s, 1.2, 20.0);
    s.noise_px = 0.1;
    s.seed = 41u;
    setup_narrow_matcher();
    assert_int_equal(run_frames(&s, 6, &n_clear), 0);
    assert_int_equal(n_clear, 6);
    assert_true(rig.res.clear_to_mm >= rig.cfg.near_min_mm);
    assert_true(abs(rig.res.mount.height_mm - 1200) <= 30);
    assert_true(abs(rig.res.mount.pitch_mdeg - 20000) <= 500);
    rig_teardown(&rig);
}

/* A 15 cm drop 2.5 m ahead, in the range: reported within 10 % of its
 * distance and never vouched past it. */
static void test_range_drop_in_range_is_found(void **state)
{
    synth_scene_t s;
    int n_clear = 0;
    (void)state;
    synth_flat(&s, 1.2, 20.0);
    synth_step(&s, 2.5, -0.15);
    s.noise_px = 0.1;
    s.seed = 43u;
    setup_narrow_matcher();
    assert_true(run_frames(&s, 6, &n_clear) >= 3);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_HAZARD);
    assert_true(rig.res.n_hazards >= 1u);
    assert_true(abs(rig.res.hazards[0].range_mm - 2500) <= 250);
    assert_true(rig.res.clear_to_mm <= 2750);
    rig_teardown(&rig);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_range_flat_floor_beyond_the_range),
        cmocka_unit_test(test_range_drop_in_range_is_found),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
