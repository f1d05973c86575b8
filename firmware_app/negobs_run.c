/*
 * negobs_run: the device program. This file: signals, start-up and
 * shutdown (main); the rest in run_settings.c (settings, command line,
 * log), run_devices.c (motor output, cameras, calibration table) and
 * run_loop.c (the main loop), sharing run_app.h.
 *
 *   negobs_run [options] LEFT RIGHT      LEFT/RIGHT: /dev/videoN or replay:DIR
 *                                        or libcamera:N / libcamera:ID
 *
 * Main loop, top to bottom:
 *   1. settings: defaults <- --config FILE <- command-line options
 *   2. [--calib: the rectification table loaded and checked]
 *   3. motor output opened, motor thread started; the library's alert
 *      state machine plays READY
 *   4. [--record: writer thread started, unless DIR holds a session]
 *      camera pair opened and started
 *   5. for each synchronised pair: [queued for the writer thread] ->
 *      [rectify] -> app_process_pair() -> the library's alert state
 *      machine -> motor schedule -> motor thread; once per second a status
 *      line (fps, latency, dropped pairs)
 *   6. on any terminating signal, --frames N, or end of a replay: stop,
 *      summary, motor off
 *
 * The recording is optional: a failure stops it (logged once, in the
 * summary), never the warnings (negobs_port/record_queue.h).
 *
 * No fresh verdict within watchdog_ms -> no-information pattern: the
 * schedule handed to the motor thread already switches to it at that time
 * (app_alert.h), whether the main loop is alive or not; the motor
 * thread's own watchdog is a last resort (backstop_ms()).
 *
 * All buffers are static and sized by NEGOBS_RUN_MAX_W/H. Each usable
 * pair runs the library's whole pipeline (see app_pipeline.h): stereo,
 * ground model, drop-off detection with temporal confirmation.
 */
#define _POSIX_C_SOURCE 200809L

#include <string.h>
#include <unistd.h>

#include "negobs_port/clock.h"
#include "negobs_port/cpu.h"
#include "run_app.h"

/* Longest wait for the library's READY pattern before the cameras open. */
#define APP_READY_MAX_MS 1000u
/* The motor thread's own watchdog is a last resort: every posted schedule
 * already switches to no-information watchdog_ms after the last verdict
 * and then loops it (app_alert.h), on the motor thread's clock. It fires
 * after twice that (at least 1 s more), so that it never cuts into what
 * the library plays while a slow pair is being judged. */
static uint32_t backstop_ms(uint32_t watchdog_ms)
{
    return watchdog_ms < 1000u ? watchdog_ms + 1000u : 2u * watchdog_ms;
}
/* ---- signals -------------------------------------------------------- */

/* Every signal whose default action ends the process is caught, so no
 * signal can stop negobs_run mid-pattern with the motor on:
 *  - asked to stop (SIGINT, SIGTERM, SIGHUP, SIGQUIT): clean shutdown,
 *    summary, motor off, exit 0;
 *  - any other terminating signal (SIGUSR1/2, SIGALRM, SIGXCPU, SIGPWR,
 *    SIGIO, real-time signals, ...): the same shutdown, exit 128 + the
 *    signal number, so that a supervisor sees an abnormal end;
 *  - SIGPIPE and SIGXFSZ that the kernel raises for one of our own writes
 *    (a closed console pipe, the file size limit while recording) are
 *    swallowed: that write fails with EPIPE / EFBIG and its owner handles
 *    it (motor output fault, recording stopped) while the warnings go on.
 *    Sent by another process they stop it like the signals above;
 *  - faults (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGSYS, SIGTRAP):
 *    motor off with async-signal-safe calls, then the default action.
 * SIGKILL and power loss cannot be caught: docs/RUNNING.md says what the
 * hardware does then. */
volatile sig_atomic_t run_stop_requested;
volatile sig_atomic_t run_stop_signal;

static void on_stop_signal(int sig)
{
    run_stop_signal = sig;
    run_stop_requested = 1;
}

