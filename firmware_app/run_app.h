/*
 * negobs_run's modules (see negobs_run.c for the whole program):
 *   run_settings.c  settings, config keys, command line, log
 *   run_devices.c   motor output, cameras, calibration table
 *   run_loop.c      the main loop: pipeline, alert, recording, status
 *   run_service.c   systemd readiness/watchdog, journald priorities
 *   run_json.c      --log-json lines and the recorded session's meta.txt
 *   run_button.c    the push button (pause, sensitivity presets)
 *   negobs_run.c    signals, start-up and shutdown (main)
 * They share the settings (run_cfg) and the device handles below; the
 * pipeline, the alert state machine, the recorder and the calibration
 * table stay private to their module.
 */
#ifndef NEGOBS_RUN_APP_H
#define NEGOBS_RUN_APP_H

#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "app_alert.h"
#include "app_pipeline.h"
#include "negobs/alert.h"
#include "negobs/image.h"
#include "negobs_port/motor.h"
#include "negobs_port/camera.h"

#ifndef NEGOBS_RUN_DEFAULT_ALERT
#define NEGOBS_RUN_DEFAULT_ALERT "console"
#endif
#ifndef NEGOBS_RUN_DEFAULT_CAMERA
#define NEGOBS_RUN_DEFAULT_CAMERA "replay"
#endif
#ifndef NEGOBS_RUN_MAX_W
#define NEGOBS_RUN_MAX_W 1280
#endif
#ifndef NEGOBS_RUN_MAX_H
#define NEGOBS_RUN_MAX_H 800
#endif

/* Exit codes (documented in --help and docs/RUNNING.md). */
enum {
    EXIT_OK = 0,      /* frames done, end of replay, or SIGINT/SIGTERM */
    EXIT_RUNTIME = 1, /* failure while running (corrupt replay, ...)   */
    EXIT_USAGE = 2,   /* bad option or argument                        */
    EXIT_CONFIG = 3,  /* config file missing or invalid                */
    EXIT_CAMERA = 4,  /* camera could not be opened or started         */
    EXIT_ALERT = 5,   /* motor output could not be opened              */
    EXIT_CALIB = 6    /* calibration table unreadable, corrupt,
                            truncated or for another frame size          */
};

enum { LOG_ERROR = 0, LOG_WARN = 1, LOG_INFO = 2, LOG_DEBUG = 3 };

/* ---- settings (run_settings.c) -------------------------------------- */

typedef struct run_settings {
    char alert[96];
    int32_t width;
    int32_t height;
    int32_t fps;
    int32_t frames;
    char record[256];
    char log_level[16];
    int32_t pair_tol_ms;
    int32_t frozen_frames;
    int32_t watchdog_ms;
    int32_t exposure;
    int32_t gain;
    int32_t pwm_period_ns;
    char pwm_sysfs_root[128];
    bool gpio_active_low;
    bool replay_loop;
    int32_t status_interval_ms;
    char calib[256];
    negobs_alert_config_t alert_cfg;
    app_pipeline_config_t app;
    int32_t capture_width; /* V4L2 frame asked of the camera, 0 = off */
    int32_t capture_height;
    char pixel_format[8];   /* V4L2 fourcc asked for, "" = cheapest listed */
    bool size_given;        /* --width/--height given                   */
    bool alert_binary;      /* config alert_binary                      */
    bool vertical_align;    /* config vertical_align                    */
    bool row_crop;          /* config row_crop                          */
    char camera_left[128];  /* LEFT when none is given on the command line */
    char camera_right[128]; /* RIGHT, likewise                             */
    char log_json[256];     /* --log-json FILE: one JSON line per pair     */
    char mount_file[256];   /* remembered mounting (app_mount.h), "" = off */
    char button[96];        /* gpio:CHIP:LINE of the push button, or ""    */
    bool button_active_low; /* pressed = line low (button to ground)       */
    int32_t button_long_ms; /* held this long: a long press                */
    int32_t sensitivity;    /* preset at start (run_button.c)              */
    bool focal_given;       /* focal_px set by config or command line      */
    bool baseline_given;    /* baseline_mm likewise                        */
    int32_t threads;        /* config threads (0: online cores)         */
} run_settings_t;

extern run_settings_t run_cfg;
extern int run_log_level;
extern uint64_t run_log_t0_ms;

typedef struct run_args {
    const char *config;
    const char *motor_off; /* --motor-off SPEC: switch it off, exit */
    const char *left;
    const char *right;
    bool list_cameras;             /* --list-cameras [NODE...]          */
    const char *const *list_nodes; /* the nodes named after it         */
    int n_list_nodes;
} run_args_t;

void settings_default(void);
/** Returns -1 to continue, else an exit code. */
int parse_args(int argc, char **argv, run_args_t *a);
int usage_error(const char *fmt, const char *arg);
/** 0 when SPEC is a well-formed --alert value. */
int check_alert_spec(const char *spec);
/** Split "a:b:c" into kind and two fields; returns the fields found, -1
 *  when a part does not fit (the outputs are then not filled). */
int split_spec(const char *spec, char *kind, size_t klen, char *f1, size_t l1,
               char *f2, size_t l2);
