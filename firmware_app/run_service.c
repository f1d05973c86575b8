/*
 * negobs_run under systemd: readiness, watchdog and stop notifications
 * (the sd_notify protocol, when built with libsystemd), and journald
 * priorities.
 *
 * Readiness means "a pair has been judged": the unit's Type=notify start
 * only succeeds once cameras, pipeline and motor work together, so a
 * service that cannot see never counts as started. The watchdog is fed
 * from the main loop, and only when a pair came from the cameras (judged,
 * or taken and skipped while the wearer paused the device): a stuck camera
 * or a hung loop stops the keep-alives and systemd restarts the service
 * (WatchdogSec= in the unit), while the motor thread already plays
 * no-information on its own.
 *
 * The notifications are sent without waiting (notify()): libsystemd's
 * sd_notify() blocks while the notify socket's queue is full (a PID 1
 * that is busy or stopped, or any reader that stops reading; the queue
 * holds net.unix.max_dgram_qlen datagrams, as few as 10), and the main
 * loop would then stop judging pairs while the motor thread could only
 * say no-information. A notification the queue cannot take is dropped
 * and counted (the summary's notify_dropped=); a lost keep-alive is what
 * a stalled supervisor would see anyway.
 *
 * journald: when stderr is the journal (systemd sets JOURNAL_STREAM to
 * its device:inode), every log line starts with the sd-daemon priority
 * prefix ("<3>" error, "<4>" warning, "<6>" info, "<7>" debug), which
 * journald turns into the entry's priority, so `journalctl -p warning`
 * shows the warnings alone. Elsewhere the lines stay plain.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "negobs_port/clock.h"
#include "run_app.h"

#ifdef NEGOBS_HAVE_SYSTEMD
#include <systemd/sd-daemon.h>
#endif

static bool service_ready;
static int notify_fd = -1; /* datagram socket, non-blocking; -1: none */
static struct sockaddr_un notify_addr;
static socklen_t notify_addr_len;
static unsigned long notify_dropped;
static uint64_t watchdog_every_ms; /* 0: no watchdog asked for */
static uint64_t watchdog_last_ms;

bool run_log_journal;

/* JOURNAL_STREAM="DEV:INODE" names the stream journald reads; stderr is
 * the journal only when it is that very file (a redirected stderr of a
 * child is not). */
static bool stderr_is_journal(void)
{
    const char *js = getenv("JOURNAL_STREAM");
    struct stat st;
    unsigned long long dev = 0;
    unsigned long long ino = 0;
    char *end = NULL;
    if (js == NULL || fstat(STDERR_FILENO, &st) != 0) {
        return false;
    }
    dev = strtoull(js, &end, 10);
    if (end == js || *end != ':') {
        return false;
    }
    js = end + 1;
    ino = strtoull(js, &end, 10);
    if (end == js || *end != '\0') {
        return false;
    }
    return dev == (unsigned long long)st.st_dev &&
           ino == (unsigned long long)st.st_ino;
}

#ifdef NEGOBS_HAVE_SYSTEMD
/* NOTIFY_SOCKET: a path, or "@name" for the abstract namespace (the
 * leading '@' becomes a NUL byte, and the address has no terminator). */
static void notify_open(void)
{
    const char *e = getenv("NOTIFY_SOCKET");
    size_t n;
    int fd;
    if (e == NULL || (e[0] != '/' && e[0] != '@')) {
        return;
    }
    n = strlen(e);
    if (n < 2 || n > sizeof notify_addr.sun_path - 1) {
        logmsg(LOG_WARN, "NOTIFY_SOCKET is not a socket address; no systemd "
                         "notifications");
        return;
    }
    fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
        logmsg(LOG_WARN, "notify socket: %s; no systemd notifications",
               strerror(errno));
        return;
    }
    memset(&notify_addr, 0, sizeof notify_addr);
    notify_addr.sun_family = AF_UNIX;
    memcpy(notify_addr.sun_path, e, n);
    if (e[0] == '@') {
        notify_addr.sun_path[0] = '\0';
        notify_addr_len = (socklen_t)(offsetof(struct sockaddr_un, sun_path) +
                                      n);
    } else {
        notify_addr_len = (socklen_t)sizeof notify_addr;
    }
    notify_fd = fd;
}
#endif

/* One datagram, never waiting: a full queue drops it (counted). */
static void notify(const char *state)
{
    ssize_t n;
    if (notify_fd < 0) {
        return;
    }
    do {
        n = sendto(notify_fd, state, strlen(state),
                   MSG_DONTWAIT | MSG_NOSIGNAL,
                   (const struct sockaddr *)&notify_addr, notify_addr_len);
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
        notify_dropped++;
    }
}

unsigned long service_notify_dropped(void)
{
    return notify_dropped;
}

void service_init(void)
{
    run_log_journal = stderr_is_journal();
#ifdef NEGOBS_HAVE_SYSTEMD
    notify_open();
    {
        uint64_t usec = 0;
        /* keep-alives at a quarter of WatchdogSec: two may be lost to a
         * slow pair before systemd acts */
        if (sd_watchdog_enabled(0, &usec) > 0 && usec >= 4000u) {
            watchdog_every_ms = usec / 4000u;
        }
    }
#endif
}

bool service_watchdog_on(void)
{
    return watchdog_every_ms > 0u;
}

void service_pair_done(void)
{
    uint64_t now;
    if (!service_ready) {
        service_ready = true;
        notify("READY=1\nSTATUS=judging pairs");
        logmsg(LOG_INFO, "first pair judged: ready");
    }
    if (watchdog_every_ms == 0u) {
        return;
    }
    now = negobs_clock_now_ms();
    if (now - watchdog_last_ms >= watchdog_every_ms) {
        watchdog_last_ms = now;
        notify("WATCHDOG=1");
    }
}

void service_status(const char *text)
{
    char buf[160];
    (void)snprintf(buf, sizeof buf, "STATUS=%s", text);
    notify(buf);
}

void service_stopping(void)
{
    notify("STOPPING=1");
}

int service_log_priority(int level)
{
    static const int prio[] = {3, 4, 6, 7}; /* err, warning, info, debug */
    return (level >= 0 && level <= LOG_DEBUG) ? prio[level] : 6;
}
