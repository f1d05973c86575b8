/*
 * negobs_run: the device program.
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

#include <errno.h>
#include <getopt.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app_alert.h"
#include "app_pipeline.h"
#include "negobs/rectify.h"
#include "negobs/status.h"
#include "negobs/version.h"
#include "negobs_port/alert.h"
#include "negobs_port/camera.h"
#include "negobs_port/camera_replay.h"
#include "negobs_port/camera_libcamera.h"
#include "negobs_port/camera_v4l2.h"
#include "negobs_port/clock.h"
#include "negobs_port/config.h"
#include "negobs_port/record_queue.h"

#ifndef NEGOBS_RUN_DEFAULT_ALERT
#define NEGOBS_RUN_DEFAULT_ALERT "console"
#endif
#ifndef NEGOBS_RUN_DEFAULT_CAMERA
#define NEGOBS_RUN_DEFAULT_CAMERA "replay"
#endif
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
/* Largest calibration table read (grid shift >= 1 at 1280 x 800). */
#define APP_CALIB_MAX_BYTES (6u * 1024u * 1024u)

#ifndef NEGOBS_RUN_MAX_W
#define NEGOBS_RUN_MAX_W 1280
#endif
#ifndef NEGOBS_RUN_MAX_H
#define NEGOBS_RUN_MAX_H 800
#endif

/* Exit codes (documented in --help and docs/RUNNING.md). */
enum {
    EXIT_OK = 0,         /* frames done, end of replay, or SIGINT/SIGTERM */
    EXIT_RUNTIME = 1,    /* failure while running (corrupt replay, ...)   */
    EXIT_USAGE = 2,      /* bad option or argument                        */
    EXIT_CONFIG = 3,     /* config file missing or invalid                */
    EXIT_CAMERA = 4,     /* camera could not be opened or started         */
    EXIT_ALERT = 5,      /* motor output could not be opened              */
    EXIT_CALIB = 6       /* calibration table unreadable, corrupt,
                            truncated or for another frame size          */
};

enum { LOG_ERROR = 0, LOG_WARN = 1, LOG_INFO = 2, LOG_DEBUG = 3 };

/* ---- settings ------------------------------------------------------- */

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
} run_settings_t;

static run_settings_t S;
static bool size_given;
static bool alert_binary_flag;
static bool vertical_align_flag;
static bool row_crop_flag = true;

static const negobs_cfg_key_t config_keys[] = {
    {"alert", NEGOBS_CFG_STRING, S.alert, 0, sizeof S.alert,
     "gpio:CHIP:LINE | pwm:CHIP:CHANNEL | console | none"},
    {"width", NEGOBS_CFG_INT, &S.width, 16, NEGOBS_RUN_MAX_W,
     "capture width in pixels (default 640)"},
    {"height", NEGOBS_CFG_INT, &S.height, 16, NEGOBS_RUN_MAX_H,
     "capture height in pixels (default 480)"},
    {"fps", NEGOBS_CFG_INT, &S.fps, 0, 240,
     "frame rate; replay: pacing, 0 = as fast as possible (default 30)"},
    {"frames", NEGOBS_CFG_INT, &S.frames, 0, INT32_MAX,
     "stop after this many pairs, 0 = run until stopped (default 0)"},
    {"record", NEGOBS_CFG_STRING, S.record, 0, sizeof S.record,
     "record every pair to this folder (default: off)"},
    {"log_level", NEGOBS_CFG_STRING, S.log_level, 0, sizeof S.log_level,
     "error | warn | info | debug (default info)"},
    {"pair_tolerance_ms", NEGOBS_CFG_INT, &S.pair_tol_ms, 0, 1000,
     "max left/right timestamp difference of a pair (default 10)"},
    {"frozen_frames", NEGOBS_CFG_INT, &S.frozen_frames, 0, 10000,
     "identical frames in a row after which a V4L2 camera counts as "
     "frozen -> no-info; 0 = off (default 10)"},
    {"watchdog_ms", NEGOBS_CFG_INT, &S.watchdog_ms, 50, 10000,
     "no fresh pair for this long -> no-info pattern (default 300)"},
    {"exposure", NEGOBS_CFG_INT, &S.exposure, -1, INT32_MAX,
     "manual exposure for both cameras, driver units; -1 auto (default)"},
    {"gain", NEGOBS_CFG_INT, &S.gain, -1, INT32_MAX,
     "gain for both cameras, driver units; -1 leave as is (default)"},
    {"pwm_period_ns", NEGOBS_CFG_INT, &S.pwm_period_ns, 1000, 1000000000,
     "PWM period (default 1000000 = 1 kHz)"},
    {"pwm_sysfs_root", NEGOBS_CFG_STRING, S.pwm_sysfs_root, 0,
     sizeof S.pwm_sysfs_root,
     "sysfs PWM class folder (default /sys/class/pwm)"},
    {"gpio_active_low", NEGOBS_CFG_BOOL, &S.gpio_active_low, 0, 1,
     "motor on = line low (default false)"},
    {"replay_loop", NEGOBS_CFG_BOOL, &S.replay_loop, 0, 1,
     "start a replay over at its end (default false)"},
    {"status_interval_ms", NEGOBS_CFG_INT, &S.status_interval_ms, 100,
     600000, "period of the status line (default 1000)"},
    {"dark_mean_min", NEGOBS_CFG_INT, &S.app.dark_mean_min, 0, 255,
     "mean grey below this -> no-info (default 20)"},
    {"saturation_permille_max", NEGOBS_CFG_INT, &S.app.sat_permille_max, 0,
     1000, "share of pixels >= 250 above this -> no-info (default 300)"},
    {"texture_std_min", NEGOBS_CFG_INT, &S.app.texture_std_min, 0, 127,
     "5x5 std dev that counts as texture (default 4)"},
    {"texture_permille_min", NEGOBS_CFG_INT, &S.app.texture_permille_min, 0,
     1000, "share of textured windows below this -> no-info (default 20)"},
    {"lr_mean_diff_max", NEGOBS_CFG_INT, &S.app.lr_mean_diff_max, 0, 255,
     "left/right mean grey difference above this -> no-info (default 60)"},
    {"focal_px", NEGOBS_CFG_INT, &S.app.focal_px, 50, 4000,
     "focal length of the rectified frames, pixels (default 250)"},
    {"baseline_mm", NEGOBS_CFG_INT, &S.app.baseline_mm, 10, 1000,
     "stereo baseline, mm (default 120)"},
    {"cam_height_mm", NEGOBS_CFG_INT, &S.app.cam_height_mm, 300, 3000,
     "camera height above the ground, mm (default 1200)"},
    {"cam_pitch_mdeg", NEGOBS_CFG_INT, &S.app.cam_pitch_mdeg, 0, 60000,
     "downward pitch, 1/1000 degree (default 20000)"},
    {"max_disp", NEGOBS_CFG_INT, &S.app.max_disp, 8, 255,
     "largest disparity searched, pixels (default 63)"},
    {"vertical_align", NEGOBS_CFG_BOOL, &vertical_align_flag, 0, 1,
     "estimate and remove a sub-pixel, row-varying vertical misalignment "
     "before matching, for rigs without a calibration table (default "
     "false)"},
    {"row_crop", NEGOBS_CFG_BOOL, &row_crop_flag, 0, 1,
     "match only the rows from the top of the warning range down, found "
     "from the last frame's ground (about 15-30 % less matching time); "
     "false matches every row (default true)"},
    {"calib", NEGOBS_CFG_STRING, S.calib, 0, sizeof S.calib,
     "rectification table from negobs_calib; its f, B, cx, cy replace "
     "focal_px and baseline_mm (default: none, frames are rectified)"},
    {"alert_intensity_permille", NEGOBS_CFG_INT,
     &S.alert_cfg.intensity_permille, 1, 1000,
     "drive level of every pulse (default 1000)"},
    {"caution_far_mm", NEGOBS_CFG_INT, &S.alert_cfg.band_far_mm, 0, 100000,
     "caution range >= this: slow double pulse every 1.0 s (default 3000)"},
    {"caution_mid_mm", NEGOBS_CFG_INT, &S.alert_cfg.band_mid_mm, 0, 100000,
     "caution range >= this: every 0.6 s, nearer every 0.4 s (default "
     "2200; <= caution_far_mm)"},
    {"alert_binary", NEGOBS_CFG_BOOL, &alert_binary_flag, 0, 1,
     "one caution pattern (every 0.6 s) whatever the range (default false)"},
    {"imminent_hold_ms", NEGOBS_CFG_INT, &S.alert_cfg.imminent_hold_ms, 0,
     5000, "imminent keeps playing this long after its last verdict "
     "(default 1000)"},
    {"heartbeat_period_ms", NEGOBS_CFG_INT,
     &S.alert_cfg.heartbeat_period_ms, 0, 60000,
     "while clear, one brief pulse this often so a dead device is noticed; "
     "0 = off, else >= 1000 (default 5000)"},
    {"heartbeat_pulse_ms", NEGOBS_CFG_INT, &S.alert_cfg.heartbeat_pulse_ms,
     0, 15000, "length of the heartbeat pulse, 80 .. a quarter of the "
     "period (default 80)"},
    {"max_frame_age_ms", NEGOBS_CFG_INT, &S.app.max_frame_age_ms, 1, 60000,
     "age of a pair when its processing starts above which it is stale -> "
     "no-info (default 150; raise only for slow emulators)"},
    {"latency_budget_ms", NEGOBS_CFG_INT, &S.app.latency_budget_ms, 0, 60000,
     "capture-to-verdict time above which a clear verdict is not trusted "
     "-> no-info; warnings pass (default 250; 0 = off)"},
};
#define N_KEYS (sizeof config_keys / sizeof config_keys[0])

