/*
 * The vouched range (clear_to_mm, short_sight) on analytic synthetic maps
 * (tests/support/scene_disp.h): rig of the project targets (H = 1.2 m, pitch
 * 20 deg, f = 250 px at 320x240, B = 120 mm), noise sigma 0.25 px unless
 * stated. Definitions: docs/DETECTION.md, "Verdicts and the vouched range".
 */
#include <math.h>

#include "cmocka_all.h"
#include "scene_util.h"
#include "test_rng.h"
#include "detect/detect_int.h"
#include "detect/detect_internal.h"

static rig_t rig;

static void scene(synth_scene_t *s, double noise, uint32_t seed)
{
    synth_flat(s, 1.2, 20.0);
    s->noise_px = noise;
    s->seed = seed;
}

/* Image row of the level floor at forward distance d_m (the scene's true
 * geometry, roll 0). */
static int32_t floor_row(const synth_scene_t *s, double d_m)
{
    const double d2r = 3.14159265358979323846 / 180.0;
    double f = rig.cfg.rig.focal_q4 / 16.0;
    double cy = rig.cfg.rig.cy_q4 / 16.0;
    return (int32_t)lround(cy +
                           f * tan(atan(s->h_m / d_m) - s->pitch_deg * d2r));
}

/* Forward floor distance (m) seen by image row v (the scene's geometry). */
static double row_floor_m(const synth_scene_t *s, int32_t v)
{
    const double d2r = 3.14159265358979323846 / 180.0;
    double f = rig.cfg.rig.focal_q4 / 16.0;
    double cy = rig.cfg.rig.cy_q4 / 16.0;
    return s->h_m / tan(s->pitch_deg * d2r + atan((v - cy) / f));
}

/* A 10 cm drop crossed at 30 deg whose corridor part begins at 4.4 m:
 * in most strips its lower surface lies past the scan's end (5 m), so no
 * deficit row shows and nothing past it is vouched. The vouched range
 * stops where a minimum drop's lower surface would still be in the scan,
 * range_max * H / (H + h), and the frame stays CLEAR (at least the
 * warning range). The clean floor shows the same limit. */
