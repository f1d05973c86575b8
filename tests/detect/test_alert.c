/*
 * Alert state machine tests with a fake millisecond clock. The harness
 * ticks every millisecond (a port may tick less often, but never later
 * than cmd.next_change_ms) and records every motor edge.
 */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/alert.h"
#include "negobs/detect.h" /* negobs_alert_input_from_result */

#define MAX_EDGES 4096

typedef struct edge {
    uint32_t t;
    int on;
} edge_t;

typedef struct sim {
    negobs_alert_t a;
    negobs_alert_config_t cfg;
    negobs_motor_cmd_t cmd;
    edge_t e[MAX_EDGES];
    int n;
    int on;
    uint32_t t;
    negobs_alert_input_t in;
    int feed; /* 1: a verdict every 100 ms                    */
} sim_t;

static sim_t sim;

static void sim_init(int ready)
{
    memset(&sim, 0, sizeof sim);
    negobs_alert_config_default(&sim.cfg);
    sim.cfg.ready_on_start = ready;
    assert_int_equal(negobs_alert_init(&sim.a, &sim.cfg, NULL, 0), NEGOBS_OK);
    sim.feed = 1;
}

static void sim_set(negobs_alert_level_t lv, int32_t range, int no_info,
                    int batt)
{
    sim.in.level = lv;
    sim.in.range_mm = range;
    sim.in.no_info = no_info;
    sim.in.battery_low = batt;
}

/* Run until time t1 (exclusive). */
static void sim_run(uint32_t t1)
{
    for (; sim.t < t1; sim.t++) {
        const negobs_alert_input_t *p = NULL;
        if (sim.feed && sim.t % 100u == 0u) {
            sim.in.verdict_ms = sim.t;
            p = &sim.in;
        }
        assert_int_equal(negobs_alert_update(&sim.a, sim.t, p, &sim.cmd),
                         NEGOBS_OK);
        assert_true((int32_t)(sim.cmd.next_change_ms - sim.t) > 0);
        assert_int_equal(sim.cmd.duty_permille,
                         sim.cmd.on ? sim.cfg.intensity_permille : 0);
        if (sim.cmd.on != sim.on) {
            assert_true(sim.n < MAX_EDGES);
            sim.e[sim.n].t = sim.t;
            sim.e[sim.n].on = sim.cmd.on;
            sim.n++;
            sim.on = sim.cmd.on;
        }
    }
}

/* Assert the edges recorded from index `from` equal times[] (alternating
 * on, off, on, ... starting with on). */
static void expect_edges(int from, const uint32_t *times, int count)
{
    int i;
    assert_true(sim.n - from >= count);
    for (i = 0; i < count; i++) {
        if (sim.e[from + i].t != times[i] ||
            sim.e[from + i].on != ((i % 2) == 0)) {
            print_error("edge %d: got t=%u on=%d, want t=%u on=%d\n", i,
                        sim.e[from + i].t, sim.e[from + i].on, times[i],
                        (i % 2) == 0);
        }
        assert_int_equal(sim.e[from + i].t, times[i]);
        assert_int_equal(sim.e[from + i].on, (i % 2) == 0);
    }
}

static void test_alert_ready_self_test_then_silence(void **state)
{
    static const uint32_t want[] = {0, 100, 200, 300};
    (void)state;
    sim_init(1);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(3000);
    expect_edges(0, want, 4);
    assert_int_equal(sim.n, 4);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NONE);
}

static void test_alert_imminent_300_on_100_off(void **state)
{
    static const uint32_t want[] = {0, 300, 400, 700, 800, 1100};
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_IMMINENT, 900, 0, 0);
    sim_run(1150);
    expect_edges(0, want, 6);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_IMMINENT);
}

