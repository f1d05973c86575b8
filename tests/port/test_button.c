/*
 * The push button: press classification on a fake clock
 * (firmware_app/app_button.c) and the GPIO input backend against a fake
 * chip (open/ioctl/close replaced at link time, as test_gpio_cdev.c does
 * for the motor line): the v2 input request (offset, input, active-low,
 * pull-up, consumer), the fallback without bias, samples, and errors.
 */
#define _DEFAULT_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <string.h>

#include <linux/gpio.h>

#include "app_button.h"
#include "cmocka_all.h"
#include "negobs_port/input.h"

#define CHIP_FD 800
#define LINE_FD 801

static struct {
    char opened[64];
    int open_errno;
    int bias_errno; /* requests with a bias flag fail with this */
    int all_errno;  /* every request fails with this */
    int requests;
    struct gpio_v2_line_request req;
    int level;     /* logical value the kernel reports (1 = active) */
    int get_errno; /* value reads fail with this */
    int line_open;
    int chip_open;
} fake;

int __real_open64(const char *path, int flags, ...);
int __wrap_open64(const char *path, int flags, ...);
int __real_close(int fd);
int __wrap_close(int fd);
int __real_ioctl(int fd, unsigned long req, ...);
int __wrap_ioctl(int fd, unsigned long req, ...);

int __wrap_open64(const char *path, int flags, ...)
{
    mode_t mode = 0;
    va_list ap;
    size_t n;
    va_start(ap, flags);
    if ((flags & O_CREAT) != 0) {
        mode = (mode_t)va_arg(ap, unsigned int);
    }
    va_end(ap);
    if (strncmp(path, "/dev/gpiochip", 13) != 0) {
        return __real_open64(path, flags, mode);
    }
    n = strlen(path);
    if (n >= sizeof fake.opened) {
        n = sizeof fake.opened - 1u;
    }
    memcpy(fake.opened, path, n);
    fake.opened[n] = '\0';
    if (fake.open_errno != 0) {
        errno = fake.open_errno;
        return -1;
    }
    fake.chip_open = 1;
    return CHIP_FD;
}

int __wrap_close(int fd)
{
    if (fd == CHIP_FD) {
        fake.chip_open = 0;
        return 0;
    }
    if (fd == LINE_FD) {
        fake.line_open = 0;
        return 0;
    }
    return __real_close(fd);
}

int __wrap_ioctl(int fd, unsigned long req, ...)
{
    va_list ap;
    void *arg;
    va_start(ap, req);
    arg = va_arg(ap, void *);
    va_end(ap);
    if (fd == CHIP_FD && req == GPIO_V2_GET_LINE_IOCTL) {
        struct gpio_v2_line_request *r = arg;
        fake.requests++;
        fake.req = *r;
        if (fake.all_errno != 0) {
            errno = fake.all_errno;
            return -1;
        }
        if (fake.bias_errno != 0 &&
            (r->config.flags & (GPIO_V2_LINE_FLAG_BIAS_PULL_UP |
                                GPIO_V2_LINE_FLAG_BIAS_PULL_DOWN)) != 0) {
            errno = fake.bias_errno;
            return -1;
        }
        r->fd = LINE_FD;
        fake.line_open = 1;
        return 0;
    }
    if (fd == LINE_FD && req == GPIO_V2_LINE_GET_VALUES_IOCTL) {
        struct gpio_v2_line_values *v = arg;
        if (fake.get_errno != 0) {
            errno = fake.get_errno;
            return -1;
        }
        v->bits = (v->mask & 1u) != 0u && fake.level ? 1u : 0u;
        return 0;
    }
    return __real_ioctl(fd, req, arg);
}

static int reset(void **state)
{
    (void)state;
    memset(&fake, 0, sizeof fake);
    return 0;
}

/* ---- classification ------------------------------------------------- */

/* Feed `level` every 10 ms from *t for `ms`; count the events. */
static void hold(app_button_t *b, uint32_t *t, int32_t level, uint32_t ms,
                 int *shorts, int *longs)
{
    uint32_t k;
    for (k = 0; k < ms; k += APP_BUTTON_POLL_MS, *t += APP_BUTTON_POLL_MS) {
        app_button_event_t e = app_button_sample(b, level, *t);
        *shorts += e == APP_BUTTON_SHORT;
        *longs += e == APP_BUTTON_LONG;
    }
}

