/*
 * Travel along the floor between two frames (detect/detect_travel.c).
 * The frames are rendered here by casting each pixel's ray onto a floor
 * with a known texture, from a camera at a known height and pitch moved by
 * a known distance, so every expectation follows from the rendering.
 */
#include <math.h>

#include "cmocka_all.h"
#include "detect/detect_internal.h"
#include "test_rng.h"

#define W 320
#define H 240
#define F_PX 250.0
#define HEIGHT_MM 1200
#define PITCH_DEG 20.0

static uint8_t px[W * H];
static const negobs_image_u8_t img = {px, W, H, W};
static uint32_t rng = 777u;

static double gauss(void)
{
    return test_gauss12(&rng);
}

/* A floor texture of several scales (mm along the heading, across it). */
static double floor_grey(double fwd, double lat)
{
    return 128.0 + 30.0 * sin(fwd / 23.0) * cos(lat / 31.0) +
           20.0 * sin(fwd / 61.0 + lat / 47.0) +
           15.0 * cos(fwd / 11.0 - lat / 17.0);
}

/* The camera `walked_mm` along the floor, pitch down PITCH_DEG, no roll,
 * turned by `yaw_deg` about the floor's normal (the walk keeps its
 * heading); sensor noise of sigma `noise` grey levels. Above the horizon:
 * 200. */
static void render_turned(double walked_mm, double yaw_deg, double noise)
{
    const double psi = yaw_deg * 3.14159265358979323846 / 180.0;
    const double p = PITCH_DEG * 3.14159265358979323846 / 180.0;
    const double ny = cos(p);
    const double nz = sin(p);
    int u;
    int v;
    for (v = 0; v < H; v++) {
        for (u = 0; u < W; u++) {
            double rx = (u - (W - 1) / 2.0) / F_PX;
            double ry = (v - (H - 1) / 2.0) / F_PX;
            double rn = ry * ny + nz; /* ray . n, rz = 1 */
            double g = 200.0;
            if (rn > 1e-3) {
                double t = HEIGHT_MM / rn;
                /* fwd = (0, -sin p, cos p), right = (1, 0, 0) */
                double fwd = t * (-ry * nz + ny);
                double lat = t * rx;
                g = floor_grey(fwd * cos(psi) - lat * sin(psi) + walked_mm,
                               fwd * sin(psi) + lat * cos(psi));
            }
            g += noise * gauss();
            px[v * W + u] = (uint8_t)(g < 0 ? 0 : (g > 255 ? 255 : g + 0.5));
        }
    }
}

static void render(double walked_mm, double noise)
{
    render_turned(walked_mm, 0.0, noise);
}

typedef struct geo {
    negobs_rig_t rig;
    negobs_ground_plane_t plane;
    negobs_ground_frame_t frame;
} geo_t;

static void geo_init(geo_t *g)
{
    negobs_ground_pose_t pose = {HEIGHT_MM, (int32_t)(PITCH_DEG * 1000), 0};
    negobs_ground_pose_t back;
    negobs_rig_default(&g->rig, W, H);
    assert_int_equal(negobs_ground_plane_from_pose(&g->rig, &pose, &g->plane),
                     NEGOBS_OK);
    assert_int_equal(
        negobs_ground_pose_from_plane(&g->rig, &g->plane, &back, &g->frame),
        NEGOBS_OK);
}

/* Walks 120 mm between frames 100 ms apart (1.2 m/s), the camera turned
 * by yaw_deg[k] on frame k (NULL: no turn), and checks that every frame
 * after the first reads 120 mm within one candidate step of the grid
 * (200 mm / 24 = 8 mm) plus rounding. */
static void assert_walk_reads(const double *yaw_deg, int frames)
{
    static travel_track_t t[TRAVEL_TRACKS];
    int32_t pair = 0;
    geo_t g;
    int k;
    geo_init(&g);
    travel_reset(t);
    for (k = 0; k < frames; k++) {
        int32_t mm;
        render_turned(120.0 * k, (yaw_deg != NULL) ? yaw_deg[k] : 0.0, 2.0);
        mm = travel_step(t, &g.rig, &g.plane, &g.frame, &img,
                         1000u + 100u * (uint32_t)k, NULL, &pair);
        if (k == 0) {
            assert_int_equal(mm, 0); /* nothing held yet */
        } else {
            assert_in_range(mm, 104, 136);
        }
        assert_int_equal(pair, mm); /* measured from the last frame */
    }
}

