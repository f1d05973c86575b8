/*
 * negobs_run under systemd: readiness, watchdog and stop notifications
 * (sd_notify, when built with libsystemd), and journald priorities.
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
 * journald: when stderr is the journal (systemd sets JOURNAL_STREAM to
 * its device:inode), every log line starts with the sd-daemon priority
 * prefix ("<3>" error, "<4>" warning, "<6>" info, "<7>" debug), which
 * journald turns into the entry's priority, so `journalctl -p warning`
 * shows the warnings alone. Elsewhere the lines stay plain.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "negobs_port/clock.h"
#include "run_app.h"

#ifdef NEGOBS_HAVE_SYSTEMD
#include <systemd/sd-daemon.h>
#endif

static bool service_ready;
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

void service_init(void)
{
    run_log_journal = stderr_is_journal();
#ifdef NEGOBS_HAVE_SYSTEMD
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

static void notify(const char *state)
{
#ifdef NEGOBS_HAVE_SYSTEMD
    (void)sd_notify(0, state);
#else
    (void)state;
#endif
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
