/* negobs_run's settings: defaults, config keys, command line, log. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <getopt.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "negobs/version.h"
#include "negobs_port/clock.h"
#include "app_config.h"
#include "app_logout.h"
#include "negobs_port/pool.h"
#include "run_app.h"

run_settings_t run_cfg;
int run_log_level = LOG_INFO;
uint64_t run_log_t0_ms;

#define N_KEYS (sizeof config_keys / sizeof config_keys[0])

static const app_cfg_key_t config_keys[] = {
    {"alert", APP_CFG_STRING, run_cfg.alert, 0, sizeof run_cfg.alert,
     "gpio:CHIP:LINE | pwm:CHIP:CHANNEL | console | none"},
    {"width", APP_CFG_INT, &run_cfg.width, 16, NEGOBS_RUN_MAX_W,
     "capture width in pixels (default 640)"},
    {"height", APP_CFG_INT, &run_cfg.height, 16, NEGOBS_RUN_MAX_H,
     "capture height in pixels (default 480)"},
    {"capture_width", APP_CFG_INT, &run_cfg.capture_width, 0, NEGOBS_MAX_DIM,
     "V4L2: frame width asked of the camera (both eyes when side by side); "
     "each eye is cropped and binned to width x height, focal_px is for "
     "this size; 0 = no binning (default 0)"},
    {"capture_height", APP_CFG_INT, &run_cfg.capture_height, 0, NEGOBS_MAX_DIM,
     "V4L2: frame height asked of the camera (default 0)"},
    {"pixel_format", APP_CFG_STRING, run_cfg.pixel_format, 0,
     sizeof run_cfg.pixel_format,
     "V4L2: fourcc asked of the camera (GREY, YUYV, Y10, Y16, MJPG, ...); "
     "empty = the cheapest usable one it lists (default)"},
    {"fps", APP_CFG_INT, &run_cfg.fps, 0, 240,
     "frame rate; replay: pacing, 0 = as fast as possible (default 30)"},
    {"frames", APP_CFG_INT, &run_cfg.frames, 0, INT32_MAX,
     "stop after this many pairs, 0 = run until stopped (default 0)"},
    {"record", APP_CFG_STRING, run_cfg.record, 0, sizeof run_cfg.record,
     "record every pair to this folder (default: off)"},
    {"log_level", APP_CFG_STRING, run_cfg.log_level, 0,
     sizeof run_cfg.log_level, "error | warn | info | debug (default info)"},
    {"pair_tolerance_ms", APP_CFG_INT, &run_cfg.pair_tol_ms, 0, 1000,
     "max left/right timestamp difference of a pair (default 10)"},
    {"frozen_frames", APP_CFG_INT, &run_cfg.frozen_frames, 0, 10000,
     "identical frames in a row after which a V4L2 camera counts as "
     "frozen -> no-info; 0 = off (default 10)"},
    {"watchdog_ms", APP_CFG_INT, &run_cfg.watchdog_ms, 50, 10000,
     "no fresh pair for this long -> no-info pattern (default 300)"},
    {"exposure", APP_CFG_INT, &run_cfg.exposure, -1, INT32_MAX,
     "manual exposure for both cameras, driver units; -1 auto (default)"},
    {"gain", APP_CFG_INT, &run_cfg.gain, -1, INT32_MAX,
     "gain for both cameras, driver units; -1 leave as is (default)"},
    {"pwm_period_ns", APP_CFG_INT, &run_cfg.pwm_period_ns, 1000, 1000000000,
     "PWM period (default 1000000 = 1 kHz)"},
    {"pwm_sysfs_root", APP_CFG_STRING, run_cfg.pwm_sysfs_root, 0,
     sizeof run_cfg.pwm_sysfs_root,
     "sysfs PWM class folder (default /sys/class/pwm)"},
    {"gpio_active_low", APP_CFG_BOOL, &run_cfg.gpio_active_low, 0, 1,
     "motor on = line low (default false)"},
    {"replay_loop", APP_CFG_BOOL, &run_cfg.replay_loop, 0, 1,
     "start a replay over at its end (default false)"},
    {"status_interval_ms", APP_CFG_INT, &run_cfg.status_interval_ms, 100,
     600000, "period of the status line (default 1000)"},
    {"dark_mean_min", APP_CFG_INT, &run_cfg.app.dark_mean_min, 0, 255,
     "mean grey of either image below this -> no-info (default: the "
     "detector's, 20)"},
    {"saturation_permille_max", APP_CFG_INT, &run_cfg.app.sat_permille_max, 0,
     1000,
     "share of pixels >= 250 in either image above this -> no-info "
     "(default: the detector's, 250)"},
    {"texture_min_q4", APP_CFG_INT, &run_cfg.app.texture_min_q4, 0, 4096,
     "mean |horizontal gradient| of either image below this, 1/16 grey "
     "level -> no-info (default: the detector's, 24)"},
    {"lr_mean_diff_max", APP_CFG_INT, &run_cfg.app.lr_mean_diff_max, 0, 255,
     "left/right mean grey difference above this -> no-info (default 60)"},
    {"focal_px", APP_CFG_INT, &run_cfg.app.focal_px, 50, 4000,
     "focal length of the rectified frames, pixels (default 250)"},
    {"baseline_mm", APP_CFG_INT, &run_cfg.app.baseline_mm, 10, 1000,
     "stereo baseline, mm (default 120)"},
    {"cam_height_mm", APP_CFG_INT, &run_cfg.app.cam_height_mm, 0, 3000,
     "camera height hint, mm (default 1200; 0: no hint); the detector "
     "measures the mounting, the hint only verifies the start"},
    {"cam_pitch_mdeg", APP_CFG_INT, &run_cfg.app.cam_pitch_mdeg, 0, 60000,
     "downward pitch hint, 1/1000 degree (default 20000)"},
    {"max_disp", APP_CFG_INT, &run_cfg.app.max_disp, 8, 255,
     "largest disparity searched, pixels (default 63)"},
    {"vertical_align", APP_CFG_BOOL, &run_cfg.vertical_align, 0, 1,
     "estimate and remove a sub-pixel, row-varying vertical misalignment "
     "before matching, for rigs without a calibration table (default "
     "false)"},
    {"row_crop", APP_CFG_BOOL, &run_cfg.row_crop, 0, 1,
     "match only the rows from the top of the warning range down, found "
     "from the last frame's ground (about 15-30 % less matching time); "
     "false matches every row (default true)"},
    {"threads", APP_CFG_INT, &run_cfg.threads, 0, NEGOBS_POOL_MAX_THREADS,
     "threads that run the matcher's row bands; the disparities are the "
     "same for every count; 0 = one per online core (default 0)"},
    {"calib", APP_CFG_STRING, run_cfg.calib, 0, sizeof run_cfg.calib,
     "rectification table from negobs_calib; its f, B, cx, cy replace "
     "focal_px and baseline_mm (default: none, frames are rectified)"},
    {"alert_intensity_permille", APP_CFG_INT,
     &run_cfg.alert_cfg.intensity_permille, 1, 1000,
     "drive level of every pulse (default 1000)"},
    {"caution_far_mm", APP_CFG_INT, &run_cfg.alert_cfg.band_far_mm, 0, 100000,
     "caution range >= this: slow double pulse every 1.0 s (default 3000)"},
    {"caution_mid_mm", APP_CFG_INT, &run_cfg.alert_cfg.band_mid_mm, 0, 100000,
     "caution range >= this: every 0.6 s, nearer every 0.4 s (default "
     "2200; <= caution_far_mm)"},
    {"alert_binary", APP_CFG_BOOL, &run_cfg.alert_binary, 0, 1,
     "one caution pattern (every 0.6 s) whatever the range (default false)"},
    {"imminent_hold_ms", APP_CFG_INT, &run_cfg.alert_cfg.imminent_hold_ms, 0,
     5000,
     "imminent keeps playing this long after its last verdict "
     "(default 1000)"},
    {"heartbeat_period_ms", APP_CFG_INT,
     &run_cfg.alert_cfg.heartbeat_period_ms, 0, 60000,
     "while clear, one brief pulse this often so a dead device is noticed; "
     "0 = off, else >= 1000 (default 5000)"},
    {"heartbeat_pulse_ms", APP_CFG_INT, &run_cfg.alert_cfg.heartbeat_pulse_ms,
     0, 15000,
     "length of the heartbeat pulse, 80 .. a quarter of the "
     "period (default 80)"},
    {"max_frame_age_ms", APP_CFG_INT, &run_cfg.app.max_frame_age_ms, 1, 60000,
     "age of a pair when its processing starts above which it is stale -> "
     "no-info (default 150; raise only for slow emulators)"},
    {"latency_budget_ms", APP_CFG_INT, &run_cfg.app.latency_budget_ms, 0,
     60000,
     "capture-to-verdict time above which a clear verdict is not trusted "
     "-> no-info; warnings pass (default 250; 0 = off)"},
    {"camera_left", APP_CFG_STRING, run_cfg.camera_left, 0,
     sizeof run_cfg.camera_left,
     "LEFT camera when the command line names none (the service's way)"},
    {"camera_right", APP_CFG_STRING, run_cfg.camera_right, 0,
     sizeof run_cfg.camera_right,
     "RIGHT camera, likewise (empty for replay:DIR)"},
    {"log_json", APP_CFG_STRING, run_cfg.log_json, 0, sizeof run_cfg.log_json,
     "one JSON line per judged pair to this file, negobs_png's fields "
     "(default: off)"},
    {"mount_file", APP_CFG_STRING, run_cfg.mount_file, 0,
     sizeof run_cfg.mount_file,
     "keep the mounting measured with evidence on the floor in this file "
     "and start with it as the cam_height_mm / cam_pitch_mdeg hints "
     "(they replace the configured ones; default: off)"},
    {"button", APP_CFG_STRING, run_cfg.button, 0, sizeof run_cfg.button,
     "push button input gpio:CHIP:LINE (file:PATH: its first byte, '1' "
     "pressed; tests): long press pause/resume, short press next "
     "sensitivity preset (default: none)"},
    {"button_active_low", APP_CFG_BOOL, &run_cfg.button_active_low, 0, 1,
     "pressed = line low, a button to ground with a pull-up (default true)"},
    {"button_long_ms", APP_CFG_INT, &run_cfg.button_long_ms, 300, 10000,
     "a press held this long is a long press (default 1000)"},
    {"sensitivity", APP_CFG_INT, &run_cfg.sensitivity, 0, 2,
     "preset at start: 0 every warning, 1 caution only nearer than "
     "caution_mid_mm, 2 imminent only (default 0)"},
};

void settings_default(void)
{
    memset(&run_cfg, 0, sizeof run_cfg);
    (void)snprintf(run_cfg.alert, sizeof run_cfg.alert, "%s",
                   NEGOBS_RUN_DEFAULT_ALERT);
    run_cfg.width = 640;
    run_cfg.height = 480;
    run_cfg.fps = 30;
    (void)snprintf(run_cfg.log_level, sizeof run_cfg.log_level, "info");
    run_cfg.pair_tol_ms = NEGOBS_CAPTURE_PAIR_TOL_MS_DEFAULT;
    run_cfg.frozen_frames = NEGOBS_CAPTURE_FROZEN_FRAMES_DEFAULT;
    run_cfg.watchdog_ms = 300;
    run_cfg.exposure = -1;
    run_cfg.gain = -1;
    run_cfg.pwm_period_ns = 1000000;
    (void)snprintf(run_cfg.pwm_sysfs_root, sizeof run_cfg.pwm_sysfs_root,
                   "/sys/class/pwm");
    run_cfg.status_interval_ms = 1000;
    run_cfg.row_crop = true;
    run_cfg.button_active_low = true;
    run_cfg.button_long_ms = 1000;
    negobs_alert_config_default(&run_cfg.alert_cfg);
    app_pipeline_config_default(&run_cfg.app);
}

/* ---- logging -------------------------------------------------------- */

