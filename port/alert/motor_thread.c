/*
 * Motor thread: plays schedules with real timing and acts as watchdog.
 *
 * The main loop may block in a camera wait for hundreds of milliseconds,
 * far longer than an 80 ms pulse, so the executor runs in its own thread
 * that sleeps on a condition variable until the next segment boundary, a
 * new schedule, or the watchdog deadline, whichever comes first. The
 * condition variable uses CLOCK_MONOTONIC so wall-clock steps cannot
 * stretch or cut a pulse.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "negobs_port/motor.h"
#include "negobs_port/clock.h"

static void abs_deadline(struct timespec *ts, uint64_t deadline_ms)
{
    ts->tv_sec = (time_t)(deadline_ms / 1000u);
    ts->tv_nsec = (long)((deadline_ms % 1000u) * 1000000u);
}

/*
 * A failed write leaves the executor's level unknown, so its next tick
 * writes again; this makes that tick come soon. While failing, the motor
 * is told "no information" so that the first pattern the user feels once
 * the output is back is that one, held long enough to be noticed.
 * Returns the delay to the next wake-up wanted (ms), or `next` unchanged.
 */
static int64_t output_health(negobs_motor_thread_t *t, uint64_t now,
                             int64_t next)
{
    /* A silent pattern writes nothing, so a dead output would go unseen
     * until the next pulse: write the current level again now and then. */
    if (now - t->last_refresh_ms >= NEGOBS_MOTOR_REFRESH_MS) {
        t->last_refresh_ms = now;
        t->exec.level = -1;
        next = negobs_motor_exec_tick(&t->exec, now);
    }
    if (t->exec.last_status != NEGOBS_OK) {
        if (!t->out_failing) {
            t->out_failing = true;
            t->out_faults++;
            t->stale_playing = true;
            (void)negobs_motor_exec_start(&t->exec, &t->stale, now);
        }
        return (int64_t)NEGOBS_MOTOR_RETRY_MS;
    }
    if (!t->out_failing) {
        t->ok_level = t->exec.level; /* confirmed by a write that worked */
        return next;
    }
    /* Failing, and this write worked. Writing the level the output already
     * had proves nothing (the PWM core skips such a write without touching
     * the hardware): only a changed level counts as back. */
    if (t->exec.level < 0 || t->exec.level == t->ok_level) {
        return next;
    }
    t->out_failing = false;
    t->stale_playing = true;
    (void)negobs_motor_exec_start(&t->exec, &t->stale, now);
    t->hold_until_ms = now + NEGOBS_MOTOR_RECOVER_HOLD_MS;
    t->ok_level = t->exec.level;
    /* the schedule's own next boundary (the caller also wakes for the end
     * of the hold) */
    return negobs_motor_exec_tick(&t->exec, now);
}

static void *motor_main(void *arg)
{
    negobs_motor_thread_t *t = arg;
    (void)pthread_mutex_lock(&t->lock);
    while (t->running) {
        uint64_t now = negobs_clock_now_ms();
        uint64_t wake_at;
        int64_t next;
        struct timespec ts;

        if (t->have_pending && !t->out_failing && now >= t->hold_until_ms) {
            t->have_pending = false;
            t->stale_playing = false;
            if (!t->exec.active || t->pending_restart ||
                !negobs_motor_schedule_equal(&t->pending, &t->exec.sched)) {
                (void)negobs_motor_exec_start(&t->exec, &t->pending, now);
            }
        }
        if (t->watchdog_ms > 0 && !t->stale_playing && !t->out_failing &&
            now >= t->hold_until_ms &&
            now - t->last_post_ms >= t->watchdog_ms) {
            /* No fresh verdict: whatever played is no longer backed by
             * data, so say "no information" instead. */
            t->stale_playing = true;
            t->watchdog_fires++;
            (void)negobs_motor_exec_start(&t->exec, &t->stale, now);
        }
        next = negobs_motor_exec_tick(&t->exec, now);
        next = output_health(t, now, next);
        wake_at = now + NEGOBS_MOTOR_REFRESH_MS;
        if (next >= 0 && now + (uint64_t)next < wake_at) {
            wake_at = now + (uint64_t)next;
        }
        if (now < t->hold_until_ms && t->hold_until_ms < wake_at) {
            wake_at = t->hold_until_ms;
        }
        if (t->watchdog_ms > 0 && !t->stale_playing &&
            t->last_post_ms + t->watchdog_ms < wake_at) {
            wake_at = t->last_post_ms + t->watchdog_ms;
        }
        abs_deadline(&ts, wake_at);
        (void)pthread_cond_timedwait(&t->wake, &t->lock, &ts);
    }
    negobs_motor_exec_stop(&t->exec);
    (void)pthread_mutex_unlock(&t->lock);
    return NULL;
}

