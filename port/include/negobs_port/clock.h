/*
 * Monotonic clock of the platform layer.
 *
 * Everything that times something (frame pairing, watchdog, motor
 * schedules, status lines) uses CLOCK_MONOTONIC, never wall time, so a
 * clock step (NTP, RTC set) cannot fire or starve a timer.
 */
#ifndef NEGOBS_PORT_CLOCK_H
#define NEGOBS_PORT_CLOCK_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Monotonic time in nanoseconds (arbitrary epoch, never steps). */
uint64_t negobs_clock_now_ns(void);

/** @brief Monotonic time in milliseconds (same epoch as the ns clock). */
uint64_t negobs_clock_now_ms(void);

/**
 * @brief Sleep until the monotonic clock reaches `deadline_ns`.
 *
 * Restarts after signals unless `*stop` (may be NULL) became non-zero.
 * Returns at once when the deadline has already passed.
 */
void negobs_clock_sleep_until_ns(uint64_t deadline_ns,
                                 const volatile int *stop);

/** @brief Sleep for `ms` milliseconds (restarted after signals). */
void negobs_clock_sleep_ms(uint32_t ms);

/**
 * A clock the motor executor and other timers can be given, so tests can
 * drive time by hand (a fake clock) instead of sleeping.
 */
typedef struct negobs_clock_src {
    uint64_t (*now_ms)(void *ctx); /**< current monotonic time, ms */
    void *ctx;                     /**< passed back to now_ms      */
} negobs_clock_src_t;

/** @brief The real monotonic clock as a negobs_clock_src_t. */
negobs_clock_src_t negobs_clock_monotonic(void);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CLOCK_H */