static void settings_default(void)
{
    memset(&S, 0, sizeof S);
    (void)snprintf(S.alert, sizeof S.alert, "%s", NEGOBS_RUN_DEFAULT_ALERT);
    S.width = 640;
    S.height = 480;
    S.fps = 30;
    (void)snprintf(S.log_level, sizeof S.log_level, "info");
    S.pair_tol_ms = NEGOBS_CAMERA_PAIR_TOL_MS_DEFAULT;
    S.frozen_frames = NEGOBS_CAMERA_FROZEN_FRAMES_DEFAULT;
    S.watchdog_ms = 300;
    S.exposure = -1;
    S.gain = -1;
    S.pwm_period_ns = 1000000;
    (void)snprintf(S.pwm_sysfs_root, sizeof S.pwm_sysfs_root,
                   "/sys/class/pwm");
    S.status_interval_ms = 1000;
    negobs_alert_config_default(&S.alert_cfg);
    app_pipeline_config_default(&S.app);
}

/* ---- logging -------------------------------------------------------- */

static int log_level = LOG_INFO;
static uint64_t log_t0_ms;

static void logmsg(int level, const char *fmt, ...)
{
    static const char *const tag[] = {"error", "warn", "info", "debug"};
    va_list ap;
    uint64_t t;
    if (level > log_level) {
        return;
    }
    t = negobs_clock_now_ms() - log_t0_ms;
    fprintf(stderr, "[%5lu.%03lu] %s: ", (unsigned long)(t / 1000u),
            (unsigned long)(t % 1000u), tag[level]);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

/* The matcher's stage clock: monotonic ns modulo 2^32 (it takes
 * differences of successive reads). */
static uint32_t stage_clock_ns(void *user)
{
    (void)user;
    return (uint32_t)negobs_clock_now_ns();
}

static int parse_log_level(const char *s)
{
    static const char *const names[] = {"error", "warn", "info", "debug"};
    int i;
    for (i = 0; i < 4; i++) {
        if (strcmp(s, names[i]) == 0) {
            return i;
        }
    }
    if (s[0] >= '0' && s[0] <= '3' && s[1] == '\0') {
        return s[0] - '0';
    }
    return -1;
}

/* ---- command line --------------------------------------------------- */

static void usage(FILE *out)
{
    fprintf(out,
"Usage: negobs_run [options] LEFT RIGHT\n"
"       negobs_run [options] replay:DIR\n"
"       negobs_run [--config FILE] --motor-off SPEC\n"
"\n"
"Warns of drop-offs ahead through a vibration motor, from a stereo pair.\n"
"LEFT/RIGHT: /dev/videoN (V4L2) or replay:DIR (a folder of left_NNNN.pgm /\n"
"right_NNNN.pgm pairs or a session recorded with --record) or libcamera:N /\n"
"libcamera:ID (index or id of a libcamera camera). A bare name uses\n"
"the build's default camera backend (" NEGOBS_RUN_DEFAULT_CAMERA ").\n"
"\n"
"Each pair passes an image-quality gate (too dark, saturated, textureless ->\n"
"no-information pattern), then the library's stereo matching and drop-off\n"
"detection; the library's alert state machine chooses the motor pattern\n"
"(ready, caution by distance band, imminent, no-information); no fresh\n"
"verdict for watchdog_ms (300) plays no-information.\n"
"Set the camera geometry (focal_px, baseline_mm, cam_height_mm,\n"
"cam_pitch_mdeg) in --config for a real rig: wrong values blind it.\n"
"\n"
"Options:\n"
"  --config FILE        read key = value settings (applied before options)\n"
"  --calib FILE         rectification table from negobs_calib: every pair is\n"
"                       rectified; its f, B, cx, cy replace focal_px and\n"
"                       baseline_mm; no --width/--height: the table's size\n"
"  --alert SPEC         gpio:CHIP:LINE | pwm:CHIP:CHANNEL | console | none\n"
"                       (default " NEGOBS_RUN_DEFAULT_ALERT ")\n"
"  --width N, --height N   capture size (default 640x480; max %dx%d)\n"
"  --fps N              frame rate (default 30; replay: pacing, 0 = fastest)\n"
"  --frames N           stop after N pairs (default: run until stopped)\n"
"  --record DIR         record every pair as a session (see docs/RUNNING.md)\n"
"  --log-level LEVEL    error | warn | info | debug (default info)\n"
"  --motor-off SPEC     switch the motor output SPEC off and exit (the\n"
"                       service's ExecStopPost; no camera arguments)\n"
"  --help               this text, then the config keys\n"
"  --version            print the version\n"
"\n"
"Exit codes: 0 done or stopped by SIGINT/SIGTERM/SIGHUP/SIGQUIT, 1 runtime\n"
"failure (also the end of a damaged recorded session),\n"
"2 usage error, 3 config error, 4 camera failure, 5 motor output failure,\n"
"6 calibration table refused (unreadable, corrupt, truncated, other size),\n"
"128+N stopped by another terminating signal N (motor off, summary logged).\n",
            NEGOBS_RUN_MAX_W, NEGOBS_RUN_MAX_H);
}

typedef struct run_args {
    const char *config;
    const char *motor_off;  /* --motor-off SPEC: switch it off, exit */
    const char *left;
    const char *right;
} run_args_t;

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "negobs_run: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'negobs_run --help'.\n");
    return EXIT_USAGE;
}

