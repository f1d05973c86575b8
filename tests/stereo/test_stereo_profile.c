/*
 * Memory profiles: the fast profile's growth memo changes instructions
 * and workspace only. Both profiles must give the same disparities,
 * confidences and statistics on generated scenes (several ranges, a
 * vertical offset, a range narrower than the memo band and one wider), also
 * after the memo's strip stamps have wrapped and with too little scratch
 * lent to the DP for every row's pointers; the DP gives the memo back
 * empty; and the workspace stays within the documented budgets.
 */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "scene_pair.h"
#include "stereo/stereo_int.h"

#define W 160
#define H 120

static uint8_t left[W * H];
static uint8_t right[W * H];
static int16_t gt[W * H];
static uint8_t occ[W * H];
static uint8_t tex[W * H];

/* a multiple of 16, so both buffers are 16-byte aligned */
#define WS_BYTES                                                              \
    ((NEGOBS_STEREO_WORKSPACE_MAX_FAST(W, H, 127) + 15u) & ~(size_t)15u)
static uint8_t ws_buf[2][WS_BYTES] __attribute__((aligned(16)));

typedef struct run {
    negobs_stereo_t ctx;
    uint8_t *ws;
    int16_t disp[W * H];
    uint8_t conf[W * H];
    negobs_stereo_stats_t st;
} run_t;

static run_t g_run[2];

/* Overrides of the default config for the next init_run (-1: default). */
static int32_t g_tau_q14 = -1;
static int32_t g_texture_min = -1;
static int32_t g_queue = -1;

static void init_run(run_t *r, int32_t profile, int32_t max_disp,
                     int32_t strip_rows)
{
    negobs_stereo_config_t cfg;
    size_t bytes = 0;
    negobs_stereo_config_default(&cfg, W, H);
    cfg.max_disp = max_disp;
    cfg.strip_rows = strip_rows;
    cfg.memory_profile = profile;
    if (g_tau_q14 >= 0) {
        cfg.ncc_tau_q14 = g_tau_q14;
    }
    if (g_texture_min >= 0) {
        cfg.texture_min = g_texture_min;
    }
    if (g_queue >= 0) {
        cfg.queue_capacity = g_queue;
    }
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &bytes), NEGOBS_OK);
    assert_true(bytes <= WS_BYTES);
    r->ws = ws_buf[r == &g_run[1]];
    assert_int_equal(negobs_stereo_init(&r->ctx, &cfg, r->ws, bytes),
                     NEGOBS_OK);
}

static void process(run_t *r)
{
    negobs_image_u8_t li = {left, W, H, W};
    negobs_image_u8_t ri = {right, W, H, W};
    negobs_image_s16_t di = {r->disp, W, H, W};
    negobs_image_u8_t ci = {r->conf, W, H, W};
    assert_int_equal(
        negobs_stereo_process(&r->ctx, &li, &ri, &di, &ci, &r->st), NEGOBS_OK);
    memset(r->st.stage_ticks, 0, sizeof r->st.stage_ticks);
}

static void render(uint32_t seed, int32_t d_top, int32_t d_bottom,
                   int32_t voff)
{
    synth_scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.w = W;
    sc.h = H;
    sc.d_top_q8 = d_top * 256;
    sc.d_bottom_q8 = d_bottom * 256;
    sc.drop_q8 = 6 * 256;
    sc.box_q8 = (d_bottom + 6) * 256;
    sc.voff = voff;
    sc.seed = seed;
    synth_render(&sc, left, right, gt, occ, tex);
}

static void assert_same(void)
{
    assert_memory_equal(g_run[0].disp, g_run[1].disp, sizeof g_run[0].disp);
    assert_memory_equal(g_run[0].conf, g_run[1].conf, sizeof g_run[0].conf);
    assert_memory_equal(&g_run[0].st, &g_run[1].st, sizeof g_run[0].st);
}

static void compare(int32_t max_disp, int32_t strip_rows, uint32_t seed,
                    int32_t d_top, int32_t d_bottom, int32_t voff)
{
    init_run(&g_run[0], NEGOBS_STEREO_PROFILE_COMPACT, max_disp, strip_rows);
    init_run(&g_run[1], NEGOBS_STEREO_PROFILE_FAST, max_disp, strip_rows);
    render(seed, d_top, d_bottom, voff);
    process(&g_run[0]);
    process(&g_run[1]);
    assert_true(g_run[0].st.grown > 1000u); /* the growth really ran */
    assert_same();
}

static void test_same_maps_d64(void **state)
{
    (void)state;
    compare(63, 32, 11u, 8, 30, 0);
}

static void test_same_maps_wide_range(void **state)
{
    (void)state;
    /* 128 levels: the memo band (32) covers a quarter of the range */
    compare(127, 32, 12u, 20, 70, 1);
}

static void test_same_maps_narrow_range(void **state)
{
    (void)state;
    /* 24 levels: the memo band is the whole range */
    compare(23, 16, 13u, 4, 18, 0);
}

/* With tau 0 a cell of score 0 can be accepted, so a flat cell (no
 * score) read back from the memo as anything else would change the
 * growth: a high texture threshold makes many windows flat. */
static void test_same_maps_flat_cells_tau0(void **state)
{
    (void)state;
    g_tau_q14 = 0;
    g_texture_min = 400000;
    compare(63, 32, 14u, 8, 30, 0);
    g_tau_q14 = -1;
    g_texture_min = -1;
}

/* 15 strips a frame with 8-row strips: the 63 stamps wrap every 4-5
 * frames (33 times in 140 frames), so words of old strips must read empty
 * after each clear, and frames of different content keep agreeing. */