static void test_button_short_and_long_presses(void **state)
{
    app_button_t b;
    uint32_t t = 1000;
    int s = 0;
    int l = 0;
    (void)state;
    app_button_init(&b, 1000u);
    hold(&b, &t, 0, 200, &s, &l);
    hold(&b, &t, 1, 150, &s, &l); /* a short press ... */
    assert_int_equal(s, 0);       /* ... counts at its release */
    hold(&b, &t, 0, 100, &s, &l);
    assert_int_equal(s, 1);
    assert_int_equal(l, 0);
    /* long: reported while held, at the threshold; the release adds
     * nothing */
    hold(&b, &t, 1, 990, &s, &l);
    assert_int_equal(l, 0);
    hold(&b, &t, 1, 100, &s, &l);
    assert_int_equal(l, 1);
    hold(&b, &t, 1, 3000, &s, &l);
    hold(&b, &t, 0, 100, &s, &l);
    assert_int_equal(s, 1);
    assert_int_equal(l, 1);
}

static void test_button_bounce_is_ignored(void **state)
{
    app_button_t b;
    uint32_t t = 0;
    int s = 0;
    int l = 0;
    int k;
    (void)state;
    app_button_init(&b, 1000u);
    hold(&b, &t, 0, 100, &s, &l);
    /* contact bounce: 10 ms blips, each shorter than the debounce time */
    for (k = 0; k < 5; k++) {
        hold(&b, &t, 1, 10, &s, &l);
        hold(&b, &t, 0, 10, &s, &l);
    }
    hold(&b, &t, 0, 100, &s, &l);
    assert_int_equal(s, 0);
    /* a press that bounces at both ends is still one press */
    hold(&b, &t, 1, 10, &s, &l);
    hold(&b, &t, 0, 10, &s, &l);
    hold(&b, &t, 1, 120, &s, &l);
    hold(&b, &t, 0, 10, &s, &l);
    hold(&b, &t, 1, 10, &s, &l);
    hold(&b, &t, 0, 100, &s, &l);
    assert_int_equal(s, 1);
    assert_int_equal(l, 0);
}

static void test_button_held_at_start_needs_a_release(void **state)
{
    app_button_t b;
    uint32_t t = 0;
    int s = 0;
    int l = 0;
    (void)state;
    app_button_init(&b, 1000u);
    /* stuck or shorted from the start: never pauses the device */
    hold(&b, &t, 1, 5000, &s, &l);
    hold(&b, &t, 0, 100, &s, &l);
    assert_int_equal(s + l, 0);
    hold(&b, &t, 1, 100, &s, &l);
    hold(&b, &t, 0, 100, &s, &l);
    assert_int_equal(s, 1);
}

static void test_button_clock_wrap(void **state)
{
    app_button_t b;
    uint32_t t = 0xFFFFFF00u;
    int s = 0;
    int l = 0;
    (void)state;
    app_button_init(&b, 1000u);
    hold(&b, &t, 0, 100, &s, &l);
    hold(&b, &t, 1, 1200, &s, &l); /* crosses 2^32 ms */
    assert_int_equal(l, 1);
    assert_int_equal(s, 0);
}

/* ---- what a press does ------------------------------------------------- */

static void test_preset_filter_never_hides_imminent_or_noinfo(void **state)
{
    int32_t p;
    (void)state;
    for (p = 0; p < APP_PRESET_COUNT; p++) {
        assert_int_equal(app_button_filter(p, APP_VERDICT_IMMINENT, 500, 2200),
                         APP_VERDICT_IMMINENT);
        assert_int_equal(app_button_filter(p, APP_VERDICT_NO_INFO, -1, 2200),
                         APP_VERDICT_NO_INFO);
        assert_int_equal(app_button_filter(p, APP_VERDICT_CLEAR, -1, 2200),
                         APP_VERDICT_CLEAR);
    }
    /* all: every caution */
    assert_int_equal(
        app_button_filter(APP_PRESET_ALL, APP_VERDICT_CAUTION, 4000, 2200),
        APP_VERDICT_CAUTION);
    /* near: only those nearer than caution_mid_mm */
    assert_int_equal(
        app_button_filter(APP_PRESET_NEAR, APP_VERDICT_CAUTION, 2199, 2200),
        APP_VERDICT_CAUTION);
    assert_int_equal(
        app_button_filter(APP_PRESET_NEAR, APP_VERDICT_CAUTION, 2200, 2200),
        APP_VERDICT_CLEAR);
    /* an unknown range is never quieted */
    assert_int_equal(
        app_button_filter(APP_PRESET_NEAR, APP_VERDICT_CAUTION, -1, 2200),
        APP_VERDICT_CAUTION);
    /* imminent only */
    assert_int_equal(
        app_button_filter(APP_PRESET_IMMINENT, APP_VERDICT_CAUTION, 800, 2200),
        APP_VERDICT_CLEAR);
}