static int check_alert_spec(const char *spec);

/* Values of the config file that the key table cannot vet: refused with
 * the file's name and line (exit 3), like any other bad line. */
static int check_config_value(void *user, const char *key, const char *value,
                              char *why, size_t why_len)
{
    (void)user;
    if (strcmp(key, "alert") == 0 && check_alert_spec(value) != 0) {
        (void)snprintf(why, why_len, "bad alert '%s' (want gpio:CHIP:LINE, "
                       "pwm:CHIP:CHANNEL, console or none)", value);
        return -1;
    }
    if (strcmp(key, "log_level") == 0 && parse_log_level(value) < 0) {
        (void)snprintf(why, why_len, "bad log level '%s' (want error, "
                       "warn, info or debug)", value);
        return -1;
    }
    return 0;
}

/* Returns -1 to continue, else an exit code. */
static int parse_args(int argc, char **argv, run_args_t *a)
{
    enum { O_CONFIG = 256, O_ALERT, O_WIDTH, O_HEIGHT, O_FPS, O_FRAMES,
           O_RECORD, O_LOG, O_HELP, O_VERSION, O_CALIB, O_MOTOR_OFF };
    static const struct option opts[] = {
        {"config", required_argument, NULL, O_CONFIG},
        {"alert", required_argument, NULL, O_ALERT},
        {"width", required_argument, NULL, O_WIDTH},
        {"height", required_argument, NULL, O_HEIGHT},
        {"fps", required_argument, NULL, O_FPS},
        {"frames", required_argument, NULL, O_FRAMES},
        {"record", required_argument, NULL, O_RECORD},
        {"calib", required_argument, NULL, O_CALIB},
        {"log-level", required_argument, NULL, O_LOG},
        {"help", no_argument, NULL, O_HELP},
        {"version", no_argument, NULL, O_VERSION},
        {"motor-off", required_argument, NULL, O_MOTOR_OFF},
        {NULL, 0, NULL, 0},
    };
    negobs_cfg_error_t err;
    int i;
    int c;

    /* Pass 1: --help/--version win; the config file comes first so that
     * options override it whatever their order. */
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--") == 0) {
            break;
        }
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            printf("\nConfig file keys (key = value, '#' comments):\n");
            negobs_config_print_keys(stdout, config_keys, N_KEYS);
            return EXIT_OK;
        }
        if (strcmp(argv[i], "--version") == 0) {
            printf("negobs_run %s\n", NEGOBS_VERSION_STRING);
            return EXIT_OK;
        }
        if (strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
            a->config = argv[i + 1];
        } else if (strncmp(argv[i], "--config=", 9) == 0) {
            a->config = argv[i] + 9;
        }
    }
    if (a->config != NULL) {
        memset(&err, 0, sizeof err);
        if (negobs_config_parse_file_checked(a->config, config_keys, N_KEYS,
                                             check_config_value, NULL,
                                             &err) != NEGOBS_OK) {
            fprintf(stderr, "negobs_run: %s: %s\n", a->config, err.msg);
            return EXIT_CONFIG;
        }
    }

    /* Pass 2: options, through the same table as the config file. */
    opterr = 0;
    optind = 1;
    while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
        const char *key = NULL;
        switch (c) {
        case O_CONFIG: continue;
        case O_MOTOR_OFF: a->motor_off = optarg; continue;
        case O_ALERT: key = "alert"; break;
        case O_WIDTH: key = "width"; size_given = true; break;
        case O_HEIGHT: key = "height"; size_given = true; break;
        case O_FPS: key = "fps"; break;
        case O_FRAMES: key = "frames"; break;
        case O_RECORD: key = "record"; break;
        case O_CALIB: key = "calib"; break;
        case O_LOG: key = "log_level"; break;
        case ':':
            return usage_error("option '%s' needs a value", argv[optind - 1]);
        case '?':
        default:
            return usage_error("unknown option '%s'", argv[optind - 1]);
        }
        memset(&err, 0, sizeof err);
        if (negobs_config_set(config_keys, N_KEYS, key, optarg, &err) !=
            NEGOBS_OK) {
            return usage_error("%s", err.msg);
        }
    }
    if (parse_log_level(S.log_level) < 0) {
        return usage_error("bad log level '%s'", S.log_level);
    }
    log_level = parse_log_level(S.log_level);
    if (a->motor_off != NULL) {
        if (optind < argc) {
            return usage_error("--motor-off takes no camera argument ('%s')",
                               argv[optind]);
        }
        return -1;
    }
    if (optind >= argc) {
        return usage_error("%s", "missing camera arguments LEFT RIGHT");
    }
    a->left = argv[optind++];
    if (optind < argc) {
        a->right = argv[optind++];
    }
    if (optind < argc) {
        return usage_error("unexpected argument '%s'", argv[optind]);
    }
    return -1;
}

/* ---- devices -------------------------------------------------------- */

static negobs_motor_out_t alert;
static negobs_alert_console_t alert_console;
static negobs_alert_pwm_t alert_pwm;
static negobs_alert_gpio_t alert_gpio;

static negobs_capture_t camera;
static negobs_replay_t replay_state;
static negobs_v4l2_t v4l2_state;
static negobs_libcamera_t libcamera_state;
/* Replay pixels or packed-format luma: one pair at the largest size. */
static uint8_t frame_buf[2u * NEGOBS_RUN_MAX_W * NEGOBS_RUN_MAX_H];

static negobs_motor_thread_t motor;
static app_pipeline_t pipeline;
static app_alert_t alert_sm;

/* Parse "a:b:c" into kind and two fields; returns fields found. */
static int split_spec(const char *spec, char *kind, size_t klen, char *f1,
                      size_t l1, char *f2, size_t l2)
{
    const char *p1 = strchr(spec, ':');
    const char *p2 = p1 != NULL ? strchr(p1 + 1, ':') : NULL;
    size_t n = p1 != NULL ? (size_t)(p1 - spec) : strlen(spec);
    if (n >= klen) {
        return -1;
    }
    memcpy(kind, spec, n);
    kind[n] = '\0';
    f1[0] = f2[0] = '\0';
    if (p1 == NULL) {
        return 0;
    }
    n = p2 != NULL ? (size_t)(p2 - p1 - 1) : strlen(p1 + 1);
    if (n >= l1) {
        return -1;
    }
    memcpy(f1, p1 + 1, n);
    f1[n] = '\0';
    if (p2 == NULL) {
        return 1;
    }
    if (strlen(p2 + 1) >= l2 || strchr(p2 + 1, ':') != NULL) {
        return -1;
    }
    strcpy(f2, p2 + 1);
    return 2;
}

