/*
 * negobs_run's bridge from the library's alert state machine to motor
 * schedules (firmware_app/app_alert.c), with a fake clock: the schedules
 * are the patterns of negobs/alert.h, the no-information switch comes
 * stale_ms after the last verdict without any further call, and an
 * executor that only sees the posted schedules drives the motor exactly
 * as the library does when it is called every millisecond.
 */
#include <string.h>

#include "app_alert.h"
#include "cmocka_all.h"

static negobs_alert_config_t cfg_default(void)
{
    negobs_alert_config_t c;
    negobs_alert_config_default(&c);
    return c;
}

static negobs_alert_input_t verdict(app_verdict_t v, int32_t range_mm,
                                    uint32_t t)
{
    app_frame_stats_t st;
    negobs_alert_input_t in;
    memset(&st, 0, sizeof st);
    st.nearest_range_mm = range_mm;
    app_alert_input(v, &st, t, &in);
    return in;
}

/* Schedule segments as "duty/ms" pairs for compact comparisons. */
static void expect_segments(const negobs_motor_schedule_t *s,
                            const uint16_t *want, uint32_t n_pairs,
                            uint8_t loop_start)
{
    uint32_t i;
    assert_int_equal(s->count, n_pairs);
    for (i = 0; i < n_pairs; i++) {
        assert_int_equal(s->seg[i].duty_permille, want[2 * i]);
        assert_int_equal(s->seg[i].duration_ms, want[2 * i + 1]);
    }
    assert_int_equal(s->loop_start, loop_start);
    assert_int_equal(negobs_motor_schedule_check(s), NEGOBS_OK);
}

static void test_noinfo_schedule_is_the_library_pattern(void **state)
{
    negobs_alert_config_t c = cfg_default();
    negobs_motor_schedule_t s;
    static const uint16_t want[] = {1000, 380, 0, 200, 1000, 400, 0, 200,
                                    1000, 400, 0, 200, 1000, 600, 0, 2400};
    (void)state;
    assert_int_equal(app_alert_noinfo_schedule(&c, 20, &s), NEGOBS_OK);
    expect_segments(&s, want, 8, 6);
    /* A lead that would cut the first pulse below 80 ms is not applied. */
    assert_int_equal(app_alert_noinfo_schedule(&c, 330, &s), NEGOBS_OK);
    assert_int_equal(s.seg[0].duration_ms, 400);
    c.band_mid_mm = c.band_far_mm + 1; /* invalid */
    assert_int_equal(app_alert_noinfo_schedule(&c, 0, &s), NEGOBS_ERR_INVAL);
}

static void test_start_plays_ready_then_noinfo(void **state)
{
    app_alert_t a;
    negobs_alert_config_t c = cfg_default();
    negobs_motor_schedule_t s;
    static const uint16_t want[] = {1000, 100, 0, 100, 1000, 100, 0, 100,
                                    1000, 400, 0, 200, 1000, 400, 0, 200,
                                    1000, 400, 0, 200, 1000, 600, 0, 2400};
    (void)state;
    assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
    assert_int_equal(app_alert_step(&a, 5000u, NULL, &s), NEGOBS_OK);
    assert_int_equal(app_alert_pattern(&a), NEGOBS_PATTERN_READY);
    expect_segments(&s, want, 12, 10);
}

/* After a verdict, the schedule alone switches to no-information
 * stale_ms + 1 ms later (the library's "older than stale_ms"). */
static void test_clear_then_noinfo_after_stale_ms(void **state)
{
    app_alert_t a;
    negobs_alert_config_t c = cfg_default();
    negobs_motor_schedule_t s;
    negobs_alert_input_t in;
    (void)state;
    c.ready_on_start = 0;
    assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
    in = verdict(APP_VERDICT_CLEAR, -1, 100u);
    assert_int_equal(app_alert_step(&a, 100u, &in, &s), NEGOBS_OK);
    assert_int_equal(app_alert_pattern(&a), NEGOBS_PATTERN_NONE);
    assert_int_equal(s.seg[0].duty_permille, 0);
    assert_int_equal(s.seg[0].duration_ms, 301);
    assert_int_equal(s.seg[1].duty_permille, 1000);
    assert_int_equal(s.seg[1].duration_ms, 400); /* entry burst */
    assert_int_not_equal(s.loop_start, NEGOBS_MOTOR_NO_LOOP);
    /* The same with watchdog_ms = 1000 as negobs_run sets it. */
    c.stale_ms = 1000;
    assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
    in = verdict(APP_VERDICT_CLEAR, -1, 100u);
    assert_int_equal(app_alert_step(&a, 100u, &in, &s), NEGOBS_OK);
    assert_int_equal(s.seg[0].duration_ms, 1001);
}

