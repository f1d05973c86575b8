/*
 * negobs_run's motor patterns: the library's alert state machine
 * (negobs/alert.h, docs/REQUIREMENTS.md) handed to the port's motor thread
 * (negobs_port/motor.h).
 *
 * The library decides what the motor does at every millisecond from the
 * verdicts and the caller's clock; the motor thread plays a schedule of
 * (level, duration) segments with real timing while the main loop is busy
 * judging a pair or waiting for the cameras. app_alert_step() bridges the
 * two: it advances the library to `now` with the new verdict, then runs a
 * copy of the library forward on a simulated clock with no further verdict
 * and turns what that copy switches into a motor schedule. That schedule
 * is therefore exactly what the library would command if no fresh verdict
 * came: the current pattern, then (after stale_ms, at the library's
 * priorities and minimum pulse) the no-information pattern, repeated for
 * ever. So the 300 ms no-information rule runs on the motor thread's clock
 * and holds even when the main loop hangs.
 */
#ifndef NEGOBS_APP_ALERT_H
#define NEGOBS_APP_ALERT_H

#include <stdint.h>

#include "app_pipeline.h"
#include "negobs/alert.h"
#include "negobs_port/motor.h"

/** Longest stretch a schedule looks ahead before its looped tail (ms). */
#define APP_ALERT_HORIZON_MS 20000u

typedef struct app_alert {
    negobs_alert_t lib;     /**< the real state machine                */
    negobs_motor_cmd_t cmd; /**< its last command                      */
    int32_t started;        /**< app_alert_step() has run once         */
} app_alert_t;

/**
 * @brief Check cfg (negobs_alert_init) and reset. READY plays first when
 *        cfg->ready_on_start is set.
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t app_alert_init(app_alert_t *a,
                               const negobs_alert_config_t *cfg);

/**
 * @brief Advance to now_ms with a verdict (or NULL: no new verdict) and
 *        build the schedule the motor thread should play from now on.
 *
 * Missed wake-ups (cmd.next_change_ms already past) are replayed first at
 * their own times, so the real state machine walks the same path as the
 * schedule the motor thread played. Times are wrap-safe uint32 ms and
 * must not go back.
 * @param[out] sched schedule starting at now_ms; its tail loops the
 *             no-information period (or whatever pattern the library
 *             settles in), so it never runs out.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (NULL), NEGOBS_ERR_STATE (no init).
 */
negobs_status_t app_alert_step(app_alert_t *a, uint32_t now_ms,
                               const negobs_alert_input_t *in,
                               negobs_motor_schedule_t *sched);

/**
 * @brief What negobs_run does with each verdict: app_alert_step() at the
 *        monotonic clock (negobs_clock_now_ms(), the motor thread's), with
 *        the verdict stamped now, then the schedule posted to `motor`
 *        (which also feeds its watchdog).
 * @param in      verdict or NULL (no new verdict); verdict_ms is ignored
 * @param before  pattern before this step; may be NULL
 * @return as app_alert_step().
 */
negobs_status_t app_alert_post(app_alert_t *a, negobs_motor_thread_t *motor,
                               const negobs_alert_input_t *in,
                               negobs_alert_pattern_t *before);

/**
 * @brief The library's no-information pattern (entry burst, then the
 *        repeating pulse) as a schedule, for the motor thread's own
 *        watchdog. The first pulse is shortened by `lead_ms` (>= 0, the
 *        first pulse stays >= cfg->min_pulse_ms): the watchdog fires that
 *        long after the library's own switch, whose pulse it continues.
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t app_alert_noinfo_schedule(const negobs_alert_config_t *cfg,
                                          uint32_t lead_ms,
                                          negobs_motor_schedule_t *sched);

/** @brief Verdict of one pair -> library input (no battery sensing). */
void app_alert_input(app_verdict_t v, const app_frame_stats_t *st,
                     uint32_t verdict_ms, negobs_alert_input_t *in);

/** @brief Pattern playing after the last step. */
negobs_alert_pattern_t app_alert_pattern(const app_alert_t *a);

/** @brief "ready", "caution-far", "no-info", ... */
const char *app_alert_pattern_name(negobs_alert_pattern_t p);

#endif /* NEGOBS_APP_ALERT_H */