static void on_write_signal(int sig, siginfo_t *si, void *uctx)
{
    (void)uctx;
    /* the kernel sends these for a write of ours as SI_USER from our own
     * process id; anything else came from outside */
    if (si != NULL && si->si_code == SI_USER && si->si_pid == getpid()) {
        return;
    }
    on_stop_signal(sig);
}

/* Fatal signals: the motor must not keep running after a crash. Only
 * async-signal-safe calls (write/ioctl on open descriptors), then the
 * default action runs (SA_RESETHAND). */
static void on_fatal_signal(int sig)
{
    negobs_motor_out_off_async(&run_alert);
    (void)raise(sig);
}

/* SIGINT, SIGTERM, SIGHUP, SIGQUIT: a request to stop (exit 0). */
bool is_stop_request(int sig)
{
    return sig == SIGINT || sig == SIGTERM || sig == SIGHUP || sig == SIGQUIT;
}

const char *signal_name(int sig)
{
    static const struct {
        int sig;
        const char *name;
    } names[] = {
        {SIGINT, "SIGINT"},       {SIGTERM, "SIGTERM"},
        {SIGHUP, "SIGHUP"},       {SIGQUIT, "SIGQUIT"},
        {SIGUSR1, "SIGUSR1"},     {SIGUSR2, "SIGUSR2"},
        {SIGALRM, "SIGALRM"},     {SIGXCPU, "SIGXCPU"},
        {SIGXFSZ, "SIGXFSZ"},     {SIGPIPE, "SIGPIPE"},
        {SIGVTALRM, "SIGVTALRM"}, {SIGPROF, "SIGPROF"},
        {SIGPOLL, "SIGIO"},
#ifdef SIGPWR
        {SIGPWR, "SIGPWR"},
#endif
#ifdef SIGSTKFLT
        {SIGSTKFLT, "SIGSTKFLT"},
#endif
    };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (names[i].sig == sig) {
            return names[i].name;
        }
    }
    return "a real-time signal";
}

static void install_signals(void)
{
    static const int stops[] = {
        SIGINT,    SIGTERM, SIGHUP,    SIGQUIT, SIGUSR1, SIGUSR2,
        SIGALRM,   SIGXCPU, SIGVTALRM, SIGPROF, SIGPOLL,
#ifdef SIGPWR
        SIGPWR,
#endif
#ifdef SIGSTKFLT
        SIGSTKFLT,
#endif
    };
    static const int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL,
                                SIGABRT, SIGSYS, SIGTRAP};
    struct sigaction sa;
    size_t i;
    int rt;
    memset(&sa, 0, sizeof sa);
    (void)sigemptyset(&sa.sa_mask);
    sa.sa_handler = on_stop_signal; /* no SA_RESTART: waits return EINTR */
    for (i = 0; i < sizeof stops / sizeof stops[0]; i++) {
        (void)sigaction(stops[i], &sa, NULL);
    }
#ifdef SIGRTMIN
    /* their default action is to terminate too */
    for (rt = SIGRTMIN; rt <= SIGRTMAX; rt++) {
        (void)sigaction(rt, &sa, NULL);
    }
#else
    (void)rt;
#endif
    sa.sa_handler = NULL;
    sa.sa_sigaction = on_write_signal;
    sa.sa_flags = SA_SIGINFO;
    (void)sigaction(SIGPIPE, &sa, NULL);
    (void)sigaction(SIGXFSZ, &sa, NULL);
    memset(&sa, 0, sizeof sa);
    (void)sigemptyset(&sa.sa_mask);
    sa.sa_handler = on_fatal_signal;
    sa.sa_flags = (int)SA_RESETHAND;
    for (i = 0; i < sizeof fatal / sizeof fatal[0]; i++) {
        (void)sigaction(fatal[i], &sa, NULL);
    }
}