int parse_u32(const char *s, uint32_t *out);
/** Warn when f, B or the calibration are the built-in defaults. */
void warn_default_geometry(void);
/** Write every config key as `PREFIXkey = value` lines (meta.txt). */
void settings_write_prefixed(FILE *out, const char *prefix);
void logmsg(int level, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/** Log lines dropped because stderr's reader was not taking them. */
unsigned long log_lines_dropped(void);

/* ---- devices (run_devices.c) ----------------------------------------- */

extern negobs_motor_out_t run_alert;
extern negobs_capture_t run_camera;
extern negobs_motor_thread_t run_motor;

int open_alert(const char *spec);
/** The backend's last message ("" for console/none). */
const char *alert_errmsg(void);
int motor_off(const char *spec);
int check_camera_args(const run_args_t *a);
/** --list-cameras: print what is there; EXIT_OK when a camera is usable,
 *  else EXIT_CAMERA. */
int list_cameras(const run_args_t *a);
/** V4L2 capture size: check it against the processing size and scale
 *  focal_px by the binning (before the pipeline is set up); -1 to
 *  continue, else an exit code. */
int camera_geometry(const run_args_t *a);
int open_camera(const run_args_t *a);
const char *camera_status_words(int rc);
/** Returns -1 to continue, else an exit code. */
int load_calib(const char *path);
void log_calib(const char *path);
bool calib_loaded(void);
/** Rectify a raw pair with the table into out_l/out_r (buffers of this
 *  module); 0, or EXIT_CALIB after logging why. */
int rectify_pair(const negobs_image_u8_t *l, const negobs_image_u8_t *r,
                 negobs_image_u8_t *out_l, negobs_image_u8_t *out_r);

/* ---- main loop (run_loop.c) ------------------------------------------ */

/** Pipeline and alert state machine from run_cfg; -1 to continue, else
 *  an exit code (message printed). */
int loop_setup(negobs_motor_schedule_t *noinfo_sched);
void alert_post(const negobs_alert_input_t *in);
/** The alert state machine anew, without READY (after a pause). */
void alert_restart(void);
negobs_alert_pattern_t alert_pattern_now(void);
void record_start(void);
void record_stop(void);
int run_loop(void);

/* ---- helper threads -------------------------------------------------- */

/** pthread_create() with every signal blocked in the new thread, so
 *  asynchronous signals (SIGINT, SIGTERM) reach the main thread; 0 or
 *  pthread_create()'s error. */
static inline int run_thread_start(pthread_t *t, void *(*fn)(void *),
                                   void *arg)
{
    sigset_t all;
    sigset_t old;
    int rc;
    (void)sigfillset(&all);
    (void)pthread_sigmask(SIG_BLOCK, &all, &old);
    rc = pthread_create(t, NULL, fn, arg);
    (void)pthread_sigmask(SIG_SETMASK, &old, NULL);
    return rc;
}

/* ---- systemd and journald (run_service.c) --------------------------- */

extern bool run_log_journal; /* stderr is the journal: priority prefixes */
void service_init(void);
bool service_watchdog_on(void);
/** A pair came from the cameras and was handled: READY once, WATCHDOG. */
void service_pair_done(void);
void service_status(const char *text);
void service_stopping(void);
/** Notifications the notify socket's full queue could not take. */
unsigned long service_notify_dropped(void);
/** LOG_* -> sd-daemon priority (3 err, 4 warning, 6 info, 7 debug). */
int service_log_priority(int level);

/* ---- JSON log and session metadata (run_json.c) ---------------------- */

/** Open --log-json FILE; a failure is logged once and the run goes on. */
void json_log_open(const char *path);
/** One line for a judged pair (pipeline's last result); never fails the
 *  run: a write error closes the log, logged once. */
void json_log_pair(uint32_t index, uint64_t ts_left_ns, uint64_t ts_right_ns,
                   int32_t w, int32_t h, app_verdict_t v,
                   const app_pipeline_t *p, negobs_alert_pattern_t pattern,
                   const char *preset);
void json_log_close(void);
/** JSON lines dropped because the log's reader was not taking them. */
unsigned long json_lines_dropped(void);
/** Calibration identity for meta.txt (run_devices.c). */
void calib_identity(uint32_t *crc32, size_t *bytes);
/** meta.txt in the session folder: version, geometry, calibration,
 *  config. Failure: a warning, the recording goes on. */
void session_meta_write(const char *dir, const app_pipeline_config_t *app);

/* ---- push button (run_button.c) -------------------------------------- */

/** Start the button thread when run_cfg.button is set; a failure is
 *  logged and the device runs without its button. */
void button_start(const negobs_motor_schedule_t *noinfo);
void button_stop(void);
/** Apply presses since the last call (pause/resume, preset), with their
 *  motor confirmation; true while paused. */
bool button_poll(void);
/** True while a confirmation pattern plays (verdicts wait). */
bool button_confirming(void);
/** Does the current preset pass this verdict to the motor? */
app_verdict_t button_filter(app_verdict_t v, const app_frame_stats_t *st);
const char *button_preset_name(void);

/* ---- signals (negobs_run.c) ------------------------------------------ */

extern volatile sig_atomic_t run_stop_requested;
extern volatile sig_atomic_t run_stop_signal;
bool is_stop_request(int sig);
const char *signal_name(int sig);

#endif /* NEGOBS_RUN_APP_H */
