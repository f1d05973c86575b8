/*
 * GPIO alert backend on the Linux GPIO character device, uAPI v2 with a
 * fallback to uAPI v1 for kernels older than 5.10 (the v2 request then
 * fails with ENOTTY or EINVAL before anything is claimed).
 *
 * Raw ioctls, no libgpiod: the board image needs no extra library and the
 * same code cross-builds for every target (libgpiod 1.6 would add a
 * dependency that the cross sysroots here do not have).
 * The line is requested as an output with initial value 0 (motor off)
 * and held until close; the kernel drops the request, and the line keeps
 * its last value, if the process dies, so close/off paths set 0 first.
 *
 * A chip can go away under a running program (an unbound driver, an
 * unplugged expander): writes then fail with ENODEV for good on the old
 * descriptors. The line is released and requested again, with back-off,
 * from the following writes (the motor thread keeps writing, so recovery
 * needs no timer of its own): from the same path, or from the chip with
 * the same label when it came back under another number.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <linux/gpio.h>

#include "negobs_port/motor.h"
#include "negobs_port/errmsg.h"
#include "negobs_port/clock.h"

static void gpio_error(negobs_motor_out_gpio_t *st, int err, const char *fmt,
                       ...)
{
    va_list ap;
    st->last_errno = err;
    va_start(ap, fmt);
    /* va_start() is above; clang-tidy 14 reports this false positive
     * only when it analyses several files in one run. */
    /* NOLINTNEXTLINE(clang-analyzer-valist.Uninitialized) */
    negobs_port_verrmsg(st->errmsg, sizeof st->errmsg, err, fmt, ap);
    va_end(ap);
}

static int set_line(const negobs_motor_out_gpio_t *st, int on)
{
    int rc;
    if (st->uapi_v1) {
        struct gpiohandle_data d;
        memset(&d, 0, sizeof d);
        d.values[0] = on ? 1u : 0u;
        do {
            rc = ioctl(st->line_fd, GPIOHANDLE_SET_LINE_VALUES_IOCTL, &d);
        } while (rc < 0 && errno == EINTR);
    } else {
        struct gpio_v2_line_values v;
        memset(&v, 0, sizeof v);
        v.mask = 1;
        v.bits = on ? 1u : 0u;
        do {
            rc = ioctl(st->line_fd, GPIO_V2_LINE_SET_VALUES_IOCTL, &v);
        } while (rc < 0 && errno == EINTR);
    }
    return rc;
}

/* uAPI v1 request: one output line, default 0. */
static int request_v1(negobs_motor_out_gpio_t *st, uint32_t line,
                      bool active_low)
{
    struct gpiohandle_request r;
    memset(&r, 0, sizeof r);
    r.lineoffsets[0] = line;
    r.lines = 1;
    r.flags = GPIOHANDLE_REQUEST_OUTPUT;
    if (active_low) {
        r.flags |= GPIOHANDLE_REQUEST_ACTIVE_LOW;
    }
    r.default_values[0] = 0;
    (void)snprintf(r.consumer_label, sizeof r.consumer_label, "negobs-motor");
    if (ioctl(st->chip_fd, GPIO_GET_LINEHANDLE_IOCTL, &r) < 0) {
        return -1;
    }
    st->line_fd = r.fd;
    st->uapi_v1 = true;
    return 0;
}

static negobs_status_t request_line(negobs_motor_out_gpio_t *st);
static negobs_status_t find_by_label(negobs_motor_out_gpio_t *st);
static void chip_label(int fd, char *out, size_t len);
static void release_line(negobs_motor_out_gpio_t *st);

/* A chip that comes back may get another number (an expander plugged in
 * again, a driver rebound while the old device is still referenced): look
 * for its label among /dev/gpiochip0..63. */
static negobs_status_t find_by_label(negobs_motor_out_gpio_t *st)
{
    char path[sizeof st->path];
    char label[sizeof st->label];
    int i;
    for (i = 0; i < 64; i++) {
        int fd;
        (void)snprintf(path, sizeof path, "/dev/gpiochip%d", i);
        fd = open(path, O_RDWR | O_CLOEXEC);
        if (fd < 0) {
            continue;
        }
        chip_label(fd, label, sizeof label);
        (void)close(fd);
        if (label[0] != '\0' && strcmp(label, st->label) == 0) {
            memcpy(st->path, path, sizeof path);
            return request_line(st);
        }
    }
    return NEGOBS_ERR_NODEV;
}

/* Lost line: request it again once the back-off has passed. */
static negobs_status_t retry_request(negobs_motor_out_gpio_t *st)
{
    uint64_t now = negobs_clock_now_ms();
    negobs_status_t s;
    if (now < st->retry_at_ms) {
        return NEGOBS_ERR_NODEV;
    }
    s = request_line(st);
    if (s != NEGOBS_OK && st->label[0] != '\0') {
        s = find_by_label(st);
    }
    if (s != NEGOBS_OK) {
        st->backoff_ms = st->backoff_ms >= NEGOBS_GPIO_RETRY_MAX_MS / 2u
                             ? NEGOBS_GPIO_RETRY_MAX_MS
                             : st->backoff_ms * 2u;
        st->retry_at_ms = now + st->backoff_ms;
        return NEGOBS_ERR_NODEV;
    }
    st->lost = false;
    st->reopens++;
    return NEGOBS_OK;
}

