/*
 * Frames pooled along the measured travel (detect/detect_pool.c): the
 * pooled map scatters less than one frame's, keeps a drop's edge where the
 * frame sees it, and is the frame's own map whenever the pooling has no
 * right to align (no travel, a fit that jumped or was distrusted, a
 * sample of another surface). Maps come from the analytic scene renderer
 * at 1.2 m / 20 deg, 320x240, f = 250, B = 12 cm, walking 120 mm a tick.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cmocka_all.h"
#include "detect/detect_internal.h"
#include "scene_disp.h"

#define W 320
#define H 240
#define STEP_MM 120

typedef struct pool_rig {
    negobs_detect_config_t cfg;
    detect_priv_t p;
    int16_t hist[2][W * H];
    int16_t out[W * H];
    int32_t node[NEGOBS_DETECT_POOL_BANDS * 2 * 64];
    int16_t disp[W * H];
    negobs_image_s16_t img;
    gfit_out_t g;
    int32_t pooled; /* the last call's pooled share, per mille */
} pool_rig_t;

static pool_rig_t *rig_new(void)
{
    pool_rig_t *r = calloc(1, sizeof *r);
    assert_non_null(r);
    negobs_detect_config_default(&r->cfg, W, H);
    r->cfg.pool_frames = 4;
    assert_true(det_pool_nodes(W) * 2 <= 2 * 64);
    r->p.pool_hist[0] = r->hist[0];
    r->p.pool_hist[1] = r->hist[1];
    r->p.pool_out = r->out;
    r->p.pool_node = r->node;
    r->img.data = r->disp;
    r->img.width = W;
    r->img.height = H;
    r->img.stride = W;
    return r;
}

/* The fit of a camera at h_mm / pitch_deg over level ground, as the
 * ground fit reports it, with a per-pixel sigma of 0.31 px (the maps'
 * noise is at most 0.3 px). */
static void fit_of(pool_rig_t *r, int32_t h_mm, double pitch_deg)
{
    memset(&r->g, 0, sizeof r->g);
    r->g.ok = 1;
    r->g.pose.height_mm = h_mm;
    r->g.pose.pitch_mdeg = (int32_t)lround(pitch_deg * 1000.0);
    assert_int_equal(
        negobs_ground_plane_from_pose(&r->cfg.rig, &r->g.pose, &r->g.plane),
        NEGOBS_OK);
    assert_int_equal(negobs_ground_pose_from_plane(&r->cfg.rig, &r->g.plane,
                                                   &r->g.pose, &r->g.frame),
                     NEGOBS_OK);
    r->g.pose.height_mm = h_mm; /* the plane's rounding aside */
    r->g.sigma_q4 = 5;
}

/* Level ground with, when drop_m > 0, a 15 cm drop drop_m ahead; noise
 * sigma noise_px, a new draw per seed. */
static void render(pool_rig_t *r, double drop_m, double noise_px,
                   uint32_t seed)
{
    synth_scene_t s;
    synth_flat(&s, 1.2, 20.0);
    if (drop_m > 0.0) {
        synth_step(&s, drop_m, -0.15);
    }
    s.noise_px = noise_px;
    s.seed = seed;
    synth_render(&s, &r->cfg.rig, r->disp, W);
    fit_of(r, 1200, 20.0);
}

/* Scatter (px) of map m about the ground model over rows v0..v1-1. */
static double scatter_px(const pool_rig_t *r, const int16_t *m, int v0, int v1)
{
    double s2 = 0.0;
    long n = 0;
    int u;
    int v;
    for (v = v0; v < v1; v++) {
        for (u = 8; u < W - 8; u++) {
            int32_t d = m[v * W + u];
            double e;
            if (d == NEGOBS_DISP_INVALID) {
                continue;
            }
            e = (d - negobs_ground_disp_q4(&r->g.plane, u, v)) / 16.0;
            s2 += e * e;
            n++;
        }
    }
    return (n > 0) ? sqrt(s2 / (double)n) : 1e9;
}

