/*
 * Sysfs PWM backend against a temporary tree laid out like /sys/class/pwm.
 * The tree checks paths, order of writes and formatting; kernel rules
 * (EINVAL for duty > period, EBUSY) need the emulated-hardware test.
 */
#define _XOPEN_SOURCE 700

#include <pthread.h>
#include <stdbool.h>
#include <string.h>
#include <time.h>

#include "cmocka_all.h"
#include "negobs_port/motor.h"
#include "port_test_util.h"

typedef struct fixture {
    char root[256];
    char chip[300];
} fixture_t;

static int setup(void **state)
{
    static fixture_t fx;
    memset(&fx, 0, sizeof fx);
    if (tu_mkdtemp(fx.root, sizeof fx.root, "pwm") != 0) {
        return -1;
    }
    (void)snprintf(fx.chip, sizeof fx.chip, "%s/pwmchip0", fx.root);
    if (tu_mkdir(fx.root, "pwmchip0") != 0 ||
        tu_write_str(fx.chip, "npwm", "2\n") != 0 ||
        tu_write_str(fx.chip, "export", "") != 0 ||
        tu_write_str(fx.chip, "unexport", "") != 0) {
        return -1;
    }
    *state = &fx;
    return 0;
}

static int teardown(void **state)
{
    fixture_t *fx = *state;
    tu_rm_tree(fx->root);
    return 0;
}

/* Create pwmN/ with its attribute files, as the kernel does on export. */
static void make_channel(const fixture_t *fx, unsigned ch)
{
    char dir[400];
    (void)snprintf(dir, sizeof dir, "%s/pwm%u", fx->chip, ch);
    assert_int_equal(mkdir(dir, 0755), 0);
    assert_int_equal(tu_write_str(dir, "period", "0\n"), 0);
    assert_int_equal(tu_write_str(dir, "duty_cycle", "0\n"), 0);
    assert_int_equal(tu_write_str(dir, "enable", "0\n"), 0);
    assert_int_equal(tu_write_str(dir, "polarity", "normal\n"), 0);
}

static void expect_attr(const fixture_t *fx, unsigned ch, const char *leaf,
                        const char *want)
{
    char dir[400];
    char got[64];
    (void)snprintf(dir, sizeof dir, "%s/pwm%u", fx->chip, ch);
    assert_true(tu_read(dir, leaf, got, sizeof got) >= 0);
    assert_string_equal(got, want);
}

static void test_pwm_open_writes_period_duty_enable(void **state)
{
    fixture_t *fx = *state;
    negobs_motor_out_pwm_t pwm;
    negobs_motor_out_t out;
    char exp[32];
    make_channel(fx, 0);
    assert_int_equal(
        negobs_motor_out_pwm_open(&pwm, fx->root, 0, 0, 1000000u, &out),
        NEGOBS_OK);
    expect_attr(fx, 0, "period", "1000000");
    expect_attr(fx, 0, "duty_cycle", "0");
    expect_attr(fx, 0, "enable", "1");
    /* Already exported: export must not be written. */
    assert_int_equal(tu_read(fx->chip, "export", exp, sizeof exp), 0);
    assert_string_equal(out.ops->name, "pwm");
    negobs_motor_out_close(&out);
}

static void test_pwm_duty_follows_permille_and_close_disables(void **state)
{
    fixture_t *fx = *state;
    negobs_motor_out_pwm_t pwm;
    negobs_motor_out_t out;
    make_channel(fx, 1);
    assert_int_equal(
        negobs_motor_out_pwm_open(&pwm, fx->root, 0, 1, 40000u, &out),
        NEGOBS_OK);
    assert_int_equal(negobs_motor_out_set(&out, 250), NEGOBS_OK);
    expect_attr(fx, 1, "duty_cycle", "10000");
    assert_int_equal(negobs_motor_out_set(&out, 1000), NEGOBS_OK);
    expect_attr(fx, 1, "duty_cycle", "40000");
    assert_int_equal(negobs_motor_out_set(&out, 1), NEGOBS_OK);
    expect_attr(fx, 1, "duty_cycle", "40");
    assert_int_equal(negobs_motor_out_set(&out, 1001), NEGOBS_ERR_INVAL);
    expect_attr(fx, 1, "duty_cycle", "40");
    /* The signal-handler path turns the motor off too. */
    out.ops->off_async(out.ctx);
    expect_attr(fx, 1, "duty_cycle", "0");
    assert_int_equal(negobs_motor_out_set(&out, 500), NEGOBS_OK);
    negobs_motor_out_close(&out);
    expect_attr(fx, 1, "duty_cycle", "0");
    expect_attr(fx, 1, "enable", "0");
    negobs_motor_out_close(&out); /* twice is harmless */
}