negobs_status_t negobs_motor_thread_start(negobs_motor_thread_t *t,
                                          negobs_motor_out_t *out,
                                          const negobs_motor_schedule_t *stale,
                                          uint32_t watchdog_ms)
{
    pthread_condattr_t ca;
    sigset_t all;
    sigset_t old;
    int rc;
    if (t == NULL || out == NULL || stale == NULL ||
        negobs_motor_schedule_check(stale) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    memset(t, 0, sizeof *t);
    negobs_motor_exec_init(&t->exec, out);
    t->stale = *stale;
    t->watchdog_ms = watchdog_ms;
    t->last_post_ms = negobs_clock_now_ms();
    t->ok_level = -1;
    t->running = true;
    if (pthread_mutex_init(&t->lock, NULL) != 0) {
        return NEGOBS_ERR_IO;
    }
    (void)pthread_condattr_init(&ca);
    (void)pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    rc = pthread_cond_init(&t->wake, &ca);
    (void)pthread_condattr_destroy(&ca);
    if (rc != 0) {
        (void)pthread_mutex_destroy(&t->lock);
        return NEGOBS_ERR_IO;
    }
    /* The thread inherits this mask: asynchronous signals go to the main
     * thread. Fault signals stay unblocked, so a crash in this thread
     * still reaches the program's handler (which turns the motor off). */
    (void)sigfillset(&all);
    (void)sigdelset(&all, SIGSEGV);
    (void)sigdelset(&all, SIGBUS);
    (void)sigdelset(&all, SIGFPE);
    (void)sigdelset(&all, SIGILL);
    (void)sigdelset(&all, SIGABRT);
    (void)pthread_sigmask(SIG_BLOCK, &all, &old);
    rc = pthread_create(&t->thread, NULL, motor_main, t);
    (void)pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc != 0) {
        (void)pthread_cond_destroy(&t->wake);
        (void)pthread_mutex_destroy(&t->lock);
        t->running = false;
        return NEGOBS_ERR_IO;
    }
    return NEGOBS_OK;
}

void negobs_motor_thread_post(negobs_motor_thread_t *t,
                              const negobs_motor_schedule_t *s)
{
    (void)pthread_mutex_lock(&t->lock);
    t->pending = *s;
    t->have_pending = true;
    t->pending_restart = false;
    t->last_post_ms = negobs_clock_now_ms();
    (void)pthread_cond_signal(&t->wake);
    (void)pthread_mutex_unlock(&t->lock);
}

void negobs_motor_thread_post_restart(negobs_motor_thread_t *t,
                                      const negobs_motor_schedule_t *s)
{
    (void)pthread_mutex_lock(&t->lock);
    t->pending = *s;
    t->have_pending = true;
    t->pending_restart = true;
    t->last_post_ms = negobs_clock_now_ms();
    (void)pthread_cond_signal(&t->wake);
    (void)pthread_mutex_unlock(&t->lock);
}

uint32_t negobs_motor_thread_output_faults(negobs_motor_thread_t *t,
                                           bool *failing)
{
    uint32_t n;
    (void)pthread_mutex_lock(&t->lock);
    n = t->out_faults;
    if (failing != NULL) {
        *failing = t->out_failing;
    }
    (void)pthread_mutex_unlock(&t->lock);
    return n;
}

void negobs_motor_thread_copy_msg(negobs_motor_thread_t *t, const char *msg,
                                  char *buf, size_t len)
{
    if (buf == NULL || len == 0) {
        return;
    }
    (void)pthread_mutex_lock(&t->lock);
    (void)snprintf(buf, len, "%s", msg != NULL ? msg : "");
    (void)pthread_mutex_unlock(&t->lock);
}

uint32_t negobs_motor_thread_watchdog_fires(negobs_motor_thread_t *t)
{
    uint32_t n;
    (void)pthread_mutex_lock(&t->lock);
    n = t->watchdog_fires;
    (void)pthread_mutex_unlock(&t->lock);
    return n;
}

void negobs_motor_thread_stop(negobs_motor_thread_t *t)
{
    bool was_running;
    (void)pthread_mutex_lock(&t->lock);
    was_running = t->running;
    t->running = false;
    (void)pthread_cond_signal(&t->wake);
    (void)pthread_mutex_unlock(&t->lock);
    if (was_running) {
        (void)pthread_join(t->thread, NULL);
        (void)pthread_cond_destroy(&t->wake);
        (void)pthread_mutex_destroy(&t->lock);
    }
}