static void test_caution_bands_and_imminent(void **state)
{
    static const struct {
        app_verdict_t v;
        int32_t range_mm;
        uint16_t gap_ms;
        negobs_alert_pattern_t pat;
    } cases[] = {
        {APP_VERDICT_CAUTION, 3500, 760, NEGOBS_PATTERN_CAUTION_FAR},
        {APP_VERDICT_CAUTION, 2500, 360, NEGOBS_PATTERN_CAUTION_MID},
        {APP_VERDICT_CAUTION, 1500, 160, NEGOBS_PATTERN_CAUTION_NEAR},
        {APP_VERDICT_IMMINENT, 900, 100, NEGOBS_PATTERN_IMMINENT},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        app_alert_t a;
        negobs_alert_config_t c = cfg_default();
        negobs_motor_schedule_t s;
        negobs_alert_input_t in;
        c.ready_on_start = 0;
        c.stale_ms = 5000; /* long enough to see whole periods */
        assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
        in = verdict(cases[i].v, cases[i].range_mm, 0u);
        assert_int_equal(app_alert_step(&a, 0u, &in, &s), NEGOBS_OK);
        assert_int_equal(app_alert_pattern(&a), cases[i].pat);
        if (cases[i].v == APP_VERDICT_IMMINENT) {
            assert_int_equal(s.seg[0].duty_permille, 1000);
            assert_int_equal(s.seg[0].duration_ms, 300);
            assert_int_equal(s.seg[1].duration_ms, cases[i].gap_ms);
        } else {
            /* 80 on, 80 off, 80 on, then the band's gap */
            assert_int_equal(s.seg[0].duration_ms, 80);
            assert_int_equal(s.seg[1].duration_ms, 80);
            assert_int_equal(s.seg[2].duration_ms, 80);
            assert_int_equal(s.seg[3].duty_permille, 0);
            assert_int_equal(s.seg[3].duration_ms, cases[i].gap_ms);
        }
    }
}

/* Recording output for the executor (time of every level change). */
typedef struct fake_out {
    uint64_t *now;
    uint16_t level;
} fake_out_t;

static negobs_status_t fake_set(void *ctx, uint16_t duty)
{
    ((fake_out_t *)ctx)->level = duty;
    return NEGOBS_OK;
}

static void fake_close(void *ctx)
{
    (void)ctx;
}

static const negobs_motor_out_ops_t fake_ops = {
    .name = "fake",
    .set = fake_set,
    .close = fake_close,
};

/*
 * Random verdicts at random times (including pauses far beyond stale_ms):
 * an executor that only plays the posted schedules must give, at every
 * millisecond, the level of a reference library instance driven as
 * negobs/alert.h prescribes (a call with each verdict and again at each
 * cmd.next_change_ms, nothing in between); and no pulse may be shorter
 * than min_pulse_ms. (The reference is not called every millisecond: the
 * library's output depends slightly on when it is called, e.g. the
 * IMMINENT hold restarts at every call made while the verdict is fresh.)
 */
static void follow_the_library(int32_t stale_ms)
{
    negobs_alert_config_t c = cfg_default();
    app_alert_t a;
    negobs_alert_t ref;
    negobs_motor_cmd_t cmd;
    negobs_motor_exec_t ex;
    negobs_motor_out_t out;
    fake_out_t fo;
    uint64_t now = 0;
    uint32_t seed = 12345u;
    uint32_t next_verdict = 500u;
    uint32_t on_since = 0;
    uint16_t prev = 0;
    uint32_t pulses = 0;
    uint32_t mismatches = 0;
    uint32_t t;
    uint32_t ref_next = 0;
    int32_t ref_on = 0;
    c.stale_ms = stale_ms;
    memset(&fo, 0, sizeof fo);
    fo.now = &now;
    out.ops = &fake_ops;
    out.ctx = &fo;
    negobs_motor_exec_init(&ex, &out);
    assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
    assert_int_equal(negobs_alert_init(&ref, &c, NULL, 0), NEGOBS_OK);
    for (t = 1000u; t < 1000u + 120000u; t++) {
        const negobs_alert_input_t *inp = NULL;
        negobs_alert_input_t in;
        negobs_motor_schedule_t s;
        now = t;
        if (t == 1000u || t >= next_verdict) {
            if (t > 1000u) {
                static const app_verdict_t vs[] = {
                    APP_VERDICT_CLEAR,    APP_VERDICT_CLEAR,
                    APP_VERDICT_CAUTION,  APP_VERDICT_CAUTION,
                    APP_VERDICT_IMMINENT, APP_VERDICT_NO_INFO};
                app_verdict_t v = vs[test_lcg_next(&seed) % 6u];
                in = verdict(v, 800 + (int32_t)(test_lcg_next(&seed) % 3500u),
                             t);
                inp = &in;
            }
            assert_int_equal(app_alert_step(&a, t, inp, &s), NEGOBS_OK);
            assert_int_equal(negobs_motor_exec_start(&ex, &s, now), NEGOBS_OK);
            /* mostly frames 33..400 ms apart, sometimes a long stall */
            next_verdict = t + 33u + test_lcg_next(&seed) % 370u;
            if (test_lcg_next(&seed) % 20u == 0u) {
                next_verdict += (uint32_t)stale_ms + 4000u;
            }
        } else {
            (void)negobs_motor_exec_tick(&ex, now);
        }
        if (t == 1000u || inp != NULL || (int32_t)(t - ref_next) >= 0) {
            assert_int_equal(negobs_alert_update(&ref, t, inp, &cmd),
                             NEGOBS_OK);
            ref_on = cmd.on;
            ref_next = cmd.next_change_ms;
        }
        if ((ref_on ? 1000u : 0u) != fo.level) {
            mismatches++;
        }
        if (fo.level != prev) {
            if (fo.level > 0) {
                on_since = t;
            } else {
                assert_true(t - on_since >= (uint32_t)c.min_pulse_ms);
                pulses++;
            }
            prev = fo.level;
        }
    }
    assert_int_equal(mismatches, 0);
    print_message("stale_ms %d: %u pulses\n", (int)stale_ms, (unsigned)pulses);
    assert_true(pulses > 100); /* the run really exercised the motor */
}