/* stderr as the log writes it: never waiting for its reader
 * (app_logout.h); a line that cannot go now is dropped and counted. */
static app_logout_t log_err;
static bool log_err_on;

/* The start of a line: the journal priority, the time and the level's
 * tag. Returns its length. */
static size_t log_prefix(char *buf, size_t size, int level)
{
    static const char *const tag[] = {"error", "warn", "info", "debug"};
    uint64_t t = negobs_clock_now_ms() - run_log_t0_ms;
    size_t n = 0;
    int k;
    if (run_log_journal) {
        k = snprintf(buf, size, "<%d>", service_log_priority(level));
        n = k > 0 ? (size_t)k : 0u;
    }
    k = snprintf(buf + n, size - n,
                 "[%5lu.%03lu] %s: ", (unsigned long)(t / 1000u),
                 (unsigned long)(t % 1000u), tag[level]);
    return n + (k > 0 ? (size_t)k : 0u);
}

void logmsg(int level, const char *fmt, ...)
{
    char line[1024];
    unsigned long lost;
    size_t n;
    int k;
    va_list ap;
    if (level > run_log_level) {
        return;
    }
    if (!log_err_on) {
        app_logout_init(&log_err, STDERR_FILENO, false);
        log_err_on = true;
    }
    n = log_prefix(line, sizeof line, level);
    va_start(ap, fmt);
    /* the analyser, following logmsg into its callers, loses va_start */
    /* NOLINTNEXTLINE(clang-analyzer-valist.Uninitialized) */
    k = vsnprintf(line + n, sizeof line - n, fmt, ap);
    va_end(ap);
    if (k < 0) {
        k = 0;
    }
    if ((size_t)k >= sizeof line - n - 1u) {
        n = sizeof line - 5u; /* cut: "...", the newline, the terminator */
        memcpy(line + n, "...", 3);
        n += 3;
    } else {
        n += (size_t)k;
    }
    line[n++] = '\n';
    line[n] = '\0';
    lost = app_logout_line(&log_err, line, n) == 1
               ? app_logout_take_dropped(&log_err)
               : 0u;
    if (lost > 0u) {
        /* said after the line that got through: nothing can be said
         * before it without the same wait */
        n = (size_t)snprintf(line, sizeof line,
                             "%s[log] %lu line(s) before this one dropped: "
                             "stderr was not being read\n",
                             run_log_journal ? "<4>" : "", lost);
        (void)app_logout_line(&log_err, line, n);
    }
}

