/*
 * Vibration output: motor schedules, output backends and the executor.
 *
 * A motor schedule is a short list of segments, each a drive level in
 * per-mille (0 = off, 1000 = full) held for a number of milliseconds. It is
 * played once from the first segment; when `loop_start` names a segment,
 * playback then repeats [loop_start, count) until another schedule replaces
 * it. The core library's alert state machine decides *which* schedule to
 * play; this layer only plays it with correct timing on a backend.
 *
 * Backends (one instance each, state in a caller-owned struct, no heap):
 *   console  - prints every level change to a FILE (developer aid)
 *   pwm      - Linux sysfs PWM; duty_cycle = period * level / 1000
 *   gpio     - Linux GPIO character device (uAPI v2 ioctls); on if level>0
 *   none     - discards everything
 */
#ifndef NEGOBS_PORT_MOTOR_H
#define NEGOBS_PORT_MOTOR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <pthread.h>

#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest number of segments in one schedule (64: firmware_app plays
 *  the core's alert patterns for up to several seconds ahead, e.g. 5 s of
 *  10-segment-per-second caution, then the no-information loop). */
#define NEGOBS_MOTOR_MAX_SEGMENTS 64
/** `loop_start` value for a schedule that is played once and then stops. */
#define NEGOBS_MOTOR_NO_LOOP 0xFFu
/** Highest drive level (per-mille). */
#define NEGOBS_MOTOR_FULL 1000u

/** One segment: hold `duty_permille` for `duration_ms`. */
typedef struct negobs_motor_step {
    uint16_t duty_permille; /**< 0 (off) .. 1000 (full drive)       */
    uint16_t duration_ms;   /**< 1 .. 65535 ms; 0-length is skipped */
} negobs_motor_step_t;

/** A whole pattern, passed by value (it is small). */
typedef struct negobs_motor_schedule {
    negobs_motor_step_t seg[NEGOBS_MOTOR_MAX_SEGMENTS];
    uint8_t count;      /**< segments used, 0..NEGOBS_MOTOR_MAX_SEGMENTS  */
    uint8_t loop_start; /**< first repeated segment, or NEGOBS_MOTOR_NO_LOOP */
} negobs_motor_schedule_t;

/**
 * @brief Check a schedule: count in range, durations > 0 for at least one
 *        looped segment, levels <= 1000, loop_start < count or NO_LOOP.
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_motor_schedule_check(const negobs_motor_schedule_t *s);

/** @brief True when two schedules are the same pattern. */
bool negobs_motor_schedule_equal(const negobs_motor_schedule_t *a,
                                 const negobs_motor_schedule_t *b);

/* ------------------------------------------------------------------ */
/* Output backends                                                     */

/**
 * Operations of one output backend; `ctx` is the backend's state. Backends
 * fill the table with designated initialisers; set and close are required,
 * off_async is optional. Callers use the negobs_alert_*() wrappers below.
 */
typedef struct negobs_motor_out_ops {
    const char *name;
    /** Drive the motor at `duty_permille` (0..1000). */
    negobs_status_t (*set)(void *ctx, uint16_t duty_permille);
    /**
     * Turn the motor off using only async-signal-safe calls (write, ioctl
     * on descriptors opened earlier); may be NULL. Used from a signal
     * handler as the last resort.
     */
    void (*off_async)(void *ctx);
    /** Motor off, release the device. Safe to call twice. */
    void (*close)(void *ctx);
} negobs_motor_out_ops_t;

/** A handle: ops plus backend state. */
typedef struct negobs_motor_out {
    const negobs_motor_out_ops_t *ops;
    void *ctx;
} negobs_motor_out_t;

/** Size of the per-handle diagnostic message. */
#define NEGOBS_PORT_ERRMSG_LEN 160

/** Console backend state. */
typedef struct negobs_motor_out_console {
    FILE *out;     /**< where level changes are printed */
    uint16_t last; /**< last level printed               */
    bool started;
    uint64_t t0_ms; /**< time base for printed stamps     */
} negobs_motor_out_console_t;

/** @brief Console backend writing lines "motor <t> ms: 1000 permille". */
negobs_status_t negobs_motor_out_console_open(negobs_motor_out_console_t *st,
                                              FILE *out,
                                              negobs_motor_out_t *alert);

/** @brief Backend that accepts and discards everything. */
negobs_status_t negobs_motor_out_none_open(negobs_motor_out_t *alert);

/** Sysfs PWM backend state (caller-owned; fields private). */
typedef struct negobs_motor_out_pwm {
    char root[128]; /**< class root, default "/sys/class/pwm"   */
    uint32_t chip;
    uint32_t channel;
    uint32_t period_ns;
    int duty_fd;        /**< open duty_cycle file, -1 when closed   */
    bool exported_here; /**< we exported it, so we unexport it      */
    uint16_t last;
    int last_errno;
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
} negobs_motor_out_pwm_t;

