/* Schedule executor with a fake clock and a recording output. */
#define _XOPEN_SOURCE 700

#include <string.h>
#include <time.h>

#include "cmocka_all.h"
#include "negobs_port/motor.h"

/* Output that records every level written. */
typedef struct rec_out {
    uint16_t levels[64];
    uint32_t n;
    int fail_next;      /* make the next N writes fail */
    volatile int down;  /* every write fails while set (output gone) */
    volatile int stuck; /* writes fail unless they repeat the last level
                           written (a PWM chip refusing new states) */
} rec_out_t;

static negobs_status_t rec_set(void *ctx, uint16_t duty)
{
    rec_out_t *r = ctx;
    if (r->down) {
        return NEGOBS_ERR_NODEV;
    }
    if (r->stuck && (r->n == 0 || r->levels[(r->n - 1) % 64] != duty)) {
        return NEGOBS_ERR_IO;
    }
    if (r->fail_next > 0) {
        r->fail_next--;
        return NEGOBS_ERR_IO;
    }
    if (r->n < 64) {
        r->levels[r->n] = duty;
    }
    r->n++;
    return NEGOBS_OK;
}

static void rec_close(void *ctx)
{
    (void)ctx;
}

static const negobs_motor_out_ops_t rec_ops = {
    .name = "rec",
    .set = rec_set,
    .close = rec_close,
};

static uint16_t last_level(const rec_out_t *r)
{
    assert_true(r->n > 0);
    return r->levels[r->n - 1];
}

static negobs_motor_schedule_t make(const uint16_t *pairs, uint8_t count,
                                    uint8_t loop_start)
{
    negobs_motor_schedule_t s;
    uint8_t i;
    memset(&s, 0, sizeof s);
    for (i = 0; i < count; i++) {
        s.seg[i].duty_permille = pairs[2 * i];
        s.seg[i].duration_ms = pairs[2 * i + 1];
    }
    s.count = count;
    s.loop_start = loop_start;
    return s;
}

static void test_exec_one_shot_pulses_then_idle(void **state)
{
    static const uint16_t ready[] = {1000, 100, 0, 100, 1000, 100};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_exec_t ex;
    negobs_motor_schedule_t s = make(ready, 3, NEGOBS_MOTOR_NO_LOOP);
    (void)state;
    memset(&r, 0, sizeof r);
    negobs_motor_exec_init(&ex, &out);
    assert_int_equal(negobs_motor_exec_start(&ex, &s, 1000), NEGOBS_OK);
    assert_int_equal(r.n, 1);
    assert_int_equal(last_level(&r), 1000);
    assert_int_equal(negobs_motor_exec_tick(&ex, 1050), 50);
    assert_int_equal(r.n, 1); /* no rewrite of an unchanged level */
    assert_int_equal(negobs_motor_exec_tick(&ex, 1100), 100);
    assert_int_equal(last_level(&r), 0);
    assert_int_equal(negobs_motor_exec_tick(&ex, 1199), 1);
    assert_int_equal(negobs_motor_exec_tick(&ex, 1200), 100);
    assert_int_equal(last_level(&r), 1000);
    assert_int_equal(negobs_motor_exec_tick(&ex, 1300), -1);
    assert_int_equal(last_level(&r), 0);
    assert_false(ex.active);
    assert_int_equal(r.n, 4);
}