static void test_pwm_export_without_channel_dir_times_out(void **state)
{
    fixture_t *fx = *state;
    negobs_motor_out_pwm_t pwm;
    negobs_motor_out_t out;
    char buf[32];
    assert_int_equal(
        negobs_motor_out_pwm_open(&pwm, fx->root, 0, 1, 1000000u, &out),
        NEGOBS_ERR_NODEV);
    assert_true(tu_read(fx->chip, "export", buf, sizeof buf) > 0);
    assert_string_equal(buf, "1");
    assert_non_null(strstr(pwm.errmsg, "did not appear"));
}

#ifdef NEGOBS_TEST_THREADS
/* Plays the kernel: when "N" lands in export, create pwmN/ a bit later. */
static void *fake_kernel(void *arg)
{
    const fixture_t *fx = arg;
    int i;
    for (i = 0; i < 200; i++) {
        char buf[16];
        struct timespec ts = {0, 5000000};
        if (tu_read(fx->chip, "export", buf, sizeof buf) > 0) {
            char dir[400];
            (void)nanosleep(&ts, NULL);
            (void)snprintf(dir, sizeof dir, "%s/pwm%s", fx->chip, buf);
            if (mkdir(dir, 0755) == 0) {
                (void)tu_write_str(dir, "period", "0");
                (void)tu_write_str(dir, "duty_cycle", "0");
                (void)tu_write_str(dir, "enable", "0");
            }
            return NULL;
        }
        (void)nanosleep(&ts, NULL);
    }
    return NULL;
}

static void test_pwm_exports_channel_and_unexports_on_close(void **state)
{
    fixture_t *fx = *state;
    negobs_motor_out_pwm_t pwm;
    negobs_motor_out_t out;
    pthread_t th;
    char buf[32];
    assert_int_equal(pthread_create(&th, NULL, fake_kernel, fx), 0);
    assert_int_equal(
        negobs_motor_out_pwm_open(&pwm, fx->root, 0, 1, 1000000u, &out),
        NEGOBS_OK);
    assert_int_equal(pthread_join(th, NULL), 0);
    assert_true(tu_read(fx->chip, "export", buf, sizeof buf) > 0);
    assert_string_equal(buf, "1");
    expect_attr(fx, 1, "period", "1000000");
    expect_attr(fx, 1, "enable", "1");
    negobs_motor_out_close(&out);
    assert_true(tu_read(fx->chip, "unexport", buf, sizeof buf) > 0);
    assert_string_equal(buf, "1");
}

#endif

static void test_pwm_write_failure_is_reported(void **state)
{
    fixture_t *fx = *state;
    negobs_motor_out_pwm_t pwm;
    negobs_motor_out_t out;
    char dir[400];
    make_channel(fx, 0);
    /* A directory where the period file should be: open(O_WRONLY) fails
     * even for root, unlike a read-only mode. */
    (void)snprintf(dir, sizeof dir, "%s/pwm0", fx->chip);
    assert_int_equal(remove(strcat(dir, "/period")), 0);
    assert_int_equal(mkdir(dir, 0755), 0);
    assert_int_equal(
        negobs_motor_out_pwm_open(&pwm, fx->root, 0, 0, 1000000u, &out),
        NEGOBS_ERR_IO);
    assert_non_null(strstr(pwm.errmsg, "period"));
    assert_int_not_equal(pwm.last_errno, 0);
}

static void test_pwm_missing_chip_is_nodev(void **state)
{
    fixture_t *fx = *state;
    negobs_motor_out_pwm_t pwm;
    negobs_motor_out_t out;
    assert_int_equal(
        negobs_motor_out_pwm_open(&pwm, fx->root, 7, 0, 1000000u, &out),
        NEGOBS_ERR_NODEV);
    assert_non_null(strstr(pwm.errmsg, "pwmchip7"));
    assert_int_equal(negobs_motor_out_pwm_open(&pwm, fx->root, 0, 0, 0, &out),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(
            test_pwm_open_writes_period_duty_enable, setup, teardown),
        cmocka_unit_test_setup_teardown(
            test_pwm_duty_follows_permille_and_close_disables, setup,
            teardown),
        cmocka_unit_test_setup_teardown(
            test_pwm_export_without_channel_dir_times_out, setup, teardown),
#ifdef NEGOBS_TEST_THREADS
        cmocka_unit_test_setup_teardown(
            test_pwm_exports_channel_and_unexports_on_close, setup, teardown),
#endif
        cmocka_unit_test_setup_teardown(test_pwm_write_failure_is_reported,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_pwm_missing_chip_is_nodev, setup,
                                        teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
