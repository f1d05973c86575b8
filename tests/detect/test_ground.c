/*
 * Ground plane geometry and estimation: pose <-> plane round trips, plane
 * against the analytic ground disparity, floor distances, and the fit on
 * synthetic maps (noise, roll, dropout, rejection).
 */
#include <math.h>
#include <stdlib.h>

#include "cmocka_all.h"
#include "detect/detect_int.h"
#include "detect/ground_fit.h"
#include "scene_util.h"

#define TEST_PI 3.14159265358979323846

static negobs_rig_t cam;

static void test_ground_pose_plane_round_trip(void **state)
{
    int32_t h;
    int32_t p;
    int32_t r;
    (void)state;
    negobs_rig_default(&cam, 320, 240);
    for (h = 600; h <= 2000; h += 350) {
        for (p = -5000; p <= 45000; p += 7000) {
            for (r = -15000; r <= 15000; r += 5000) {
                negobs_ground_pose_t in = {h, p, r};
                negobs_ground_pose_t out;
                negobs_ground_plane_t pl;
                assert_int_equal(negobs_ground_plane_from_pose(&cam, &in, &pl),
                                 NEGOBS_OK);
                assert_int_equal(
                    negobs_ground_pose_from_plane(&cam, &pl, &out, NULL),
                    NEGOBS_OK);
                assert_true(abs(out.height_mm - h) <= 2);
                assert_true(abs(out.pitch_mdeg - p) <= 10);
                assert_true(abs(out.roll_mdeg - r) <= 10);
            }
        }
    }
}

static void test_ground_plane_matches_analytic_disparity(void **state)
{
    static int16_t d[RIG_W * RIG_H];
    synth_scene_t s;
    negobs_ground_pose_t pose = {1200, 20000, 4000};
    negobs_ground_plane_t pl;
    int32_t u;
    int32_t v;
    (void)state;
    negobs_rig_default(&cam, RIG_W, RIG_H);
    synth_flat(&s, 1.2, 20.0);
    s.roll_deg = 4.0;
    synth_render(&s, &cam, d, RIG_W);
    assert_int_equal(negobs_ground_plane_from_pose(&cam, &pose, &pl),
                     NEGOBS_OK);
    for (v = 60; v < RIG_H; v += 7) {
        for (u = 0; u < RIG_W; u += 11) {
            int32_t ds = d[v * RIG_W + u];
            if (ds == NEGOBS_DISP_INVALID) {
                continue;
            }
            assert_true(abs(negobs_ground_disp_q4(&pl, u, v) - ds) <= 1);
        }
    }
}

static void test_ground_floor_distance_of_ground_pixels(void **state)
{
    negobs_ground_pose_t pose = {1200, 20000, 0};
    negobs_ground_plane_t pl;
    negobs_ground_frame_t fr;
    negobs_ground_pose_t back;
    int32_t v;
    (void)state;
    negobs_rig_default(&cam, RIG_W, RIG_H);
    assert_int_equal(negobs_ground_plane_from_pose(&cam, &pose, &pl),
                     NEGOBS_OK);
    assert_int_equal(negobs_ground_pose_from_plane(&cam, &pl, &back, &fr),
                     NEGOBS_OK);
    for (v = 100; v < RIG_H; v += 10) {
        double ang = 20.0 * TEST_PI / 180.0 +
                     atan((v - (cam.cy_q4 / 16.0)) / (cam.focal_q4 / 16.0));
        double ref = 1200.0 / tan(ang);
        int32_t dq = negobs_ground_disp_q4(&pl, 160, v);
        int32_t z = negobs_depth_mm_from_disp_q4(&cam, dq);
        int32_t fwd;
        int32_t lat;
        negobs_ground_floor_point(&cam, &fr, 160 * 16, v * 16, z, &fwd, &lat);
        /* Disparity rounding (1/32 px) dominates: 0.5 %. */
        assert_true(fabs(fwd - ref) <= ref * 0.005 + 2.0);
        assert_true(abs(lat) <= 10);
    }
}