static void test_exec_late_tick_keeps_pattern_phase(void **state)
{
    /* Caution pattern: 80 on, 80 off, 80 on, 760 off, repeated (1 s). */
    static const uint16_t caution[] = {1000, 80, 0, 80, 1000, 80, 0, 760};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_exec_t ex;
    negobs_motor_schedule_t s = make(caution, 4, 0);
    (void)state;
    memset(&r, 0, sizeof r);
    negobs_motor_exec_init(&ex, &out);
    assert_int_equal(negobs_motor_exec_start(&ex, &s, 0), NEGOBS_OK);
    /* 7 ms late: the off segment still ends at 160, not 167. */
    assert_int_equal(negobs_motor_exec_tick(&ex, 87), 73);
    assert_int_equal(last_level(&r), 0);
    assert_int_equal(negobs_motor_exec_tick(&ex, 161), 79);
    assert_int_equal(last_level(&r), 1000);
    /* Second period starts exactly at 1000. */
    assert_int_equal(negobs_motor_exec_tick(&ex, 999), 1);
    assert_int_equal(last_level(&r), 0);
    assert_int_equal(negobs_motor_exec_tick(&ex, 1000), 80);
    assert_int_equal(last_level(&r), 1000);
    /* Very late (a stall of ~1 h): same phase, no long catch-up loop. */
    assert_int_equal(negobs_motor_exec_tick(&ex, 3600000u + 170u), 70);
    assert_int_equal(last_level(&r), 1000);
}

static void test_exec_intro_then_loop_tail(void **state)
{
    /* No-information: 3 x 400 ms on entry, then 600 on / 2400 off. */
    static const uint16_t noinfo[] = {1000, 400, 0, 200, 1000, 400, 0, 200,
                                      1000, 400, 0, 400, 1000, 600, 0, 2400};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_exec_t ex;
    negobs_motor_schedule_t s = make(noinfo, 8, 6);
    (void)state;
    memset(&r, 0, sizeof r);
    negobs_motor_exec_init(&ex, &out);
    assert_int_equal(negobs_motor_exec_start(&ex, &s, 0), NEGOBS_OK);
    /* intro lasts 2000 ms; loop period 3000 ms starting at 2000. */
    (void)negobs_motor_exec_tick(&ex, 2100);
    assert_int_equal(last_level(&r), 1000);
    (void)negobs_motor_exec_tick(&ex, 2700);
    assert_int_equal(last_level(&r), 0);
    assert_int_equal(negobs_motor_exec_tick(&ex, 5000), 600);
    assert_int_equal(last_level(&r), 1000);
    assert_int_equal(ex.seg, 6); /* never back in the intro */
}

static void test_exec_rejects_bad_schedules(void **state)
{
    static const uint16_t too_strong[] = {1001, 100};
    static const uint16_t zero_loop[] = {1000, 100, 0, 0};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_exec_t ex;
    negobs_motor_schedule_t s;
    (void)state;
    memset(&r, 0, sizeof r);
    negobs_motor_exec_init(&ex, &out);
    s = make(too_strong, 1, NEGOBS_MOTOR_NO_LOOP);
    assert_int_equal(negobs_motor_exec_start(&ex, &s, 0), NEGOBS_ERR_INVAL);
    s = make(zero_loop, 2, 1);
    assert_int_equal(negobs_motor_exec_start(&ex, &s, 0), NEGOBS_ERR_INVAL);
    s = make(zero_loop, 2, 2);
    assert_int_equal(negobs_motor_schedule_check(&s), NEGOBS_ERR_INVAL);
    s.count = NEGOBS_MOTOR_MAX_SEGMENTS + 1;
    assert_int_equal(negobs_motor_schedule_check(&s), NEGOBS_ERR_INVAL);
    assert_int_equal(r.n, 0);
}

static void test_exec_retries_failed_write_and_stop_turns_off(void **state)
{
    static const uint16_t on[] = {700, 1000};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_exec_t ex;
    negobs_motor_schedule_t s = make(on, 1, 0);
    (void)state;
    memset(&r, 0, sizeof r);
    r.fail_next = 1;
    negobs_motor_exec_init(&ex, &out);
    assert_int_equal(negobs_motor_exec_start(&ex, &s, 0), NEGOBS_OK);
    assert_int_equal(ex.set_errors, 1);
    assert_int_equal(r.n, 0);
    (void)negobs_motor_exec_tick(&ex, 10);
    assert_int_equal(r.n, 1);
    assert_int_equal(last_level(&r), 700);
    negobs_motor_exec_stop(&ex);
    assert_int_equal(last_level(&r), 0);
    assert_int_equal(negobs_motor_exec_tick(&ex, 20), -1);
}