static void test_alert_caution_bands_by_distance(void **state)
{
    static const uint32_t far[] = {0, 80, 160, 240, 1000, 1080, 1160, 1240};
    static const uint32_t mid[] = {1900, 1980, 2060, 2140, 2500, 2580};
    static const uint32_t near[] = {4000, 4080, 4160, 4240, 4400, 4480};
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_CAUTION, 3500, 0, 0);
    sim_run(1900);
    expect_edges(0, far, 8);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_FAR);
    /* Band change: at 1900 the FAR cycle is in its gap, so MID starts with
     * that verdict. */
    sim_set(NEGOBS_LEVEL_CAUTION, 2500, 0, 0);
    sim_run(2700);
    expect_edges(8, mid, 6);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_MID);
    sim_run(3950);
    sim_set(NEGOBS_LEVEL_CAUTION, 1800, 0, 0);
    /* The MID cycle in progress started at 3700 and is in its gap until
     * 4300: the band switches with the next verdict (4000). */
    {
        int from = sim.n;
        sim_run(4500);
        expect_edges(from, near, 6);
    }
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_NEAR);
}

static void test_alert_binary_mode_has_one_caution(void **state)
{
    (void)state;
    memset(&sim, 0, sizeof sim);
    negobs_alert_config_default(&sim.cfg);
    sim.cfg.ready_on_start = 0;
    sim.cfg.binary_mode = 1;
    assert_int_equal(negobs_alert_init(&sim.a, &sim.cfg, NULL, 0), NEGOBS_OK);
    sim.feed = 1;
    sim_set(NEGOBS_LEVEL_CAUTION, 3900, 0, 0);
    sim_run(500);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_MID);
    sim_set(NEGOBS_LEVEL_CAUTION, 1600, 0, 0);
    sim_run(1500);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_MID);
}

static void test_alert_no_info_entry_burst_then_periodic(void **state)
{
    static const uint32_t want[] = {0,    400,  600,  1000, 1200,
                                    1600, 1800, 2400, 4800, 5400};
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_NONE, -1, 1, 0);
    sim_run(5500);
    expect_edges(0, want, 10);
}

static void test_alert_no_info_rearm(void **state)
{
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_NONE, -1, 1, 0);
    sim_run(3000);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(5000);
    /* Back within the re-arm time: straight to the periodic pulse. */
    sim_set(NEGOBS_LEVEL_NONE, -1, 1, 0);
    {
        int from = sim.n;
        sim_run(6000);
        assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NO_INFO);
        assert_true(sim.n - from >= 2);
        assert_int_equal(sim.e[from + 1].t - sim.e[from].t, 600);
    }
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(18000);
    sim_set(NEGOBS_LEVEL_NONE, -1, 1, 0);
    sim_run(18100);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NO_INFO_ENTRY);
}

static void test_alert_watchdog_stale_verdict_gives_no_info(void **state)
{
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(1001); /* last verdict at 1000 */
    sim.feed = 0;
    sim_run(1300);
    assert_int_equal(sim.n, 0);
    sim_run(1400);
    /* stale_ms = 300: NO_INFO from 1301. */
    assert_true(sim.n >= 1);
    assert_int_equal(sim.e[0].t, 1301);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NO_INFO_ENTRY);
    /* Before the first verdict ever: READY, then NO_INFO. */
    sim_init(1);
    sim.feed = 0;
    sim_run(1000);
    assert_int_equal(sim.e[0].t, 0);
    assert_int_equal(sim.e[4].t, 400);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NO_INFO_ENTRY);
}

/* sim_init() with the heartbeat off (tests that count every edge of
 * another pattern over many seconds of "clear"). */
static void sim_init_quiet(int ready)
{
    sim_init(ready);
    sim.cfg.heartbeat_period_ms = 0;
    assert_int_equal(negobs_alert_init(&sim.a, &sim.cfg, NULL, 0), NEGOBS_OK);
}