static negobs_status_t gpio_set(void *ctx, uint16_t permille)
{
    negobs_motor_out_gpio_t *st = ctx;
    int on = permille > 0;
    if (permille > NEGOBS_MOTOR_FULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (st->lost && retry_request(st) != NEGOBS_OK) {
        return NEGOBS_ERR_NODEV;
    }
    if (st->line_fd < 0) {
        return NEGOBS_ERR_STATE;
    }
    if (set_line(st, on) != 0) {
        int e = errno;
        gpio_error(st, e, "set line %u on %s", (unsigned)st->line, st->path);
        if (e == ENODEV || e == ENXIO || e == EIO) {
            /* The chip is gone: these descriptors stay dead. */
            release_line(st);
            st->lost = true;
            st->backoff_ms = NEGOBS_GPIO_RETRY_MIN_MS;
            st->retry_at_ms = negobs_clock_now_ms() + st->backoff_ms;
            return NEGOBS_ERR_NODEV;
        }
        return NEGOBS_ERR_IO;
    }
    st->value = on;
    return NEGOBS_OK;
}

static void gpio_off_async(void *ctx)
{
    negobs_motor_out_gpio_t *st = ctx;
    if (st->line_fd >= 0) {
        (void)set_line(st, 0);
    }
}

static void gpio_close(void *ctx)
{
    negobs_motor_out_gpio_t *st = ctx;
    if (st->line_fd >= 0) {
        (void)set_line(st, 0);
    }
    release_line(st);
    st->lost = false;
}

static const negobs_motor_out_ops_t gpio_ops = {
    .name = "gpio",
    .set = gpio_set,
    .off_async = gpio_off_async,
    .close = gpio_close,
};

/* Label of an open chip ("" when the kernel does not say). */
static void chip_label(int fd, char *out, size_t len)
{
    struct gpiochip_info info;
    memset(&info, 0, sizeof info);
    out[0] = '\0';
    if (ioctl(fd, GPIO_GET_CHIPINFO_IOCTL, &info) == 0) {
        info.label[sizeof info.label - 1] = '\0';
        (void)snprintf(out, len, "%s", info.label);
    }
}

/* Open the chip and request the line (motor off); fds in st on success.
 * The first time the chip's label is kept; later, a chip at that path
 * with another label is not ours. */
static negobs_status_t request_line(negobs_motor_out_gpio_t *st)
{
    struct gpio_v2_line_request req;
    char label[sizeof st->label];
    st->chip_fd = open(st->path, O_RDWR | O_CLOEXEC);
    if (st->chip_fd < 0) {
        gpio_error(st, errno, "open %s", st->path);
        return NEGOBS_ERR_NODEV;
    }
    chip_label(st->chip_fd, label, sizeof label);
    if (st->label[0] == '\0') {
        (void)snprintf(st->label, sizeof st->label, "%s", label);
    } else if (strcmp(label, st->label) != 0) {
        gpio_error(st, 0, "%s is '%s', not '%s'", st->path, label, st->label);
        (void)close(st->chip_fd);
        st->chip_fd = -1;
        return NEGOBS_ERR_NODEV;
    }
    memset(&req, 0, sizeof req);
    req.offsets[0] = st->line;
    req.num_lines = 1;
    (void)snprintf(req.consumer, sizeof req.consumer, "negobs-motor");
    req.config.flags = GPIO_V2_LINE_FLAG_OUTPUT;
    if (st->active_low) {
        req.config.flags |= GPIO_V2_LINE_FLAG_ACTIVE_LOW;
    }
    req.config.num_attrs = 1;
    req.config.attrs[0].attr.id = GPIO_V2_LINE_ATTR_ID_OUTPUT_VALUES;
    req.config.attrs[0].attr.values = 0; /* start with the motor off */
    req.config.attrs[0].mask = 1;
    if (ioctl(st->chip_fd, GPIO_V2_GET_LINE_IOCTL, &req) == 0) {
        st->line_fd = req.fd;
    } else if ((errno == ENOTTY || errno == EINVAL) &&
               request_v1(st, st->line, st->active_low) == 0) {
        /* Kernel without uAPI v2 (< 5.10): v1 handle obtained. */
    } else {
        int e = errno;
        gpio_error(st, e, "request line %u on %s", (unsigned)st->line,
                   st->path);
        (void)close(st->chip_fd);
        st->chip_fd = -1;
        return e == EINVAL ? NEGOBS_ERR_INVAL : NEGOBS_ERR_IO;
    }
    return NEGOBS_OK;
}

static void release_line(negobs_motor_out_gpio_t *st)
{
    if (st->line_fd >= 0) {
        (void)close(st->line_fd);
        st->line_fd = -1;
    }
    if (st->chip_fd >= 0) {
        (void)close(st->chip_fd);
        st->chip_fd = -1;
    }
}

negobs_status_t negobs_motor_out_gpio_open(negobs_motor_out_gpio_t *st,
                                           const char *chip, uint32_t line,
                                           bool active_low,
                                           negobs_motor_out_t *alert)
{
    int n;
    negobs_status_t s;
    if (st == NULL || chip == NULL || alert == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(st, 0, sizeof *st);
    st->chip_fd = -1;
    st->line_fd = -1;
    st->line = line;
    st->active_low = active_low;
    if (chip[0] == '/') {
        n = snprintf(st->path, sizeof st->path, "%s", chip);
    } else if (chip[0] >= '0' && chip[0] <= '9') {
        n = snprintf(st->path, sizeof st->path, "/dev/gpiochip%s", chip);
    } else {
        n = snprintf(st->path, sizeof st->path, "/dev/%s", chip);
    }
    if (n < 0 || (size_t)n >= sizeof st->path) {
        return NEGOBS_ERR_INVAL;
    }
    s = request_line(st);
    if (s != NEGOBS_OK) {
        return s;
    }
    alert->ops = &gpio_ops;
    alert->ctx = st;
    return NEGOBS_OK;
}