int main(int argc, char **argv)
{
    run_args_t args;
    negobs_motor_schedule_t noinfo_sched;
    int rc;

    {
        /* First of all: in a library built with -mfpu=neon the compiler may
         * use NEON in any function (config defaults included), so on a CPU
         * without it the first library call would die with SIGILL. */
        char why[256];
        if (negobs_port_cpu_check(why, sizeof why) != NEGOBS_OK) {
            fprintf(stderr, "negobs_run: %s\n", why);
            return EXIT_RUNTIME;
        }
    }
    run_log_t0_ms = negobs_clock_now_ms();
    service_init();
    settings_default();
    memset(&args, 0, sizeof args);
    rc = parse_args(argc, argv, &args);
    if (rc >= 0) {
        return rc;
    }
    if (args.list_cameras) {
        return list_cameras(&args);
    }
    if (args.motor_off != NULL) {
        /* "config": the unit's ExecStopPost needs no copy of the spec */
        return motor_off(strcmp(args.motor_off, "config") == 0
                             ? run_cfg.alert
                             : args.motor_off);
    }
    if (check_alert_spec(run_cfg.alert) != 0) {
        return usage_error("bad alert '%s' (want gpio:CHIP:LINE, "
                           "pwm:CHIP:CHANNEL, console or none)",
                           run_cfg.alert);
    }
    rc = check_camera_args(&args);
    if (rc != 0) {
        return rc;
    }
    if (run_cfg.calib[0] != '\0') {
        rc = load_calib(run_cfg.calib);
        if (rc >= 0) {
            return rc;
        }
    }
    rc = camera_geometry(&args);
    if (rc >= 0) {
        return rc;
    }
    rc = loop_setup(&noinfo_sched);
    if (rc >= 0) {
        return rc;
    }
    install_signals();
    if (calib_loaded()) {
        log_calib(run_cfg.calib);
    }
    warn_default_geometry();
    logmsg(LOG_INFO,
           "matcher threads: %ld (row bands: the same output for "
           "every count)",
           (long)run_cfg.app.threads);
    if (run_cfg.app.vertical_align) {
        logmsg(LOG_INFO, "vertical alignment stage on (sub-pixel, "
                         "row-varying model estimated from the frames)");
    }

    if (open_alert(run_cfg.alert) != 0) {
        return EXIT_ALERT;
    }
    if (negobs_motor_thread_start(
            &run_motor, &run_alert, &noinfo_sched,
            backstop_ms((uint32_t)run_cfg.watchdog_ms)) != NEGOBS_OK) {
        logmsg(LOG_ERROR, "cannot start the motor thread");
        negobs_motor_out_close(&run_alert);
        return EXIT_ALERT;
    }
    /* READY: the library plays it first; posting keeps the motor
     * thread's watchdog from cutting it while it plays. */
    {
        uint32_t waited;
        for (waited = 0; waited < APP_READY_MAX_MS; waited += 40u) {
            alert_post(NULL);
            if (alert_pattern_now() != NEGOBS_PATTERN_READY) {
                break;
            }
            negobs_clock_sleep_ms(40u);
        }
    }

    button_start(&noinfo_sched);
    if (run_cfg.log_json[0] != '\0') {
        json_log_open(run_cfg.log_json);
    }
    record_start();
    if (open_camera(&args) != 0) {
        record_stop();
        json_log_close();
        button_stop();
        negobs_motor_thread_stop(&run_motor);
        negobs_motor_out_close(&run_alert);
        return EXIT_CAMERA;
    }
    rc = run_loop();
    service_stopping();

    /* Shutdown: camera first, then the motor (off) and its output, then
     * the recording: a stalled card may hold up the writer's last pairs,
     * never the motor's switch-off. */
    negobs_capture_stop(&run_camera);
    negobs_capture_close(&run_camera);
    button_stop();
    negobs_motor_thread_stop(&run_motor);
    negobs_motor_out_close(&run_alert);
    record_stop();
    json_log_close();
    logmsg(LOG_INFO, "exit %d", rc);
    return rc;
}