static void test_ground_plane_from_pose_rejects_bad_input(void **state)
{
    negobs_ground_pose_t pose = {50, 20000, 0};
    negobs_ground_plane_t pl = {0, 0, 0};
    negobs_ground_pose_t out;
    (void)state;
    negobs_rig_default(&cam, RIG_W, RIG_H);
    assert_int_equal(negobs_ground_plane_from_pose(&cam, &pose, &pl),
                     NEGOBS_ERR_INVAL);
    pose.height_mm = 1200;
    pose.pitch_mdeg = 85000;
    assert_int_equal(negobs_ground_plane_from_pose(&cam, &pose, &pl),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_ground_plane_from_pose(NULL, &pose, &pl),
                     NEGOBS_ERR_INVAL);
    /* A plane whose disparity falls towards the bottom is no ground. */
    pl.b_q20 = -1000;
    assert_int_equal(negobs_ground_pose_from_plane(&cam, &pl, &out, NULL),
                     NEGOBS_ERR_RANGE);
}

/* Fit on one synthetic frame through the internal estimator, with the
 * baseline baseline_um (0: the default 120 mm) and, when smear_rows > 1,
 * each column averaged over smear_rows rows centred on the pixel (a
 * matcher's window blurs an edge over that many rows). */
static void fit_scene_rig(const synth_scene_t *s, int32_t baseline_um,
                          int32_t smear_rows, gfit_out_t *out)
{
    static int16_t d[RIG_W * RIG_H];
    static int16_t sm[RIG_W * RIG_H];
    static uint8_t mem[128 * 1024] __attribute__((aligned(16)));
    static negobs_detect_config_t cfg;
    negobs_image_s16_t img = {d, RIG_W, RIG_H, RIG_W};
    negobs_arena_t ar;
    gfit_t g;
    int32_t u;
    int32_t v;
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    if (baseline_um > 0) {
        cfg.rig.baseline_um = baseline_um;
    }
    negobs_arena_init(&ar, mem, sizeof mem);
    assert_int_equal(gfit_carve(&g, &ar, &cfg), NEGOBS_OK);
    synth_render(s, &cfg.rig, d, RIG_W);
    if (smear_rows > 1) {
        for (v = 0; v < RIG_H; v++) {
            for (u = 0; u < RIG_W; u++) {
                int32_t sum = 0;
                int32_t n = 0;
                int32_t k;
                for (k = v - smear_rows / 2; k <= v + smear_rows / 2; k++) {
                    if (k >= 0 && k < RIG_H &&
                        d[k * RIG_W + u] != NEGOBS_DISP_INVALID) {
                        sum += d[k * RIG_W + u];
                        n++;
                    }
                }
                sm[v * RIG_W + u] = (int16_t)((n > 0) ? (sum + n / 2) / n
                                                      : NEGOBS_DISP_INVALID);
            }
        }
        memcpy(d, sm, sizeof d);
    }
    gfit_process(&g, &img, NULL, NULL, NULL, out);
}

static void fit_scene(const synth_scene_t *s, gfit_out_t *out)
{
    fit_scene_rig(s, 0, 1, out);
}

static void test_ground_fit_recovers_pose_with_noise_and_roll(void **state)
{
    static const double rolls[] = {0.0, 4.0, -8.0};
    static const double heights[] = {1.0, 1.2, 1.45};
    static const double pitches[] = {10.0, 20.0, 30.0};
    int i;
    (void)state;
    for (i = 0; i < 3; i++) {
        synth_scene_t s;
        gfit_out_t o;
        synth_flat(&s, heights[i], pitches[i]);
        s.roll_deg = rolls[i];
        s.noise_px = 0.25;
        s.dropout = 0.15;
        s.seed = (uint32_t)i + 40u;
        fit_scene(&s, &o);
        assert_int_equal(o.ok, 1);
        assert_int_equal(o.reasons, 0);
        assert_true(abs(o.pose.height_mm - (int)(heights[i] * 1000)) <= 40);
        assert_true(abs(o.pose.pitch_mdeg - (int)(pitches[i] * 1000)) <= 800);
        assert_true(abs(o.pose.roll_mdeg - (int)(rolls[i] * 1000)) <= 800);
        assert_true(o.sigma_q4 >= 3 && o.sigma_q4 <= 6);
    }
}