unsigned long log_lines_dropped(void)
{
    return log_err_on ? log_err.dropped_total : 0u;
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
    fprintf(
        out,
        "Usage: negobs_run [options] LEFT RIGHT\n"
        "       negobs_run [options] replay:DIR\n"
        "       negobs_run --config FILE      (cameras from camera_left/right)\n"
        "       negobs_run [--config FILE] --motor-off SPEC|config\n"
        "       negobs_run --list-cameras [/dev/videoN...]\n"
        "\n"
        "Warns of drop-offs ahead through a vibration motor, from a stereo pair.\n"
        "One V4L2 node alone (or twice): both eyes side by side in each frame.\n"
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
        "Set the camera geometry (focal_px, baseline_mm) in --config for a real\n"
        "rig: wrong values blind it. The mounting (height, pitch, roll) is measured\n"
        "on the floor; cam_height_mm / cam_pitch_mdeg are only hints.\n"
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
        "  --log-json FILE      one JSON line per judged pair (negobs_png's fields)\n"
        "  --set KEY=VALUE      any config key below (after --config; repeatable)\n"
        "  --print-config       print the settings in effect (config file syntax)\n"
        "                       and exit\n"
        "  --threads N          matcher threads (default: online cores; same output)\n"
        "  --motor-off SPEC     switch the motor output SPEC off and exit (the\n"
        "                       service's ExecStopPost; no camera arguments);\n"
        "                       'config': the config's alert\n"
        "  --list-cameras [NODE...]  list V4L2 nodes (all /dev/video*, or those\n"
        "                       named) and libcamera cameras with their formats,\n"
        "                       sizes and rates, and whether negobs can use them;\n"
        "                       exit 0 when one is usable, else 4\n"
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

int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "negobs_run: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'negobs_run --help'.\n");
    return EXIT_USAGE;
}

