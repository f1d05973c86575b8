/*
 * GPIO chardev output against a fake chip: open/ioctl/close replaced at
 * link time. Checks the v2 line request (offset, output, active-low,
 * consumer, initial value 0), value writes, and the error paths.
 */
#define _DEFAULT_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <string.h>
#include <time.h>

#include <linux/gpio.h>

#include "cmocka_all.h"
#include "negobs_port/motor.h"

#define CHIP_FD 700
#define LINE_FD 701

static struct {
    char opened[64];
    int open_errno;
    int request_errno;
    struct gpio_v2_line_request req;
    int requests;
    int line_open;
    int chip_open;
    int value; /* last value written, -1 none */
    int writes;
    bool no_v2;    /* an old kernel: v2 ioctls are ENOTTY */
    int set_errno; /* value writes fail with this (chip gone: ENODEV) */
    char gone[64]; /* this chip path does not exist (ENOENT)            */
    char ours[64]; /* only this path has our label; "" = every path     */
    struct gpiohandle_request req_v1;
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
    va_start(ap, flags);
    if ((flags & O_CREAT) != 0) {
        mode = (mode_t)va_arg(ap, unsigned int);
    }
    va_end(ap);
    if (strncmp(path, "/dev/gpiochip", 13) != 0) {
        return __real_open64(path, flags, mode);
    }
    {
        /* a bounded copy: gcc's -O2 with UBSan misreads path as possibly
         * NULL in snprintf("%s") (-Wformat-truncation), after the strncmp
         * above has already read it */
        size_t n = strlen(path);
        if (n >= sizeof fake.opened) {
            n = sizeof fake.opened - 1u;
        }
        memcpy(fake.opened, path, n);
        fake.opened[n] = '\0';
    }
    if (strcmp(path, fake.gone) == 0) {
        errno = ENOENT;
        return -1;
    }
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
    if (fake.no_v2 && (req == GPIO_V2_GET_LINE_IOCTL ||
                       req == GPIO_V2_LINE_SET_VALUES_IOCTL)) {
        errno = ENOTTY;
        return -1;
    }
    if (fd == CHIP_FD && req == GPIO_GET_CHIPINFO_IOCTL) {
        struct gpiochip_info *ci = arg;
        memset(ci, 0, sizeof *ci);
        (void)snprintf(ci->label, sizeof ci->label, "%s",
                       fake.ours[0] == '\0' ||
                               strcmp(fake.opened, fake.ours) == 0
                           ? "motor-chip"
                           : "other-chip");
        return 0;
    }
    if (fd == CHIP_FD && req == GPIO_GET_LINEHANDLE_IOCTL) {
        struct gpiohandle_request *r = arg;
        fake.requests++;
        fake.req_v1 = *r;
        if (fake.request_errno != 0) {
            errno = fake.request_errno;
            return -1;
        }
        r->fd = LINE_FD;
        fake.line_open = 1;
        return 0;
    }
    if (fd == LINE_FD && req == GPIOHANDLE_SET_LINE_VALUES_IOCTL) {
        struct gpiohandle_data *d = arg;
        fake.value = d->values[0];
        fake.writes++;
        return 0;
    }
    if (fd == CHIP_FD && req == GPIO_V2_GET_LINE_IOCTL) {
        struct gpio_v2_line_request *r = arg;
        fake.requests++;
        fake.req = *r;
        if (fake.request_errno != 0) {
            errno = fake.request_errno;
            return -1;
        }
        r->fd = LINE_FD;
        fake.line_open = 1;
        return 0;
    }
    if (fd == LINE_FD && req == GPIO_V2_LINE_SET_VALUES_IOCTL) {
        struct gpio_v2_line_values *v = arg;
        if (fake.set_errno != 0) {
            errno = fake.set_errno;
            return -1;
        }
        assert_int_equal(v->mask, 1);
        fake.value = (int)(v->bits & 1u);
        fake.writes++;
        return 0;
    }
    if (fd == CHIP_FD || fd == LINE_FD) {
        errno = ENOTTY;
        return -1;
    }
    return __real_ioctl(fd, req, arg);
}

static int reset(void **state)
{
    (void)state;
    memset(&fake, 0, sizeof fake);
    fake.value = -1;
    return 0;
}