/* Last row (from the top) of column u whose value lies more than half of
 * the drop's deficit below the ground: the far side of the edge. */
static int edge_row(const pool_rig_t *r, const int16_t *m, int u)
{
    int v;
    for (v = H - 1; v > 0; v--) {
        int32_t dg = negobs_ground_disp_q4(&r->g.plane, u, v);
        int32_t d = m[v * W + u];
        /* 15 cm under 1.2 m: d = dg * 1.2 / 1.35, a deficit of dg / 9 */
        if (d != NEGOBS_DISP_INVALID && 18 * (dg - d) > dg) {
            return v;
        }
    }
    return -1;
}

/* n ticks 120 mm apart from a fresh start, each with fresh noise (seed
 * seed0 + i); drop0_m > 0: a 15 cm drop that far ahead at the first
 * tick. The last pooled map. */
static const negobs_image_s16_t *walk_ticks(pool_rig_t *r, int n,
                                            double drop0_m, double noise_px,
                                            uint32_t seed0)
{
    const negobs_image_s16_t *m = NULL;
    int i;
    for (i = 0; i < n; i++) {
        render(r, (drop0_m > 0.0) ? drop0_m - 0.12 * i : 0.0, noise_px,
               seed0 + (uint32_t)i);
        m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1,
                           (i > 0) ? STEP_MM : 0, 0u, &r->pooled);
    }
    return m;
}

/* Four ticks over level ground with fresh noise each: the pooled map
 * scatters about half as much as the frame's own. */
static void test_pool_halves_floor_noise(void **state)
{
    pool_rig_t *r = rig_new();
    const negobs_image_s16_t *m = walk_ticks(r, 4, 0.0, 0.3, 11u);
    double raw;
    double pooled;
    (void)state;
    assert_ptr_not_equal(m, &r->img);
    assert_true(r->pooled > 900); /* all but the newly seen floor */
    raw = scatter_px(r, r->disp, 140, 230);
    pooled = scatter_px(r, m->data, 140, 230);
    assert_true(raw > 0.25);
    assert_true(pooled < 0.65 * raw);
    free(r);
}

/* Walking toward a 15 cm drop, its edge 3.0 m ahead at the first tick:
 * after four ticks the pooled map's edge is on the frame's own row (the
 * noise free render's), whatever the noise. */
static void test_pool_keeps_the_edge_in_place(void **state)
{
    pool_rig_t *r = rig_new();
    const negobs_image_s16_t *m = walk_ticks(r, 4, 3.0, 0.2, 21u);
    int truth[3];
    int k;
    (void)state;
    render(r, 3.0 - 0.12 * 3, 0.0, 1u);
    for (k = 0; k < 3; k++) {
        truth[k] = edge_row(r, r->disp, 100 + 60 * k);
        assert_true(truth[k] > 0);
    }
    for (k = 0; k < 3; k++) {
        int e = edge_row(r, m->data, 100 + 60 * k);
        assert_true(abs(e - truth[k]) <= 1);
    }
    free(r);
}

/* 1 when the pooled map m equals the frame's own map bit for bit. */
static int same_as_frame(const pool_rig_t *r, const negobs_image_s16_t *m)
{
    int i;
    for (i = 0; i < W * H; i++) {
        if (m->data[i] != r->disp[i]) {
            return 0;
        }
    }
    return 1;
}

/* No measured travel over a gap longer than a tick or two (the walk
 * since is unknown), a fit that jumped by more than a head moves in a
 * tick, and a fit found wrong after the scan: each next map is the
 * frame's own. */
