/*
 * Log output that never waits: negobs_run's text log (stderr) and its JSON
 * lines log are optional outputs, and a reader that stops reading (a
 * stalled journald, a paused pager, a FIFO whose reader hangs) must not
 * stop the warnings. A line is written whole when the descriptor can take
 * it now, else dropped and counted; the caller reports the count once
 * lines flow again.
 *
 * Two kinds of descriptor:
 *  - own (the JSON log, opened by negobs_run): O_NONBLOCK is set on it, so
 *    a write takes what fits and never waits;
 *  - shared (stderr, whose open file may be a terminal other programs use):
 *    its flags are left alone. A socket (journald) is written with
 *    send(MSG_DONTWAIT); anything else only when poll() says it is ready,
 *    which for a pipe means a free page: a line up to PIPE_BUF (4096 bytes)
 *    then goes in whole without waiting. A terminal stopped with Ctrl-S
 *    can still hold a write once its buffer is nearly full.
 * A write cut short (a pipe with less room than a long JSON line) keeps
 * its remainder and finishes it before the next line, so a reader never
 * sees a line torn or two lines interleaved.
 *
 * Main thread only (negobs_run logs from its loop): no locking.
 */
#ifndef NEGOBS_APP_LOGOUT_H
#define NEGOBS_APP_LOGOUT_H

#include <stdbool.h>
#include <stddef.h>

/** Longest line kept for finishing after a short write (bytes); longer
 *  lines are cut there, and the JSON writer builds lines within it. */
#define APP_LOGOUT_LINE_MAX 32768u

typedef struct app_logout {
    int fd;
    bool own; /**< O_NONBLOCK set by app_logout_init     */
    int sock; /**< 1 socket, 0 not, -1 not known yet     */
    size_t pend_off;
    size_t pend_len; /**< remainder of a line cut short          */
    char pend[APP_LOGOUT_LINE_MAX];
    unsigned long dropped; /**< lines dropped since the caller last took
                                the count (app_logout_take_dropped) */
    unsigned long dropped_total;
    int err; /**< errno of the failure that made a write return -1 */
} app_logout_t;

/**
 * @brief Use descriptor fd. own: negobs_run opened it, set O_NONBLOCK on
 *        it (else the shared rules above).
 */
void app_logout_init(app_logout_t *o, int fd, bool own);

/**
 * @brief Write one line (len bytes, its newline included) without waiting.
 * @return 1 written (or its remainder kept to finish), 0 dropped because
 *         the reader is not ready, -1 the descriptor failed (o->err: e.g.
 *         ENOSPC, EPIPE); the caller then stops using it.
 */
int app_logout_line(app_logout_t *o, const char *line, size_t len);

/**
 * @brief Try once more, without waiting, to finish a line cut short.
 * @return 1 nothing left, 0 some left, -1 the descriptor failed.
 */
int app_logout_flush(app_logout_t *o);

/** @brief Lines dropped since the last call; the count restarts at 0. */
unsigned long app_logout_take_dropped(app_logout_t *o);

#endif
