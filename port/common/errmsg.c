/* The platform layer's diagnostic formatter (errmsg.h). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "negobs_port/errmsg.h"

void negobs_port_verrmsg(char *buf, size_t len, int err, const char *fmt,
                         va_list ap)
{
    int n;
    if (buf == NULL || len == 0) {
        return;
    }
    /* NOLINTNEXTLINE(clang-analyzer-valist.Uninitialized) */
    n = vsnprintf(buf, len, fmt, ap);
    if (n < 0) {
        buf[0] = '\0';
        return;
    }
    if (err != 0 && (size_t)n < len) {
        (void)snprintf(buf + n, len - (size_t)n, ": %s", strerror(err));
    }
}

void negobs_port_errmsg(char *buf, size_t len, int err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    /* va_start() is above; clang-tidy 14 reports this false positive
     * only when it analyses several files in one run. */
    /* NOLINTNEXTLINE(clang-analyzer-valist.Uninitialized) */
    negobs_port_verrmsg(buf, len, err, fmt, ap);
    va_end(ap);
}