static void test_pool_needs_travel_and_steady_fits(void **state)
{
    pool_rig_t *r = rig_new();
    const negobs_image_s16_t *m;
    (void)state;
    render(r, 0.0, 0.3, 31u);
    (void)det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, 0, 1000u,
                         &r->pooled);
    render(r, 0.0, 0.3, 32u);
    m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, 0, 1600u,
                       &r->pooled);
    assert_true(same_as_frame(r, m));
    assert_int_equal(r->pooled, 0);

    render(r, 0.0, 0.3, 33u);
    fit_of(r, 1280, 20.0); /* 80 mm higher than the last tick's */
    m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, STEP_MM, 1700u,
                       &r->pooled);
    assert_true(same_as_frame(r, m));
    assert_int_equal(r->pooled, 0);

    render(r, 0.0, 0.3, 34u);
    fit_of(r, 1280, 20.0); /* the same fit again: steady */
    m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, STEP_MM, 1800u,
                       &r->pooled);
    assert_false(same_as_frame(r, m)); /* steady again: pooled */
    det_pool_distrust(&r->p);
    render(r, 0.0, 0.3, 35u);
    m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, STEP_MM, 1900u,
                       &r->pooled);
    assert_true(same_as_frame(r, m));
    assert_int_equal(r->pooled, 0);

    /* without a measured travel the fits must agree more closely: 40 mm
     * pools along a measured travel, not along the assumed one */
    render(r, 0.0, 0.3, 36u);
    (void)det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, STEP_MM, 2000u,
                         &r->pooled);
    render(r, 0.0, 0.3, 37u);
    fit_of(r, 1240, 20.0);
    m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, 0, 2100u,
                       &r->pooled);
    assert_true(same_as_frame(r, m));
    render(r, 0.0, 0.3, 38u);
    fit_of(r, 1200, 20.0);
    m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, STEP_MM, 2200u,
                       &r->pooled);
    assert_false(same_as_frame(r, m));
    free(r);
}

/* n ticks 100 ms apart, toward a 15 cm drop drop0_m ahead at the first,
 * fresh noise each: the camera comes 120 mm nearer on the second tick,
 * where that travel is measured (or not, with measured_1 0), and step_m on
 * each later one, where the patches measure nothing (a floor they cannot
 * follow). *ahead_m: the drop's distance at the last tick. The last
 * pooled map. */
static const negobs_image_s16_t *walk_paced(pool_rig_t *r, int n,
                                            double drop0_m, double step_m,
                                            uint32_t seed0, int measured_1,
                                            double *ahead_m)
{
    const negobs_image_s16_t *m = NULL;
    double ahead = drop0_m;
    int i;
    for (i = 0; i < n; i++) {
        int32_t travel = 0;
        if (i == 1) {
            ahead -= 0.12;
            travel = measured_1 ? STEP_MM : 0;
        } else if (i > 1) {
            ahead -= step_m;
        }
        render(r, ahead, 0.2, seed0 + (uint32_t)i);
        m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, travel,
                           500u + 100u * (uint32_t)i, &r->pooled);
    }
    *ahead_m = ahead;
    return m;
}

/* After a pace measured at 1.2 m/s, ticks the patches cannot measure are
 * pooled along that pace plus what a walker gains in half a second (at
 * most 1.4 m/s): walking on at 1.2 m/s, or stopped dead, the pooled
 * map's edge of a drop is where the frame sees it or nearer, never
 * farther. Without a measured pace nothing is pooled: a camera that may
 * be standing still has no travel to align along. */
static void test_pool_unmeasured_travel_errs_nearer(void **state)
{
    const double steps[2] = {0.12, 0.0};
    int s;
    (void)state;
    for (s = 0; s < 2; s++) {
        pool_rig_t *r = rig_new();
        double ahead = 0.0;
        const negobs_image_s16_t *m = walk_paced(
            r, 5, 3.0, steps[s], 71u + 10u * (uint32_t)s, 1, &ahead);
        int truth[3];
        int k;
        assert_true(r->pooled > 900);
        render(r, ahead, 0.0, 1u);
        for (k = 0; k < 3; k++) {
            truth[k] = edge_row(r, r->disp, 100 + 60 * k);
            assert_true(truth[k] > 0);
        }
        for (k = 0; k < 3; k++) {
            /* rows grow toward the feet: never above the frame's edge */
            assert_true(edge_row(r, m->data, 100 + 60 * k) >= truth[k] - 1);
        }
        free(r);
    }
    {
        pool_rig_t *r = rig_new();
        double ahead = 0.0;
        const negobs_image_s16_t *m = walk_paced(r, 5, 0.0, 0.12, 91u, 1,
                                                 &ahead);
        assert_true(scatter_px(r, m->data, 140, 230) <
                    0.65 * scatter_px(r, r->disp, 140, 230));
        free(r);
    }
    {
        pool_rig_t *r = rig_new();
        double ahead = 0.0;
        const negobs_image_s16_t *m = walk_paced(r, 5, 3.0, 0.12, 95u, 0,
                                                 &ahead);
        assert_true(same_as_frame(r, m));
        assert_int_equal(r->pooled, 0);
        free(r);
    }
}

