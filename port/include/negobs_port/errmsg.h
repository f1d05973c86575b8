/*
 * The one diagnostic formatter of the platform layer.
 *
 * Every backend keeps its last diagnostic in a fixed buffer of its state
 * struct (errmsg[NEGOBS_PORT_ERRMSG_LEN] or similar) and formats it the
 * same way: the caller's text, then ": " and strerror(err) when an errno
 * value is given. Truncation keeps the caller's text, drops the suffix.
 */
#ifndef NEGOBS_PORT_ERRMSG_H
#define NEGOBS_PORT_ERRMSG_H

#include <stdarg.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Format `fmt` into buf[len], then append ": strerror(err)" when
 *        err != 0 and it fits whole after the text.
 * @param buf  destination, always NUL-terminated when len > 0 (empty when
 *             the format itself fails)
 * @param err  errno value, 0 for none
 */
void negobs_port_verrmsg(char *buf, size_t len, int err, const char *fmt,
                         va_list ap)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 4, 0)))
#endif
    ;

/** @brief negobs_port_verrmsg() with the arguments inline. */
void negobs_port_errmsg(char *buf, size_t len, int err, const char *fmt, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_ERRMSG_H */
