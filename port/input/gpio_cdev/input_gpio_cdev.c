/*
 * Push-button input on the Linux GPIO character device (uAPI v2), raw
 * ioctls like the motor output (alert_gpio_cdev.c): no libgpiod on the
 * board. The line is sampled (GPIO_V2_LINE_GET_VALUES_IOCTL) rather than
 * watched for edge events: the program polls it every 10 ms anyway to
 * time long presses, and sampling works on chips that cannot raise
 * interrupts (I2C expanders).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <linux/gpio.h>

#include "negobs_port/input.h"

static void input_error(negobs_input_gpio_t *st, int err, const char *what)
{
    int n;
    st->last_errno = err;
    /* in two steps: a long path cuts the message, never the reason */
    n = snprintf(st->errmsg, sizeof st->errmsg, "%.100s", what);
    if (n >= 0 && (size_t)n < sizeof st->errmsg) {
        (void)snprintf(st->errmsg + n, sizeof st->errmsg - (size_t)n, ": %s",
                       strerror(err));
    }
}

static int request(negobs_input_gpio_t *st, bool bias)
{
    struct gpio_v2_line_request r;
    int rc;
    memset(&r, 0, sizeof r);
    r.offsets[0] = st->line;
    r.num_lines = 1;
    (void)snprintf(r.consumer, sizeof r.consumer, "negobs-button");
    r.config.flags = GPIO_V2_LINE_FLAG_INPUT;
    if (st->active_low) {
        r.config.flags |= GPIO_V2_LINE_FLAG_ACTIVE_LOW;
    }
    if (bias) {
        r.config.flags |= st->active_low ? GPIO_V2_LINE_FLAG_BIAS_PULL_UP
                                         : GPIO_V2_LINE_FLAG_BIAS_PULL_DOWN;
    }
    do {
        rc = ioctl(st->chip_fd, GPIO_V2_GET_LINE_IOCTL, &r);
    } while (rc < 0 && errno == EINTR);
    if (rc == 0) {
        st->line_fd = r.fd;
    }
    return rc;
}

negobs_status_t negobs_input_gpio_open(negobs_input_gpio_t *st,
                                       const char *chip, uint32_t line,
                                       bool active_low)
{
    char path[128];
    int n;
    if (st == NULL || chip == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(st, 0, sizeof *st);
    st->chip_fd = -1;
    st->line_fd = -1;
    st->line = line;
    st->active_low = active_low;
    if (chip[0] == '/') {
        n = snprintf(path, sizeof path, "%s", chip);
    } else if (chip[0] >= '0' && chip[0] <= '9') {
        n = snprintf(path, sizeof path, "/dev/gpiochip%s", chip);
    } else {
        n = snprintf(path, sizeof path, "/dev/%s", chip);
    }
    if (n < 0 || (size_t)n >= sizeof path) {
        return NEGOBS_ERR_INVAL;
    }
    st->chip_fd = open(path, O_RDWR | O_CLOEXEC);
    if (st->chip_fd < 0) {
        input_error(st, errno, path);
        return (st->last_errno == ENOENT || st->last_errno == ENODEV)
                   ? NEGOBS_ERR_NODEV
                   : NEGOBS_ERR_IO;
    }
    /* bias first; chips without it refuse the flags (EINVAL/ENOTSUPP) */
    st->biased = request(st, true) == 0;
    if (!st->biased && request(st, false) != 0) {
        char what[160];
        (void)snprintf(what, sizeof what, "%s line %lu", path,
                       (unsigned long)line);
        input_error(st, errno, what);
        (void)close(st->chip_fd);
        st->chip_fd = -1;
        return NEGOBS_ERR_IO;
    }
    return NEGOBS_OK;
}

int negobs_input_gpio_read(negobs_input_gpio_t *st)
{
    struct gpio_v2_line_values v;
    int rc;
    if (st == NULL || st->line_fd < 0) {
        return NEGOBS_ERR_INVAL;
    }
    memset(&v, 0, sizeof v);
    v.mask = 1;
    do {
        rc = ioctl(st->line_fd, GPIO_V2_LINE_GET_VALUES_IOCTL, &v);
    } while (rc < 0 && errno == EINTR);
    if (rc < 0) {
        input_error(st, errno, "button read");
        return st->last_errno == ENODEV ? NEGOBS_ERR_NODEV : NEGOBS_ERR_IO;
    }
    /* the kernel applies ACTIVE_LOW: 1 is "pressed" either way */
    return (v.bits & 1u) != 0u ? 1 : 0;
}

void negobs_input_gpio_close(negobs_input_gpio_t *st)
{
    if (st == NULL) {
        return;
    }
    if (st->line_fd >= 0) {
        (void)close(st->line_fd);
        st->line_fd = -1;
    }
    if (st->chip_fd >= 0) {
        (void)close(st->chip_fd);
        st->chip_fd = -1;
    }
}