/* A clean flat map (noise 0.05 px, like the matcher's on rendered ground)
 * must give back its plane: the fit only sees the bottom quarter of the
 * rows and the detector extrapolates it to the warning range, so a slope
 * error there becomes a false deficit. Residuals rounded to whole q4 made
 * the IRLS read the model's rounding sawtooth as slope: 10/256 px off on
 * these maps (now 2/256). */
static void test_ground_fit_is_unbiased_on_a_clean_flat_map(void **state)
{
    static const double heights[] = {1.2, 1.0, 1.35, 1.2};
    static const double pitches[] = {20.0, 17.0, 23.0, 12.0};
    int i;
    int32_t worst = 0;
    (void)state;
    for (i = 0; i < 4; i++) {
        synth_scene_t s;
        gfit_out_t o;
        negobs_rig_t rig_cam;
        negobs_ground_plane_t truth;
        negobs_ground_pose_t tp;
        int32_t v;
        synth_flat(&s, heights[i], pitches[i]);
        s.noise_px = 0.05;
        s.seed = (uint32_t)i + 70u;
        fit_scene(&s, &o);
        assert_int_equal(o.ok, 1);
        negobs_rig_default(&rig_cam, RIG_W, RIG_H);
        tp.height_mm = (int32_t)(heights[i] * 1000.0 + 0.5);
        tp.pitch_mdeg = (int32_t)(pitches[i] * 1000.0 + 0.5);
        tp.roll_mdeg = 0;
        assert_int_equal(negobs_ground_plane_from_pose(&rig_cam, &tp, &truth),
                         NEGOBS_OK);
        /* from the bottom row up to the horizon's neighbourhood: the model
         * at the strip centre, in 1/256 px (q20 >> 12) */
        for (v = RIG_H - 1; v >= 0; v -= 8) {
            int64_t m = (int64_t)o.plane.a_q20 * (RIG_W / 2) +
                        (int64_t)o.plane.b_q20 * v + o.plane.c_q20;
            int64_t t = (int64_t)truth.a_q20 * (RIG_W / 2) +
                        (int64_t)truth.b_q20 * v + truth.c_q20;
            int32_t e;
            if (t < ((int64_t)2 << 20)) {
                break; /* beyond about 5 m: past every range read */
            }
            e = (int32_t)((m - t) / 4096);
            if (e < 0) {
                e = -e;
            }
            worst = (e > worst) ? e : worst;
        }
        assert_true(abs(o.pose.pitch_mdeg - tp.pitch_mdeg) <= 150);
        assert_true(abs(o.pose.height_mm - tp.height_mm) <= 8);
    }
    print_message("clean flat maps: plane within %d/256 px of the truth\n",
                  worst);
    /* a quarter of a q4 step */
    assert_true(worst <= 4);
}

static void test_ground_fit_ignores_drop_beyond_fit_rows(void **state)
{
    synth_scene_t s;
    gfit_out_t o;
    (void)state;
    synth_flat(&s, 1.2, 20.0);
    s.noise_px = 0.25;
    synth_step(&s, 1.9, -0.3);
    fit_scene(&s, &o);
    assert_int_equal(o.ok, 1);
    assert_true(abs(o.pose.height_mm - 1200) <= 40);
    assert_true(abs(o.pose.pitch_mdeg - 20000) <= 800);
}

/* A drop whose edge lies inside the fit rows (1.3-1.8 m on this rig): the
 * lower surface beyond it reads below the ground on every row past the
 * edge, and the matcher's window smears the edge over a few rows. In the
 * least squares of the nearer rows a few such rows at the top end of the
 * lever tilted the plane (a 15 cm curb at 1.42 m on the 6 cm
 * rig: 1085 mm / 14.8 deg for 1219 mm / 20.7 deg, and every range read 15-19
 * % too far); the fit now ends at the edge (ground_top). */