/* Pulses of a schedule before its tail: count and on-lengths. */
static uint32_t pulses(const negobs_motor_schedule_t *s, uint32_t upto,
                       uint16_t *on_ms)
{
    uint32_t i;
    uint32_t n = 0;
    for (i = 0; i < upto; i++) {
        if (s->seg[i].duty_permille > 0u) {
            on_ms[n++] = s->seg[i].duration_ms;
        }
    }
    return n;
}

static void test_confirmations_are_distinct_and_end_in_noinfo(void **state)
{
    negobs_motor_schedule_t tail;
    negobs_motor_schedule_t s;
    uint32_t ms = 0;
    uint16_t on[8];
    int32_t p;
    (void)state;
    /* a stand-in no-information loop: 600 on / 2400 off */
    memset(&tail, 0, sizeof tail);
    tail.seg[0].duty_permille = 1000;
    tail.seg[0].duration_ms = 600;
    tail.seg[1].duration_ms = 2400;
    tail.count = 2;
    tail.loop_start = 0;

    assert_int_equal(
        app_button_confirm_schedule(APP_CONFIRM_PAUSE, 0, 800, &tail, &s, &ms),
        NEGOBS_OK);
    assert_int_equal(pulses(&s, 2, on), 1);
    assert_int_equal(on[0], 700);
    assert_int_equal(s.seg[0].duty_permille, 800);
    assert_int_equal(s.seg[1].duration_ms, APP_CONFIRM_GAP_MS);
    assert_int_equal(ms, 700 + APP_CONFIRM_GAP_MS);
    /* the tail follows and loops: no silence after a dead main loop */
    assert_int_equal(s.count, 4);
    assert_int_equal(s.loop_start, 2);
    assert_int_equal(s.seg[2].duration_ms, 600);

    assert_int_equal(app_button_confirm_schedule(APP_CONFIRM_RESUME, 0, 1000,
                                                 &tail, &s, &ms),
                     NEGOBS_OK);
    assert_int_equal(pulses(&s, 4, on), 2);
    assert_int_equal(on[0], 300);
    assert_int_equal(ms, 300 + 200 + 300 + APP_CONFIRM_GAP_MS);

    for (p = 0; p < APP_PRESET_COUNT; p++) {
        assert_int_equal(app_button_confirm_schedule(APP_CONFIRM_PRESET, p,
                                                     1000, &tail, &s, &ms),
                         NEGOBS_OK);
        assert_int_equal(pulses(&s, (uint32_t)s.loop_start, on),
                         (uint32_t)p + 1u);
        assert_int_equal(on[0], 120);
        assert_int_equal(s.seg[s.loop_start - 1].duration_ms,
                         APP_CONFIRM_GAP_MS);
    }
    assert_int_equal(app_button_confirm_schedule(APP_CONFIRM_PRESET, 3, 1000,
                                                 &tail, &s, &ms),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(
        app_button_confirm_schedule(APP_CONFIRM_PAUSE, 0, 0, &tail, &s, &ms),
        NEGOBS_ERR_INVAL);
    tail.count = NEGOBS_MOTOR_MAX_SEGMENTS;
    assert_int_equal(app_button_confirm_schedule(APP_CONFIRM_PAUSE, 0, 1000,
                                                 &tail, &s, &ms),
                     NEGOBS_ERR_INVAL);
}

static void test_paused_schedule_reminds(void **state)
{
    negobs_motor_schedule_t s;
    (void)state;
    app_button_paused_schedule(1000, &s);
    assert_int_equal(negobs_motor_schedule_check(&s), NEGOBS_OK);
    assert_int_equal(s.loop_start, 0); /* for ever */
    assert_int_equal(s.seg[0].duty_permille, 0);
    assert_int_equal(s.seg[0].duration_ms, APP_PAUSED_PERIOD_MS);
    assert_int_equal(s.seg[1].duty_permille, 1000);
    assert_int_equal(s.seg[1].duration_ms, APP_PAUSED_PULSE_MS);
}

/* ---- the GPIO input --------------------------------------------------- */

static void test_input_request_and_samples(void **state)
{
    negobs_input_gpio_t in;
    (void)state;
    assert_int_equal(negobs_input_gpio_open(&in, "gpiochip2", 17, true),
                     NEGOBS_OK);
    assert_string_equal(fake.opened, "/dev/gpiochip2");
    assert_int_equal(fake.req.num_lines, 1);
    assert_int_equal(fake.req.offsets[0], 17);
    assert_string_equal(fake.req.consumer, "negobs-button");
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_INPUT) != 0);
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_ACTIVE_LOW) != 0);
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_BIAS_PULL_UP) != 0);
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_OUTPUT) == 0);
    assert_true(in.biased);
    fake.level = 0;
    assert_int_equal(negobs_input_gpio_read(&in), 0);
    fake.level = 1;
    assert_int_equal(negobs_input_gpio_read(&in), 1);
    negobs_input_gpio_close(&in);
    assert_int_equal(fake.line_open, 0);
    assert_int_equal(fake.chip_open, 0);
    negobs_input_gpio_close(&in); /* twice is safe */
}