/*
 * The heartbeat reaches the motor: clear verdicts every 33 ms for 12 s,
 * the executor playing only the posted schedules switches the motor on for
 * 80 ms every 5 s (its gap first), and stops beating when the verdicts
 * stop (no-information instead).
 */
static void test_heartbeat_reaches_the_motor(void **state)
{
    negobs_alert_config_t c = cfg_default();
    app_alert_t a;
    negobs_motor_exec_t ex;
    negobs_motor_out_t out;
    fake_out_t fo;
    uint64_t now = 0;
    uint32_t ons[8];
    uint32_t offs[8];
    uint32_t n_on = 0;
    uint32_t n_off = 0;
    uint16_t prev = 0;
    uint32_t t;
    (void)state;
    c.ready_on_start = 0;
    memset(&fo, 0, sizeof fo);
    fo.now = &now;
    out.ops = &fake_ops;
    out.ctx = &fo;
    negobs_motor_exec_init(&ex, &out);
    assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
    for (t = 1000u; t < 13000u; t++) {
        now = t;
        if ((t - 1000u) % 33u == 0u) {
            negobs_alert_input_t in = verdict(APP_VERDICT_CLEAR, -1, t);
            negobs_motor_schedule_t s;
            assert_int_equal(app_alert_step(&a, t, &in, &s), NEGOBS_OK);
            assert_int_equal(negobs_motor_exec_start(&ex, &s, now), NEGOBS_OK);
        } else {
            (void)negobs_motor_exec_tick(&ex, now);
        }
        if (fo.level != prev) {
            if (fo.level > 0 && n_on < 8u) {
                ons[n_on++] = t;
            } else if (fo.level == 0 && n_off < 8u) {
                offs[n_off++] = t;
            }
            prev = fo.level;
        }
    }
    assert_int_equal(app_alert_pattern(&a), NEGOBS_PATTERN_NONE);
    assert_int_equal(n_on, 2);
    assert_int_equal(n_off, 2);
    assert_int_equal(ons[0], 1000u + 4920u);
    assert_int_equal(offs[0], 1000u + 5000u);
    assert_int_equal(ons[1], 1000u + 9920u);
    assert_int_equal(offs[1], 1000u + 10000u);
}

static void test_schedules_follow_the_library_every_ms(void **state)
{
    (void)state;
    follow_the_library(300);  /* the product's watchdog_ms */
    follow_the_library(4000); /* the emulated-hardware sections' */
}

/*
 * Every schedule ends in the library's repeating no-information pulse
 * (so the motor thread never runs out of pattern), and for stale_ms up to
 * 5 s it holds the current pattern until then: no no-information pulse
 * starts before stale_ms. Beyond what 64 segments hold (stale_ms 10 s of
 * the fastest caution) no-information comes early rather than never.
 */