static void test_vouch_stops_where_a_drop_would_hide_past_the_scan(
    void **state)
{
    synth_scene_t s;
    int i;
    const int32_t lim = (5000 * 1200) / (1200 + 100);
    (void)state;
    rig_setup(&rig, NULL);
    for (i = 0; i < 3; i++) {
        scene(&s, 0.1, (uint32_t)i + 21u);
        if (i > 0) {
            s.yaw_deg = 30.0;
            /* perpendicular distance of the edge line: its corridor part
             * (+-0.6 m) begins at (d - 0.3) / cos 30 = 4.4 m */
            synth_step(&s, 4.4 * 0.8660254 + 0.3, -0.10);
        }
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        print_message("%s: state %d, clear_to %d mm, candidates %u\n",
                      (i == 0) ? "flat" : "10 cm at 4.4 m, yaw 30",
                      (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.n_candidates);
        assert_true(rig.res.clear_to_mm <= lim);
        assert_true(rig.res.clear_to_mm <= (int32_t)(1.1 * 4400.0));
        if (i == 0) {
            assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
            assert_true(rig.res.clear_to_mm >= lim - 200);
        }
    }
    rig_teardown(&rig);
}

/* A 15 cm drop approached at 1.2 m/s is confirmed; then one frame reads
 * it 18 % too far (as a ground model tilted by the drop itself did in the
 * suite at 1.4-1.6 m). clear_to_mm must not follow that sighting past the
 * drop: the track's own approach predicts the edge at 2.28 m, and the
 * frame vouches no farther than the nearer of the two. */
static void test_vouch_hazard_bound_by_its_track(void **state)
{
    synth_scene_t s;
    int i;
    (void)state;
    rig_setup(&rig, NULL);
    for (i = 0; i <= 6; i++) {
        double edge = 3.0 - 0.12 * i;
        scene(&s, 0.1, (uint32_t)i + 31u);
        synth_step(&s, (i < 6) ? edge : edge * 1.18, -0.15);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        print_message("frame %d: edge %.2f m, state %d, hazards %u (%d mm), "
                      "clear_to %d mm\n",
                      i, edge, (int)rig.res.state, rig.res.n_hazards,
                      rig.res.n_hazards ? rig.res.hazards[0].range_mm : -1,
                      rig.res.clear_to_mm);
        if (i >= 3) {
            assert_int_equal(rig.res.state, NEGOBS_DETECT_HAZARD);
        }
        assert_true(rig.res.clear_to_mm <= (int32_t)(1.1 * edge * 1000.0));
    }
    rig_teardown(&rig);
}

/* A camera told 1.5 m that sits at 1.2 m cannot verify the ground under
 * the feet (GROUND_UNVERIFIED, NO_INFO: it could be a lower floor beyond an
 * edge at or below the view's bottom rows, where the rule cannot see it).
 * It vouches nothing (clear_to_mm 0), but the floor in view is measured as
 * on any frame: noise_vouch_mm reports how far it would vouch. */
static void test_vouch_unverified_start_reports_the_floor_in_view(void **state)
{
    synth_scene_t s;
    negobs_detect_config_t c;
    int i;
    (void)state;
    negobs_detect_config_default(&c, RIG_W, RIG_H);
    c.cam_height_mm = 1500;
    rig_setup(&rig, &c);
    for (i = 0; i < 3; i++) {
        scene(&s, 0.1, (uint32_t)i + 41u);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        print_message("frame %d: state %d, reasons %u, clear_to %d mm\n", i,
                      (int)rig.res.state, rig.res.reasons,
                      rig.res.clear_to_mm);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
        assert_int_equal(rig.res.reasons, NEGOBS_DEGRADED_GROUND_UNVERIFIED);
        assert_int_equal(rig.res.clear_to_mm, 0);
        assert_true(rig.res.noise_vouch_mm >= 4000);
    }
    rig_teardown(&rig);
}

/* A textureless patch across the corridor at 2.4-2.8 m (no disparity
 * there) is unknown there: it limits clear_to_mm to the floor before it,
 * it does not make the frame NO_INFO. The same patch beside the corridor
 * changes nothing. */
static void test_vouch_textureless_patch_limits_the_range(void **state)
{
    synth_scene_t s;
    int i;
    (void)state;
    rig_setup(&rig, NULL);
    for (i = 0; i < 3; i++) {
        scene(&s, 0.25, (uint32_t)i + 1u);
        s.inv_u0 = 0;
        s.inv_u1 = RIG_W;
        s.inv_v0 = floor_row(&s, 2.8);
        s.inv_v1 = floor_row(&s, 2.4);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        print_message("patch rows %d-%d: state %d, clear_to %d mm, short "
                      "sight %d, reasons %u\n",
                      s.inv_v0, s.inv_v1, (int)rig.res.state,
                      rig.res.clear_to_mm, rig.res.short_sight,
                      rig.res.reasons);
        assert_int_equal(rig.res.reasons, 0);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
        assert_int_equal(rig.res.short_sight, 1);
        assert_true(rig.res.clear_to_mm >= rig.cfg.near_min_mm);
        assert_true(rig.res.clear_to_mm <= 2400 + 2400 / 20);
    }
    for (i = 0; i < 3; i++) {
        scene(&s, 0.25, (uint32_t)i + 11u);
        s.inv_u0 = 0;
        s.inv_u1 = 40; /* far left: outside the 1.2 m corridor there */
        s.inv_v0 = floor_row(&s, 2.8);
        s.inv_v1 = floor_row(&s, 2.4);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
        assert_int_equal(rig.res.short_sight, 0);
        assert_true(rig.res.clear_to_mm >= rig.cfg.range_warn_mm);
    }
    rig_teardown(&rig);
}

/* Two strips of clean floor (0.1 px of independent noise) whose matches
 * read 0.25 px above the model from 1.5 m to the bottom row, as a painted
 * patch or a stain can on a real matcher: a minimum drop there (0.66-0.79
 * px of deficit) still stands out of that cell's noise and offset (3 x
 * 0.03 + 0.25 px), so the floor is vouched and the frame is CLEAR.
 * Measured about the band's median, the cells' spread also carried their
 * offset, which then counted 4.8 times (3 x 1.25 + 1, about 1.1 px): the
 * walk stopped at the bottom row, inside the fit rows, and the frame was
 * NO_INFO with clear_to_mm 0. The same offset at 1 px stays unvouched. */
static void test_vouch_local_offset_is_counted_once(void **state)
{
    synth_scene_t s;
    int i;
    int k;
    (void)state;
    for (k = 0; k < 2; k++) {
        const int16_t off_q4 = (k == 0) ? 4 : 16; /* 0.25 / 1.0 px */
        for (i = 0; i < 3; i++) {
            int32_t u;
            int32_t v;
            rig_setup(&rig, NULL);
            scene(&s, 0.1, (uint32_t)i + 61u);
            synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
            for (v = floor_row(&s, 1.5); v < RIG_H; v++) {
                for (u = 144; u < 176; u++) {
                    rig.disp[v * RIG_W + u] += off_q4;
                }
            }
            assert_int_equal(rig_run(&rig), NEGOBS_OK);
            print_message("offset %d/16 px: state %d, clear_to %d mm, "
                          "reasons %u, candidates %u\n",
                          off_q4, (int)rig.res.state, rig.res.clear_to_mm,
                          rig.res.reasons, rig.res.n_candidates);
            if (k == 0) {
                assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
                assert_true(rig.res.clear_to_mm >= rig.cfg.range_warn_mm);
            } else {
                assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
                assert_true(rig.res.clear_to_mm < 1500);
            }
            rig_teardown(&rig);
        }
    }
}

/* A camera at 1.38 m / 11 deg, told its mounting: its ground fit's rows
 * (the bottom quarter) see the floor 1.86-3.0 m ahead. Two corridor strips
 * read 0.875 px high at 2.1-2.3 m (a stain the matcher reads off): the
 * walk stops there, in the fit rows, on a row where the other strips and
 * the band as a whole still vouch. The model describes its rows, so the
 * frame is CLEAR with short sight up to the patch; on the old code, noise
 * stopping the walk inside the fit rows made it 0 (NO_INFO). Noise across
 * the width of the fit rows still does
 * (test_vouch_noisy_near_field_is_no_info). */
static void test_vouch_local_patch_in_the_fit_rows_ends_the_walk_there(
    void **state)
{
    synth_scene_t s;
    negobs_detect_config_t cfg;
    int i;
    (void)state;
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    cfg.cam_height_mm = 1380;
    cfg.cam_pitch_mdeg = 11000;
    for (i = 0; i < 3; i++) {
        int32_t u;
        int32_t v;
        rig_setup(&rig, &cfg);
        synth_flat(&s, 1.38, 11.0);
        s.noise_px = 0.1;
        s.seed = (uint32_t)i + 71u;
        synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
        for (v = floor_row(&s, 2.3); v <= floor_row(&s, 2.1); v++) {
            for (u = 144; u < 176; u++) {
                rig.disp[v * RIG_W + u] += 14;
            }
        }
        assert_int_equal(rig_run(&rig), NEGOBS_OK);
        print_message("patch rows %d-%d: state %d, clear_to %d mm, "
                      "short sight %d, reasons %u, candidates %u\n",
                      floor_row(&s, 2.3), floor_row(&s, 2.1),
                      (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.short_sight, rig.res.reasons,
                      rig.res.n_candidates);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
        assert_int_equal(rig.res.short_sight, 1);
        assert_true(rig.res.clear_to_mm >= rig.cfg.near_min_mm);
        assert_true(rig.res.clear_to_mm <= 2100 + 2100 / 10);
        rig_teardown(&rig);
    }
}

/* A 20 cm drop at 2.2 m while the far field is too noisy to vouch for the
 * warning range (sigma 0.25 px at 1 m growing to 1.2 px at 5 m): the
 * drop's own strips pass the local check, so it confirms and is reported
 * (the frame-wide NOISY this replaces made every such frame NO_INFO, and
 * its candidates could never start a track). */
static void test_vouch_drop_in_clean_strips_despite_far_noise(void **state)
{
    synth_scene_t s;
    int i;
    int hazard_at = -1;
    (void)state;
    rig_setup(&rig, NULL);
    /* the far field alone: short sight */
    scene(&s, 0.25, 5u);
    s.noise_far_px = 1.2;
    assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
    assert_int_equal(rig.res.short_sight, 1);
    rig_teardown(&rig);

    rig_setup(&rig, NULL);
    for (i = 0; i < 6; i++) {
        scene(&s, 0.25, (uint32_t)i + 21u);
        s.noise_far_px = 1.2;
        synth_step(&s, 2.2, -0.20);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        print_message("frame %d: state %d, clear_to %d, candidates %u, "
                      "hazards %u, reasons %u\n",
                      i, (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.n_candidates, rig.res.n_hazards,
                      rig.res.reasons);
        {
            uint32_t k;
            for (k = 0; k < rig.res.n_candidates; k++) {
                print_message("  cand %d mm flags %u type %d\n",
                              rig.res.candidates[k].range_mm,
                              rig.res.candidates[k].flags,
                              (int)rig.res.candidates[k].type);
            }
            for (k = 0; k < rig.res.n_hazards; k++) {
                print_message("  haz %d mm flags %u\n",
                              rig.res.hazards[k].range_mm,
                              rig.res.hazards[k].flags);
            }
        }
        assert_true(rig.res.state != NEGOBS_DETECT_CLEAR ||
                    rig.res.clear_to_mm <= 2200 + 2200 / 10);
        if (rig.res.state == NEGOBS_DETECT_HAZARD && hazard_at < 0) {
            hazard_at = i;
        }
        if (rig.res.state == NEGOBS_DETECT_HAZARD) {
            assert_true(rig.res.clear_to_mm <= rig.res.nearest_range_mm ||
                        rig.res.nearest_range_mm < 0);
            assert_true(rig.res.clear_to_mm <= rig.res.hazards[0].range_mm);
        }
    }
    /* confirmed by the third or fourth frame (3 of 5; the first frame's
     * two candidates start two tracks) */
    assert_true(hazard_at >= 2 && hazard_at <= 3);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_HAZARD);
    rig_teardown(&rig);
}

/* Grey 128 plus uniform noise of +-amp (amp 0: flat) on a w x h image. */
static void grey_noise(uint8_t *px, int w, int h, int amp, uint32_t seed)
{
    int i;
    for (i = 0; i < w * h; i++) {
        uint32_t r = test_lcg_next(&seed);
        px[i] = (uint8_t)(128 + (amp > 0 ? (int)((r >> 8) %
                                                 (uint32_t)(2 * amp + 1)) -
                                               amp
                                         : 0));
    }
}

static int16_t half_map[(RIG_W / 2) * (RIG_H / 2)];

/* Frames of a 20 cm drop at 2.2 m with the given left images; returns the
 * first frame with a confirmed hazard, -1 for none. With `halved`, the map
 * is what a half-resolution pass supplies (pipeline/coarse.c): each 2x2
 * block carries its top-left value rounded to an even 1/16 px, and
 * half_map holds those values halved; else half_map is offset by one
 * pixel, so no full-size value is a half-size one. */
static int drop_frames_with_left(const negobs_image_u8_t *left,
                                 const negobs_image_u8_t *left_half,
                                 int halved)
{
    static const negobs_image_s16_t hm = {half_map, RIG_W / 2, RIG_H / 2,
                                          RIG_W / 2};
    synth_scene_t s;
    int i;
    int hazard_at = -1;
    rig.frame.left = left;
    rig.frame.left_half = left_half;
    rig.frame.disp_half_q4 = (left_half != NULL) ? &hm : NULL;
    for (i = 0; i < 6; i++) {
        int x;
        int y;
        scene(&s, 0.25, (uint32_t)i + 21u);
        synth_step(&s, 2.2, -0.20);
        synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
        for (y = 0; y < RIG_H; y++) {
            for (x = 0; x < RIG_W; x++) {
                int16_t d = rig.disp[(y & ~1) * RIG_W + (x & ~1)];
                int16_t h = d;
                int16_t full = d;
                if (d != NEGOBS_DISP_INVALID) {
                    h = (int16_t)(d / 2);
                    full = (int16_t)(2 * h);
                }
                if (halved) {
                    rig.disp[y * RIG_W + x] = full;
                }
                half_map[(y / 2) * (RIG_W / 2) + x / 2] = h;
                if (!halved && h != NEGOBS_DISP_INVALID) {
                    half_map[(y / 2) * (RIG_W / 2) + x / 2] = (int16_t)(h + 8);
                }
            }
        }
        assert_int_equal(rig_run(&rig), NEGOBS_OK);
        if (rig.res.state == NEGOBS_DETECT_HAZARD && hazard_at < 0) {
            hazard_at = i;
        }
    }
    return hazard_at;
}

/* Texture under a candidate at the scale the map was measured at: a left
 * image with nothing but noise fails the box test, so the drop's candidate
 * cannot start a track. The same frames whose map came from a
 * half-resolution pass over a textured half-size image pass it at that
 * scale; with the full-size matcher's values in the box they do not. A
 * half-size image of the wrong size is a malformed frame. */
static void test_vouch_texture_at_the_half_scale(void **state)
{
    static uint8_t full[RIG_W * RIG_H];
    static uint8_t half[(RIG_W / 2) * (RIG_H / 2)];
    negobs_image_u8_t left = {full, RIG_W, RIG_H, RIG_W};
    negobs_image_u8_t left_half = {half, RIG_W / 2, RIG_H / 2, RIG_W / 2};
    negobs_image_u8_t wrong = {half, RIG_W / 2, RIG_H / 2 - 1, RIG_W / 2};
    (void)state;
    grey_noise(full, RIG_W, RIG_H, 6, 7u); /* flat paint: noise only */
    grey_noise(half, RIG_W / 2, RIG_H / 2, 3, 9u);

    rig_setup(&rig, NULL);
    assert_int_equal(drop_frames_with_left(&left, NULL, 1), -1);
    rig_teardown(&rig);

    rig_setup(&rig, NULL);
    assert_int_equal(drop_frames_with_left(&left, &left_half, 1), -1);
    rig_teardown(&rig);

    grey_noise(half, RIG_W / 2, RIG_H / 2, 40, 9u); /* textured at half */
    rig_setup(&rig, NULL);
    assert_in_range(drop_frames_with_left(&left, &left_half, 1), 2, 3);
    rig_teardown(&rig);

    rig_setup(&rig, NULL);
    assert_int_equal(drop_frames_with_left(&left, &left_half, 0), -1);
    rig_teardown(&rig);

    rig_setup(&rig, NULL);
    rig.frame.left = &left;
    rig.frame.left_half = &wrong;
    {
        synth_scene_t s;
        scene(&s, 0.25, 21u);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_ERR_INVAL);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
        assert_true(rig.res.reasons & NEGOBS_DEGRADED_BAD_INPUT);
    }
    rig_teardown(&rig);
}

/* Sensor noise (uniform, +-noise_amp) over a grain that is constant on
 * 4x4 blocks (uniform, +-grain_amp): the second differences of the noise
 * estimate see the grain only at block borders, a 5x5 window's variance
 * sees all of it. */
static void grain_over_noise(uint8_t *px, int grain_amp, int noise_amp,
                             uint32_t seed)
{
    static int8_t grain[(RIG_W / 4 + 1) * (RIG_H / 4 + 1)];
    int x;
    int y;
    for (x = 0; x < (RIG_W / 4 + 1) * (RIG_H / 4 + 1); x++) {
        uint32_t r = test_lcg_next(&seed);
        grain[x] = (int8_t)((int)((r >> 8) % (uint32_t)(2 * grain_amp + 1)) -
                            grain_amp);
    }
    for (y = 0; y < RIG_H; y++) {
        for (x = 0; x < RIG_W; x++) {
            uint32_t r = test_lcg_next(&seed);
            int n = (int)((r >> 8) % (uint32_t)(2 * noise_amp + 1)) -
                    noise_amp;
            px[y * RIG_W + x] =
                (uint8_t)(128 + grain[(y / 4) * (RIG_W / 4 + 1) + x / 4] + n);
        }
    }
}

/* A deep deficit on weak grain (detect.c, cand_textured): the 20 cm drop
 * at 2.2 m (about 1.9 px deep) on a left image of grain +-10 on 4x4
 * blocks under noise of +-6 (the noise estimate reads it as about
 * sigma 4: most 5x5 windows hold 1.5 times that variance, few 4 times)
 * fails the texture test for a signal-to-noise of 3 but passes the weak
 * one, and is confirmed; on noise alone (+-10, flat paint) it still is
 * not. */
static void test_vouch_deep_drop_on_weak_grain(void **state)
{
    static uint8_t full[RIG_W * RIG_H];
    negobs_image_u8_t left = {full, RIG_W, RIG_H, RIG_W};
    int32_t m;
    (void)state;
    grain_over_noise(full, 10, 6, 5u);
    m = det_noise_median(&left);
    assert_false(det_box_textured(&left, m, 40, 40, RIG_W - 40, RIG_H - 40));
    assert_true(
        det_box_weak_textured(&left, m, 40, 40, RIG_W - 40, RIG_H - 40));
    rig_setup(&rig, NULL);
    assert_in_range(drop_frames_with_left(&left, NULL, 1), 2, 3);
    rig_teardown(&rig);

    grain_over_noise(full, 0, 10, 5u);
    rig_setup(&rig, NULL);
    assert_int_equal(drop_frames_with_left(&left, NULL, 1), -1);
    rig_teardown(&rig);
}

/* Frames of a drop of drop_m at 2.2 m under row-correlated matcher noise
 * (strip medians wander by about row_px); returns the first frame with a
 * confirmed hazard, -1 for none. No frame may vouch past the edge. */
static int drop_frames_in_row_noise(double drop_m, double row_px)
{
    synth_scene_t s;
    int i;
    int hazard_at = -1;
    for (i = 0; i < 6; i++) {
        scene(&s, 0.25, (uint32_t)i + 41u);
        s.noise_row_px = row_px;
        s.noise_row_len_px = 48;
        s.noise_row_rows = 4;
        synth_step(&s, 2.2, -drop_m);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        assert_true(rig.res.clear_to_mm <= 2200 + 2200 / 10);
        if (rig.res.state == NEGOBS_DETECT_HAZARD && hazard_at < 0) {
            hazard_at = i;
        }
    }
    return hazard_at;
}

/* The local check with a candidate's own deficit (detect_vouch.c,
 * vouch_own_deficit): in noise of 0.25 px on the strip medians a minimum
 * drop at 2.2 m (0.9 px deep, k = 3) cannot be vouched for, but a 30 cm
 * drop there is 2.4 px deep and stands out, so its candidate may start a
 * track; a 10 cm one in the same noise still may not. */
static void test_vouch_deep_drop_stands_out_of_noise(void **state)
{
    (void)state;
    rig_setup(&rig, NULL);
    assert_in_range(drop_frames_in_row_noise(0.30, 0.25), 2, 4);
    rig_teardown(&rig);
    rig_setup(&rig, NULL);
    assert_int_equal(drop_frames_in_row_noise(0.10, 0.25), -1);
    rig_teardown(&rig);
}

/*
 * No false vouch on walks at 1.2 m/s (10 fps) towards drops: 5 cm drops
 * count while their edge is within 1.5 m, 10 cm drops everywhere, as long
 * as the edge is in view (beyond the floor seen by the bottom row; nearer
 * ones are the hold logic's). A frame whose clear_to_mm exceeds 1.1x the
 * edge's floor distance is a false vouch. Plain noise, noise growing with
 * range, and row-correlated matcher noise.
 */
static int walk_false_vouches(double drop_m, double noise_far,
                              double row_noise, uint32_t seed, int *judged,
                              int *clear_frames)
{
    synth_scene_t s;
    double edge;
    int i;
    int fv = 0;
    rig_setup(&rig, NULL);
    for (i = 0, edge = 5.0; edge > 0.4; i++, edge -= 0.12) {
        double bottom;
        int counts;
        scene(&s, 0.25, seed + (uint32_t)i);
        s.noise_far_px = noise_far;
        if (row_noise > 0.0) {
            s.noise_row_px = row_noise;
            s.noise_row_len_px = 48;
            s.noise_row_rows = 4;
        }
        synth_step(&s, edge, -drop_m);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        bottom = row_floor_m(&s, RIG_H - 1);
        counts = edge > bottom && (drop_m >= 0.099 || edge <= 1.5);
        if (!counts) {
            continue;
        }
        (*judged)++;
        *clear_frames += rig.res.state == NEGOBS_DETECT_CLEAR;
        if (rig.res.clear_to_mm > (int32_t)(1.1 * edge * 1000.0)) {
            print_message("false vouch: %.0f mm drop at %.2f m, state %d, "
                          "clear_to %d mm\n",
                          drop_m * 1000.0, edge, (int)rig.res.state,
                          rig.res.clear_to_mm);
            fv++;
        }
    }
    rig_teardown(&rig);
    return fv;
}

static void test_vouch_no_false_vouch_on_walks(void **state)
{
    static const double drops[] = {0.05, 0.10};
    static const double far[] = {0.0, 0.8, 0.0};
    static const double row[] = {0.0, 0.0, 0.15};
    int di;
    int ni;
    uint32_t seed;
    int total = 0;
    int judged = 0;
    int clear_frames = 0;
    (void)state;
    for (di = 0; di < 2; di++) {
        for (ni = 0; ni < 3; ni++) {
            for (seed = 0; seed < 2; seed++) {
                total += walk_false_vouches(drops[di], far[ni], row[ni],
                                            100u * seed + 7u, &judged,
                                            &clear_frames);
            }
        }
    }
    print_message("false vouches: %d of %d judged frames (%d CLEAR)\n", total,
                  judged, clear_frames);
    assert_true(judged > 100);
    assert_int_equal(total, 0);
}

/* In HAZARD clear_to_mm is at most the nearest hazard's range; in NO_INFO
 * it is still reported, and a gating reason makes it 0. */
static void test_vouch_bounds_by_state(void **state)
{
    synth_scene_t s;
    int i;
    (void)state;
    rig_setup(&rig, NULL);
    for (i = 0; i < 5; i++) {
        scene(&s, 0.25, (uint32_t)i + 31u);
        synth_step(&s, 3.0 - 0.1 * i, -0.25);
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        if (rig.res.state == NEGOBS_DETECT_HAZARD) {
            uint32_t k;
            for (k = 0; k < rig.res.n_hazards; k++) {
                assert_true(rig.res.clear_to_mm <=
                            rig.res.hazards[k].range_mm);
            }
        }
        assert_true(rig.res.clear_to_mm <= (int32_t)((3.0 - 0.1 * i) * 1100));
    }
    assert_int_equal(rig.res.state, NEGOBS_DETECT_HAZARD);
    /* unsynced: NO_INFO, clear_to 0 */
    scene(&s, 0.25, 40u);
    synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
    rig.now_ms += 100;
    rig.frame.t_left_ms = rig.now_ms - 40;
    rig.frame.t_right_ms = rig.now_ms - 10;
    rig.frame.now_ms = rig.now_ms;
    assert_int_equal(negobs_detect_process(&rig.det, &rig.frame, &rig.res),
                     NEGOBS_OK);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
    assert_int_equal(rig.res.clear_to_mm, 0);
    assert_int_equal(rig.res.short_sight, 0);
    rig_teardown(&rig);
    /* the near-zone minimum is a config field with its bounds */
    {
        negobs_detect_config_t cfg;
        size_t bytes = 0;
        negobs_detect_config_default(&cfg, RIG_W, RIG_H);
        assert_int_equal(cfg.near_min_mm, 1500);
        cfg.near_min_mm = -1;
        assert_int_equal(negobs_detect_workspace_size(&cfg, &bytes),
                         NEGOBS_ERR_INVAL);
        cfg.near_min_mm = cfg.range_max_mm + 1;
        assert_int_equal(negobs_detect_workspace_size(&cfg, &bytes),
                         NEGOBS_ERR_INVAL);
    }
}

/* Noise under the feet (the bottom 40 rows, row-correlated 0.6 px) leaves
 * less than the near-zone minimum vouched: NO_INFO with NOISY, and
 * clear_to_mm still reported. The same noise lies in the fit rows, so a
 * frame's fitted height can also stray from the hint by the start check's
 * 50 mm: it is then unverified, which is NO_INFO as well and says so. */
static void test_vouch_noisy_near_field_is_no_info(void **state)
{
    synth_scene_t s;
    int i;
    (void)state;
    rig_setup(&rig, NULL);
    for (i = 0; i < 3; i++) {
        scene(&s, 0.25, (uint32_t)i + 51u);
        s.noise_row_px = 0.6;
        s.noise_row_len_px = 48;
        s.noise_row_rows = 4;
        s.noise_row_v0 = RIG_H - 40;
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
        print_message("near noise: state %d, clear_to %d, reasons %u\n",
                      (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.reasons);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
        assert_true(rig.res.reasons & (NEGOBS_DEGRADED_NOISY |
                                       NEGOBS_DEGRADED_GROUND_UNVERIFIED));
        assert_true(rig.res.clear_to_mm < rig.cfg.near_min_mm);
    }
    rig_teardown(&rig);
}

/* A camera told its true mounting (h_m, pitch) and fed the scene n times
 * (a switch-on: confirmation needs 3 of 5 frames); the last frame stays
 * in rig.res. */
static void run_mounted(const synth_scene_t *s0, int n)
{
    negobs_detect_config_t cfg;
    synth_scene_t s = *s0;
    int i;
    negobs_detect_config_default(&cfg, RIG_W, RIG_H);
    cfg.cam_height_mm = (int32_t)lround(s.h_m * 1000.0);
    cfg.cam_pitch_mdeg = (int32_t)lround(s.pitch_deg * 1000.0);
    rig_setup(&rig, &cfg);
    for (i = 0; i < n; i++) {
        s.seed = s0->seed + (uint32_t)i;
        assert_int_equal(rig_frame(&rig, &s), NEGOBS_OK);
    }
}

/* A wall across the corridor 1.2 m ahead (nearer than the near-zone
 * minimum) on clean floor: every lane is barred at its foot, so the floor
 * up to it is vouched and nothing beyond can be walked into: CLEAR with
 * short sight, clear_to_mm = blocked_at_mm at the wall's foot (within the
 * 10 % range tolerance). NO_INFO before barred lanes. */
static void test_vouch_wall_in_near_zone_is_clear_to_its_foot(void **state)
{
    synth_scene_t s;
    uint32_t seed;
    (void)state;
    for (seed = 1; seed <= 3; seed++) {
        synth_flat(&s, 1.2, 35.0);
        s.noise_px = 0.25;
        s.seed = 10u * seed;
        synth_step(&s, 1.2, 2.5);
        run_mounted(&s, 5);
        print_message("wall at 1.2 m: state %d, clear_to %d, blocked_at %d, "
                      "reasons %u\n",
                      (int)rig.res.state, rig.res.clear_to_mm,
                      rig.res.blocked_at_mm, rig.res.reasons);
        assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
        assert_int_equal(rig.res.short_sight, 1);
        assert_int_equal(rig.res.clear_to_mm, rig.res.blocked_at_mm);
        assert_true(rig.res.blocked_at_mm >= 1000 &&
                    rig.res.blocked_at_mm <= 1200 + 1200 / 10);
        rig_teardown(&rig);
    }
}

/* What a walker steps onto or around does not bar the corridor: a 15 cm
 * up-step and a 35 deg flight of stairs up (17 cm risers) at 1.2 m stay
 * NO_INFO (the floor beyond them is reached), and so does a wall whose
 * foot lies behind a 10 cm drop at 0.95 m: the drop is not vouched past
 * (never CLEAR beyond 1.1 x its distance). A post 0.3 m wide in the
 * middle bars only its own lanes: the floor beside it is walked on and
 * must be vouched, never the post's foot alone. */
static void test_vouch_only_a_tall_face_bars(void **state)
{
    synth_scene_t s;
    int k;
    (void)state;
    synth_flat(&s, 1.2, 35.0);
    s.noise_px = 0.25;
    s.seed = 71u;
    synth_step(&s, 1.2, 0.15);
    run_mounted(&s, 5);
    assert_int_equal(rig.res.blocked_at_mm, 0);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_NO_INFO);
    rig_teardown(&rig);

    synth_flat(&s, 1.2, 35.0);
    s.noise_px = 0.25;
    s.seed = 81u;
    for (k = 0; k < 8; k++) {
        synth_step(&s, 1.2 + 0.24 * k, 0.17 * (k + 1));
    }
    run_mounted(&s, 5);
    print_message("stairs up: state %d, clear_to %d, blocked_at %d\n",
                  (int)rig.res.state, rig.res.clear_to_mm,
                  rig.res.blocked_at_mm);
    assert_int_equal(rig.res.blocked_at_mm, 0);
    assert_true(rig.res.state != NEGOBS_DETECT_CLEAR ||
                rig.res.clear_to_mm >= rig.cfg.near_min_mm);
    rig_teardown(&rig);

    synth_flat(&s, 1.2, 35.0);
    s.noise_px = 0.25;
    s.seed = 91u;
    synth_step(&s, 0.95, -0.10);
    synth_step(&s, 1.3, 2.5);
    run_mounted(&s, 5);
    print_message("drop before a wall: state %d, clear_to %d, blocked_at "
                  "%d\n",
                  (int)rig.res.state, rig.res.clear_to_mm,
                  rig.res.blocked_at_mm);
    assert_true(rig.res.clear_to_mm <= 950 + 950 / 10);
    assert_true(rig.res.state != NEGOBS_DETECT_CLEAR);
    rig_teardown(&rig);

    synth_flat(&s, 1.2, 35.0);
    s.noise_px = 0.25;
    s.seed = 101u;
    synth_step(&s, 1.2, 2.5);
    s.lat_half_m = 0.15;
    run_mounted(&s, 5);
    print_message("post: state %d, clear_to %d, blocked_at %d\n",
                  (int)rig.res.state, rig.res.clear_to_mm,
                  rig.res.blocked_at_mm);
    assert_int_equal(rig.res.blocked_at_mm, 0);
    assert_true(rig.res.state != NEGOBS_DETECT_CLEAR ||
                rig.res.clear_to_mm >= rig.cfg.near_min_mm);
    rig_teardown(&rig);
}

/* A low camera (0.6 m, 20 deg) sees the floor 0.58 m ahead, where the
 * corridor is wider than the image and the ground disparity is 39 px: the
 * right camera cannot see the floor of the left image's first 39 columns
 * there, and no matcher returns anything for them. Those columns are out
 * of the stereo view, like floor outside the image: they do not stop the
 * walk (it used to stop at the bottom row: NO_INFO, clear_to_mm 0). */
static void test_vouch_floor_outside_the_stereo_view_is_not_unseen(
    void **state)
{
    synth_scene_t s;
    int32_t u;
    int32_t v;
    (void)state;
    synth_flat(&s, 0.6, 20.0);
    s.noise_px = 0.2;
    s.seed = 121u;
    run_mounted(&s, 1);
    synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
    for (v = 0; v < RIG_H; v++) {
        for (u = 0; u < RIG_W; u++) {
            int16_t *d = &rig.disp[v * RIG_W + u];
            if (*d != NEGOBS_DISP_INVALID && u * 16 < *d) {
                *d = NEGOBS_DISP_INVALID; /* no right-image pixel */
            }
        }
    }
    assert_int_equal(rig_run(&rig), NEGOBS_OK);
    print_message("low camera: state %d, clear_to %d, reasons %u\n",
                  (int)rig.res.state, rig.res.clear_to_mm, rig.res.reasons);
    assert_true(rig.res.clear_to_mm >= rig.cfg.near_min_mm);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
    rig_teardown(&rig);
}

/* A rectified left image: textured grey levels 40..199 (an LCG; no run of
 * 8 equal neighbours), with the columns u >= W - fill_px set to fill_value
 * (the rectification's constant fill) or, when dark, random levels 0..7
 * (a real dark but textured region). */
static void left_image(uint8_t *px, int32_t fill_px, int fill_value, int dark)
{
    uint32_t st = 77u;
    int32_t u;
    int32_t v;
    for (v = 0; v < RIG_H; v++) {
        for (u = 0; u < RIG_W; u++) {
            uint32_t r = test_lcg_next(&st);
            if (u < RIG_W - fill_px) {
                px[v * RIG_W + u] = (uint8_t)(40u + (r >> 16) % 160u);
            } else {
                px[v * RIG_W + u] = dark ? (uint8_t)((r >> 16) % 8u)
                                         : (uint8_t)fill_value;
            }
        }
    }
}

static uint8_t left_px[RIG_W * RIG_H];
static uint8_t right_px[RIG_W * RIG_H];

/* The right image of left_image: the fill at the first fill_px columns. */
static void right_image(uint8_t *px, int32_t fill_px, int dark)
{
    int32_t u;
    int32_t v;
    left_image(px, fill_px, 0, dark);
    for (v = 0; v < RIG_H; v++) {
        for (u = 0; u < RIG_W / 2; u++) {
            uint8_t t = px[v * RIG_W + u];
            px[v * RIG_W + u] = px[v * RIG_W + RIG_W - 1 - u];
            px[v * RIG_W + RIG_W - 1 - u] = t;
        }
    }
}

/* One frame of the low camera of the stereo-view test (0.6 m, 20 deg: at
 * the bottom row the corridor is wider than the image) with the left
 * image's last fill_px columns and the right image's first fill_px columns
 * unmatched (no disparity where either falls) and fill or dark texture
 * there in the images. Returns the result's clear_to_mm. */
static int32_t low_camera_with_border(const synth_scene_t *s0, int32_t fill_px,
                                      int dark)
{
    synth_scene_t s = *s0;
    negobs_image_u8_t left;
    negobs_image_u8_t right;
    int32_t u;
    int32_t v;
    int i;
    run_mounted(&s, 0);
    left_image(left_px, fill_px, 0, dark);
    left.data = left_px;
    left.width = RIG_W;
    left.height = RIG_H;
    left.stride = RIG_W;
    /* the right image: its first fill_px columns are fill (mirrored) */
    right_image(right_px, fill_px, dark);
    right.data = right_px;
    right.width = RIG_W;
    right.height = RIG_H;
    right.stride = RIG_W;
    rig.frame.left = &left;
    rig.frame.right = &right;
    /* 6 frames: a fill is taken in at most 8 px per frame */
    for (i = 0; i < 6; i++) {
        s.seed = s0->seed + (uint32_t)i;
        synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
        for (v = 0; v < RIG_H; v++) {
            for (u = 0; u < RIG_W; u++) {
                int16_t *d = &rig.disp[v * RIG_W + u];
                if ((*d != NEGOBS_DISP_INVALID && u * 16 < *d) ||
                    u >= RIG_W - fill_px ||
                    (*d != NEGOBS_DISP_INVALID &&
                     u * 16 - *d < fill_px * 16)) {
                    *d = NEGOBS_DISP_INVALID;
                }
            }
        }
        assert_int_equal(rig_run(&rig), NEGOBS_OK);
    }
    rig.frame.left = NULL;
    rig.frame.right = NULL;
    print_message("border %d px (dark %d): state %d, clear_to %d, reasons "
                  "%u\n",
                  fill_px, dark, (int)rig.res.state, rig.res.clear_to_mm,
                  rig.res.reasons);
    return rig.res.clear_to_mm;
}

/* A black rectification fill over the left image's last 40 columns and the
 * right image's first 40, inside the corridor at the bottom rows: out of the camera's view, like floor
 * outside the image, so the verdict is the one without the border (it used
 * to stop the walk at the bottom row: NO_INFO, clear_to_mm 0). A real dark
 * region there, textured under sensor noise, is not fill: unmatched floor
 * in view, which stops the walk. */
static void test_vouch_rectification_fill_is_out_of_view(void **state)
{
    synth_scene_t s;
    int32_t ref;
    int32_t with_fill;
    (void)state;
    synth_flat(&s, 0.6, 20.0);
    s.noise_px = 0.2;
    s.seed = 121u;
    ref = low_camera_with_border(&s, 0, 0);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
    rig_teardown(&rig);
    with_fill = low_camera_with_border(&s, 40, 0);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_CLEAR);
    assert_true(with_fill >= rig.cfg.near_min_mm);
    assert_true(with_fill * 10 >= ref * 9 && with_fill * 9 <= ref * 10);
    rig_teardown(&rig);
    (void)low_camera_with_border(&s, 40, 1);
    assert_true(rig.res.state != NEGOBS_DETECT_CLEAR);
    assert_true(rig.res.clear_to_mm < rig.cfg.near_min_mm);
    rig_teardown(&rig);
}