static void test_ground_fit_stops_at_an_edge_inside_the_fit_rows(void **state)
{
    /* the 6 cm rig, 5 rows of smear */
    static const double edges[] = {1.42, 1.50, 1.60, 1.70, 1.45, 1.55};
    static const double drops[] = {0.15, 0.15, 0.10, 0.15, 0.10, 0.30};
    negobs_rig_t c6;
    negobs_ground_pose_t tp = {1200, 20000, 0};
    negobs_ground_plane_t truth;
    negobs_ground_pose_t tpb;
    negobs_ground_frame_t tf;
    int i;
    int32_t worst = 0;
    (void)state;
    negobs_rig_default(&c6, RIG_W, RIG_H);
    c6.baseline_um = 60000;
    assert_int_equal(negobs_ground_plane_from_pose(&c6, &tp, &truth),
                     NEGOBS_OK);
    assert_int_equal(negobs_ground_pose_from_plane(&c6, &truth, &tpb, &tf),
                     NEGOBS_OK);
    for (i = 0; i < 6; i++) {
        synth_scene_t s;
        gfit_out_t o;
        int32_t v = RIG_H - 1;
        int32_t d_t;
        int32_t d_m;
        int32_t r_t = 0;
        int32_t r_m = 0;
        int32_t e_pm;
        synth_flat(&s, 1.2, 20.0);
        s.noise_px = 0.15;
        s.seed = (uint32_t)i + 90u;
        synth_step(&s, edges[i], -drops[i]);
        fit_scene_rig(&s, 60000, 5, &o);
        assert_int_equal(o.ok, 1);
        /* the edge's row at the centre column: where its range is read */
        while (v > 0 &&
               (double)tp.height_mm / 1000.0 /
                       tan((tp.pitch_mdeg / 1000.0 +
                            atan((v - 119.5) / 250.0) * 180.0 / TEST_PI) *
                           TEST_PI / 180.0) <
                   edges[i]) {
            v--;
        }
        /* the floor distance the detector reads there (det_model_point) */
        d_m = negobs_ground_disp_q4(&o.plane, RIG_W / 2, v);
        negobs_ground_floor_point(&c6, &o.frame, (RIG_W / 2) * 16, v * 16,
                                  negobs_depth_mm_from_disp_q4(&c6, d_m), &r_m,
                                  NULL);
        d_t = negobs_ground_disp_q4(&truth, RIG_W / 2, v);
        negobs_ground_floor_point(&c6, &tf, (RIG_W / 2) * 16, v * 16,
                                  negobs_depth_mm_from_disp_q4(&c6, d_t), &r_t,
                                  NULL);
        e_pm = abs(r_m - r_t) * 1000 / r_t;
        print_message("  edge %.2f m (row %d), drop %.2f m: %d mm, %d mdeg; "
                      "range there %d mm for %d (%d permille)\n",
                      edges[i], v, drops[i], o.pose.height_mm,
                      o.pose.pitch_mdeg, r_m, r_t, e_pm);
        worst = (e_pm > worst) ? e_pm : worst;
    }
    /* within the 5 % the issue allows for the median range error */
    assert_true(worst <= 30);
}

/* Priors, not hints: a floor is accepted wherever a worn camera can be
 * (0.6-2.0 m, 0-60 deg down, |roll| <= 20 deg), whatever cam_height_mm and
 * cam_pitch_mdeg say, and rejected only outside them. With the old
 * tolerance box around the hint (1.2 +- 0.3 m, 20 +- 15 deg, roll 12) the
 * accepted poses below were GROUND_REJECTED. */
static void test_ground_fit_accepts_any_physical_mounting(void **state)
{
    /* the last three: roll near the prior's 20 deg, where a low camera's
     * floor spreads over 17 px of disparity along a row */
    static const double hs[] = {0.65, 0.8, 1.6, 1.95, 1.2,
                                1.0,  1.9, 1.2, 0.7,  0.7};
    static const double ps[] = {8.0,  45.0, 10.0, 35.0, 55.0,
                                20.0, 2.0,  20.0, 10.0, 40.0};
    static const double rs[] = {0.0,  5.0, -3.0, 0.0,  0.0,
                                16.0, 0.0, 19.0, 19.0, -19.0};
    int i;
    (void)state;
    for (i = 0; i < 10; i++) {
        synth_scene_t s;
        gfit_out_t o;
        synth_flat(&s, hs[i], ps[i]);
        s.roll_deg = rs[i];
        s.noise_px = 0.25;
        s.seed = (uint32_t)i + 70u;
        fit_scene(&s, &o);
        print_message("H %.2f m pitch %.0f roll %.0f: ok %d, %d mm %d mdeg "
                      "roll %d\n",
                      hs[i], ps[i], rs[i], o.ok, (int)o.pose.height_mm,
                      (int)o.pose.pitch_mdeg, (int)o.pose.roll_mdeg);
        assert_int_equal(o.ok, 1);
        assert_true(abs(o.pose.height_mm - (int)(hs[i] * 1000)) <=
                    (int)(hs[i] * 40));
        assert_true(abs(o.pose.pitch_mdeg - (int)(ps[i] * 1000)) <= 800);
        assert_true(abs(o.pose.roll_mdeg - (int)(rs[i] * 1000)) <= 800);
    }
}

