/*
 * Alert state machine: detector verdicts + a millisecond clock -> one
 * vibration motor (on/off + duty). Pure logic; the port executes the
 * command and calls negobs_alert_update() again no later than
 * cmd.next_change_ms (from a timer that the vision thread cannot starve:
 * without a fresh verdict for stale_ms the output becomes NO_INFO).
 *
 * Patterns (docs/REQUIREMENTS.md; every pulse >= min_pulse_ms = 80 ms):
 *
 *   READY        2 x (100 on, 100 off), once after init
 *   CAUTION      80 on, 80 off, 80 on, then off; repeated every
 *                1000 / 600 / 400 ms by distance band (far / mid / near)
 *   IMMINENT     300 on, 100 off, continuous
 *   NO_INFO      on entry 3 x (400 on, 200 off), then 600 on every 3000 ms
 *   LOW_BATTERY  4 x (80 on, 120 off), once per battery_period_ms
 *   SHORT_SIGHT  160 on, 1840 off, repeated: CLEAR, but vouched for less
 *                than the warning range (detector result short_sight)
 *   NONE         (clear) the heartbeat: one heartbeat_pulse_ms (80) pulse
 *                every heartbeat_period_ms (5000), after a silent gap;
 *                heartbeat_period_ms = 0 makes clear silent
 *
 * Priorities: IMMINENT > CAUTION > SHORT_SIGHT > READY > NO_INFO >
 * LOW_BATTERY. A higher
 * priority pre-empts at once; a lower one waits until the motor is off
 * (a pulse is never cut). Caution band changes wait for the gap after the
 * two-pulse burst. IMMINENT is held for imminent_hold_ms after its last
 * verdict, so a brief degraded blip does not turn it into "unknown".
 *
 * Heartbeat: a motor that is simply off (a crash, SIGKILL, a flat battery,
 * a broken wire) feels exactly like "clear", so while clear the motor
 * gives a brief pulse every few seconds and the wearer notices when it
 * stops. 5 s: missed within one or two periods (about 7-14 m of walking
 * at 1.4 m/s), and rare enough not to mask or tire; 80 ms, the shortest
 * pulse that is reliably felt, and a single one, so it is never confused
 * with CAUTION (two pulses every 0.4-1 s), NO_INFO (400-600 ms pulses)
 * or IMMINENT. It has the lowest priority: every other pattern pre-empts
 * it. The command reports it as NEGOBS_PATTERN_NONE (nothing to warn of).
 */
#ifndef NEGOBS_ALERT_H
#define NEGOBS_ALERT_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/status.h"
#include "negobs/verdict.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum negobs_alert_pattern {
    NEGOBS_PATTERN_NONE = 0,
    NEGOBS_PATTERN_READY = 1,
    NEGOBS_PATTERN_LOW_BATTERY = 2,
    NEGOBS_PATTERN_NO_INFO_ENTRY = 3,
    NEGOBS_PATTERN_NO_INFO = 4,
    NEGOBS_PATTERN_CAUTION_FAR = 5,
    NEGOBS_PATTERN_CAUTION_MID = 6,
    NEGOBS_PATTERN_CAUTION_NEAR = 7,
    NEGOBS_PATTERN_IMMINENT = 8,
    NEGOBS_PATTERN_SHORT_SIGHT = 9,
    NEGOBS_PATTERN_COUNT = 10
} negobs_alert_pattern_t;

/** Segments listed in a motor command. */
#define NEGOBS_ALERT_MAX_SEGMENTS 8

typedef struct negobs_alert_config {
    int32_t min_pulse_ms;        /**< shortest on-time (default 80 ms)   */
    int32_t intensity_permille;  /**< PWM duty of every pulse (1000)     */
    int32_t band_far_mm;         /**< caution range >= this: FAR (3000)  */
    int32_t band_mid_mm;         /**< >= this: MID, else NEAR (2200 mm)  */
    int32_t binary_mode;         /**< 1: one caution pattern (MID) (0)   */
    int32_t stale_ms;            /**< no verdict this long: NO_INFO (300) */
    int32_t noinfo_rearm_ms;     /**< entry burst again after (10000 ms) */
    int32_t battery_period_ms;   /**< low-battery repeat (60000 ms)      */
    int32_t imminent_hold_ms;    /**< keep IMMINENT after it (1000 ms)   */
    int32_t ready_on_start;      /**< play READY after init (1)          */
    int32_t heartbeat_period_ms; /**< clear: a pulse this often (5000);
                                      0 = off, else 1000..60000         */
    int32_t heartbeat_pulse_ms;  /**< its length (80): min_pulse_ms ..
                                      heartbeat_period_ms / 4           */
} negobs_alert_config_t;

