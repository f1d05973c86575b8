/* Monotonic clock on POSIX (clock_gettime / clock_nanosleep). */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <time.h>

#include "negobs_port/clock.h"

uint64_t negobs_clock_now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

uint64_t negobs_clock_now_ms(void)
{
    return negobs_clock_now_ns() / 1000000u;
}

void negobs_clock_sleep_until_ns(uint64_t deadline_ns,
                                 const volatile int *stop)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(deadline_ns / 1000000000u);
    ts.tv_nsec = (long)(deadline_ns % 1000000000u);
    for (;;) {
        int rc = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
        if (rc != EINTR || (stop != NULL && *stop != 0)) {
            return;
        }
    }
}

void negobs_clock_sleep_ms(uint32_t ms)
{
    negobs_clock_sleep_until_ns(
        negobs_clock_now_ns() + (uint64_t)ms * 1000000u, NULL);
}

static uint64_t monotonic_ms(void *ctx)
{
    (void)ctx;
    return negobs_clock_now_ms();
}

negobs_clock_src_t negobs_clock_monotonic(void)
{
    negobs_clock_src_t c;
    c.now_ms = monotonic_ms;
    c.ctx = NULL;
    return c;
}