static void test_alert_low_battery_once_per_period(void **state)
{
    static const uint32_t want[] = {0, 80, 200, 280, 400, 480, 600, 680};
    static const uint32_t again[] = {60000, 60080};
    (void)state;
    sim_init_quiet(0);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 1);
    sim_run(59000);
    expect_edges(0, want, 8);
    assert_int_equal(sim.n, 8);
    sim_run(61000);
    expect_edges(8, again, 2);
    assert_int_equal(sim.n, 16);
}

static void test_alert_imminent_preempts_caution_at_once(void **state)
{
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_CAUTION, 3500, 0, 0);
    sim_run(500); /* in the long gap of the FAR cycle */
    sim_set(NEGOBS_LEVEL_IMMINENT, 1400, 0, 0);
    sim_run(501);
    assert_int_equal(sim.e[sim.n - 1].t, 500);
    assert_int_equal(sim.e[sim.n - 1].on, 1);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_IMMINENT);
}

static void test_alert_imminent_survives_degraded_blip(void **state)
{
    int i;
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_IMMINENT, 1000, 0, 0);
    sim_run(1000);
    sim_set(NEGOBS_LEVEL_NONE, -1, 1, 0); /* degraded for 0.5 s */
    sim_run(1500);
    for (i = 0; i < sim.n; i++) {
        /* Still the 300/100 rhythm: no 400 ms NO_INFO pulse. */
        if (sim.e[i].on && i + 1 < sim.n) {
            assert_int_equal(sim.e[i + 1].t - sim.e[i].t, 300);
        }
    }
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_IMMINENT);
    /* After imminent_hold_ms (1 s) without IMMINENT: NO_INFO. */
    sim_run(3000);
    assert_true(sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO_ENTRY ||
                sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO);
}

static void test_alert_caution_not_cut_by_lower_priority(void **state)
{
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_CAUTION, 3500, 0, 0);
    sim_run(1000);
    /* 1000: a new double pulse starts; degrade now: caution has priority
     * over NO_INFO only while the verdict says CAUTION. */
    sim_set(NEGOBS_LEVEL_NONE, -1, 1, 0);
    sim_run(1020);
    /* The pulse that began at 1000 is not cut. */
    assert_int_equal(sim.e[sim.n - 1].t, 1000);
    assert_int_equal(sim.cmd.on, 1);
    sim_run(1100);
    assert_int_equal(sim.e[sim.n - 1].t, 1080);
    assert_int_equal(sim.e[sim.n - 1].on, 0);
    assert_true(sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO_ENTRY);
    /* A 100 ms gap keeps the two patterns apart, then the 400 ms pulse. */
    sim_run(1700);
    assert_int_equal(sim.e[sim.n - 2].t, 1180);
    assert_int_equal(sim.e[sim.n - 2].on, 1);
    assert_int_equal(sim.e[sim.n - 1].t, 1580);
}

static void test_alert_caution_beats_no_info(void **state)
{
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_CAUTION, 2500, 1, 0);
    sim_run(700);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_MID);
}

static void test_alert_min_pulse_holds_under_random_inputs(void **state)
{
    uint32_t rng = 99;
    uint32_t next_change = 0;
    int i;
    (void)state;
    sim_init(1);
    sim.feed = 0;
    for (sim.t = 0; sim.t < 120000u;) {
        if (sim.t >= next_change) {
            uint32_t r = test_lcg_next(&rng);
            sim.in.level = (negobs_alert_level_t)(r % 3u);
            sim.in.range_mm = (int32_t)(1000u + (r >> 4) % 4000u);
            sim.in.no_info = (int32_t)((r >> 12) % 4u == 0u);
            sim.in.battery_low = (int32_t)((r >> 14) % 8u == 0u);
            sim.in.verdict_ms = sim.t;
            next_change = sim.t + 5u + (r >> 16) % 200u;
            assert_int_equal(
                negobs_alert_update(&sim.a, sim.t, &sim.in, &sim.cmd),
                NEGOBS_OK);
        } else {
            assert_int_equal(
                negobs_alert_update(&sim.a, sim.t, NULL, &sim.cmd), NEGOBS_OK);
        }
        if (sim.cmd.on != sim.on) {
            if (sim.n < MAX_EDGES) {
                sim.e[sim.n].t = sim.t;
                sim.e[sim.n].on = sim.cmd.on;
                sim.n++;
            }
            sim.on = sim.cmd.on;
        }
        sim.t++;
    }
    assert_true(sim.n > 100);
    for (i = 0; i + 1 < sim.n; i++) {
        if (sim.e[i].on) {
            assert_true(sim.e[i + 1].t - sim.e[i].t >= 80u);
        }
    }
}