static void test_schedule_equal_compares_content(void **state)
{
    static const uint16_t a[] = {1000, 80, 0, 80};
    static const uint16_t b[] = {1000, 80, 0, 81};
    negobs_motor_schedule_t sa = make(a, 2, 0);
    negobs_motor_schedule_t sb = make(a, 2, 0);
    (void)state;
    assert_true(negobs_motor_schedule_equal(&sa, &sb));
    sb = make(b, 2, 0);
    assert_false(negobs_motor_schedule_equal(&sa, &sb));
    sb = make(a, 2, NEGOBS_MOTOR_NO_LOOP);
    assert_false(negobs_motor_schedule_equal(&sa, &sb));
}

#ifdef NEGOBS_TEST_THREADS
/* Real-time check of the thread: short margins-safe intervals only. */
static void sleep_ms(long ms)
{
    struct timespec ts;
    ts.tv_sec = ms / 1000;
    ts.tv_nsec = (ms % 1000) * 1000000L;
    (void)nanosleep(&ts, NULL);
}

static void test_thread_watchdog_plays_stale_pattern(void **state)
{
    static const uint16_t stale[] = {1000, 30000};
    static const uint16_t quiet[] = {0, 30000};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_thread_t t;
    negobs_motor_schedule_t st = make(stale, 1, 0);
    negobs_motor_schedule_t q = make(quiet, 1, 0);
    int i;
    (void)state;
    memset(&r, 0, sizeof r);
    /* Generous margins: loaded CI machines stall threads for tens of ms. */
    assert_int_equal(negobs_motor_thread_start(&t, &out, &st, 150), NEGOBS_OK);
    /* Fed every 10 ms: the watchdog stays quiet. */
    for (i = 0; i < 10; i++) {
        negobs_motor_thread_post(&t, &q);
        sleep_ms(10);
    }
    assert_int_equal(negobs_motor_thread_watchdog_fires(&t), 0);
    /* Starved: it must take over within its period (+ generous slack). */
    sleep_ms(600);
    assert_int_equal(negobs_motor_thread_watchdog_fires(&t), 1);
    negobs_motor_thread_stop(&t);
    assert_true(r.n >= 3);
    assert_int_equal(r.levels[r.n - 2], 1000); /* stale pattern played */
    assert_int_equal(r.levels[r.n - 1], 0);    /* off after stop */
}

static void test_thread_output_fault_retries_then_holds_no_info(void **state)
{
    static const uint16_t stale[] = {500, 30000};
    static const uint16_t p7[] = {700, 30000};
    static const uint16_t p3[] = {300, 30000};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_thread_t t;
    negobs_motor_schedule_t st = make(stale, 1, 0);
    negobs_motor_schedule_t a = make(p7, 1, 0);
    negobs_motor_schedule_t b = make(p3, 1, 0);
    bool failing = true;
    uint32_t n_down;
    int i;
    (void)state;
    memset(&r, 0, sizeof r);
    /* No watchdog: only the output fault may switch to `stale`. */
    assert_int_equal(negobs_motor_thread_start(&t, &out, &st, 0), NEGOBS_OK);
    negobs_motor_thread_post(&t, &a);
    sleep_ms(100);
    assert_int_equal(last_level(&r), 700);
    assert_int_equal(negobs_motor_thread_output_faults(&t, &failing), 0);
    assert_false(failing);
    /* The output goes away while a new pattern is asked for. */
    r.down = 1;
    negobs_motor_thread_post(&t, &b);
    sleep_ms(400);
    assert_int_equal(negobs_motor_thread_output_faults(&t, &failing), 1);
    assert_true(failing);
    assert_true(t.exec.set_errors >= 2); /* retried, not given up */
    n_down = r.n;
    /* Back: within a retry period `stale` is written, and it holds for
     * NEGOBS_MOTOR_RECOVER_HOLD_MS although `b` is posted all along. */
    r.down = 0;
    for (i = 0; i < 30; i++) {
        negobs_motor_thread_post(&t, &b);
        sleep_ms(10);
    }
    assert_int_equal(negobs_motor_thread_output_faults(&t, &failing), 1);
    assert_false(failing);
    assert_true(r.n > n_down);
    assert_int_equal(r.levels[n_down], 500);
    assert_int_equal(last_level(&r), 500);
    /* After the hold, the posted pattern resumes by itself. */
    for (i = 0; i < (int)(NEGOBS_MOTOR_RECOVER_HOLD_MS / 50u) + 20; i++) {
        negobs_motor_thread_post(&t, &b);
        sleep_ms(50);
    }
    assert_int_equal(last_level(&r), 300);
    negobs_motor_thread_stop(&t);
    assert_int_equal(last_level(&r), 0);
}

