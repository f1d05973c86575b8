/*
 * Sysfs PWM alert backend (ROOT/pwmchipC/pwmN/{period,duty_cycle,enable}).
 *
 * The class root is a parameter, so tests point it at a temporary folder
 * laid out like /sys/class/pwm. Such a tree checks paths, order and
 * formatting only; the kernel's own rules (duty <= period, EBUSY on a
 * channel held elsewhere) are exercised by the emulated-hardware test.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "negobs_port/motor.h"
#include "negobs_port/errmsg.h"
#include "negobs_port/clock.h"

#define PWM_DEFAULT_ROOT "/sys/class/pwm"
/* TUNABLE: how long to wait for pwmN/ after export (udev, permissions). */
#define PWM_EXPORT_WAIT_MS 1000u
#define PWM_EXPORT_POLL_MS 10u

static void pwm_error(negobs_motor_out_pwm_t *st, int err, const char *fmt,
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

static int chan_path(const negobs_motor_out_pwm_t *st, char *buf, size_t len,
                     const char *leaf)
{
    int n;
    if (leaf == NULL) {
        n = snprintf(buf, len, "%s/pwmchip%u/pwm%u", st->root,
                     (unsigned)st->chip, (unsigned)st->channel);
    } else {
        n = snprintf(buf, len, "%s/pwmchip%u/pwm%u/%s", st->root,
                     (unsigned)st->chip, (unsigned)st->channel, leaf);
    }
    return (n < 0 || (size_t)n >= len) ? -1 : 0;
}

/* Write a decimal value at offset 0 of an open file (and cut what was
 * there, for plain files; sysfs ignores the truncate). Async-signal-safe. */
static int write_value_fd(int fd, const char *txt, size_t len)
{
    ssize_t w;
    (void)ftruncate(fd, 0);
    do {
        w = pwrite(fd, txt, len, 0);
    } while (w < 0 && errno == EINTR);
    return (w == (ssize_t)len) ? 0 : -1;
}

static negobs_status_t write_file(negobs_motor_out_pwm_t *st, const char *path,
                                  unsigned long value)
{
    char txt[24];
    int fd;
    int n = snprintf(txt, sizeof txt, "%lu", value);
    fd = open(path, O_WRONLY | O_CLOEXEC);
    if (fd < 0) {
        pwm_error(st, errno, "open %s", path);
        return errno == ENOENT ? NEGOBS_ERR_NODEV : NEGOBS_ERR_IO;
    }
    if (write_value_fd(fd, txt, (size_t)n) != 0) {
        int e = errno;
        (void)close(fd);
        pwm_error(st, e, "write %s to %s", txt, path);
        return NEGOBS_ERR_IO;
    }
    if (close(fd) != 0) {
        pwm_error(st, errno, "close %s", path);
        return NEGOBS_ERR_IO;
    }
    return NEGOBS_OK;
}

static negobs_status_t write_leaf(negobs_motor_out_pwm_t *st, const char *leaf,
                                  unsigned long value)
{
    char path[256];
    if (chan_path(st, path, sizeof path, leaf) != 0) {
        pwm_error(st, 0, "path too long");
        return NEGOBS_ERR_INVAL;
    }
    return write_file(st, path, value);
}

static unsigned long duty_ns(const negobs_motor_out_pwm_t *st,
                             uint16_t permille)
{
    return (unsigned long)(((uint64_t)st->period_ns * permille) / 1000u);
}

static negobs_status_t pwm_set(void *ctx, uint16_t permille)
{
    negobs_motor_out_pwm_t *st = ctx;
    char txt[24];
    int n;
    if (permille > NEGOBS_MOTOR_FULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (st->duty_fd < 0) {
        return NEGOBS_ERR_STATE;
    }
    n = snprintf(txt, sizeof txt, "%lu", duty_ns(st, permille));
    if (write_value_fd(st->duty_fd, txt, (size_t)n) != 0) {
        pwm_error(st, errno, "write duty_cycle %s", txt);
        return NEGOBS_ERR_IO;
    }
    st->last = permille;
    return NEGOBS_OK;
}

static void pwm_off_async(void *ctx)
{
    negobs_motor_out_pwm_t *st = ctx;
    if (st->duty_fd >= 0) {
        (void)write_value_fd(st->duty_fd, "0", 1);
    }
}

static void pwm_close(void *ctx)
{
    negobs_motor_out_pwm_t *st = ctx;
    char path[256];
    if (st->duty_fd < 0) {
        return;
    }
    (void)pwm_set(st, 0);
    (void)close(st->duty_fd);
    st->duty_fd = -1;
    (void)write_leaf(st, "enable", 0);
    if (st->exported_here) {
        int n = snprintf(path, sizeof path, "%s/pwmchip%u/unexport", st->root,
                         (unsigned)st->chip);
        if (n > 0 && (size_t)n < sizeof path) {
            (void)write_file(st, path, st->channel);
        }
    }
}

static const negobs_motor_out_ops_t pwm_ops = {
    .name = "pwm",
    .set = pwm_set,
    .off_async = pwm_off_async,
    .close = pwm_close,
};

static bool is_dir(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

negobs_status_t negobs_motor_out_pwm_open(negobs_motor_out_pwm_t *st,
                                          const char *root, uint32_t chip,
                                          uint32_t channel, uint32_t period_ns,
                                          negobs_motor_out_t *alert)
{
    char path[256];
    negobs_status_t s;
    uint32_t waited = 0;
    int n;

    if (st == NULL || alert == NULL || period_ns == 0) {
        return NEGOBS_ERR_INVAL;
    }
    memset(st, 0, sizeof *st);
    st->duty_fd = -1;
    if (root == NULL) {
        root = PWM_DEFAULT_ROOT;
    }
    if (strlen(root) >= sizeof st->root) {
        pwm_error(st, 0, "sysfs root too long");
        return NEGOBS_ERR_INVAL;
    }
    memcpy(st->root, root, strlen(root) + 1u); /* length checked above */
    st->chip = chip;
    st->channel = channel;
    st->period_ns = period_ns;

    n = snprintf(path, sizeof path, "%s/pwmchip%u", root, (unsigned)chip);
    if (n < 0 || (size_t)n >= sizeof path) {
        return NEGOBS_ERR_INVAL;
    }
    if (!is_dir(path)) {
        pwm_error(st, ENOENT, "no PWM chip %s", path);
        return NEGOBS_ERR_NODEV;
    }
    (void)chan_path(st, path, sizeof path, NULL);
    if (!is_dir(path)) {
        char exp[256];
        n = snprintf(exp, sizeof exp, "%s/pwmchip%u/export", root,
                     (unsigned)chip);
        if (n < 0 || (size_t)n >= sizeof exp) {
            return NEGOBS_ERR_INVAL;
        }
        s = write_file(st, exp, channel);
        if (s != NEGOBS_OK) {
            return s == NEGOBS_ERR_NODEV ? NEGOBS_ERR_NODEV : NEGOBS_ERR_IO;
        }
        st->exported_here = true;
        /* Export is asynchronous: wait, bounded, for the directory. */
        while (!is_dir(path) && waited < PWM_EXPORT_WAIT_MS) {
            negobs_clock_sleep_ms(PWM_EXPORT_POLL_MS);
            waited += PWM_EXPORT_POLL_MS;
        }
        if (!is_dir(path)) {
            pwm_error(st, ENOENT, "%s did not appear after export", path);
            return NEGOBS_ERR_NODEV;
        }
    }
    /* duty 0 first: a new period shorter than the old duty is refused.
     * On a channel never configured (period 0) the kernel refuses that
     * write itself (EINVAL, any state needs a period), and there is no old
     * duty to clear: go on, the period write decides. */
    s = write_leaf(st, "duty_cycle", 0);
    if (s != NEGOBS_OK && st->last_errno == EINVAL) {
        s = NEGOBS_OK;
    }
    if (s == NEGOBS_OK) {
        s = write_leaf(st, "period", period_ns);
    }
    if (s == NEGOBS_OK) {
        s = write_leaf(st, "duty_cycle", 0);
    }
    if (s == NEGOBS_OK) {
        s = write_leaf(st, "enable", 1);
    }
    if (s != NEGOBS_OK) {
        return NEGOBS_ERR_IO;
    }
    (void)chan_path(st, path, sizeof path, "duty_cycle");
    st->duty_fd = open(path, O_WRONLY | O_CLOEXEC);
    if (st->duty_fd < 0) {
        pwm_error(st, errno, "open %s", path);
        return NEGOBS_ERR_IO;
    }
    alert->ops = &pwm_ops;
    alert->ctx = st;
    return NEGOBS_OK;
}