/* The fill extent itself: constant fill and edge replication (each row its
 * own constant) are found per row, a curved fill cut at the lower quartile
 * of its width; dark texture is not; a run over a
 * quarter of the width is not fill (a clipped scene, or a broken
 * rectification); too few rows with a run is not fill; a clipped black
 * object 20 rows high beside the fill does not widen it. */
static void test_vouch_fill_extent(void **state)
{
    negobs_image_u8_t img;
    int16_t u0[RIG_H];
    int16_t u1[RIG_H];
    int32_t u;
    int32_t v;
    (void)state;
    img.data = left_px;
    img.width = RIG_W;
    img.height = RIG_H;
    img.stride = RIG_W;
    left_image(left_px, 24, 0, 0);
    assert_int_equal(negobs_detect_fill_extent(&img, u0, u1), NEGOBS_OK);
    for (v = 0; v < RIG_H; v++) {
        assert_int_equal(u0[v], 0);
        assert_int_equal(u1[v], RIG_W - 24);
    }
    left_image(left_px, 24, 0, 1);
    assert_int_equal(negobs_detect_fill_extent(&img, u0, u1), NEGOBS_OK);
    for (v = 0; v < RIG_H; v++) {
        assert_int_equal(u1[v], RIG_W);
    }
    /* replication at the left border, width growing 10..33 px with the
     * row, each row the grey level of its sensor edge pixel */
    left_image(left_px, 0, 0, 0);
    for (v = 0; v < RIG_H; v++) {
        for (u = 0; u < 10 + v / 10; u++) {
            left_px[v * RIG_W + u] = (uint8_t)(50 + v / 3);
        }
    }
    assert_int_equal(negobs_detect_fill_extent(&img, u0, u1), NEGOBS_OK);
    for (v = 0; v < RIG_H; v++) {
        /* the row's own width, cut at the lower quartile (about 16) */
        int32_t wd = 10 + v / 10;
        assert_true(u0[v] >= (wd < 15 ? wd : 15) && u0[v] <= wd + 1);
        assert_int_equal(u1[v], RIG_W);
    }
    /* black fill of 24 px with a black object 60 px wide over rows
     * 100-119 beside it */
    left_image(left_px, 24, 0, 0);
    for (v = 100; v < 120; v++) {
        memset(left_px + v * RIG_W + RIG_W - 60, 0, 60);
    }
    assert_int_equal(negobs_detect_fill_extent(&img, u0, u1), NEGOBS_OK);
    for (v = 0; v < RIG_H; v++) {
        assert_int_equal(u1[v], RIG_W - 24);
    }
    /* a clipped region over half the width, and fill on too few rows */
    left_image(left_px, RIG_W / 2, 255, 0);
    for (v = RIG_H / 8; v < RIG_H; v++) {
        memset(left_px + v * RIG_W + RIG_W / 2, 200, RIG_W / 2 - 12);
        for (u = RIG_W - 12; u < RIG_W; u++) {
            left_px[v * RIG_W + u] = (uint8_t)(40 + (u * 7 + v * 3) % 50);
        }
    }
    assert_int_equal(negobs_detect_fill_extent(&img, u0, u1), NEGOBS_OK);
    for (v = 0; v < RIG_H; v++) {
        assert_int_equal(u1[v], RIG_W);
    }
    assert_int_equal(negobs_detect_fill_extent(NULL, u0, u1),
                     NEGOBS_ERR_INVAL);
}