/**
 * @brief Open a sysfs PWM channel as motor output.
 *
 * Writes `CHANNEL` to ROOT/pwmchipCHIP/export unless pwmCHANNEL/ exists,
 * waits up to 1 s for pwmCHANNEL/ to appear (export is asynchronous on
 * real kernels, udev may still be fixing permissions), then writes
 * duty_cycle 0, period, duty_cycle 0 again and enable 1.
 * @param root       sysfs class root; NULL means "/sys/class/pwm"
 * @param period_ns  PWM period (e.g. 1000000 for 1 kHz); > 0
 * @return NEGOBS_OK; NEGOBS_ERR_NODEV (no chip or channel),
 *         NEGOBS_ERR_IO (a write failed, see st->errmsg),
 *         NEGOBS_ERR_INVAL (bad arguments).
 */
negobs_status_t negobs_motor_out_pwm_open(negobs_motor_out_pwm_t *st,
                                          const char *root, uint32_t chip,
                                          uint32_t channel, uint32_t period_ns,
                                          negobs_motor_out_t *alert);

/** Re-request back-off of a lost GPIO line (ms), doubled per failure. */
#define NEGOBS_GPIO_RETRY_MIN_MS 100u
#define NEGOBS_GPIO_RETRY_MAX_MS 2000u

/** GPIO character-device backend state (fields private). */
typedef struct negobs_motor_out_gpio {
    int chip_fd;
    int line_fd;
    uint32_t line;
    int value;
    bool uapi_v1; /**< kernel < 5.10: line held through uAPI v1 */
    bool active_low;
    char path[128]; /**< chip device, kept to request the line again */
    char label[32]; /**< chip label, to find it again if renumbered */
    bool lost;      /**< a write failed: line released, re-request  */
    uint64_t retry_at_ms;
    uint32_t backoff_ms;
    uint32_t reopens; /**< successful re-requests                     */
    int last_errno;
    char errmsg[NEGOBS_PORT_ERRMSG_LEN];
} negobs_motor_out_gpio_t;

/**
 * @brief Request one output line through the GPIO chardev (uAPI v2, or v1
 *        on kernels older than 5.10).
 * @param chip  "/dev/gpiochip0", "gpiochip0" or "0"
 * @param line  line offset on that chip
 * @param active_low  drive the line low for "motor on"
 * @return NEGOBS_OK, NEGOBS_ERR_NODEV (no chip), NEGOBS_ERR_IO (request
 *         refused, e.g. line busy; see st->errmsg), NEGOBS_ERR_INVAL.
 *
 * A write that fails later (the chip was unbound or unplugged: ENODEV)
 * releases the line; the following writes request it again with back-off
 * (NEGOBS_GPIO_RETRY_MIN_MS doubling to _MAX_MS) from the same chip path,
 * or from the /dev/gpiochipN with the same label when the chip came back
 * under another number, and return NEGOBS_ERR_NODEV until it is back.
 */
negobs_status_t negobs_motor_out_gpio_open(negobs_motor_out_gpio_t *st,
                                           const char *chip, uint32_t line,
                                           bool active_low,
                                           negobs_motor_out_t *alert);

/** @brief Convenience wrappers around alert->ops. */
static inline negobs_status_t negobs_motor_out_set(negobs_motor_out_t *a,
                                                   uint16_t duty_permille)
{
    return a->ops->set(a->ctx, duty_permille);
}
static inline void negobs_motor_out_close(negobs_motor_out_t *a)
{
    if (a->ops != NULL) {
        a->ops->close(a->ctx);
    }
}
/**
 * @brief The backend's async-signal-safe motor off, when it has one (and a
 *        handle is open); nothing otherwise. Safe in a signal handler: it
 *        only reads two pointers before the call.
 */
static inline void negobs_motor_out_off_async(negobs_motor_out_t *a)
{
    if (a->ops != NULL && a->ops->off_async != NULL) {
        a->ops->off_async(a->ctx);
    }
}

/* ------------------------------------------------------------------ */
/* Schedule executor                                                   */

/**
 * Plays schedules on an output. It is driven by negobs_motor_exec_tick()
 * with the current time, so it has no thread and no clock of its own:
 * tests give it fake times, the motor thread below gives it real ones.
 * Segment boundaries are anchored to the schedule start (no drift when a
 * tick comes late; late ticks skip whole segments as needed).
 */
typedef struct negobs_motor_exec {
    negobs_motor_out_t *out;
    negobs_motor_schedule_t sched;
    bool active;         /**< a schedule is playing                    */
    uint8_t seg;         /**< current segment index                    */
    uint64_t seg_end_ms; /**< when the current segment ends            */
    int32_t level;       /**< level last written, -1 = unknown         */
    uint32_t set_errors; /**< output writes that failed                */
    negobs_status_t last_status;
} negobs_motor_exec_t;

/** @brief Bind an executor to an output; nothing plays yet. */
void negobs_motor_exec_init(negobs_motor_exec_t *ex, negobs_motor_out_t *out);

/**
 * @brief Start `s` from its first segment at time `now_ms` (replaces any
 *        schedule playing) and apply its first level.
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL (schedule fails the check).
 */
negobs_status_t negobs_motor_exec_start(negobs_motor_exec_t *ex,
                                        const negobs_motor_schedule_t *s,
                                        uint64_t now_ms);

