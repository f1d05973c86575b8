/*
 * negobs_run's log output that never waits (firmware_app/app_logout.c):
 * a reader that stops reading costs lines, counted, never a wait; lines
 * reach the reader whole and in order; a broken descriptor is reported.
 * Every test runs under alarm(): a write that waits fails it (SIGALRM)
 * instead of hanging the suite.
 */
#define _GNU_SOURCE /* F_SETPIPE_SZ */
#include <errno.h>
#include <fcntl.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmocka.h>

#include "app_logout.h"

static app_logout_t out;

/* A pipe of one page where the platform allows it (Linux), so a few
 * lines fill it. */
static void small_pipe(int fds[2])
{
    assert_int_equal(pipe(fds), 0);
#ifdef F_SETPIPE_SZ
    (void)fcntl(fds[1], F_SETPIPE_SZ, 4096);
#endif
}

/* Everything the read end holds now. */
static size_t drain(int fd, char *buf, size_t cap)
{
    size_t n = 0;
    int fl = fcntl(fd, F_GETFL);
    (void)fcntl(fd, F_SETFL, fl | O_NONBLOCK);
    for (;;) {
        ssize_t r = read(fd, buf + n, cap - n);
        if (r <= 0) {
            break;
        }
        n += (size_t)r;
    }
    (void)fcntl(fd, F_SETFL, fl);
    return n;
}

static void make_line(char *buf, size_t len, int id)
{
    memset(buf, 'a' + id % 26, len - 1u);
    (void)snprintf(buf, len, "%06d", id);
    buf[6] = ' ';
    buf[len - 1u] = '\n';
}

/* Every line in buf is whole: id, then len - 8 copies of its letter. */
static int lines_whole(const char *buf, size_t n, size_t len, int *count)
{
    size_t i;
    *count = 0;
    if (n % len != 0u) {
        return 0;
    }
    for (i = 0; i < n; i += len) {
        int id = atoi(buf + i);
        size_t k;
        for (k = 7; k + 1u < len; k++) {
            if (buf[i + k] != 'a' + id % 26) {
                return 0;
            }
        }
        if (buf[i + len - 1u] != '\n') {
            return 0;
        }
        (*count)++;
    }
    return 1;
}

/* stderr-like (shared, flags left alone): a full pipe drops lines at
 * once; once read, the next line goes in whole and the count is handed
 * over once. */
static void test_logout_full_pipe_drops_without_waiting(void **state)
{
    int fds[2];
    char line[200];
    static char got[1 << 20];
    int i;
    int written = 0;
    int dropped = 0;
    int count = 0;
    size_t n;
    (void)state;
    small_pipe(fds);
    app_logout_init(&out, fds[1], false);
    assert_int_equal(fcntl(fds[1], F_GETFL) & O_NONBLOCK, 0);
    alarm(10);
    for (i = 0; i < 2000; i++) {
        make_line(line, sizeof line, i);
        if (app_logout_line(&out, line, sizeof line) == 1) {
            written++;
        } else {
            dropped++;
        }
    }
    alarm(0);
    assert_true(written > 0);
    assert_true(dropped > 0);
    assert_int_equal(out.dropped, (unsigned long)dropped);
    n = drain(fds[0], got, sizeof got);
    assert_true(lines_whole(got, n, sizeof line, &count));
    assert_int_equal(count, written);
    make_line(line, sizeof line, 7);
    assert_int_equal(app_logout_line(&out, line, sizeof line), 1);
    assert_int_equal(app_logout_take_dropped(&out), (unsigned long)dropped);
    assert_int_equal(app_logout_take_dropped(&out), 0);
    assert_int_equal(out.dropped_total, (unsigned long)dropped);
    n = drain(fds[0], got, sizeof got);
    assert_int_equal(n, sizeof line);
    assert_int_equal(atoi(got), 7);
    (void)close(fds[0]);
    (void)close(fds[1]);
}

/* The JSON log's own descriptor: a line longer than the room left is
 * written in part and finished before the next line, which waits its
 * turn (dropped meanwhile): the reader sees whole lines in order. */
static void test_logout_long_lines_finish_before_the_next(void **state)
{
    int fds[2];
    static char line[9000];
    static char got[1 << 20];
    size_t n = 0;
    int i;
    int sent = 0;
    int count = 0;
    int prev = -1;
    size_t k;
    (void)state;
    small_pipe(fds);
    app_logout_init(&out, fds[1], true);
    assert_int_not_equal(fcntl(fds[1], F_GETFL) & O_NONBLOCK, 0);
    alarm(10);
    for (i = 0; i < 400; i++) {
        make_line(line, sizeof line, i);
        if (app_logout_line(&out, line, sizeof line) == 1) {
            sent++;
        }
        if (i % 3 == 2) { /* a reader that reads now and then */
            n += drain(fds[0], got + n, sizeof got - n);
        }
    }
    while (app_logout_flush(&out) == 0) {
        n += drain(fds[0], got + n, sizeof got - n);
    }
    n += drain(fds[0], got + n, sizeof got - n);
    alarm(0);
    assert_true(sent > 0);
    assert_true(out.dropped_total > 0u);
    assert_true(lines_whole(got, n, sizeof line, &count));
    assert_int_equal(count, sent);
    for (k = 0; k < n; k += sizeof line) { /* in order */
        assert_true(atoi(got + k) > prev);
        prev = atoi(got + k);
    }
    (void)close(fds[0]);
    (void)close(fds[1]);
}

/* journald's stream socket (shared): send(MSG_DONTWAIT), never a wait. */
static void test_logout_socket_full_drops(void **state)
{
    int sv[2];
    char line[300];
    int i;
    int dropped = 0;
    (void)state;
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    app_logout_init(&out, sv[1], false);
    alarm(10);
    for (i = 0; i < 20000 && dropped == 0; i++) {
        make_line(line, sizeof line, i);
        if (app_logout_line(&out, line, sizeof line) == 0) {
            dropped++;
        }
    }
    alarm(0);
    assert_int_equal(out.sock, 1);
    assert_int_equal(dropped, 1);
    (void)close(sv[0]);
    (void)close(sv[1]);
}

/* A reader gone (EPIPE) is a failure the caller hears about; a regular
 * file takes every line. */
static void test_logout_broken_and_file(void **state)
{
    int fds[2];
    char line[64];
    char path[] = "/tmp/negobs-logout-XXXXXX";
    int fd;
    int i;
    (void)state;
    assert_int_equal(pipe(fds), 0);
    (void)close(fds[0]);
    app_logout_init(&out, fds[1], false);
    make_line(line, sizeof line, 1);
    assert_int_equal(app_logout_line(&out, line, sizeof line), -1);
    assert_int_equal(out.err, EPIPE);
    (void)close(fds[1]);

    fd = mkstemp(path);
    assert_true(fd >= 0);
    app_logout_init(&out, fd, true);
    for (i = 0; i < 1000; i++) {
        make_line(line, sizeof line, i);
        assert_int_equal(app_logout_line(&out, line, sizeof line), 1);
    }
    assert_int_equal(out.dropped_total, 0);
    assert_int_equal(lseek(fd, 0, SEEK_END), 1000 * (off_t)sizeof line);
    (void)close(fd);
    (void)unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_logout_full_pipe_drops_without_waiting),
        cmocka_unit_test(test_logout_long_lines_finish_before_the_next),
        cmocka_unit_test(test_logout_socket_full_drops),
        cmocka_unit_test(test_logout_broken_and_file),
    };
    (void)signal(SIGPIPE, SIG_IGN);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