static void test_alert_schedule_lists_upcoming_segments(void **state)
{
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_IMMINENT, 1000, 0, 0);
    sim_run(1);
    assert_int_equal(sim.cmd.n_segments, NEGOBS_ALERT_MAX_SEGMENTS);
    assert_int_equal(sim.cmd.segments[0].start_ms, 0);
    assert_int_equal(sim.cmd.segments[0].on, 1);
    assert_int_equal(sim.cmd.segments[1].start_ms, 300);
    assert_int_equal(sim.cmd.segments[1].on, 0);
    assert_int_equal(sim.cmd.segments[2].start_ms, 400);
    assert_int_equal(sim.cmd.segments[2].on, 1);
    assert_int_equal(sim.cmd.segments[2].duty_permille, 1000);
    assert_int_equal(sim.cmd.next_change_ms, 300);
}

/* Clear is not silence: one 80 ms pulse every 5 s, its gap first, so a
 * dead device (no pulse) is told apart from "nothing ahead". */
static void test_alert_heartbeat_pulses_while_clear(void **state)
{
    static const uint32_t want[] = {4920, 5000, 9920, 10000, 14920, 15000};
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(16000);
    expect_edges(0, want, 6);
    assert_int_equal(sim.n, 6);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NONE);
    /* the schedule lists the next beat */
    sim_run(16001);
    assert_true(sim.cmd.n_segments >= 2);
    assert_int_equal(sim.cmd.segments[1].start_ms, 19920);
    assert_int_equal(sim.cmd.segments[1].on, 1);
    assert_int_equal(sim.cmd.segments[2].start_ms, 20000);
    assert_int_equal(sim.cmd.segments[2].on, 0);
}

static void test_alert_heartbeat_configurable_and_off(void **state)
{
    static const uint32_t want[] = {1900, 2000, 3900, 4000};
    (void)state;
    sim_init(0);
    sim.cfg.heartbeat_period_ms = 2000;
    sim.cfg.heartbeat_pulse_ms = 100;
    assert_int_equal(negobs_alert_init(&sim.a, &sim.cfg, NULL, 0), NEGOBS_OK);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(4500);
    expect_edges(0, want, 4);
    assert_int_equal(sim.n, 4);
    sim_init_quiet(0);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(30000);
    assert_int_equal(sim.n, 0);
}

/* The heartbeat has the lowest priority: a caution verdict pre-empts it
 * at once (a started beat keeps its minimum pulse); after the caution,
 * clear starts again with the gap, never with a pulse that would read
 * as a third caution pulse. */
static void test_alert_heartbeat_yields_to_warnings(void **state)
{
    int i;
    (void)state;
    sim_init(0);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(4900);
    assert_int_equal(sim.n, 0);
    sim_set(NEGOBS_LEVEL_CAUTION, 2500, 0, 0);
    sim.in.verdict_ms = sim.t;
    assert_int_equal(negobs_alert_update(&sim.a, sim.t, &sim.in, &sim.cmd),
                     NEGOBS_OK);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_MID);
    assert_int_equal(sim.cmd.on, 1);
    sim_run(6000);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim.n = 0;
    sim_run(10000);
    /* first heartbeat pulse at least a whole gap after the last caution
     * pulse ended */
    for (i = 0; i < sim.n; i++) {
        if (sim.e[i].on && sim.e[i].t > 6600) {
            assert_true(sim.e[i].t >= 6100 + 4920);
        }
    }
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NONE);
    /* no verdicts: no-information, not a heartbeat */
    sim.feed = 0;
    sim_run(10500);
    assert_true(sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO_ENTRY ||
                sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO);
}