/* The pace is kept for 500 ms: on the sixth unmeasured tick after it
 * (600 ms) the map is the frame's own again. */
static void test_pool_pace_expires(void **state)
{
    pool_rig_t *r = rig_new();
    double ahead = 0.0;
    const negobs_image_s16_t *m = walk_paced(r, 8, 3.0, 0.12, 97u, 1, &ahead);
    (void)state;
    assert_true(same_as_frame(r, m));
    assert_int_equal(r->pooled, 0);
    free(r);
    r = rig_new();
    m = walk_paced(r, 7, 3.0, 0.12, 97u, 1, &ahead); /* the fifth: 500 ms */
    assert_false(same_as_frame(r, m));
    free(r);
}

/* Between ticks, and with pool_frames 1 (no buffers), the map is the
 * frame's own descriptor. */
static void test_pool_off_between_ticks(void **state)
{
    pool_rig_t *r = rig_new();
    (void)state;
    render(r, 0.0, 0.3, 41u);
    assert_ptr_equal(
        det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 0, 0, 0u, &r->pooled),
        &r->img);
    r->p.pool_out = NULL;
    assert_ptr_equal(det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, STEP_MM,
                                    0u, &r->pooled),
                     &r->img);
    free(r);
}

/* A pixel whose value disagrees with its pooled history by more than the
 * gate (a person stepping into view) keeps its own value. */
static void test_pool_gate_keeps_another_surface(void **state)
{
    pool_rig_t *r = rig_new();
    const negobs_image_s16_t *m;
    (void)state;
    (void)walk_ticks(r, 3, 0.0, 0.1, 51u);
    render(r, 0.0, 0.1, 54u);
    r->disp[200 * W + 160] = (int16_t)(r->disp[200 * W + 160] +
                                       3 * NEGOBS_DISP_ONE);
    m = det_pool_frame(&r->p, &r->cfg, &r->img, &r->g, 1, STEP_MM, 0u,
                       &r->pooled);
    assert_int_equal(m->data[200 * W + 160], r->disp[200 * W + 160]);
    free(r);
}

/* An executor that runs the jobs last first, on worker (job mod 3), and
 * counts them: the layout is the library's, not the executor's. */
typedef struct rev_exec {
    int32_t runs;
    int32_t jobs;
} rev_exec_t;

static void rev_run(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg)
{
    rev_exec_t *x = (rev_exec_t *)user;
    int32_t j;
    x->runs++;
    for (j = n_jobs - 1; j >= 0; j--) {
        fn(arg, j, j % 3);
        x->jobs++;
    }
}

/* n ticks toward a 15 cm drop drop0_m ahead, the same frames through a
 * (bands in order, here) and b (on b's executor): every pooled map,
 * history and pooled share must be equal. */