static int parse_u32(const char *s, uint32_t *out)
{
    char *end = NULL;
    unsigned long v;
    if (s[0] < '0' || s[0] > '9') {
        return -1;
    }
    errno = 0;
    v = strtoul(s, &end, 10);
    if (errno != 0 || *end != '\0' || v > 0xFFFFFFFFul) {
        return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

/* Check the alert spec without opening anything (usage errors first). */
static int check_alert_spec(const char *spec)
{
    char kind[16];
    char f1[64];
    char f2[16];
    uint32_t u;
    int n = split_spec(spec, kind, sizeof kind, f1, sizeof f1, f2, sizeof f2);
    if (n < 0) {
        return -1; /* a field too long: kind/f1/f2 are not filled */
    }
    if ((strcmp(kind, "console") == 0 || strcmp(kind, "none") == 0) &&
        n == 0) {
        return 0;
    }
    if (strcmp(kind, "gpio") == 0 && n == 2 && f1[0] != '\0' &&
        parse_u32(f2, &u) == 0) {
        return 0;
    }
    if (strcmp(kind, "pwm") == 0 && n == 2 && parse_u32(f1, &u) == 0 &&
        parse_u32(f2, &u) == 0) {
        return 0;
    }
    return -1;
}

static int open_alert(const char *spec)
{
    char kind[16];
    char f1[64];
    char f2[16];
    uint32_t a = 0;
    uint32_t b = 0;
    negobs_status_t s;
    (void)split_spec(spec, kind, sizeof kind, f1, sizeof f1, f2, sizeof f2);
    if (strcmp(kind, "console") == 0) {
        s = negobs_alert_console_open(&alert_console, stdout, &alert);
    } else if (strcmp(kind, "none") == 0) {
        s = negobs_alert_none_open(&alert);
    } else if (strcmp(kind, "pwm") == 0) {
        (void)parse_u32(f1, &a);
        (void)parse_u32(f2, &b);
        s = negobs_alert_pwm_open(&alert_pwm, S.pwm_sysfs_root, a, b,
                                  (uint32_t)S.pwm_period_ns, &alert);
        if (s != NEGOBS_OK) {
            logmsg(LOG_ERROR, "pwm output: %s", alert_pwm.errmsg);
        }
    } else {
        (void)parse_u32(f2, &b);
        s = negobs_alert_gpio_open(&alert_gpio, f1, b, S.gpio_active_low,
                                   &alert);
        if (s != NEGOBS_OK) {
            logmsg(LOG_ERROR, "gpio output: %s", alert_gpio.errmsg);
        }
    }
    if (s != NEGOBS_OK) {
        logmsg(LOG_ERROR, "cannot open motor output '%s': %s", spec,
               negobs_status_str(s));
        return -1;
    }
    logmsg(LOG_INFO, "motor output: %s", spec);
    return 0;
}

/* negobs_run --motor-off SPEC: the systemd unit's ExecStopPost, run after
 * negobs_run ended in any way (even SIGKILL): open the output, which
 * drives it off (GPIO line low / inactive, PWM duty 0), and close it
 * (PWM disabled, line released). */
static int motor_off(const char *spec)
{
    if (check_alert_spec(spec) != 0) {
        return usage_error("bad motor output '%s' (want gpio:CHIP:LINE, "
                           "pwm:CHIP:CHANNEL, console or none)", spec);
    }
    if (open_alert(spec) != 0) {
        return EXIT_ALERT;
    }
    if (negobs_alert_set(&alert, 0) != NEGOBS_OK) {
        logmsg(LOG_ERROR, "motor output '%s': cannot switch it off", spec);
        negobs_alert_close(&alert);
        return EXIT_ALERT;
    }
    negobs_alert_close(&alert);
    logmsg(LOG_INFO, "motor off: %s", spec);
    return EXIT_OK;
}

/* Which backend an argument names: "replay", "v4l2", or the default. */
static const char *camera_kind(const char *arg)
{
    if (strncmp(arg, "replay:", 7) == 0) {
        return "replay";
    }
    if (strncmp(arg, "v4l2:", 5) == 0 || strncmp(arg, "/dev/", 5) == 0) {
        return "v4l2";
    }
    if (strncmp(arg, NEGOBS_LIBCAMERA_PREFIX,
                sizeof NEGOBS_LIBCAMERA_PREFIX - 1u) == 0) {
        return "libcamera";
    }
    return NEGOBS_RUN_DEFAULT_CAMERA;
}

static int check_camera_args(const run_args_t *a)
{
    const char *k = camera_kind(a->left);
    if (strcmp(k, "replay") == 0) {
        if (a->right != NULL && strcmp(a->right, a->left) != 0) {
            return usage_error("%s", "a replay folder holds both sides: give "
                                     "replay:DIR once (or twice the same)");
        }
        return 0;
    }
    if (strcmp(k, "v4l2") == 0) {
        if (a->right == NULL) {
            return usage_error("%s", "missing RIGHT camera");
        }
        if (strcmp(camera_kind(a->right), "v4l2") != 0) {
            return usage_error("RIGHT '%s' must be a V4L2 device too",
                               a->right);
        }
        return 0;
    }
    if (strcmp(k, "libcamera") == 0) {
        if (a->right == NULL || strcmp(camera_kind(a->right), k) != 0) {
            return usage_error("%s", "RIGHT must be a libcamera camera too "
                                     "(libcamera:N or libcamera:ID)");
        }
        return 0;
    }
    return usage_error("camera backend '%s' is not built into negobs_run", k);
}

/* What a camera or replay status means, for the log line after the
 * backend's own message (which names the file or device). */
static const char *camera_status_words(int rc)
{
    switch (rc) {
    case NEGOBS_ERR_NODEV: return "not found";
    case NEGOBS_ERR_IO: return "read error";
    case NEGOBS_ERR_CORRUPT: return "damaged or malformed data";
    case NEGOBS_ERR_NOSPACE: return "frames too large";
    case NEGOBS_ERR_INVAL: return "invalid";
    case NEGOBS_ERR_UNSUPPORTED: return "not supported";
    default: return negobs_status_str((negobs_status_t)rc);
    }
}

static int open_camera(const run_args_t *a)
{
    negobs_camera_config_t cfg;
    negobs_status_t s;
    negobs_camera_config_default(&cfg);
    cfg.left = a->left;
    cfg.right = a->right != NULL ? a->right : a->left;
    cfg.width = S.width;
    cfg.height = S.height;
    cfg.fps = S.fps;
    cfg.pair_tol_ms = S.pair_tol_ms;
    cfg.frozen_frames = S.frozen_frames;
    cfg.exposure = S.exposure;
    cfg.gain = S.gain;
    cfg.loop = S.replay_loop;
    if (strcmp(camera_kind(a->left), "replay") == 0) {
        if (!size_given) {
            cfg.width = 0; /* take the size of the files */
            cfg.height = 0;
        }
        s = negobs_replay_init(&replay_state, frame_buf, sizeof frame_buf,
                               &camera);
    } else if (strcmp(camera_kind(a->left), "libcamera") == 0) {
        s = negobs_libcamera_init(&libcamera_state, frame_buf,
                                  sizeof frame_buf, &camera);
    } else {
        s = negobs_v4l2_init(&v4l2_state, frame_buf, sizeof frame_buf,
                             &camera);
    }
    if (s == NEGOBS_OK) {
        s = negobs_camera_open(&camera, &cfg);
        if (s == NEGOBS_OK) {
            s = negobs_camera_start(&camera);
            if (s != NEGOBS_OK) {
                negobs_camera_close(&camera);
            }
        }
    }
    if (s != NEGOBS_OK) {
        logmsg(LOG_ERROR, "camera %s: %s (%s)", a->left,
               negobs_camera_errmsg(&camera), camera_status_words(s));
        return -1;
    }
    if (strcmp(camera_kind(a->left), "replay") == 0 &&
        negobs_replay_damage(&replay_state)[0] != '\0') {
        logmsg(LOG_WARN, "replay: %s", negobs_replay_damage(&replay_state));
    }
    logmsg(LOG_INFO, "camera: %s backend, %s %s", camera.ops->name, cfg.left,
           cfg.right);
    return 0;
}

/* ---- calibration ---------------------------------------------------- */

/* The table stays here for the whole run (the library keeps a pointer to
 * it); rectified pairs go to rect_buf. */
static uint8_t calib_table[APP_CALIB_MAX_BYTES];
static size_t calib_bytes;
static negobs_rectify_info_t calib_info;
static negobs_rectify_config_t rect_cfg;
static negobs_rectify_t rect_ctx;
static uint8_t rect_ws[NEGOBS_RECTIFY_WORKSPACE_MAX(NEGOBS_RUN_MAX_W)]
    __attribute__((aligned(16)));
static uint8_t rect_buf[2u * NEGOBS_RUN_MAX_W * NEGOBS_RUN_MAX_H];
static bool rect_ready;

static uint32_t rd_u32le(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
           ((uint32_t)p[3] << 24);
}

/* Why the library refused a table, in words a person can act on: decoded
 * from the documented header (docs/CALIBRATION.md, section 3). */
static void calib_why(negobs_status_t st, char *msg, size_t len)
{
    uint32_t total;
    if (st == NEGOBS_ERR_UNSUPPORTED) {
        (void)snprintf(msg, len, "unsupported table version or format "
                                 "(this negobs_run reads version %d.x)",
                       NEGOBS_RECTIFY_VERSION_MAJOR);
        return;
    }
    if (calib_bytes < NEGOBS_RECTIFY_HEADER_BYTES) {
        (void)snprintf(msg, len, "truncated: %lu bytes, shorter than the "
                                 "%d-byte header",
                       (unsigned long)calib_bytes,
                       NEGOBS_RECTIFY_HEADER_BYTES);
        return;
    }
    if (memcmp(calib_table, NEGOBS_RECTIFY_MAGIC, 8) != 0) {
        (void)snprintf(msg, len, "not a negobs rectification table "
                                 "(bad magic)");
        return;
    }
    total = rd_u32le(calib_table + 16);
    if ((size_t)total > calib_bytes) {
        (void)snprintf(msg, len, "truncated: %lu of the %lu bytes its "
                                 "header declares",
                       (unsigned long)calib_bytes, (unsigned long)total);
        return;
    }
    (void)snprintf(msg, len, "corrupt: checksum (CRC32) or header values "
                             "do not match");
}

/* Read and check the table, set the geometry and the capture size. */
static int load_calib(const char *path)
{
    char why[128];
    FILE *f = fopen(path, "rb");
    negobs_status_t st;
    bool more;
    bool err;
    if (f == NULL) {
        fprintf(stderr, "negobs_run: calibration table %s: %s\n", path,
                strerror(errno));
        return EXIT_CALIB;
    }
    calib_bytes = fread(calib_table, 1, sizeof calib_table, f);
    more = fgetc(f) != EOF;
    err = ferror(f) != 0;
    (void)fclose(f);
    if (err) {
        fprintf(stderr, "negobs_run: calibration table %s: read error\n",
                path);
        return EXIT_CALIB;
    }
    if (more) {
        fprintf(stderr, "negobs_run: calibration table %s: larger than %u "
                        "bytes (use a coarser negobs_calib --grid-shift)\n",
                path, APP_CALIB_MAX_BYTES);
        return EXIT_CALIB;
    }
    st = negobs_rectify_table_check(calib_table, calib_bytes, 0, 0,
                                    &calib_info);
    if (st != NEGOBS_OK) {
        calib_why(st, why, sizeof why);
        fprintf(stderr, "negobs_run: calibration table %s refused: %s\n",
                path, why);
        return EXIT_CALIB;
    }
    if (calib_info.width > NEGOBS_RUN_MAX_W ||
        calib_info.height > NEGOBS_RUN_MAX_H) {
        fprintf(stderr, "negobs_run: calibration table %s refused: it is "
                        "for %ldx%ld, larger than %dx%d\n",
                path, (long)calib_info.width, (long)calib_info.height,
                NEGOBS_RUN_MAX_W, NEGOBS_RUN_MAX_H);
        return EXIT_CALIB;
    }
    if (size_given && (S.width != calib_info.width ||
                       S.height != calib_info.height)) {
        fprintf(stderr, "negobs_run: calibration table %s refused: size "
                        "mismatch: the table is for %ldx%ld, the capture "
                        "size is %ldx%ld\n",
                path, (long)calib_info.width, (long)calib_info.height,
                (long)S.width, (long)S.height);
        return EXIT_CALIB;
    }
    /* The table's size is the capture size (a replay keeps its files'
     * size; the first pair is checked against the table). */
    S.width = calib_info.width;
    S.height = calib_info.height;
    /* Measured geometry wins over the config's nominal values. */
    S.app.focal_q4 = (int32_t)((calib_info.f_q16 + 2048u) >> 12);
    S.app.baseline_um = (int32_t)calib_info.baseline_um;
    S.app.cx_q4 = calib_info.cx_q16 >= 0
                      ? (int32_t)((calib_info.cx_q16 + 2048) >> 12) : -1;
    S.app.cy_q4 = calib_info.cy_q16 >= 0
                      ? (int32_t)((calib_info.cy_q16 + 2048) >> 12) : -1;
    return -1;
}

/* One line with what the table brings (after the log is set up). */
static void log_calib(const char *path)
{
    uint32_t f100 = (uint32_t)(((uint64_t)calib_info.f_q16 * 100u +
                                32768u) >> 16);
    int32_t cx100 = (int32_t)(((int64_t)calib_info.cx_q16 * 100 + 32768) /
                              65536);
    int32_t cy100 = (int32_t)(((int64_t)calib_info.cy_q16 * 100 + 32768) /
                              65536);
    logmsg(LOG_INFO,
           "calib: %s: %ldx%ld grid 2^%ld f_px=%lu.%02lu baseline_mm=%lu.%03lu "
           "cx=%ld.%02ld cy=%ld.%02ld (replace focal_px=%ld baseline_mm=%ld)",
           path, (long)calib_info.width, (long)calib_info.height,
           (long)calib_info.grid_shift, (unsigned long)(f100 / 100u),
           (unsigned long)(f100 % 100u),
           (unsigned long)(calib_info.baseline_um / 1000u),
           (unsigned long)(calib_info.baseline_um % 1000u),
           (long)(cx100 / 100), (long)(cx100 < 0 ? -cx100 % 100 : cx100 % 100),
           (long)(cy100 / 100), (long)(cy100 < 0 ? -cy100 % 100 : cy100 % 100),
           (long)S.app.focal_px, (long)S.app.baseline_mm);
    if (calib_info.doffs_q16 != 0) {
        logmsg(LOG_WARN, "calib: the table has a disparity offset "
                         "(doffs_q16 %ld) that the detector ignores",
               (long)calib_info.doffs_q16);
    }
}

/* Set up the remap for the first pair's size; -1 when it does not fit. */
static int rectify_setup(int32_t w, int32_t h)
{
    size_t ws = 0;
    negobs_status_t st;
    if (w != calib_info.width || h != calib_info.height) {
        logmsg(LOG_ERROR, "calib: size mismatch: the table is for %ldx%ld, "
                          "the camera delivers %ldx%ld",
               (long)calib_info.width, (long)calib_info.height, (long)w,
               (long)h);
        return -1;
    }
    negobs_rectify_config_default(&rect_cfg, w, h);
    rect_cfg.table = calib_table;
    rect_cfg.table_bytes = calib_bytes;
    st = negobs_rectify_workspace_size(&rect_cfg, &ws);
    if (st == NEGOBS_OK && ws > sizeof rect_ws) {
        st = NEGOBS_ERR_NOSPACE;
    }
    if (st == NEGOBS_OK) {
        st = negobs_rectify_init(&rect_ctx, &rect_cfg, rect_ws, ws);
    }
    if (st != NEGOBS_OK) {
        logmsg(LOG_ERROR, "calib: cannot set up rectification: %s",
               negobs_status_str(st));
        return -1;
    }
    rect_ready = true;
    return 0;
}

/* ---- alert ---------------------------------------------------------- */

/* Advance the library's alert state machine (NULL: no new verdict) and
 * hand the motor thread what it should play from now on. */
static void alert_post(const negobs_alert_input_t *in)
{
    negobs_alert_pattern_t before = NEGOBS_PATTERN_NONE;
    if (app_alert_post(&alert_sm, &motor, in, &before) != NEGOBS_OK) {
        return; /* cannot happen after a successful init */
    }
    if (app_alert_pattern(&alert_sm) != before) {
        logmsg(LOG_INFO, "pattern %s -> %s", app_alert_pattern_name(before),
               app_alert_pattern_name(app_alert_pattern(&alert_sm)));
    }
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
static volatile sig_atomic_t stop_requested;
static volatile sig_atomic_t stop_signal;

static void on_stop_signal(int sig)
{
    stop_signal = sig;
    stop_requested = 1;
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
    if (alert.ops != NULL && alert.ops->off_async != NULL) {
        alert.ops->off_async(alert.ctx);
    }
    (void)raise(sig);
}

/* SIGINT, SIGTERM, SIGHUP, SIGQUIT: a request to stop (exit 0). */
static bool is_stop_request(int sig)
{
    return sig == SIGINT || sig == SIGTERM || sig == SIGHUP ||
           sig == SIGQUIT;
}

static const char *signal_name(int sig)
{
    static const struct { int sig; const char *name; } names[] = {
        {SIGINT, "SIGINT"},     {SIGTERM, "SIGTERM"}, {SIGHUP, "SIGHUP"},
        {SIGQUIT, "SIGQUIT"},   {SIGUSR1, "SIGUSR1"}, {SIGUSR2, "SIGUSR2"},
        {SIGALRM, "SIGALRM"},   {SIGXCPU, "SIGXCPU"}, {SIGXFSZ, "SIGXFSZ"},
        {SIGPIPE, "SIGPIPE"},   {SIGVTALRM, "SIGVTALRM"},
        {SIGPROF, "SIGPROF"},   {SIGPOLL, "SIGIO"},
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
        SIGINT,  SIGTERM,   SIGHUP,  SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM,
        SIGXCPU, SIGVTALRM, SIGPROF, SIGPOLL,
#ifdef SIGPWR
        SIGPWR,
#endif
#ifdef SIGSTKFLT
        SIGSTKFLT,
#endif
    };
    static const int fatal[] = {SIGSEGV, SIGBUS,  SIGFPE, SIGILL,
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

/* ---- main loop ------------------------------------------------------ */

typedef struct run_status {
    uint64_t next_ms;
    uint64_t window_start_ms;
    uint32_t pairs;
    uint64_t lat_sum_us;
    uint64_t lat_max_us;
    app_verdict_t verdict;
    uint32_t verdicts[4];  /* pairs per verdict over the whole run */
} run_status_t;

static void status_line(run_status_t *st, uint64_t now)
{
    negobs_camera_stats_t cs;
    uint64_t span = now - st->window_start_ms;
    unsigned long fps10 = span > 0
        ? (unsigned long)((uint64_t)st->pairs * 10000u / span) : 0;
    unsigned long lat = st->pairs > 0
        ? (unsigned long)(st->lat_sum_us / st->pairs / 100u) : 0;
    negobs_camera_get_stats(&camera, &cs);
    logmsg(LOG_INFO,
           "status fps=%lu.%lu latency_ms=%lu.%lu max=%lu dropped=%lu "
           "timeouts=%lu reopens=%lu verdict=%s reason=%s mean=%ld/%ld "
           "texture=%ld/%ld watchdog=%lu pattern=%s",
           fps10 / 10u, fps10 % 10u, lat / 10u, lat % 10u,
           (unsigned long)(st->lat_max_us / 1000u),
           (unsigned long)cs.dropped_pairs, (unsigned long)cs.timeouts,
           (unsigned long)cs.reopens, app_verdict_name(st->verdict),
           app_reason_name(pipeline.last.reason),
           (long)pipeline.last.mean[0], (long)pipeline.last.mean[1],
           (long)pipeline.last.texture_permille[0],
           (long)pipeline.last.texture_permille[1],
           (unsigned long)negobs_motor_thread_watchdog_fires(&motor),
           app_alert_pattern_name(app_alert_pattern(&alert_sm)));
    st->window_start_ms = now;
    st->next_ms = now + (uint64_t)S.status_interval_ms;
    st->pairs = 0;
    st->lat_sum_us = 0;
    st->lat_max_us = 0;
}

/* Motor output faults (the motor thread retries and plays no-info;
 * port/alert): say when writes start failing and when they work again. */
static void check_motor_output(bool *was_failing)
{
    bool failing = false;
    uint32_t faults = negobs_motor_thread_output_faults(&motor, &failing);
    char why[NEGOBS_PORT_ERRMSG_LEN];
    /* the motor thread writes the backend's message: copy under its lock */
    negobs_motor_thread_copy_msg(
        &motor,
        alert.ctx == (void *)&alert_gpio  ? alert_gpio.errmsg
        : alert.ctx == (void *)&alert_pwm ? alert_pwm.errmsg
                                          : "",
        why, sizeof why);
    if (failing && !*was_failing) {
        logmsg(LOG_WARN, "motor: output failing (%s), retrying; no-info "
               "once it is back (fault %lu)", why, (unsigned long)faults);
    } else if (!failing && *was_failing) {
        logmsg(LOG_INFO, "motor: output back, no-info for %u ms",
               (unsigned)NEGOBS_MOTOR_RECOVER_HOLD_MS);
    }
    *was_failing = failing;
}

/* ---- recording ------------------------------------------------------ */

/* Queued pairs for the writer thread (negobs_port/record_queue.h). 8
 * slots absorb about 270 ms of card stall at 30 fps; beyond that the
 * newest pairs are dropped (counted). At 640x480 they hold 4.9 MB. */
#define APP_RECORD_SLOTS 8u
static uint8_t rec_buf[APP_RECORD_SLOTS * 2u * NEGOBS_RUN_MAX_W *
                       NEGOBS_RUN_MAX_H];
static negobs_record_queue_t recq;
static char record_refused[NEGOBS_PORT_ERRMSG_LEN];
static bool record_fail_logged;

/* Before anything runs: an existing session is never recorded over. The
 * refusal stops the recording only; the device still warns. */
static void record_start(void)
{
    char why[NEGOBS_PORT_ERRMSG_LEN];
    if (S.record[0] == '\0') {
        return;
    }
    if (negobs_recorder_check_dir(S.record, why, sizeof why) != NEGOBS_OK) {
        (void)snprintf(record_refused, sizeof record_refused, "%s", why);
        logmsg(LOG_ERROR, "record: %s; running without recording", why);
        return;
    }
    if (negobs_recq_start(&recq, S.record, rec_buf,
                          2u * NEGOBS_RUN_MAX_W * NEGOBS_RUN_MAX_H,
                          APP_RECORD_SLOTS) != NEGOBS_OK) {
        (void)snprintf(record_refused, sizeof record_refused,
                       "cannot start the recording thread");
        logmsg(LOG_ERROR, "record: %s; running without recording",
               record_refused);
        return;
    }
    logmsg(LOG_INFO, "recording to %s", S.record);
}

/* Hand the pair to the writer thread (never waits for the card); say
 * once when the recording has stopped on an error. */
static void record_pair(const negobs_frame_pair_t *pair)
{
    negobs_recq_stats_t rs;
    if (!recq.running || record_fail_logged) {
        return;
    }
    if (negobs_recq_push(&recq, pair) >= 0) {
        return;
    }
    negobs_recq_stats(&recq, &rs);
    if (rs.state == NEGOBS_RECQ_FAILED) {
        record_fail_logged = true;
        logmsg(LOG_ERROR, "record: stopped: %s (%lu pairs recorded); "
               "detection and alerting go on",
               rs.errmsg, (unsigned long)rs.written);
    }
}

/* "record=off", "record=recording written=.. dropped=..", ... */
static void record_summary(char *out, size_t len)
{
    negobs_recq_stats_t rs;
    if (S.record[0] == '\0') {
        (void)snprintf(out, len, "record=off");
        return;
    }
    if (record_refused[0] != '\0') {
        (void)snprintf(out, len, "record=refused (%s)", record_refused);
        return;
    }
    negobs_recq_stats(&recq, &rs);
    (void)snprintf(out, len, "record=%s written=%lu dropped=%lu%s%s%s",
                   negobs_recq_state_name(rs.state),
                   (unsigned long)rs.written,
                   (unsigned long)(rs.dropped + rs.discarded),
                   rs.state == NEGOBS_RECQ_FAILED ? " (" : "",
                   rs.state == NEGOBS_RECQ_FAILED ? rs.errmsg : "",
                   rs.state == NEGOBS_RECQ_FAILED ? ")" : "");
}

static void log_summary(uint32_t done, const run_status_t *st)
{
    negobs_camera_stats_t cs;
    char rec[NEGOBS_PORT_ERRMSG_LEN + 64];
    negobs_camera_get_stats(&camera, &cs);
    record_summary(rec, sizeof rec);
    logmsg(LOG_INFO,
           "summary pairs=%lu no-info=%lu clear=%lu caution=%lu "
           "imminent=%lu last_reason=%s dropped=%lu timeouts=%lu %s",
           (unsigned long)done, (unsigned long)st->verdicts[0],
           (unsigned long)st->verdicts[1], (unsigned long)st->verdicts[2],
           (unsigned long)st->verdicts[3],
           app_reason_name(pipeline.last.reason),
           (unsigned long)cs.dropped_pairs, (unsigned long)cs.timeouts, rec);
}

static int run_loop(void)
{
    run_status_t st;
    negobs_frame_pair_t pair;
    uint32_t done = 0;
    int last_err = NEGOBS_OK;
    bool motor_failing = false;
    memset(&st, 0, sizeof st);
    st.window_start_ms = negobs_clock_now_ms();
    st.next_ms = st.window_start_ms + (uint64_t)S.status_interval_ms;
    st.verdict = APP_VERDICT_NO_INFO;

    while (!stop_requested) {
        uint64_t now;
        int rc = negobs_camera_get_pair(&camera, &pair, S.watchdog_ms);
        now = negobs_clock_now_ms();
        if (rc == NEGOBS_OK) {
            app_verdict_t v;
            uint64_t lat_us;
            negobs_alert_input_t in;
            const negobs_image_u8_t *img_l = &pair.left.y;
            const negobs_image_u8_t *img_r = &pair.right.y;
            negobs_image_u8_t rect_l;
            negobs_image_u8_t rect_r;
            record_pair(&pair);
            if (calib_bytes > 0) {
                /* Record raw, judge rectified (a recorded session can be
                 * replayed with the same table). */
                int32_t w = img_l->width;
                int32_t h = img_l->height;
                if (!rect_ready && rectify_setup(w, h) != 0) {
                    negobs_camera_release(&camera, &pair);
                    return EXIT_CALIB;
                }
                rect_l.data = rect_buf;
                rect_r.data = rect_buf + (size_t)w * (size_t)h;
                rect_l.width = rect_r.width = w;
                rect_l.height = rect_r.height = h;
                rect_l.stride = rect_r.stride = w;
                if (negobs_rectify_process(&rect_ctx, img_l, img_r, &rect_l,
                                           &rect_r, NULL) != NEGOBS_OK) {
                    logmsg(LOG_ERROR, "calib: cannot rectify a %ldx%ld pair",
                           (long)w, (long)h);
                    negobs_camera_release(&camera, &pair);
                    return EXIT_CALIB;
                }
                img_l = &rect_l;
                img_r = &rect_r;
            }
            v = app_process_pair_at(
                &pipeline, img_l, img_r,
                (uint32_t)(pair.left.ts_ns / 1000000u),
                (uint32_t)(pair.right.ts_ns / 1000000u), (uint32_t)now);
            {
                /* the verdict is about the moment of capture: a clear one
                 * that took too long to reach is not trusted */
                uint64_t t_done = negobs_clock_now_ns();
                uint64_t age_ms = (t_done > pair.left.ts_ns)
                                      ? (t_done - pair.left.ts_ns) / 1000000u
                                      : 0u;
                v = app_pipeline_latency_gate(
                    &pipeline, v,
                    (int32_t)((age_ms > 600000u) ? 600000u : age_ms));
            }
            app_alert_input(v, &pipeline.last, 0u, &in);
            alert_post(&in);
            logmsg(LOG_DEBUG, "pair %lu verdict %s first_row %ld",
                   (unsigned long)done, app_verdict_name(v),
                   (long)pipeline.last.first_row);
            if (log_level >= LOG_DEBUG && pipeline.last.stereo_us > 0u) {
                const uint32_t *us = pipeline.last.stage_us;
                logmsg(LOG_DEBUG,
                       "stage times of pair %lu: stereo_us %lu (gcs %lu dp %lu "
                       "other %lu)",
                       (unsigned long)done,
                       (unsigned long)pipeline.last.stereo_us,
                       (unsigned long)us[NEGOBS_STEREO_STAGE_GCS],
                       (unsigned long)us[NEGOBS_STEREO_STAGE_DP],
                       (unsigned long)(pipeline.last.stereo_us -
                                       us[NEGOBS_STEREO_STAGE_GCS] -
                                       us[NEGOBS_STEREO_STAGE_DP]));
            }
            lat_us = (negobs_clock_now_ns() - pair.left.ts_ns) / 1000u;
            negobs_camera_release(&camera, &pair);
            if (v != st.verdict) {
                /* For "detector", say which NEGOBS_DEGRADED_* bits
                 * (negobs/detect.h) made it blind: stale or unsynced
                 * frames read very differently from a bad ground fit. */
                if (pipeline.last.reason == APP_REASON_DETECTOR) {
                    logmsg(LOG_INFO, "verdict %s -> %s (detector 0x%lx)",
                           app_verdict_name(st.verdict), app_verdict_name(v),
                           (unsigned long)pipeline.last.detect_reasons);
                } else {
                    logmsg(LOG_INFO, "verdict %s -> %s (%s)",
                           app_verdict_name(st.verdict), app_verdict_name(v),
                           app_reason_name(pipeline.last.reason));
                }
            }
            st.verdict = v;
            st.verdicts[v & 3]++;
            st.pairs++;
            st.lat_sum_us += lat_us;
            if (lat_us > st.lat_max_us) {
                st.lat_max_us = lat_us;
            }
            last_err = NEGOBS_OK;
            done++;
            if (S.frames > 0 && done >= (uint32_t)S.frames) {
                logmsg(LOG_INFO, "%lu pairs processed", (unsigned long)done);
                break;
            }
        } else if (rc == NEGOBS_CAMERA_END) {
            logmsg(LOG_INFO, "end of replay after %lu pairs",
                   (unsigned long)done);
            break;
        } else if (rc == NEGOBS_ERR_AGAIN) {
            continue; /* signal: the loop condition decides */
        } else if (rc == NEGOBS_ERR_TIMEOUT || rc == NEGOBS_ERR_NODEV ||
                   rc == NEGOBS_ERR_IO) {
            /* No data: say so at once rather than wait for the watchdog
             * (the library keeps a recent IMMINENT for its hold time). */
            negobs_alert_input_t in;
            app_alert_input(APP_VERDICT_NO_INFO, NULL, 0u, &in);
            alert_post(&in);
            if (rc != last_err) {
                logmsg(LOG_WARN, "camera: %s%s%s",
                       negobs_status_str((negobs_status_t)rc),
                       negobs_camera_errmsg(&camera)[0] != '\0' ? ": " : "",
                       negobs_camera_errmsg(&camera));
            }
            if (st.verdict != APP_VERDICT_NO_INFO) {
                logmsg(LOG_INFO, "verdict %s -> no-info (camera)",
                       app_verdict_name(st.verdict));
            }
            st.verdict = APP_VERDICT_NO_INFO;
            last_err = rc;
        } else {
            logmsg(LOG_ERROR, "camera: %s (%s)", negobs_camera_errmsg(&camera),
                   camera_status_words(rc));
            log_summary(done, &st);
            return EXIT_RUNTIME;
        }
        check_motor_output(&motor_failing);
        if (now >= st.next_ms) {
            status_line(&st, now);
        }
    }
    if (stop_requested) {
        logmsg(LOG_INFO, "stop requested (%s), shutting down",
               signal_name((int)stop_signal));
    }
    log_summary(done, &st);
    if (stop_requested && !is_stop_request((int)stop_signal)) {
        return 128 + (int)stop_signal;
    }
    return EXIT_OK;
}

int main(int argc, char **argv)
{
    run_args_t args;
    negobs_motor_schedule_t noinfo_sched;
    int rc;

    log_t0_ms = negobs_clock_now_ms();
    settings_default();
    memset(&args, 0, sizeof args);
    rc = parse_args(argc, argv, &args);
    if (rc >= 0) {
        return rc;
    }
    if (args.motor_off != NULL) {
        return motor_off(args.motor_off);
    }
    if (check_alert_spec(S.alert) != 0) {
        return usage_error("bad alert '%s' (want gpio:CHIP:LINE, "
                           "pwm:CHIP:CHANNEL, console or none)", S.alert);
    }
    rc = check_camera_args(&args);
    if (rc != 0) {
        return rc;
    }
    if (S.calib[0] != '\0') {
        rc = load_calib(S.calib);
        if (rc >= 0) {
            return rc;
        }
    }
    /* The detector must accept every pair the capture layer pairs. */
    S.app.sync_tol_ms = S.pair_tol_ms;
    S.app.vertical_align = vertical_align_flag ? 1 : 0;
    S.app.row_crop = row_crop_flag ? 1 : 0;
    if (app_pipeline_init(&pipeline, &S.app) != NEGOBS_OK) {
        if (calib_bytes > 0) {
            fprintf(stderr, "negobs_run: calibration table %s refused: its "
                            "geometry is outside the detector's range\n",
                    S.calib);
            return EXIT_CALIB;
        }
        fprintf(stderr, "negobs_run: bad image-quality thresholds\n");
        return EXIT_CONFIG;
    }
    if (log_level >= LOG_DEBUG) {
        /* where the matcher's time goes, on the device itself */
        app_pipeline_set_clock(&pipeline, stage_clock_ns, NULL);
    }
    /* One staleness limit: the library's and the watchdog's. */
    S.alert_cfg.stale_ms = S.watchdog_ms;
    S.alert_cfg.binary_mode = alert_binary_flag ? 1 : 0;
    if (app_alert_init(&alert_sm, &S.alert_cfg) != NEGOBS_OK ||
        app_alert_noinfo_schedule(&S.alert_cfg, 0u, &noinfo_sched) !=
            NEGOBS_OK) {
        fprintf(stderr, "negobs_run: bad alert settings (caution_mid_mm "
                        "must not exceed caution_far_mm; heartbeat_period_ms "
                        "0 or 1000..60000, heartbeat_pulse_ms 80 .. a quarter "
                        "of it)\n");
        return EXIT_CONFIG;
    }
    install_signals();
    if (calib_bytes > 0) {
        log_calib(S.calib);
    }
    if (S.app.vertical_align) {
        logmsg(LOG_INFO, "vertical alignment stage on (sub-pixel, "
                         "row-varying model estimated from the frames)");
    }

    if (open_alert(S.alert) != 0) {
        return EXIT_ALERT;
    }
    if (negobs_motor_thread_start(&motor, &alert, &noinfo_sched,
                                  backstop_ms((uint32_t)S.watchdog_ms)) !=
        NEGOBS_OK) {
        logmsg(LOG_ERROR, "cannot start the motor thread");
        negobs_alert_close(&alert);
        return EXIT_ALERT;
    }
    /* READY: the library plays it first; posting keeps the motor
     * thread's watchdog from cutting it while it plays. */
    {
        uint32_t waited;
        for (waited = 0; waited < APP_READY_MAX_MS; waited += 40u) {
            alert_post(NULL);
            if (app_alert_pattern(&alert_sm) != NEGOBS_PATTERN_READY) {
                break;
            }
            negobs_clock_sleep_ms(40u);
        }
    }

    record_start();
    if (open_camera(&args) != 0) {
        negobs_recq_stop(&recq);
        negobs_motor_thread_stop(&motor);
        negobs_alert_close(&alert);
        return EXIT_CAMERA;
    }
    rc = run_loop();


    /* Shutdown: camera first, then the motor (off), then the output. */
    negobs_camera_stop(&camera);
    negobs_camera_close(&camera);
    negobs_recq_stop(&recq);
    negobs_motor_thread_stop(&motor);
    negobs_alert_close(&alert);
    logmsg(LOG_INFO, "exit %d", rc);
    return rc;
}