static void test_ground_fit_rejects_what_cannot_be_a_floor(void **state)
{
    synth_scene_t s;
    gfit_out_t o;
    (void)state;
    synth_flat(&s, 1.2, 66.0); /* prior: at most 60 deg down */
    s.noise_px = 0.25;
    fit_scene(&s, &o);
    assert_int_equal(o.ok, 0);
    assert_true(o.reasons & NEGOBS_DEGRADED_GROUND_REJECTED);
    synth_flat(&s, 2.5, 20.0); /* prior: at most 2.0 m */
    s.noise_px = 0.25;
    fit_scene(&s, &o);
    assert_int_equal(o.ok, 0);
    synth_flat(&s, 1.2, 20.0);
    s.roll_deg = 26.0; /* prior: |roll| <= 20 */
    fit_scene(&s, &o);
    assert_int_equal(o.ok, 0);
    /* Mostly invalid: too few ground pixels. */
    synth_flat(&s, 1.2, 20.0);
    s.dropout = 0.9;
    fit_scene(&s, &o);
    assert_int_equal(o.ok, 0);
    assert_true(o.reasons & NEGOBS_DEGRADED_FEW_GROUND);
}

/* Where the fit looks: the floor is found wherever the mounting priors let
 * it lie, not only where the bottom rows of the image happen to show it
 * (docs/DETECTION.md section 4, "Where the fit looks"). The maps are
 * rendered, then edited: a near object beyond the matcher's search range
 * leaves its pixels unmatched, save for a few chance matches at random
 * disparities. */
static uint32_t edit_rng = 1u;

static int32_t edit_rand(int32_t n)
{
    edit_rng = edit_rng * 1103515245u + 12345u;
    return (int32_t)((edit_rng >> 8) % (uint32_t)n);
}

/* Columns [u0, u1) of rows [v0, RIG_H) covered by an object too near to
 * match: invalid, but chance_pct % of the pixels carry a random disparity
 * of the 64 px search range. */
static void cover_near(int16_t *d, int32_t u0, int32_t u1, int32_t v0,
                       int32_t chance_pct)
{
    int32_t u;
    int32_t v;
    for (v = v0; v < RIG_H; v++) {
        for (u = u0; u < u1; u++) {
            d[v * RIG_W + u] = (int16_t)((edit_rand(100) < chance_pct)
                                             ? edit_rand(64 * 16)
                                             : NEGOBS_DISP_INVALID);
        }
    }
}

typedef void (*map_edit_fn)(int16_t *d);

/* fit_scene with the rendered map edited before the fit. */
static void fit_scene_edit(const synth_scene_t *s, map_edit_fn edit,
                           gfit_out_t *out)
{
    static int16_t d[RIG_W * RIG_H];
    static uint8_t mem[128 * 1024] __attribute__((aligned(16)));
    static negobs_detect_config_t cfg;
    negobs_image_s16_t img = {d, RIG_W, RIG_H, RIG_W};
    negobs_arena_t ar;
    gfit_t g;
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    negobs_arena_init(&ar, mem, sizeof mem);
    assert_int_equal(gfit_carve(&g, &ar, &cfg), NEGOBS_OK);
    synth_render(s, &cfg.rig, d, RIG_W);
    edit(d);
    gfit_process(&g, &img, NULL, NULL, NULL, out);
}

/* Two hands, 0.35-0.5 m away, over the outer columns of the bottom 90
 * rows (the whole bottom band); the floor between them is weakly matched
 * (45 % dropout). Over the whole band only 22 % of the samples are
 * valid, and the old fit said FEW_GROUND; the strips between the hands
 * hold 55 % and span over a quarter of the width: the floor is fitted. */