/* Walking at 120 mm a frame, frame 3 shows a blank floor (a frame blown
 * out by an exposure step, or one whose fit was off): frames 3 and 4
 * cannot read their travel from the last frame, so frame 4 reads it from
 * frame 2, both intervals at once, and the walk loses nothing; the
 * pooling's travel (pair) stays that of the last frame alone. */
static void test_travel_reads_across_a_frame_it_cannot_read(void **state)
{
    static travel_track_t t[TRAVEL_TRACKS];
    int32_t pair = 0;
    int32_t sum = 0;
    geo_t g;
    int k;
    (void)state;
    geo_init(&g);
    travel_reset(t);
    for (k = 0; k < 7; k++) {
        int32_t mm;
        int i;
        render(120.0 * k, 2.0);
        if (k == 3) {
            for (i = 0; i < W * H; i++) {
                px[i] = (uint8_t)(128 + (i % 3));
            }
        }
        mm = travel_step(t, &g.rig, &g.plane, &g.frame, &img,
                         1000u + 100u * (uint32_t)k, NULL, &pair);
        if (k == 3) {
            assert_int_equal(mm, 0);
        } else if (k == 4) {
            /* 240 mm on a grid of 400 / 24 mm */
            assert_int_equal(pair, 0);
            assert_in_range(mm, 216, 264);
        } else if (k > 0) {
            assert_in_range(mm, 104, 136);
            assert_int_equal(pair, mm);
        }
        sum += mm;
    }
    assert_in_range(sum, 6 * 120 - 40, 6 * 120 + 40);
}

/* Standing still for six frames with fresh noise, the camera turning by
 * turn_deg and back on every other frame: no travel. */
static void assert_standing_reads_nothing(double turn_deg)
{
    static travel_track_t t[TRAVEL_TRACKS];
    int32_t pair = 0;
    geo_t g;
    int k;
    geo_init(&g);
    travel_reset(t);
    for (k = 0; k < 6; k++) {
        render_turned(0.0, (k % 2 == 0) ? 0.0 : turn_deg, 3.0);
        assert_int_equal(travel_step(t, &g.rig, &g.plane, &g.frame, &img,
                                     1000u + 100u * (uint32_t)k, NULL, &pair),
                         0);
    }
}

static void test_travel_reads_a_walk(void **state)
{
    (void)state;
    assert_walk_reads(NULL, 5);
}

/* Standing still: the same floor with fresh noise reads no travel. */
static void test_travel_standing_still_reads_nothing(void **state)
{
    (void)state;
    assert_standing_reads_nothing(0.0);
}

/* Faster than the grid (3.5 m/s), a gap longer than 500 ms, no image, an
 * image of another size, a blank floor: nothing is counted. */
static void test_travel_counts_nothing_it_cannot_see(void **state)
{
    static travel_track_t t[TRAVEL_TRACKS];
    int32_t pair = 0;
    static uint8_t small_px[16 * 16];
    const negobs_image_u8_t small = {small_px, 16, 16, 16};
    geo_t g;
    int i;
    (void)state;
    geo_init(&g);
    travel_reset(t);
    render(0.0, 2.0);
    (void)travel_step(t, &g.rig, &g.plane, &g.frame, &img, 1000u, NULL, &pair);
    render(350.0, 2.0);
    assert_int_equal(
        travel_step(t, &g.rig, &g.plane, &g.frame, &img, 1100u, NULL, &pair),
        0);
    render(470.0, 2.0);
    assert_int_equal(
        travel_step(t, &g.rig, &g.plane, &g.frame, &img, 1700u, NULL, &pair),
        0);
    assert_int_equal(
        travel_step(t, &g.rig, &g.plane, &g.frame, NULL, 1800u, NULL, &pair),
        0);
    assert_int_equal(
        travel_step(t, &g.rig, &g.plane, &g.frame, &small, 1900u, NULL, &pair),
        0);
    for (i = 0; i < W * H; i++) {
        px[i] = 128;
    }
    (void)travel_step(t, &g.rig, &g.plane, &g.frame, &img, 2000u, NULL, &pair);
    assert_int_equal(
        travel_step(t, &g.rig, &g.plane, &g.frame, &img, 2100u, NULL, &pair),
        0);
}

/* Walking 120 mm a frame while the camera turns to and fro by 1.5 and
 * 2.5 deg between frames (the trunk's sway at the stride's rate): read as
 * without the turn. Searched for T alone, the first step read 166 mm. */