static void test_gpio_requests_output_line_off(void **state)
{
    negobs_motor_out_gpio_t g;
    negobs_motor_out_t out;
    const struct gpio_v2_line_config *c = &fake.req.config;
    (void)state;
    assert_int_equal(
        negobs_motor_out_gpio_open(&g, "gpiochip2", 17, false, &out),
        NEGOBS_OK);
    assert_string_equal(fake.opened, "/dev/gpiochip2");
    assert_int_equal(fake.req.num_lines, 1);
    assert_int_equal(fake.req.offsets[0], 17);
    assert_string_equal(fake.req.consumer, "negobs-motor");
    assert_true((c->flags & GPIO_V2_LINE_FLAG_OUTPUT) != 0);
    assert_true((c->flags & GPIO_V2_LINE_FLAG_ACTIVE_LOW) == 0);
    assert_int_equal(c->num_attrs, 1);
    assert_int_equal(c->attrs[0].attr.id, GPIO_V2_LINE_ATTR_ID_OUTPUT_VALUES);
    assert_int_equal(c->attrs[0].attr.values, 0); /* starts off */
    assert_int_equal(c->attrs[0].mask, 1);
    assert_string_equal(out.ops->name, "gpio");
}

static void test_gpio_levels_switch_line_and_close_turns_off(void **state)
{
    negobs_motor_out_gpio_t g;
    negobs_motor_out_t out;
    (void)state;
    assert_int_equal(negobs_motor_out_gpio_open(&g, "0", 3, true, &out),
                     NEGOBS_OK);
    assert_string_equal(fake.opened, "/dev/gpiochip0");
    assert_true((fake.req.config.flags & GPIO_V2_LINE_FLAG_ACTIVE_LOW) != 0);
    assert_int_equal(negobs_motor_out_set(&out, 1), NEGOBS_OK);
    assert_int_equal(fake.value, 1);
    assert_int_equal(negobs_motor_out_set(&out, 0), NEGOBS_OK);
    assert_int_equal(fake.value, 0);
    assert_int_equal(negobs_motor_out_set(&out, 1000), NEGOBS_OK);
    assert_int_equal(fake.value, 1);
    assert_int_equal(negobs_motor_out_set(&out, 1001), NEGOBS_ERR_INVAL);
    assert_int_equal(fake.value, 1);
    out.ops->off_async(out.ctx);
    assert_int_equal(fake.value, 0);
    assert_int_equal(negobs_motor_out_set(&out, 500), NEGOBS_OK);
    negobs_motor_out_close(&out);
    assert_int_equal(fake.value, 0);
    assert_int_equal(fake.line_open, 0);
    assert_int_equal(fake.chip_open, 0);
    negobs_motor_out_close(&out);
}

static void test_gpio_errors_are_reported(void **state)
{
    negobs_motor_out_gpio_t g;
    negobs_motor_out_t out;
    (void)state;
    fake.open_errno = ENOENT;
    assert_int_equal(
        negobs_motor_out_gpio_open(&g, "/dev/gpiochip9", 0, false, &out),
        NEGOBS_ERR_NODEV);
    assert_non_null(strstr(g.errmsg, "/dev/gpiochip9"));
    fake.open_errno = 0;
    fake.request_errno = EBUSY;
    assert_int_equal(
        negobs_motor_out_gpio_open(&g, "gpiochip0", 4, false, &out),
        NEGOBS_ERR_IO);
    assert_non_null(strstr(g.errmsg, "line 4"));
    assert_int_equal(g.last_errno, EBUSY);
    assert_int_equal(fake.chip_open, 0); /* nothing leaked */
    fake.request_errno = EINVAL;         /* offset beyond the chip */
    assert_int_equal(
        negobs_motor_out_gpio_open(&g, "gpiochip0", 99, false, &out),
        NEGOBS_ERR_INVAL);
}

static void test_gpio_falls_back_to_uapi_v1_on_old_kernels(void **state)
{
    negobs_motor_out_gpio_t g;
    negobs_motor_out_t out;
    (void)state;
    fake.no_v2 = true;
    assert_int_equal(
        negobs_motor_out_gpio_open(&g, "gpiochip0", 5, true, &out), NEGOBS_OK);
    assert_true(g.uapi_v1);
    assert_int_equal(fake.req_v1.lines, 1);
    assert_int_equal(fake.req_v1.lineoffsets[0], 5);
    assert_true((fake.req_v1.flags & GPIOHANDLE_REQUEST_OUTPUT) != 0);
    assert_true((fake.req_v1.flags & GPIOHANDLE_REQUEST_ACTIVE_LOW) != 0);
    assert_int_equal(fake.req_v1.default_values[0], 0);
    assert_string_equal(fake.req_v1.consumer_label, "negobs-motor");
    assert_int_equal(negobs_motor_out_set(&out, 300), NEGOBS_OK);
    assert_int_equal(fake.value, 1);
    negobs_motor_out_close(&out);
    assert_int_equal(fake.value, 0);
    assert_int_equal(fake.line_open, 0);
}