/** One verdict for the alert logic. */
typedef struct negobs_alert_input {
    negobs_alert_level_t level; /**< most urgent confirmed hazard      */
    int32_t range_mm;           /**< its range (mm)                    */
    int32_t no_info;            /**< detector degraded                 */
    int32_t battery_low;        /**< battery low                       */
    uint32_t verdict_ms;        /**< time of the verdict (ms)          */
    int32_t short_sight;        /**< CLEAR, vouched for less than the
                                     warning range                     */
} negobs_alert_input_t;

/** A stretch of constant motor output. */
typedef struct negobs_motor_segment {
    uint32_t start_ms;     /**< absolute start time (ms)             */
    int32_t on;            /**< 1 = motor on                         */
    int32_t duty_permille; /**< PWM duty when on, 0 when off         */
} negobs_motor_segment_t;

/** Motor command: what to do now and what is scheduled next. */
typedef struct negobs_motor_cmd {
    int32_t on;                     /**< motor on now                  */
    int32_t duty_permille;          /**< duty now (0 when off)         */
    uint32_t next_change_ms;        /**< call update again by then     */
    negobs_alert_pattern_t pattern; /**< pattern playing               */
    uint32_t n_segments;            /**< upcoming segments (from now)  */
    negobs_motor_segment_t segments[NEGOBS_ALERT_MAX_SEGMENTS];
} negobs_motor_cmd_t;

/** Context; fields are private. */
typedef struct negobs_alert {
    negobs_alert_config_t cfg;
    uint32_t magic;
    int32_t started;
    negobs_alert_pattern_t pat;
    uint32_t pat_start_ms;
    int32_t ready_pending;
    int32_t have_input;
    negobs_alert_input_t in;
    int32_t imminent_seen;
    uint32_t last_imminent_ms;
    int32_t noinfo_seen;
    uint32_t last_noinfo_ms;
    int32_t battery_played;
    uint32_t battery_start_ms;
    int32_t motor_on;
    uint32_t on_since_ms;
} negobs_alert_t;

/** @brief Defaults (see the field comments). */
void negobs_alert_config_default(negobs_alert_config_t *cfg);

/** @brief The alert logic needs no workspace: *bytes_out = 0. */
negobs_status_t negobs_alert_workspace_size(const negobs_alert_config_t *cfg,
                                            size_t *bytes_out);

/**
 * @brief Validate cfg (min_pulse_ms 30..1000, every pattern pulse must be
 *        at least min_pulse_ms, duty 1..1000, heartbeat as documented at
 *        its fields, ...) and reset the state.
 *        workspace may be NULL (size 0).
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_alert_init(negobs_alert_t *ctx,
                                  const negobs_alert_config_t *cfg,
                                  void *workspace, size_t workspace_bytes);

/**
 * @brief Advance to now_ms, with a new verdict or NULL (timer tick).
 *        Times are wrap-safe uint32 milliseconds and must not go back.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (NULL ctx/out),
 *         NEGOBS_ERR_STATE (not initialised).
 */
negobs_status_t negobs_alert_update(negobs_alert_t *ctx, uint32_t now_ms,
                                    const negobs_alert_input_t *input,
                                    negobs_motor_cmd_t *cmd);

struct negobs_detect_result; /* negobs/detect.h */

/** @brief Verdict from a detector result. */
void negobs_alert_input_from_result(const struct negobs_detect_result *res,
                                    int32_t battery_low, uint32_t verdict_ms,
                                    negobs_alert_input_t *in);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_ALERT_H */