/* A 20 cm drop 1.5 m ahead of a 1.2 m / 20 deg camera, with a black fill
 * over the left image's last 40 columns: the drop in the visible part is
 * still a hazard. */
static void test_vouch_drop_beside_fill_is_found(void **state)
{
    synth_scene_t s;
    negobs_image_u8_t left;
    int32_t u;
    int32_t v;
    int i;
    (void)state;
    synth_flat(&s, 1.2, 20.0);
    synth_step(&s, 1.5, -0.2);
    s.noise_px = 0.25;
    s.seed = 31u;
    run_mounted(&s, 0);
    left_image(left_px, 40, 0, 0);
    left.data = left_px;
    left.width = RIG_W;
    left.height = RIG_H;
    left.stride = RIG_W;
    rig.frame.left = &left;
    for (i = 0; i < 5; i++) {
        s.seed = 31u + (uint32_t)i;
        synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
        for (v = 0; v < RIG_H; v++) {
            for (u = RIG_W - 40; u < RIG_W; u++) {
                rig.disp[v * RIG_W + u] = NEGOBS_DISP_INVALID;
            }
        }
        assert_int_equal(rig_run(&rig), NEGOBS_OK);
    }
    print_message("drop beside fill: state %d, level %d, range %d, "
                  "clear_to %d\n",
                  (int)rig.res.state, (int)rig.res.level,
                  rig.res.nearest_range_mm, rig.res.clear_to_mm);
    assert_int_equal(rig.res.state, NEGOBS_DETECT_HAZARD);
    assert_true(rig.res.clear_to_mm <= 1500 + 150);
    rig.frame.left = NULL;
    rig_teardown(&rig);
}