static void test_alert_heartbeat_config_checks(void **state)
{
    negobs_alert_config_t cfg;
    negobs_alert_t a;
    (void)state;
    negobs_alert_config_default(&cfg);
    assert_int_equal(cfg.heartbeat_period_ms, 5000);
    assert_int_equal(cfg.heartbeat_pulse_ms, 80);
    cfg.heartbeat_period_ms = 999;
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    cfg.heartbeat_period_ms = 60001;
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    cfg.heartbeat_period_ms = 1000;
    cfg.heartbeat_pulse_ms = 251; /* more than a quarter of the period */
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    cfg.heartbeat_pulse_ms = 79; /* shorter than min_pulse_ms */
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    cfg.heartbeat_pulse_ms = 250;
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_OK);
    cfg.heartbeat_period_ms = 0; /* off: the pulse is not looked at */
    cfg.heartbeat_pulse_ms = 0;
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_OK);
}

static void test_alert_config_and_argument_checks(void **state)
{
    negobs_alert_config_t cfg;
    negobs_alert_t a;
    negobs_motor_cmd_t cmd;
    size_t bytes = 7;
    (void)state;
    negobs_alert_config_default(&cfg);
    assert_int_equal(negobs_alert_workspace_size(&cfg, &bytes), NEGOBS_OK);
    assert_int_equal(bytes, 0);
    cfg.min_pulse_ms = 100; /* longer than the 80 ms caution pulses */
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    negobs_alert_config_default(&cfg);
    cfg.intensity_permille = 0;
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    negobs_alert_config_default(&cfg);
    cfg.band_far_mm = 1000; /* below band_mid */
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_alert_init(NULL, &cfg, NULL, 0), NEGOBS_ERR_INVAL);
    memset(&a, 0, sizeof a);
    assert_int_equal(negobs_alert_update(&a, 0, NULL, &cmd), NEGOBS_ERR_STATE);
    assert_int_equal(negobs_alert_update(NULL, 0, NULL, &cmd),
                     NEGOBS_ERR_INVAL);
    negobs_alert_config_default(&cfg);
    cfg.intensity_permille = 400;
    assert_int_equal(negobs_alert_init(&a, &cfg, NULL, 0), NEGOBS_OK);
    assert_int_equal(negobs_alert_update(&a, 0, NULL, NULL), NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_alert_update(&a, 0, NULL, &cmd), NEGOBS_OK);
    assert_int_equal(cmd.pattern, NEGOBS_PATTERN_READY);
    assert_int_equal(cmd.duty_permille, 400);
}

/* CLEAR with short sight: one 160 ms pulse every 2 s. It pre-empts the
 * READY self-test (higher priority), is pre-empted at once by a caution,
 * and comes back after it; a full CLEAR ends it after the pulse. */
