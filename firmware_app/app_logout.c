/* Log output that never waits (app_logout.h). */
#define _POSIX_C_SOURCE 200809L

#include "app_logout.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#ifndef MSG_NOSIGNAL
#define MSG_NOSIGNAL 0 /* SIGPIPE is ignored by negobs_run anyway */
#endif

void app_logout_init(app_logout_t *o, int fd, bool own)
{
    memset(o, 0, sizeof *o);
    o->fd = fd;
    o->own = own;
    o->sock = -1;
    if (own) {
        int fl = fcntl(fd, F_GETFL);
        if (fl >= 0) {
            (void)fcntl(fd, F_SETFL, fl | O_NONBLOCK);
        }
    }
}

/* One write that does not wait: bytes taken, 0 when the reader is not
 * ready, -1 on failure (errno). */
static ssize_t write_now(app_logout_t *o, const char *p, size_t n)
{
    ssize_t w;
    if (!o->own && o->sock != 0) {
        w = send(o->fd, p, n, MSG_DONTWAIT | MSG_NOSIGNAL);
        if (w >= 0) {
            o->sock = 1;
            return w;
        }
        if (errno != ENOTSOCK) {
            return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)
                       ? 0
                       : -1;
        }
        o->sock = 0;
    }
    if (!o->own) {
        struct pollfd pf;
        pf.fd = o->fd;
        pf.events = POLLOUT;
        pf.revents = 0;
        if (poll(&pf, 1, 0) <= 0 || (pf.revents & POLLOUT) == 0) {
            /* POLLERR / POLLHUP alone: the write below would report it,
             * but only if it is tried */
            if ((pf.revents & (POLLERR | POLLHUP | POLLNVAL)) == 0) {
                return 0;
            }
        }
    }
    w = write(o->fd, p, n);
    if (w >= 0) {
        return w;
    }
    return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? 0
                                                                       : -1;
}

/* Finish a line cut short. 1 done, 0 not yet, -1 failed. */
static int flush_pending(app_logout_t *o)
{
    while (o->pend_len > 0u) {
        ssize_t w = write_now(o, o->pend + o->pend_off, o->pend_len);
        if (w < 0) {
            o->err = errno;
            return -1;
        }
        if (w == 0) {
            return 0;
        }
        o->pend_off += (size_t)w;
        o->pend_len -= (size_t)w;
    }
    o->pend_off = 0;
    return 1;
}

int app_logout_line(app_logout_t *o, const char *line, size_t len)
{
    ssize_t w;
    int f = flush_pending(o);
    if (f <= 0) {
        if (f == 0) {
            o->dropped++;
            o->dropped_total++;
        }
        return f;
    }
    if (len > APP_LOGOUT_LINE_MAX) {
        len = APP_LOGOUT_LINE_MAX;
    }
    w = write_now(o, line, len);
    if (w < 0) {
        o->err = errno;
        return -1;
    }
    if (w == 0) {
        o->dropped++;
        o->dropped_total++;
        return 0;
    }
    if ((size_t)w < len) {
        /* the rest goes first next time: no torn line */
        memcpy(o->pend, line + w, len - (size_t)w);
        o->pend_off = 0;
        o->pend_len = len - (size_t)w;
        (void)flush_pending(o);
    }
    return 1;
}

int app_logout_flush(app_logout_t *o)
{
    return flush_pending(o);
}

unsigned long app_logout_take_dropped(app_logout_t *o)
{
    unsigned long n = o->dropped;
    o->dropped = 0;
    return n;
}