/* Values of the config file that the key table cannot vet: refused with
 * the file's name and line (exit 3), like any other bad line. */
static int check_config_value(void *user, const char *key, const char *value,
                              char *why, size_t why_len)
{
    char kind[16];
    char f1[64];
    char f2[16];
    uint32_t u;
    (void)user;
    if (strcmp(key, "focal_px") == 0) {
        run_cfg.focal_given = true;
    } else if (strcmp(key, "baseline_mm") == 0) {
        run_cfg.baseline_given = true;
    } else if (strcmp(key, "width") == 0 || strcmp(key, "height") == 0) {
        if (user != NULL) {
            /* --set, as --width/--height: no longer the replay's size */
            run_cfg.size_given = true;
        }
    }
    if (strcmp(key, "button") == 0 && value[0] != '\0' &&
        !(strncmp(value, "file:", 5) == 0 && value[5] != '\0') &&
        (split_spec(value, kind, sizeof kind, f1, sizeof f1, f2, sizeof f2) !=
             2 ||
         strcmp(kind, "gpio") != 0 || f1[0] == '\0' ||
         parse_u32(f2, &u) != 0)) {
        (void)snprintf(why, why_len,
                       "bad button '%s' (want gpio:CHIP:LINE or file:PATH)",
                       value);
        return -1;
    }
    if (strcmp(key, "alert") == 0 && check_alert_spec(value) != 0) {
        (void)snprintf(why, why_len,
                       "bad alert '%s' (want gpio:CHIP:LINE, "
                       "pwm:CHIP:CHANNEL, console or none)",
                       value);
        return -1;
    }
    if (strcmp(key, "log_level") == 0 && parse_log_level(value) < 0) {
        (void)snprintf(why, why_len,
                       "bad log level '%s' (want error, "
                       "warn, info or debug)",
                       value);
        return -1;
    }
    return 0;
}