static void assert_pooled_alike(pool_rig_t *a, pool_rig_t *b, int n,
                                double drop0_m, uint32_t seed0)
{
    int i;
    for (i = 0; i < n; i++) {
        const negobs_image_s16_t *ma;
        const negobs_image_s16_t *mb;
        render(a, drop0_m - 0.12 * i, 0.2, seed0 + (uint32_t)i);
        render(b, drop0_m - 0.12 * i, 0.2, seed0 + (uint32_t)i);
        ma = det_pool_frame(&a->p, &a->cfg, &a->img, &a->g, 1,
                            (i > 0) ? STEP_MM : 0, 0u, &a->pooled);
        mb = det_pool_frame(&b->p, &b->cfg, &b->img, &b->g, 1,
                            (i > 0) ? STEP_MM : 0, 0u, &b->pooled);
        assert_memory_equal(ma->data, mb->data, sizeof(int16_t) * W * H);
        assert_memory_equal(a->hist, b->hist, sizeof a->hist);
        assert_int_equal(a->pooled, b->pooled);
    }
    assert_true(a->pooled > 900); /* the walk did pool */
}

/* The pass runs in NEGOBS_DETECT_POOL_BANDS row bands on an executor:
 * walking toward a drop, run last band first on three workers, it equals
 * the pass run in order. */
static void test_pool_bands_on_an_executor(void **state)
{
    pool_rig_t *a = rig_new();
    pool_rig_t *b = rig_new();
    rev_exec_t x = {0, 0};
    (void)state;
    b->p.exec.workers = 3;
    b->p.exec.run = rev_run;
    b->p.exec.user = &x;
    assert_pooled_alike(a, b, 5, 3.0, 61u);
    assert_int_equal(x.runs, 5);
    assert_int_equal(x.jobs, 5 * NEGOBS_DETECT_POOL_BANDS);
    free(a);
    free(b);
}

/* A faulty executor: skips the first job and hands a job index past the
 * last one instead of the second. */
static void skip_run(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg)
{
    int32_t j;
    (void)user;
    for (j = 1; j < n_jobs; j++) {
        fn(arg, (j == 1) ? n_jobs + 5 : j, 0);
    }
}

/* The bands such an executor skipped run on the calling thread, and the
 * index past the last is ignored: the maps equal the serial ones (a
 * skipped band would keep the last frame's rows). */
static void test_pool_faulty_executor_changes_nothing(void **state)
{
    pool_rig_t *a = rig_new();
    pool_rig_t *b = rig_new();
    (void)state;
    b->p.exec.workers = 1;
    b->p.exec.run = skip_run;
    assert_pooled_alike(a, b, 3, 2.5, 71u);
    free(a);
    free(b);
}

/* The workspace grows by the pooling's buffers only when it is on, and
 * a pool_frames outside 1..4 is refused. */
static void test_pool_config_and_workspace(void **state)
{
    negobs_detect_config_t cfg;
    size_t off = 0;
    size_t on = 0;
    (void)state;
    negobs_detect_config_default(&cfg, W, H);
    assert_int_equal(cfg.pool_frames, 4);
    cfg.pool_frames = 1;
    assert_int_equal(negobs_detect_workspace_size(&cfg, &off), NEGOBS_OK);
    cfg.pool_frames = 4;
    assert_int_equal(negobs_detect_workspace_size(&cfg, &on), NEGOBS_OK);
    assert_true(on >= off + (size_t)W * H * 6u);
    cfg.pool_frames = 5;
    assert_int_equal(negobs_detect_workspace_size(&cfg, &on),
                     NEGOBS_ERR_INVAL);
    cfg.pool_frames = 0;
    assert_int_equal(negobs_detect_workspace_size(&cfg, &on),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pool_halves_floor_noise),
        cmocka_unit_test(test_pool_keeps_the_edge_in_place),
        cmocka_unit_test(test_pool_needs_travel_and_steady_fits),
        cmocka_unit_test(test_pool_unmeasured_travel_errs_nearer),
        cmocka_unit_test(test_pool_pace_expires),
        cmocka_unit_test(test_pool_off_between_ticks),
        cmocka_unit_test(test_pool_gate_keeps_another_surface),
        cmocka_unit_test(test_pool_config_and_workspace),
        cmocka_unit_test(test_pool_bands_on_an_executor),
        cmocka_unit_test(test_pool_faulty_executor_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