static void test_travel_reads_a_walk_while_turning(void **state)
{
    static const double yaw_deg[] = {0.0, 1.5, 0.0, -2.5, 0.0, 2.5, 1.0};
    (void)state;
    assert_walk_reads(yaw_deg, (int)(sizeof yaw_deg / sizeof yaw_deg[0]));
}

/* Standing still while the head turns by 2 deg a frame reads no travel
 * (searched for T alone: 83 mm), and a turn faster than the search (5 deg
 * between frames, looking aside) counts nothing while walking. */
static void test_travel_turning_in_place_reads_nothing(void **state)
{
    static travel_track_t t[TRAVEL_TRACKS];
    int32_t pair = 0;
    geo_t g;
    (void)state;
    assert_standing_reads_nothing(2.0);
    geo_init(&g);
    travel_reset(t);
    render_turned(0.0, 0.0, 2.0);
    (void)travel_step(t, &g.rig, &g.plane, &g.frame, &img, 2000u, NULL, &pair);
    render_turned(120.0, 5.0, 2.0);
    assert_int_equal(
        travel_step(t, &g.rig, &g.plane, &g.frame, &img, 2100u, NULL, &pair),
        0);
}

/* Executors for the search's jobs: the last job first, on two
 * "workers"; and a faulty one that skips job 1. */
static void run_reversed(void *user, int32_t n_jobs, negobs_job_fn fn,
                         void *arg)
{
    int32_t j;
    (void)user;
    for (j = n_jobs - 1; j >= 0; j--) {
        fn(arg, j, (n_jobs - 1 - j) % 2);
    }
}

static void run_skipping(void *user, int32_t n_jobs, negobs_job_fn fn,
                         void *arg)
{
    int32_t j;
    (void)user;
    for (j = 0; j < n_jobs; j++) {
        if (j != 1) {
            fn(arg, j, 0);
        }
    }
}

/* With workers, the turn search's coarse stage runs as jobs (each with
 * its own pruning bound, merged in turn order): in any order, or with a
 * job the executor skipped (run here), every frame reads what one pass
 * over all turns (no executor) reads, on a walk that turns both ways and
 * on one that stands turning. */
static void test_travel_jobs_in_any_order_read_the_same(void **state)
{
    static travel_track_t t0[TRAVEL_TRACKS];
    static travel_track_t t1[TRAVEL_TRACKS];
    static travel_track_t t2[TRAVEL_TRACKS];
    static const double yaw_deg[] = {0.0, 1.5,  0.0, -2.5, 0.0,  2.5,
                                     1.0, -1.0, 2.0, 0.5,  -2.0, 0.0};
    const negobs_executor_t rev = {2, run_reversed, NULL};
    const negobs_executor_t skip = {2, run_skipping, NULL};
    const int n = (int)(sizeof yaw_deg / sizeof yaw_deg[0]);
    geo_t g;
    int moved = 0;
    int32_t pair = 0;
    int k;
    (void)state;
    geo_init(&g);
    travel_reset(t0);
    travel_reset(t1);
    travel_reset(t2);
    for (k = 0; k < 2 * n; k++) {
        /* walking for n frames, then standing while turning */
        const double walked = 120.0 * ((k < n) ? k : n);
        const uint32_t now = 1000u + 100u * (uint32_t)k;
        int32_t mm0;
        render_turned(walked, yaw_deg[k % n], 2.5);
        mm0 = travel_step(t0, &g.rig, &g.plane, &g.frame, &img, now, NULL,
                          &pair);
        assert_int_equal(travel_step(t1, &g.rig, &g.plane, &g.frame, &img, now,
                                     &rev, &pair),
                         mm0);
        assert_int_equal(travel_step(t2, &g.rig, &g.plane, &g.frame, &img, now,
                                     &skip, &pair),
                         mm0);
        moved += mm0 > 0;
    }
    assert_true(moved >= n - 2); /* the walk reads, so the search ran */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_travel_reads_a_walk),
        cmocka_unit_test(test_travel_standing_still_reads_nothing),
        cmocka_unit_test(test_travel_counts_nothing_it_cannot_see),
        cmocka_unit_test(test_travel_reads_across_a_frame_it_cannot_read),
        cmocka_unit_test(test_travel_reads_a_walk_while_turning),
        cmocka_unit_test(test_travel_turning_in_place_reads_nothing),
        cmocka_unit_test(test_travel_jobs_in_any_order_read_the_same),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