/* --set KEY=VALUE: any key of the table, vetted as in the config file;
 * -1 to go on, else the exit code (2: a usage error). */
static int set_option(const char *kv)
{
    char key[64];
    char why[128];
    const char *eq = strchr(kv, '=');
    app_cfg_error_t err;
    size_t n = eq != NULL ? (size_t)(eq - kv) : 0u;
    if (eq == NULL || n == 0u || n >= sizeof key) {
        return usage_error("--set wants KEY=VALUE, got '%s'", kv);
    }
    memcpy(key, kv, n);
    key[n] = '\0';
    memset(&err, 0, sizeof err);
    if (app_config_set(config_keys, N_KEYS, key, eq + 1, &err) != NEGOBS_OK) {
        return usage_error("--set: %s", err.msg);
    }
    why[0] = '\0';
    if (check_config_value(&run_cfg, key, eq + 1, why, sizeof why) != 0) {
        fprintf(stderr, "negobs_run: --set %s: %s\n", key, why);
        return usage_error("%s", "bad --set value");
    }
    return -1;
}

/* Pass 1 of the command line: --help/--version win; the config file is
 * read first so that options override it whatever their order. -1 to go
 * on, else the exit code. */
static int read_config_first(int argc, char **argv, run_args_t *a)
{
    app_cfg_error_t err;
    int i;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--") == 0) {
            break;
        }
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            printf("\nConfig file keys (key = value, '#' comments):\n");
            app_config_print_keys(stdout, config_keys, N_KEYS);
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
        if (app_config_parse_file_checked(a->config, config_keys, N_KEYS,
                                          check_config_value, NULL,
                                          &err) != NEGOBS_OK) {
            fprintf(stderr, "negobs_run: %s: %s\n", a->config, err.msg);
            return EXIT_CONFIG;
        }
    }
    return -1;
}