static void edit_hands(int16_t *d)
{
    cover_near(d, 0, 112, 150, 8);
    cover_near(d, 208, RIG_W, 150, 8);
}

static void test_ground_fit_finds_the_floor_between_near_hands(void **state)
{
    static const double hs[] = {1.6, 1.75, 1.45};
    static const double ps[] = {35.0, 40.0, 28.0};
    static const double rs[] = {0.0, -6.0, 4.0};
    int i;
    (void)state;
    for (i = 0; i < 3; i++) {
        synth_scene_t s;
        gfit_out_t o;
        synth_flat(&s, hs[i], ps[i]);
        s.roll_deg = rs[i];
        s.noise_px = 0.25;
        s.dropout = 0.45;
        s.seed = (uint32_t)i + 300u;
        edit_rng = (uint32_t)i + 1u;
        fit_scene_edit(&s, edit_hands, &o);
        print_message("hands, H %.2f m pitch %.0f roll %.0f: ok %d "
                      "(valid %d permille, support %d), %d mm %d mdeg roll "
                      "%d\n",
                      hs[i], ps[i], rs[i], o.ok, (int)o.valid_permille,
                      (int)o.support_permille, (int)o.pose.height_mm,
                      (int)o.pose.pitch_mdeg, (int)o.pose.roll_mdeg);
        assert_true(o.valid_permille < 250); /* the old gate's FEW_GROUND */
        assert_int_equal(o.ok, 1);
        assert_true(abs(o.pose.height_mm - (int)(hs[i] * 1000)) <=
                    (int)(hs[i] * 40));
        assert_true(abs(o.pose.pitch_mdeg - (int)(ps[i] * 1000)) <= 800);
        assert_true(abs(o.pose.roll_mdeg - (int)(rs[i] * 1000)) <= 1500);
    }
}

/* An object across the whole width of the bottom band (a bag, a table's
 * edge held in front of the camera): the floor shows only in the rows
 * above it. The old fit, bound to the bottom band, said FEW_GROUND; the
 * wide band finds the floor there. */
static void edit_bottom_band(int16_t *d)
{
    cover_near(d, 0, RIG_W, 176, 5);
}

static void test_ground_fit_looks_above_a_covered_bottom_band(void **state)
{
    static const double hs[] = {1.2, 1.6, 0.9};
    static const double ps[] = {20.0, 30.0, 12.0};
    int i;
    (void)state;
    for (i = 0; i < 3; i++) {
        synth_scene_t s;
        gfit_out_t o;
        synth_flat(&s, hs[i], ps[i]);
        s.noise_px = 0.25;
        s.seed = (uint32_t)i + 310u;
        edit_rng = (uint32_t)i + 11u;
        fit_scene_edit(&s, edit_bottom_band, &o);
        print_message("bottom band covered, H %.2f m pitch %.0f: ok %d wide "
                      "%d, %d mm %d mdeg\n",
                      hs[i], ps[i], o.ok, (int)o.wide, (int)o.pose.height_mm,
                      (int)o.pose.pitch_mdeg);
        assert_int_equal(o.ok, 1);
        assert_int_equal(o.wide, 1);
        assert_true(abs(o.pose.height_mm - (int)(hs[i] * 1000)) <=
                    (int)(hs[i] * 40));
        assert_true(abs(o.pose.pitch_mdeg - (int)(ps[i] * 1000)) <= 800);
    }
}

/* A cupboard front 1.3 m ahead over the left 60 % of the bottom band
 * (disparity f B / Z constant down its face, the matcher's noise on it),
 * the floor beside it: the fit must be the floor's, not a plane bent
 * toward the front. */
static void edit_front(int16_t *d)
{
    int32_t u;
    int32_t v;
    for (v = 150; v < RIG_H; v++) {
        for (u = 0; u < 192; u++) {
            d[v * RIG_W + u] = (int16_t)(250 * 120 * 16 / 1300 + edit_rand(9) -
                                         4);
        }
    }
}