static void test_schedules_are_complete(void **state)
{
    static const int32_t stales[] = {300, 1000, 4000, 5000, 10000};
    static const struct {
        app_verdict_t v;
        int32_t range_mm;
    } vs[] = {
        {APP_VERDICT_CLEAR, -1},     {APP_VERDICT_CAUTION, 3500},
        {APP_VERDICT_CAUTION, 2500}, {APP_VERDICT_CAUTION, 1500},
        {APP_VERDICT_IMMINENT, 800}, {APP_VERDICT_NO_INFO, -1},
    };
    size_t i;
    size_t j;
    (void)state;
    for (i = 0; i < sizeof stales / sizeof stales[0]; i++) {
        for (j = 0; j < sizeof vs / sizeof vs[0]; j++) {
            app_alert_t a;
            negobs_alert_config_t c = cfg_default();
            negobs_motor_schedule_t s;
            negobs_alert_input_t in;
            uint32_t k;
            uint32_t t = 0;
            uint32_t first_long = 0xFFFFFFFFu;
            c.ready_on_start = 0;
            c.stale_ms = stales[i];
            assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
            in = verdict(vs[j].v, vs[j].range_mm, 1000u);
            assert_int_equal(app_alert_step(&a, 1000u, &in, &s), NEGOBS_OK);
            assert_int_equal(negobs_motor_schedule_check(&s), NEGOBS_OK);
            assert_int_not_equal(s.loop_start, NEGOBS_MOTOR_NO_LOOP);
            assert_int_equal(s.count - s.loop_start, 2);
            assert_int_equal(s.seg[s.loop_start].duration_ms, 600);
            assert_int_equal(s.seg[s.loop_start + 1].duration_ms, 2400);
            /* the first no-information pulse (>= 400 ms on) */
            for (k = 0; k < s.count; k++) {
                if (s.seg[k].duty_permille > 0 &&
                    s.seg[k].duration_ms >= 400) {
                    first_long = t;
                    break;
                }
                t += s.seg[k].duration_ms;
            }
            if (vs[j].v == APP_VERDICT_NO_INFO) {
                assert_int_equal(first_long, 0);
            } else if (stales[i] <= 5000) {
                assert_true(first_long >= (uint32_t)stales[i]);
            } else {
                assert_true(first_long < 0xFFFFFFFFu);
            }
        }
    }
}

/* IMMINENT is not replaced by no-information when verdicts stop: it
 * keeps playing for imminent_hold_ms, then no-information follows. */
static void test_imminent_hold_outlives_stale(void **state)
{
    app_alert_t a;
    negobs_alert_config_t c = cfg_default();
    negobs_motor_schedule_t s;
    negobs_alert_input_t in;
    uint32_t i;
    uint32_t t = 0;
    uint32_t imminent_ms = 0;
    (void)state;
    c.ready_on_start = 0;
    assert_int_equal(app_alert_init(&a, &c), NEGOBS_OK);
    in = verdict(APP_VERDICT_IMMINENT, 700, 0u);
    assert_int_equal(app_alert_step(&a, 0u, &in, &s), NEGOBS_OK);
    /* imminent periods (300 on + 100 off) up to the first long pulse */
    for (i = 0; i + 1 < s.count && s.seg[i].duration_ms == 300 &&
                s.seg[i + 1].duration_ms == 100;
         i += 2) {
        t += 400u;
    }
    imminent_ms = t;
    assert_true(imminent_ms >= (uint32_t)c.imminent_hold_ms);
    assert_true(imminent_ms <=
                (uint32_t)(c.imminent_hold_ms + c.stale_ms + 400));
    /* then the no-information entry burst, looped tail */
    assert_int_equal(s.seg[i].duty_permille, 1000);
    assert_true(
        s.seg[i].duration_ms == 400 ||
        (s.seg[i].duration_ms == 300 && s.seg[i + 1].duty_permille == 0));
    assert_int_not_equal(s.loop_start, NEGOBS_MOTOR_NO_LOOP);
}

static void test_arguments(void **state)
{
    app_alert_t a;
    negobs_alert_config_t c = cfg_default();
    negobs_motor_schedule_t s;
    (void)state;
    assert_int_equal(app_alert_init(NULL, &c), NEGOBS_ERR_INVAL);
    assert_int_equal(app_alert_init(&a, NULL), NEGOBS_ERR_INVAL);
    c.min_pulse_ms = 10;
    assert_int_equal(app_alert_init(&a, &c), NEGOBS_ERR_INVAL);
    assert_int_equal(app_alert_step(NULL, 0u, NULL, &s), NEGOBS_ERR_INVAL);
    memset(&a, 0, sizeof a);
    assert_int_equal(app_alert_step(&a, 0u, NULL, &s), NEGOBS_ERR_STATE);
    assert_string_equal(app_alert_pattern_name(NEGOBS_PATTERN_IMMINENT),
                        "imminent");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_noinfo_schedule_is_the_library_pattern),
        cmocka_unit_test(test_start_plays_ready_then_noinfo),
        cmocka_unit_test(test_clear_then_noinfo_after_stale_ms),
        cmocka_unit_test(test_caution_bands_and_imminent),
        cmocka_unit_test(test_heartbeat_reaches_the_motor),
        cmocka_unit_test(test_schedules_follow_the_library_every_ms),
        cmocka_unit_test(test_schedules_are_complete),
        cmocka_unit_test(test_imminent_hold_outlives_stale),
        cmocka_unit_test(test_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
