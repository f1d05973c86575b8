/*
 * The platform layer's shared pieces: the one diagnostic formatter
 * (errmsg.h) and the ops-table wrappers' handling of optional ops.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs_port/motor.h"
#include "negobs_port/camera.h"
#include "negobs_port/errmsg.h"

static void test_errmsg_appends_strerror(void **state)
{
    char buf[128];
    char want[128];
    (void)state;
    negobs_port_errmsg(buf, sizeof buf, ENOENT, "open %s", "/dev/video9");
    (void)snprintf(want, sizeof want, "open /dev/video9: %s",
                   strerror(ENOENT));
    assert_string_equal(buf, want);
    negobs_port_errmsg(buf, sizeof buf, 0, "no frames from %s", "left");
    assert_string_equal(buf, "no frames from left");
}

/* A text that fills the buffer keeps its start; the suffix never
 * overwrites it, and the result stays terminated. */
static void test_errmsg_truncates_safely(void **state)
{
    char buf[8];
    (void)state;
    memset(buf, 'x', sizeof buf);
    negobs_port_errmsg(buf, sizeof buf, EIO, "%s", "abcdefghijk");
    assert_string_equal(buf, "abcdefg");
    negobs_port_errmsg(buf, sizeof buf, EIO, "abc");
    assert_int_equal(strncmp(buf, "abc: ", 5), 0);
    assert_int_equal(strlen(buf), sizeof buf - 1);
    negobs_port_errmsg(buf, 0, EIO, "abc"); /* nothing written */
}

static negobs_status_t min_open(void *ctx, const negobs_capture_config_t *cfg)
{
    (void)ctx;
    (void)cfg;
    return NEGOBS_OK;
}
static int min_get_pair(void *ctx, negobs_frame_pair_t *pair, int32_t ms)
{
    (void)ctx;
    (void)pair;
    (void)ms;
    return NEGOBS_CAPTURE_END;
}
static int min_closed;
static void min_close(void *ctx)
{
    (void)ctx;
    min_closed++;
}

/* A source with only the required ops: the wrappers fill in the rest. */
static void test_capture_optional_ops_may_be_null(void **state)
{
    static const negobs_capture_ops_t ops = {
        .name = "minimal",
        .open = min_open,
        .get_pair = min_get_pair,
        .close = min_close,
    };
    negobs_capture_t c = {&ops, NULL};
    negobs_capture_config_t cfg;
    negobs_capture_stats_t st;
    negobs_frame_pair_t pair;
    (void)state;
    negobs_capture_config_default(&cfg);
    memset(&st, 0xff, sizeof st);
    memset(&pair, 0, sizeof pair);
    assert_int_equal(negobs_capture_open(&c, &cfg), NEGOBS_OK);
    assert_int_equal(negobs_capture_start(&c), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&c, &pair, 10),
                     NEGOBS_CAPTURE_END);
    negobs_capture_release(&c, &pair);
    negobs_capture_get_stats(&c, &st);
    assert_int_equal(st.pairs, 0);
    assert_int_equal(st.frozen_pairs, 0);
    assert_string_equal(negobs_capture_errmsg(&c), "");
    negobs_capture_stop(&c);
    negobs_capture_close(&c);
    assert_int_equal(min_closed, 1);
}

static negobs_status_t out_set(void *ctx, uint16_t level)
{
    *(uint16_t *)ctx = level;
    return NEGOBS_OK;
}
static void out_close(void *ctx)
{
    *(uint16_t *)ctx = 0;
}

/* off_async is optional; the wrapper is a no-op without it, and without
 * an open handle (a signal may come before the output is opened). */
static void test_motor_out_off_async_is_optional(void **state)
{
    static const negobs_motor_out_ops_t ops = {
        .name = "plain",
        .set = out_set,
        .close = out_close,
    };
    uint16_t level = 0;
    negobs_motor_out_t none = {NULL, NULL};
    negobs_motor_out_t out = {&ops, &level};
    (void)state;
    negobs_motor_out_off_async(&none);
    assert_int_equal(negobs_motor_out_set(&out, 700), NEGOBS_OK);
    negobs_motor_out_off_async(&out);
    assert_int_equal(level, 700);
    negobs_motor_out_close(&out);
    assert_int_equal(level, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_errmsg_appends_strerror),
        cmocka_unit_test(test_errmsg_truncates_safely),
        cmocka_unit_test(test_capture_optional_ops_may_be_null),
        cmocka_unit_test(test_motor_out_off_async_is_optional),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