/**
 * @brief Advance to `now_ms`, writing the output when the level changes.
 * @return Milliseconds until the next change (>= 1), or -1 when idle
 *         (schedule finished, motor off).
 */
int64_t negobs_motor_exec_tick(negobs_motor_exec_t *ex, uint64_t now_ms);

/** @brief Stop playing and switch the motor off. */
void negobs_motor_exec_stop(negobs_motor_exec_t *ex);

/* ------------------------------------------------------------------ */
/* Motor thread with watchdog                                          */

/** The current level is written again this often (ms), so that an output
 *  that died during a silent pattern is noticed. */
#define NEGOBS_MOTOR_REFRESH_MS 1000u
/** While output writes fail, they are retried this often (ms). */
#define NEGOBS_MOTOR_RETRY_MS 100u
/** After the output comes back, `stale` plays this long before the main
 *  loop's pattern again (ms): the no-information entry burst. */
#define NEGOBS_MOTOR_RECOVER_HOLD_MS 2000u

/**
 * A POSIX thread that runs an executor against the monotonic clock and
 * doubles as the watchdog: when negobs_motor_thread_post() has not been
 * called for `watchdog_ms`, it plays `stale` (the no-information pattern)
 * on its own, whatever the main loop is stuck in.
 *
 * Output faults: the level is written again every NEGOBS_MOTOR_REFRESH_MS
 * even when it does not change, so a dead output is seen during silence
 * too. When a write to the backend fails, the thread switches to
 * `stale` and retries every NEGOBS_MOTOR_RETRY_MS (backends such as gpio
 * reopen their device from those writes). The user felt nothing, or a
 * stuck level, meanwhile; so when a write of a changed level succeeds
 * again (rewriting the level the output holds proves nothing: the PWM core
 * skips such writes, which also means a PWM fault is only seen at the next
 * level change), `stale` plays for NEGOBS_MOTOR_RECOVER_HOLD_MS before
 * posted patterns resume.
 * The struct is caller-owned; its fields are private.
 */
typedef struct negobs_motor_thread {
    negobs_motor_exec_t exec;
    negobs_motor_schedule_t pending;
    negobs_motor_schedule_t stale;
    uint32_t watchdog_ms;
    uint64_t last_post_ms;
    bool have_pending;
    bool pending_restart; /**< start `pending` anew even if equal       */
    bool stale_playing;
    bool running;
    uint32_t watchdog_fires;
    bool out_failing;       /**< the last output write failed          */
    uint32_t out_faults;    /**< times the output started failing       */
    uint64_t hold_until_ms; /**< stale forced until then (recovery)     */
    uint64_t last_refresh_ms;
    int32_t ok_level; /**< last level a write confirmed, -1 none  */
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t thread;
} negobs_motor_thread_t;

/**
 * @brief Start the thread. `stale` is played when posts stop for
 *        `watchdog_ms` (0 disables the watchdog). Asynchronous signals
 *        are blocked in the thread so the main thread receives
 *        SIGINT/SIGTERM; fault signals (SIGSEGV, SIGABRT, ...) are not.
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL, NEGOBS_ERR_IO (thread not created).
 */
negobs_status_t negobs_motor_thread_start(negobs_motor_thread_t *t,
                                          negobs_motor_out_t *out,
                                          const negobs_motor_schedule_t *stale,
                                          uint32_t watchdog_ms);

/**
 * @brief Feed the watchdog and ask for schedule `s`. A schedule equal to
 *        the one playing keeps playing (not restarted), so the main loop
 *        may post its verdict every frame.
 */
void negobs_motor_thread_post(negobs_motor_thread_t *t,
                              const negobs_motor_schedule_t *s);

/**
 * @brief negobs_motor_thread_post(), but `s` always starts again from its
 *        first segment, even when it equals the one playing: for
 *        schedules computed relative to the moment of the post (firmware_app
 *        turns the core library's alert state machine into such
 *        schedules; the same schedule posted later is a later pattern).
 */
void negobs_motor_thread_post_restart(negobs_motor_thread_t *t,
                                      const negobs_motor_schedule_t *s);

/** @brief Number of times the watchdog took over. */
uint32_t negobs_motor_thread_watchdog_fires(negobs_motor_thread_t *t);

/**
 * @brief Output health, for logs.
 * @param failing  set to true while writes to the backend fail (may be
 *                 NULL); the backend's errmsg says why
 * @return Times the output started failing since start; failed writes in
 *         total are in the executor's set_errors.
 */
uint32_t negobs_motor_thread_output_faults(negobs_motor_thread_t *t,
                                           bool *failing);

/**
 * @brief Copy a backend's errmsg into `buf` (NUL-terminated) under the
 *        thread's lock: the thread writes it (from the backend's set()),
 *        so reading it elsewhere without the lock could see it half
 *        rewritten.
 */
void negobs_motor_thread_copy_msg(negobs_motor_thread_t *t, const char *msg,
                                  char *buf, size_t len);

/** @brief Stop and join the thread; the motor is off afterwards. */
void negobs_motor_thread_stop(negobs_motor_thread_t *t);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_MOTOR_H */