static void test_ground_fit_ignores_a_front_in_the_bottom_band(void **state)
{
    synth_scene_t s;
    gfit_out_t o;
    (void)state;
    synth_flat(&s, 1.2, 20.0);
    s.noise_px = 0.25;
    s.seed = 320u;
    edit_rng = 21u;
    fit_scene_edit(&s, edit_front, &o);
    print_message("front: ok %d, %d mm %d mdeg roll %d\n", o.ok,
                  (int)o.pose.height_mm, (int)o.pose.pitch_mdeg,
                  (int)o.pose.roll_mdeg);
    assert_int_equal(o.ok, 1);
    assert_true(abs(o.pose.height_mm - 1200) <= 48);
    assert_true(abs(o.pose.pitch_mdeg - 20000) <= 800);
    assert_true(abs(o.pose.roll_mdeg) <= 800);
}

/* The danger of a fit that looks anywhere: the near floor is textureless
 * (unmatched over the whole bottom band) and a 15 cm drop lies under it;
 * only the lower surface beyond is matched, so the wide band fits the
 * lower floor (a camera 15 cm higher). That fit may be reported, but the
 * frame must never vouch past the drop: unmatched rows that may be floor
 * stay unseen floor, and the walk starts at the bottom row. */
static void test_ground_fit_anywhere_never_vouches_past_a_hidden_drop(
    void **state)
{
    /* the last: a 45 deg camera, whose plane at the bottom row lies
     * within mount_verify_near_mm of the feet; a wide-band fit must not
     * verify the start by it (the floor it rests on is the lower one) */
    static const double edges[] = {1.3, 1.6, 1.9, 0.8};
    static const double pitches[] = {20.0, 20.0, 20.0, 45.0};
    rig_t *r = malloc(sizeof *r);
    int i;
    int k;
    (void)state;
    assert_non_null(r);
    for (i = 0; i < 4; i++) {
        rig_setup(r, NULL);
        for (k = 0; k < 6; k++) {
            synth_scene_t s;
            synth_flat(&s, 1.2, pitches[i]);
            s.noise_px = 0.15;
            s.seed = (uint32_t)(i * 10 + k) + 330u;
            synth_step(&s, edges[i], -0.15);
            s.inv_u0 = 0;
            s.inv_u1 = RIG_W;
            s.inv_v0 = (i == 3) ? 165 : 176;
            s.inv_v1 = RIG_H;
            assert_int_equal(rig_frame(r, &s), NEGOBS_OK);
            print_message("drop at %.1f m under a textureless near floor "
                          "(pitch %.0f): state %d, clear_to %d mm, ground "
                          "%d, %d mm, reasons %u\n",
                          edges[i], pitches[i], (int)r->res.state,
                          r->res.clear_to_mm, (int)r->res.ground_valid,
                          (int)r->res.pose.height_mm, r->res.reasons);
            assert_true(r->res.state != NEGOBS_DETECT_CLEAR);
            assert_true(r->res.clear_to_mm * 10 <= (int)(edges[i] * 11000));
            if (r->res.ground_valid) {
                assert_true((r->res.reasons &
                             NEGOBS_DEGRADED_GROUND_UNVERIFIED) != 0u);
            }
        }
        rig_teardown(r);
    }
    free(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ground_pose_plane_round_trip),
        cmocka_unit_test(test_ground_plane_matches_analytic_disparity),
        cmocka_unit_test(test_ground_floor_distance_of_ground_pixels),
        cmocka_unit_test(test_ground_plane_from_pose_rejects_bad_input),
        cmocka_unit_test(test_ground_fit_recovers_pose_with_noise_and_roll),
        cmocka_unit_test(test_ground_fit_is_unbiased_on_a_clean_flat_map),
        cmocka_unit_test(test_ground_fit_ignores_drop_beyond_fit_rows),
        cmocka_unit_test(test_ground_fit_stops_at_an_edge_inside_the_fit_rows),
        cmocka_unit_test(test_ground_fit_accepts_any_physical_mounting),
        cmocka_unit_test(test_ground_fit_rejects_what_cannot_be_a_floor),
        cmocka_unit_test(test_ground_fit_finds_the_floor_between_near_hands),
        cmocka_unit_test(test_ground_fit_looks_above_a_covered_bottom_band),
        cmocka_unit_test(test_ground_fit_ignores_a_front_in_the_bottom_band),
        cmocka_unit_test(
            test_ground_fit_anywhere_never_vouches_past_a_hidden_drop),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