static void sleep_ms(long ms)
{
    struct timespec ts;
    ts.tv_sec = ms / 1000;
    ts.tv_nsec = (ms % 1000) * 1000000L;
    (void)nanosleep(&ts, NULL);
}

static void test_gpio_chip_gone_is_requested_again_with_backoff(void **state)
{
    negobs_motor_out_gpio_t st;
    negobs_motor_out_t out;
    (void)state;
    assert_int_equal(
        negobs_motor_out_gpio_open(&st, "/dev/gpiochip1", 0, false, &out),
        NEGOBS_OK);
    assert_int_equal(negobs_motor_out_set(&out, 1000), NEGOBS_OK);
    assert_int_equal(fake.requests, 1);
    /* The chip goes away (driver unbound): the write fails for good on
     * these descriptors, which are released. */
    fake.set_errno = ENODEV;
    assert_int_equal(negobs_motor_out_set(&out, 0), NEGOBS_ERR_NODEV);
    assert_non_null(strstr(st.errmsg, "/dev/gpiochip1"));
    assert_int_equal(fake.line_open, 0);
    assert_int_equal(fake.chip_open, 0);
    /* Within the back-off: no new request. */
    assert_int_equal(negobs_motor_out_set(&out, 0), NEGOBS_ERR_NODEV);
    assert_int_equal(fake.requests, 1);
    /* Still gone after the back-off: one try, then the back-off doubles. */
    fake.open_errno = ENOENT;
    sleep_ms((long)NEGOBS_GPIO_RETRY_MIN_MS + 30);
    assert_int_equal(negobs_motor_out_set(&out, 0), NEGOBS_ERR_NODEV);
    assert_int_equal(st.backoff_ms, 2u * NEGOBS_GPIO_RETRY_MIN_MS);
    assert_int_equal(fake.requests, 1);
    /* Back: the next write after the back-off requests the line from the
     * same path (motor off first) and drives it. */
    fake.open_errno = 0;
    fake.set_errno = 0;
    sleep_ms(2L * NEGOBS_GPIO_RETRY_MIN_MS + 30);
    assert_int_equal(negobs_motor_out_set(&out, 1000), NEGOBS_OK);
    assert_int_equal(fake.requests, 2);
    assert_string_equal(fake.opened, "/dev/gpiochip1");
    assert_int_equal(fake.req.config.attrs[0].attr.values, 0);
    assert_int_equal(fake.value, 1);
    assert_int_equal(st.reopens, 1);
    negobs_motor_out_close(&out);
    assert_int_equal(fake.value, 0);
    assert_int_equal(fake.line_open, 0);
}

static void test_gpio_chip_back_under_another_number_is_found_by_label(
    void **state)
{
    negobs_motor_out_gpio_t st;
    negobs_motor_out_t out;
    (void)state;
    assert_int_equal(
        negobs_motor_out_gpio_open(&st, "/dev/gpiochip3", 0, false, &out),
        NEGOBS_OK);
    assert_string_equal(st.label, "motor-chip");
    fake.set_errno = ENODEV;
    assert_int_equal(negobs_motor_out_set(&out, 1000), NEGOBS_ERR_NODEV);
    /* Back as gpiochip4; gpiochip0..2 are other chips, 3 is gone. */
    fake.set_errno = 0;
    (void)snprintf(fake.gone, sizeof fake.gone, "/dev/gpiochip3");
    (void)snprintf(fake.ours, sizeof fake.ours, "/dev/gpiochip4");
    sleep_ms((long)NEGOBS_GPIO_RETRY_MIN_MS + 30);
    assert_int_equal(negobs_motor_out_set(&out, 1000), NEGOBS_OK);
    assert_string_equal(st.path, "/dev/gpiochip4");
    assert_int_equal(fake.requests, 2);
    assert_int_equal(fake.value, 1);
    negobs_motor_out_close(&out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_gpio_requests_output_line_off, reset),
        cmocka_unit_test_setup(
            test_gpio_levels_switch_line_and_close_turns_off, reset),
        cmocka_unit_test_setup(test_gpio_errors_are_reported, reset),
        cmocka_unit_test_setup(
            test_gpio_chip_gone_is_requested_again_with_backoff, reset),
        cmocka_unit_test_setup(
            test_gpio_chip_back_under_another_number_is_found_by_label, reset),
        cmocka_unit_test_setup(test_gpio_falls_back_to_uapi_v1_on_old_kernels,
                               reset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