/* Returns -1 to continue, else an exit code. */
int parse_args(int argc, char **argv, run_args_t *a)
{
    enum {
        O_CONFIG = 256,
        O_ALERT,
        O_WIDTH,
        O_HEIGHT,
        O_FPS,
        O_FRAMES,
        O_RECORD,
        O_LOG,
        O_HELP,
        O_VERSION,
        O_CALIB,
        O_MOTOR_OFF,
        O_SET,
        O_LOG_JSON,
        O_PRINT_CONFIG,
        O_LIST_CAMERAS,
        O_THREADS
    };
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
        {"set", required_argument, NULL, O_SET},
        {"log-json", required_argument, NULL, O_LOG_JSON},
        {"print-config", no_argument, NULL, O_PRINT_CONFIG},
        {"list-cameras", no_argument, NULL, O_LIST_CAMERAS},
        {"threads", required_argument, NULL, O_THREADS},
        {NULL, 0, NULL, 0},
    };
    app_cfg_error_t err;
    bool print_config = false;
    int rc;
    int c;

    rc = read_config_first(argc, argv, a);
    if (rc >= 0) {
        return rc;
    }

    /* Pass 2: options, through the same table as the config file. */
    opterr = 0;
    optind = 1;
    while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
        const char *key = NULL;
        switch (c) {
        case O_CONFIG: continue;
        case O_MOTOR_OFF: a->motor_off = optarg; continue;
        case O_LIST_CAMERAS: a->list_cameras = true; continue;
        case O_ALERT: key = "alert"; break;
        case O_WIDTH:
            key = "width";
            run_cfg.size_given = true;
            break;
        case O_HEIGHT:
            key = "height";
            run_cfg.size_given = true;
            break;
        case O_FPS: key = "fps"; break;
        case O_FRAMES: key = "frames"; break;
        case O_RECORD: key = "record"; break;
        case O_CALIB: key = "calib"; break;
        case O_LOG: key = "log_level"; break;
        case O_LOG_JSON: key = "log_json"; break;
        case O_PRINT_CONFIG: print_config = true; continue;
        case O_SET:
            rc = set_option(optarg);
            if (rc >= 0) {
                return rc;
            }
            continue;
        case O_THREADS: key = "threads"; break;
        case ':':
            return usage_error("option '%s' needs a value", argv[optind - 1]);
        case '?':
        default: return usage_error("unknown option '%s'", argv[optind - 1]);
        }
        memset(&err, 0, sizeof err);
        if (app_config_set(config_keys, N_KEYS, key, optarg, &err) !=
            NEGOBS_OK) {
            return usage_error("%s", err.msg);
        }
    }
    if (parse_log_level(run_cfg.log_level) < 0) {
        return usage_error("bad log level '%s'", run_cfg.log_level);
    }
    if (print_config) {
        /* what the service would run with, as a config file */
        settings_write_prefixed(stdout, "");
        return EXIT_OK;
    }
    run_log_level = parse_log_level(run_cfg.log_level);
    if (a->list_cameras) {
        a->list_nodes = (const char *const *)(argv + optind);
        a->n_list_nodes = argc - optind;
        return -1;
    }
    if (a->motor_off != NULL) {
        if (optind < argc) {
            return usage_error("--motor-off takes no camera argument ('%s')",
                               argv[optind]);
        }
        return -1;
    }
    if (optind >= argc && run_cfg.camera_left[0] != '\0') {
        a->left = run_cfg.camera_left;
        a->right = run_cfg.camera_right[0] != '\0' ? run_cfg.camera_right
                                                   : NULL;
        return -1;
    }
    if (optind >= argc) {
        return usage_error("%s", "missing camera arguments LEFT RIGHT (or "
                                 "camera_left/camera_right in the config)");
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

/* Parse "a:b:c" into kind and two fields; returns fields found. */
int split_spec(const char *spec, char *kind, size_t klen, char *f1, size_t l1,
               char *f2, size_t l2)
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

int parse_u32(const char *s, uint32_t *out)
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
int check_alert_spec(const char *spec)
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

/* Wrong geometry silently mis-ranges every drop-off: say so when the
 * rig's f or B, or the rectification, are the built-in guesses. The
 * mounting needs no warning: the detector measures it on the floor. */
void warn_default_geometry(void)
{
    if (calib_loaded()) {
        return; /* the table's measured f, B, cx, cy are used */
    }
    if (!run_cfg.focal_given) {
        logmsg(LOG_WARN,
               "geometry: focal_px %ld is the built-in default, not this "
               "rig's: ranges will be wrong (set focal_px, or --calib)",
               (long)run_cfg.app.focal_px);
    }
    if (!run_cfg.baseline_given) {
        logmsg(LOG_WARN,
               "geometry: baseline_mm %ld is the built-in default, not this "
               "rig's: ranges will be wrong (set baseline_mm, or --calib)",
               (long)run_cfg.app.baseline_mm);
    }
    logmsg(LOG_WARN, "geometry: no calibration table: the frames are taken "
                     "as rectified (negobs_calib, then calib = TABLE)");
}

/* Every key as `key = value` (the config file's syntax). */
void settings_write_prefixed(FILE *out, const char *prefix)
{
    size_t i;
    for (i = 0; i < N_KEYS; i++) {
        const app_cfg_key_t *k = &config_keys[i];
        switch (k->type) {
        case APP_CFG_INT:
            fprintf(out, "%s%s = %ld\n", prefix, k->key,
                    (long)*(const int32_t *)k->ptr);
            break;
        case APP_CFG_BOOL:
            fprintf(out, "%s%s = %s\n", prefix, k->key,
                    *(const bool *)k->ptr ? "true" : "false");
            break;
        default:
            fprintf(out, "%s%s =%s%s\n", prefix, k->key,
                    ((const char *)k->ptr)[0] != '\0' ? " " : "",
                    (const char *)k->ptr);
            break;
        }
    }
}