static void test_thread_rewrite_of_the_held_level_is_not_recovery(void **state)
{
    /* The no-info stand-in pulses 500 / 0: while only 0 (the level held)
     * can be written, the output is still failing. */
    static const uint16_t stale[] = {500, 100, 0, 100};
    static const uint16_t quiet[] = {0, 30000};
    static const uint16_t loud[] = {700, 30000};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_thread_t t;
    negobs_motor_schedule_t st = make(stale, 2, 0);
    negobs_motor_schedule_t q = make(quiet, 1, 0);
    negobs_motor_schedule_t l = make(loud, 1, 0);
    bool failing = false;
    int i;
    (void)state;
    memset(&r, 0, sizeof r);
    assert_int_equal(negobs_motor_thread_start(&t, &out, &st, 0), NEGOBS_OK);
    negobs_motor_thread_post(&t, &q);
    sleep_ms(100);
    r.stuck = 1;
    negobs_motor_thread_post(&t, &l);
    for (i = 0; i < 8; i++) {
        sleep_ms(100);
        assert_int_equal(negobs_motor_thread_output_faults(&t, &failing), 1);
        assert_true(failing);
    }
    r.stuck = 0;
    sleep_ms(400);
    assert_int_equal(negobs_motor_thread_output_faults(&t, &failing), 1);
    assert_false(failing);
    negobs_motor_thread_stop(&t);
}

static void test_thread_dead_output_is_seen_during_silence(void **state)
{
    static const uint16_t stale[] = {500, 30000};
    static const uint16_t quiet[] = {0, 30000};
    rec_out_t r;
    negobs_motor_out_t out = {&rec_ops, &r};
    negobs_motor_thread_t t;
    negobs_motor_schedule_t st = make(stale, 1, 0);
    negobs_motor_schedule_t q = make(quiet, 1, 0);
    bool failing = false;
    (void)state;
    memset(&r, 0, sizeof r);
    assert_int_equal(negobs_motor_thread_start(&t, &out, &st, 0), NEGOBS_OK);
    negobs_motor_thread_post(&t, &q);
    sleep_ms(100);
    /* Silence writes nothing new; the refresh still finds the output
     * gone within NEGOBS_MOTOR_REFRESH_MS (+ slack for loaded machines). */
    r.down = 1;
    sleep_ms((long)NEGOBS_MOTOR_REFRESH_MS + 400);
    assert_int_equal(negobs_motor_thread_output_faults(&t, &failing), 1);
    assert_true(failing);
    r.down = 0;
    negobs_motor_thread_stop(&t);
}

#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exec_one_shot_pulses_then_idle),
        cmocka_unit_test(test_exec_late_tick_keeps_pattern_phase),
        cmocka_unit_test(test_exec_intro_then_loop_tail),
        cmocka_unit_test(test_exec_rejects_bad_schedules),
        cmocka_unit_test(test_exec_retries_failed_write_and_stop_turns_off),
        cmocka_unit_test(test_schedule_equal_compares_content),
#ifdef NEGOBS_TEST_THREADS
        cmocka_unit_test(test_thread_watchdog_plays_stale_pattern),
        cmocka_unit_test(test_thread_output_fault_retries_then_holds_no_info),
        cmocka_unit_test(test_thread_dead_output_is_seen_during_silence),
        cmocka_unit_test(
            test_thread_rewrite_of_the_held_level_is_not_recovery),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