/* The ground fit's valid share counts only samples in view: 70 % of the
 * pixels unmatched at random and a fill over the last 70 columns leave 23 %
 * of all samples valid, but 30 % of those in view. Without the fill, the
 * 70 unmatched columns are no support (section 4, "Support"): the strips
 * left of them hold 30 % and span over a quarter of the width, so the fit
 * stands there too (the old share over the whole band said FEW_GROUND). */
static void test_vouch_fill_is_not_in_the_valid_share(void **state)
{
    synth_scene_t s;
    negobs_image_u8_t left;
    int32_t u;
    int32_t v;
    int with;
    int i;
    (void)state;
    for (with = 0; with < 2; with++) {
        synth_flat(&s, 1.2, 20.0);
        s.noise_px = 0.25;
        s.dropout = 0.7;
        s.seed = 41u;
        run_mounted(&s, 0);
        left_image(left_px, with ? 70 : 0, 0, 0);
        left.data = left_px;
        left.width = RIG_W;
        left.height = RIG_H;
        left.stride = RIG_W;
        rig.frame.left = &left;
        for (i = 0; i < 10; i++) { /* the fill is taken in 8 px a frame */
            s.seed = 41u + (uint32_t)i;
            synth_render(&s, &rig.cfg.rig, rig.disp, RIG_W);
            for (v = 0; v < RIG_H; v++) {
                for (u = RIG_W - 70; u < RIG_W; u++) {
                    rig.disp[v * RIG_W + u] = NEGOBS_DISP_INVALID;
                }
            }
            assert_int_equal(rig_run(&rig), NEGOBS_OK);
        }
        rig.frame.left = NULL;
        print_message("fill %d: valid %d permille, reasons %u\n", with,
                      rig.res.ground_valid_permille, rig.res.reasons);
        if (with) {
            assert_true(rig.res.ground_valid_permille >= 280);
        } else {
            assert_true(rig.res.ground_valid_permille < 250);
        }
        assert_int_equal(rig.res.ground_valid, 1);
        rig_teardown(&rig);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vouch_textureless_patch_limits_the_range),
        cmocka_unit_test(test_vouch_local_offset_is_counted_once),
        cmocka_unit_test(
            test_vouch_local_patch_in_the_fit_rows_ends_the_walk_there),
        cmocka_unit_test(test_vouch_hazard_bound_by_its_track),
        cmocka_unit_test(
            test_vouch_unverified_start_reports_the_floor_in_view),
        cmocka_unit_test(
            test_vouch_stops_where_a_drop_would_hide_past_the_scan),
        cmocka_unit_test(test_vouch_rectification_fill_is_out_of_view),
        cmocka_unit_test(test_vouch_fill_extent),
        cmocka_unit_test(test_vouch_fill_is_not_in_the_valid_share),
        cmocka_unit_test(test_vouch_drop_beside_fill_is_found),
        cmocka_unit_test(test_vouch_drop_in_clean_strips_despite_far_noise),
        cmocka_unit_test(test_vouch_texture_at_the_half_scale),
        cmocka_unit_test(test_vouch_deep_drop_on_weak_grain),
        cmocka_unit_test(test_vouch_deep_drop_stands_out_of_noise),
        cmocka_unit_test(test_vouch_no_false_vouch_on_walks),
        cmocka_unit_test(test_vouch_bounds_by_state),
        cmocka_unit_test(test_vouch_noisy_near_field_is_no_info),
        cmocka_unit_test(test_vouch_wall_in_near_zone_is_clear_to_its_foot),
        cmocka_unit_test(test_vouch_only_a_tall_face_bars),
        cmocka_unit_test(
            test_vouch_floor_outside_the_stereo_view_is_not_unseen),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