static void test_alert_short_sight_gentle_pattern(void **state)
{
    static const uint32_t want[] = {0, 160, 2000, 2160, 4000, 4160};
    (void)state;
    sim_init(1);
    sim.in.short_sight = 1;
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(300);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_SHORT_SIGHT);
    sim_init(0);
    sim.in.short_sight = 1;
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(4500);
    expect_edges(0, want, 6);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_SHORT_SIGHT);
    /* a caution verdict at 6000, while the short-sight pulse is on: it
     * pre-empts (priority), the pulse keeps its minimum length */
    sim_run(6000);
    sim_set(NEGOBS_LEVEL_CAUTION, 2500, 0, 0);
    sim_run(6300);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_CAUTION_MID);
    /* back to short sight: it waits for the caution's pulse to end */
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim_run(7000);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_SHORT_SIGHT);
    /* an imminent hazard too */
    sim_set(NEGOBS_LEVEL_IMMINENT, 900, 0, 0);
    sim_run(7300);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_IMMINENT);
    /* NO_INFO never plays short sight, nor does a stale verdict */
    sim_set(NEGOBS_LEVEL_NONE, -1, 1, 0);
    sim_run(9000);
    assert_true(sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO ||
                sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO_ENTRY);
    sim_set(NEGOBS_LEVEL_NONE, -1, 0, 0);
    sim.feed = 0;
    sim_run(12000);
    assert_true(sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO ||
                sim.cmd.pattern == NEGOBS_PATTERN_NO_INFO_ENTRY);
    /* a full CLEAR: silence once the pulse in progress has ended */
    sim.feed = 1;
    sim.in.short_sight = 0;
    sim_run(16000);
    assert_int_equal(sim.cmd.pattern, NEGOBS_PATTERN_NONE);
    assert_int_equal(sim.cmd.on, 0);
}

static void test_alert_input_from_detect_result(void **state)
{
    negobs_detect_result_t res;
    negobs_alert_input_t in;
    (void)state;
    memset(&res, 0, sizeof res);
    res.state = NEGOBS_DETECT_NO_INFO;
    res.level = NEGOBS_LEVEL_CAUTION;
    res.nearest_range_mm = 2700;
    negobs_alert_input_from_result(&res, 1, 1234, &in);
    assert_int_equal(in.level, NEGOBS_LEVEL_CAUTION);
    assert_int_equal(in.range_mm, 2700);
    assert_int_equal(in.no_info, 1);
    assert_int_equal(in.battery_low, 1);
    assert_int_equal(in.verdict_ms, 1234);
    assert_int_equal(in.short_sight, 0);
    /* short sight only on a CLEAR verdict */
    res.short_sight = 1;
    negobs_alert_input_from_result(&res, 0, 1300, &in);
    assert_int_equal(in.short_sight, 0);
    res.state = NEGOBS_DETECT_CLEAR;
    res.level = NEGOBS_LEVEL_NONE;
    negobs_alert_input_from_result(&res, 0, 1300, &in);
    assert_int_equal(in.short_sight, 1);
    assert_int_equal(in.no_info, 0);
    negobs_alert_input_from_result(NULL, 0, 5, &in);
    assert_int_equal(in.no_info, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alert_ready_self_test_then_silence),
        cmocka_unit_test(test_alert_imminent_300_on_100_off),
        cmocka_unit_test(test_alert_caution_bands_by_distance),
        cmocka_unit_test(test_alert_binary_mode_has_one_caution),
        cmocka_unit_test(test_alert_no_info_entry_burst_then_periodic),
        cmocka_unit_test(test_alert_no_info_rearm),
        cmocka_unit_test(test_alert_watchdog_stale_verdict_gives_no_info),
        cmocka_unit_test(test_alert_low_battery_once_per_period),
        cmocka_unit_test(test_alert_imminent_preempts_caution_at_once),
        cmocka_unit_test(test_alert_imminent_survives_degraded_blip),
        cmocka_unit_test(test_alert_caution_not_cut_by_lower_priority),
        cmocka_unit_test(test_alert_caution_beats_no_info),
        cmocka_unit_test(test_alert_min_pulse_holds_under_random_inputs),
        cmocka_unit_test(test_alert_schedule_lists_upcoming_segments),
        cmocka_unit_test(test_alert_heartbeat_pulses_while_clear),
        cmocka_unit_test(test_alert_heartbeat_configurable_and_off),
        cmocka_unit_test(test_alert_heartbeat_yields_to_warnings),
        cmocka_unit_test(test_alert_heartbeat_config_checks),
        cmocka_unit_test(test_alert_config_and_argument_checks),
        cmocka_unit_test(test_alert_short_sight_gentle_pattern),
        cmocka_unit_test(test_alert_input_from_detect_result),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