static void test_same_maps_after_stamp_wrap(void **state)
{
    int i;
    (void)state;
    init_run(&g_run[0], NEGOBS_STEREO_PROFILE_COMPACT, 47, 8);
    init_run(&g_run[1], NEGOBS_STEREO_PROFILE_FAST, 47, 8);
    for (i = 0; i < 140; i++) {
        render(100u + (uint32_t)(i % 3), 8 + i % 3, 30, 0);
        process(&g_run[0]);
        process(&g_run[1]);
        if (i % 20 == 0 || i >= 135) {
            assert_same();
        }
    }
    assert_same();
}

/* The DP keeps its stage-1 pointers between its passes in the memo
 * (fast, a byte per band cell) or in the growth's strip scratch (compact,
 * two bits; dp.c). With 16 levels, 8-row strips and a 16-entry queue the
 * memo has 80 KiB, room for 85 of the 116 records (161 + ~5.5 x 160 bytes
 * each), the strip scratch about 40 KiB, room for 112 two-bit records;
 * the other rows run stage 1 twice: both kinds of rows in one frame, in
 * both profiles. */
static void test_same_maps_store_partly_full(void **state)
{
    (void)state;
    g_queue = 16;
    compare(15, 8, 15u, 3, 9, 0);
    g_queue = -1;
}

/* After a frame every memo word is empty or written by this frame's
 * growth (a stamp 1 .. memo_gen): no DP record is left over for a later
 * strip to read as a correlation. */
static void test_memo_given_back_empty(void **state)
{
    const stx_t *s;
    size_t n;
    size_t i;
    size_t stale = 0;
    (void)state;
    init_run(&g_run[1], NEGOBS_STEREO_PROFILE_FAST, 63, 32);
    render(16u, 8, 30, 0);
    process(&g_run[1]);
    s = (const stx_t *)g_run[1].ctx.priv;
    assert_non_null(s->memo);
    n = (size_t)s->sh * (size_t)s->w * (size_t)s->memo_k;
    for (i = 0; i < n; i++) {
        uint32_t gen = s->memo[i] >> STX_MEMO_NUM_BITS;
        if (s->memo[i] != 0u && (gen == 0u || gen > s->memo_gen)) {
            stale++;
        }
    }
    assert_int_equal(stale, 0);
}

static void test_workspace_budgets(void **state)
{
    negobs_stereo_config_t cfg;
    size_t compact = 0;
    size_t fast = 0;
    (void)state;
    negobs_stereo_config_default(&cfg, 320, 240);
    cfg.memory_profile = NEGOBS_STEREO_PROFILE_COMPACT;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &compact), NEGOBS_OK);
    assert_true(compact <= 512u * 1024u);
    assert_true(compact <= NEGOBS_STEREO_WORKSPACE_MAX_COMPACT(320, 240, 63));
    cfg.memory_profile = NEGOBS_STEREO_PROFILE_FAST;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &fast), NEGOBS_OK);
    assert_true(fast > compact);
    assert_true(fast <= NEGOBS_STEREO_WORKSPACE_MAX_FAST(320, 240, 63));
    negobs_stereo_config_default(&cfg, 640, 480);
    cfg.memory_profile = NEGOBS_STEREO_PROFILE_FAST;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &fast), NEGOBS_OK);
    assert_true(fast <= 4u * 1024u * 1024u);
    /* per-worker scratch included: the memo narrows as workers are
     * added, and one worker's memo (its 32 levels) stays */
    {
        int32_t k;
        size_t one = fast;
        for (k = 1; k <= 4; k++) {
            size_t comp = 0;
            cfg.band_workers = k;
            cfg.memory_profile = NEGOBS_STEREO_PROFILE_COMPACT;
            assert_int_equal(negobs_stereo_workspace_size(&cfg, &comp),
                             NEGOBS_OK);
            cfg.memory_profile = NEGOBS_STEREO_PROFILE_FAST;
            assert_int_equal(negobs_stereo_workspace_size(&cfg, &fast),
                             NEGOBS_OK);
            assert_true(fast <= NEGOBS_STEREO_FAST_BUDGET);
            assert_true(fast >= comp);
            if (k == 1) {
                assert_int_equal(fast, one);
            }
        }
        /* 2 workers at 320x240 keep the whole memo (within budget) */
        negobs_stereo_config_default(&cfg, 320, 240);
        cfg.band_workers = 2;
        cfg.memory_profile = NEGOBS_STEREO_PROFILE_FAST;
        assert_int_equal(negobs_stereo_workspace_size(&cfg, &fast), NEGOBS_OK);
        cfg.memory_profile = NEGOBS_STEREO_PROFILE_COMPACT;
        assert_int_equal(negobs_stereo_workspace_size(&cfg, &compact),
                         NEGOBS_OK);
        /* more than 31 levels a worker: the whole memo (a worker with a
         * memo has no score cache, so the difference is a little less
         * than the two memos) */
        assert_true(fast > compact + 2u * 320u * 32u * 4u *
                                         (NEGOBS_STEREO_MEMO_LEVELS - 1));
        cfg.band_workers = 1;
        cfg.memory_profile = NEGOBS_STEREO_PROFILE_FAST;
    }
    cfg.memory_profile = 2;
    assert_int_equal(negobs_stereo_workspace_size(&cfg, &fast),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_maps_d64),
        cmocka_unit_test(test_same_maps_wide_range),
        cmocka_unit_test(test_same_maps_narrow_range),
        cmocka_unit_test(test_same_maps_after_stamp_wrap),
        cmocka_unit_test(test_same_maps_flat_cells_tau0),
        cmocka_unit_test(test_same_maps_store_partly_full),
        cmocka_unit_test(test_memo_given_back_empty),
        cmocka_unit_test(test_workspace_budgets),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