static void test_input_active_high_pulls_down(void **state)
{
    negobs_input_gpio_t in;
    (void)state;
    assert_int_equal(negobs_input_gpio_open(&in, "0", 3, false), NEGOBS_OK);
    assert_string_equal(fake.opened, "/dev/gpiochip0");
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_ACTIVE_LOW) == 0);
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_BIAS_PULL_DOWN) !=
                0);
    negobs_input_gpio_close(&in);
}

static void test_input_without_bias_support(void **state)
{
    negobs_input_gpio_t in;
    (void)state;
    fake.bias_errno = EINVAL;
    assert_int_equal(negobs_input_gpio_open(&in, "/dev/gpiochip1", 4, true),
                     NEGOBS_OK);
    assert_int_equal(fake.requests, 2);
    assert_false(in.biased);
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_BIAS_PULL_UP) == 0);
    negobs_input_gpio_close(&in);
}

static void test_input_errors(void **state)
{
    negobs_input_gpio_t in;
    (void)state;
    fake.open_errno = ENOENT;
    assert_int_equal(negobs_input_gpio_open(&in, "gpiochip7", 1, true),
                     NEGOBS_ERR_NODEV);
    assert_non_null(strstr(in.errmsg, "/dev/gpiochip7"));
    fake.open_errno = 0;
    /* line busy (with and without bias): refused, nothing left open */
    fake.bias_errno = EBUSY;
    fake.all_errno = EBUSY;
    assert_int_equal(negobs_input_gpio_open(&in, "gpiochip0", 1, true),
                     NEGOBS_ERR_IO);
    assert_non_null(strstr(in.errmsg, "line 1"));
    assert_int_equal(fake.chip_open, 0);
    fake.bias_errno = 0;
    fake.all_errno = 0;
    /* the chip goes away while running */
    assert_int_equal(negobs_input_gpio_open(&in, "gpiochip0", 1, true),
                     NEGOBS_OK);
    fake.get_errno = ENODEV;
    assert_int_equal(negobs_input_gpio_read(&in), NEGOBS_ERR_NODEV);
    assert_non_null(strstr(in.errmsg, "button read"));
    negobs_input_gpio_close(&in);
    assert_int_equal(negobs_input_gpio_read(&in), NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_input_gpio_open(NULL, "0", 1, true),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_button_short_and_long_presses),
        cmocka_unit_test(test_button_bounce_is_ignored),
        cmocka_unit_test(test_button_held_at_start_needs_a_release),
        cmocka_unit_test(test_button_clock_wrap),
        cmocka_unit_test(test_preset_filter_never_hides_imminent_or_noinfo),
        cmocka_unit_test(test_confirmations_are_distinct_and_end_in_noinfo),
        cmocka_unit_test(test_paused_schedule_reminds),
        cmocka_unit_test_setup(test_input_request_and_samples, reset),
        cmocka_unit_test_setup(test_input_active_high_pulls_down, reset),
        cmocka_unit_test_setup(test_input_without_bias_support, reset),
        cmocka_unit_test_setup(test_input_errors, reset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
