/* negobs_run's devices: motor output, cameras, calibration table. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <string.h>

#include "negobs/rectify.h"
#include "negobs/status.h"
#include "negobs_port/camera_libcamera.h"
#include "negobs_port/camera_list.h"
#include "negobs_port/camera_replay.h"
#include "negobs_port/camera_v4l2.h"
#include "run_app.h"

/* Largest calibration table read (grid shift >= 1 at 1280 x 800). */
#define APP_CALIB_MAX_BYTES (6u * 1024u * 1024u)

negobs_motor_out_t run_alert;
negobs_capture_t run_camera;
negobs_motor_thread_t run_motor;

static negobs_motor_out_console_t alert_console;
static negobs_motor_out_pwm_t alert_pwm;
static negobs_motor_out_gpio_t alert_gpio;
static negobs_replay_t replay_state;
static negobs_v4l2_t v4l2_state;
static negobs_libcamera_t libcamera_state;
/* Replay pixels or packed-format luma: one pair at the largest size. */
static uint8_t frame_buf[2u * NEGOBS_RUN_MAX_W * NEGOBS_RUN_MAX_H];
/* V4L2 conversion, per node: a decoded MJPEG frame up to the largest
 * capture size plus the binned eyes (negobs_v4l2_conv_scratch_bytes()). */
#define RUN_MAX_CAPTURE_W 2560
#define RUN_MAX_CAPTURE_H 1024
static uint8_t
    v4l2_scratch[2u * ((size_t)RUN_MAX_CAPTURE_W * RUN_MAX_CAPTURE_H +
                       (size_t)NEGOBS_RUN_MAX_W * NEGOBS_RUN_MAX_H)];

int open_alert(const char *spec)
{
    char kind[16];
    char f1[64];
    char f2[16];
    uint32_t a = 0;
    uint32_t b = 0;
    negobs_status_t s;
    (void)split_spec(spec, kind, sizeof kind, f1, sizeof f1, f2, sizeof f2);
    if (strcmp(kind, "console") == 0) {
        s = negobs_motor_out_console_open(&alert_console, stdout, &run_alert);
    } else if (strcmp(kind, "none") == 0) {
        s = negobs_motor_out_none_open(&run_alert);
    } else if (strcmp(kind, "pwm") == 0) {
        (void)parse_u32(f1, &a);
        (void)parse_u32(f2, &b);
        s = negobs_motor_out_pwm_open(&alert_pwm, run_cfg.pwm_sysfs_root, a, b,
                                      (uint32_t)run_cfg.pwm_period_ns,
                                      &run_alert);
        if (s != NEGOBS_OK) {
            logmsg(LOG_ERROR, "pwm output: %s", alert_pwm.errmsg);
        }
    } else {
        (void)parse_u32(f2, &b);
        s = negobs_motor_out_gpio_open(&alert_gpio, f1, b,
                                       run_cfg.gpio_active_low, &run_alert);
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

const char *alert_errmsg(void)
{
    return run_alert.ctx == (void *)&alert_gpio  ? alert_gpio.errmsg
           : run_alert.ctx == (void *)&alert_pwm ? alert_pwm.errmsg
                                                 : "";
}

/* negobs_run --motor-off SPEC: the systemd unit's ExecStopPost, run after
 * negobs_run ended in any way (even SIGKILL): open the output, which
 * drives it off (GPIO line low / inactive, PWM duty 0), and close it
 * (PWM disabled, line released). */
int motor_off(const char *spec)
{
    if (check_alert_spec(spec) != 0) {
        return usage_error("bad motor output '%s' (want gpio:CHIP:LINE, "
                           "pwm:CHIP:CHANNEL, console or none)",
                           spec);
    }
    if (open_alert(spec) != 0) {
        return EXIT_ALERT;
    }
    if (negobs_motor_out_set(&run_alert, 0) != NEGOBS_OK) {
        logmsg(LOG_ERROR, "motor output '%s': cannot switch it off", spec);
        negobs_motor_out_close(&run_alert);
        return EXIT_ALERT;
    }
    negobs_motor_out_close(&run_alert);
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

int check_camera_args(const run_args_t *a)
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
            return 0; /* one node: side by side */
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

static const char *v4l2_path(const char *arg)
{
    return strncmp(arg, "v4l2:", 5) == 0 ? arg + 5 : arg;
}

/* One V4L2 node given (or the same twice): both eyes side by side. */
static bool side_by_side(const run_args_t *a)
{
    return strcmp(camera_kind(a->left), "v4l2") == 0 &&
           (a->right == NULL ||
            strcmp(v4l2_path(a->right), v4l2_path(a->left)) == 0);
}

int list_cameras(const run_args_t *a)
{
    int usable = 0;
    int i;
    if (a->n_list_nodes > 0) {
        for (i = 0; i < a->n_list_nodes; i++) {
            if (negobs_v4l2_list_node(v4l2_path(a->list_nodes[i]), stdout) ==
                NEGOBS_OK) {
                usable++;
            }
        }
    } else {
        int lc;
        printf("V4L2 nodes:\n");
        usable = negobs_v4l2_list_all(stdout);
        printf("\nlibcamera cameras:\n");
        lc = negobs_libcamera_list(stdout);
        usable += lc > 0 ? lc : 0;
    }
    fflush(stdout);
    if (usable == 0) {
        fprintf(stderr, "negobs_run: no usable camera found\n");
        return EXIT_CAMERA;
    }
    return EXIT_OK;
}

/* The plan the configured capture size gives, or -1 when none is set. */
static int capture_plan(const run_args_t *a, negobs_bin_plan_t *plan)
{
    int32_t eye_w;
    int32_t eye_h;
    if (strcmp(camera_kind(a->left), "v4l2") != 0 ||
        (run_cfg.capture_width == 0 && run_cfg.capture_height == 0)) {
        return -1;
    }
    if (run_cfg.capture_width == 0 || run_cfg.capture_height == 0 ||
        negobs_sbs_eye_size(run_cfg.capture_width, run_cfg.capture_height,
                            side_by_side(a), &eye_w, &eye_h) != NEGOBS_OK ||
        negobs_bin_plan(eye_w, eye_h, run_cfg.width, run_cfg.height, plan) !=
            NEGOBS_OK) {
        return EXIT_USAGE;
    }
    return 0;
}

/* pixel_format as a fourcc: 1 to 4 printable characters, padded with
 * spaces as V4L2 names them ("Y16" -> 'Y16 '); 0 when empty, -1 when
 * malformed. */
static int pixel_format_fourcc(uint32_t *fourcc)
{
    const char *p = run_cfg.pixel_format;
    size_t n = strlen(p);
    size_t i;
    *fourcc = 0;
    if (n == 0u) {
        return 0;
    }
    if (n > 4u) {
        return -1;
    }
    for (i = 0; i < 4u; i++) {
        unsigned char c = i < n ? (unsigned char)p[i] : (unsigned char)' ';
        if (c < 0x20u || c > 0x7Eu) {
            return -1;
        }
        *fourcc |= (uint32_t)c << (8u * i);
    }
    return 0;
}

int camera_geometry(const run_args_t *a)
{
    negobs_bin_plan_t plan;
    uint32_t fourcc;
    int rc;
    if (pixel_format_fourcc(&fourcc) != 0) {
        fprintf(stderr,
                "negobs_run: pixel_format '%s' is not a fourcc (1 to 4 "
                "characters, e.g. Y16)\n",
                run_cfg.pixel_format);
        return EXIT_USAGE;
    }
    rc = capture_plan(a, &plan);
    if (rc < 0) {
        return -1;
    }
    if (rc != 0) {
        fprintf(stderr,
                "negobs_run: capture size %ldx%ld%s cannot give %ldx%ld "
                "(set both capture_width and capture_height, each eye at "
                "least the processing size)\n",
                (long)run_cfg.capture_width, (long)run_cfg.capture_height,
                side_by_side(a) ? " side by side" : "", (long)run_cfg.width,
                (long)run_cfg.height);
        return EXIT_USAGE;
    }
    /* focal_px is for the captured eye; a calibration table is made on
     * the processing images and already at their scale */
    if (!calib_loaded()) {
        int32_t f_q4 = run_cfg.app.focal_q4 > 0 ? run_cfg.app.focal_q4
                                                : run_cfg.app.focal_px * 16;
        negobs_bin_intrinsics_q4(&plan, &f_q4, &run_cfg.app.cx_q4,
                                 &run_cfg.app.cy_q4);
        run_cfg.app.focal_q4 = f_q4;
    }
    return -1;
}

/* What a camera or replay status means, for the log line after the
 * backend's own message (which names the file or device). */
const char *camera_status_words(int rc)
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

/* The camera must deliver the capture size the focal was scaled for. */
static int check_v4l2_geometry(const run_args_t *a)
{
    const negobs_v4l2_conv_t *c = &v4l2_state.dev[0].conv;
    negobs_bin_plan_t want;
    char cc[5];
    int i;
    for (i = 0; i < 4; i++) {
        cc[i] = (char)((c->fourcc >> (8 * i)) & 0x7Fu);
    }
    cc[4] = '\0';
    logmsg(LOG_INFO,
           "camera: %s %ldx%ld%s -> %ldx%ld per eye (%ldx%ld bins, crop at "
           "%ld,%ld)",
           cc, (long)c->width, (long)c->height,
           c->side_by_side ? " side by side" : "", (long)c->plan.out_w,
           (long)c->plan.out_h, (long)c->plan.k, (long)c->plan.k,
           (long)c->plan.x0, (long)c->plan.y0);
    if (capture_plan(a, &want) == 0 && (c->width != run_cfg.capture_width ||
                                        c->height != run_cfg.capture_height)) {
        logmsg(LOG_ERROR,
               "camera delivers %ldx%ld, not the capture size %ldx%ld that "
               "focal_px was scaled for: set capture_width/capture_height "
               "to a size it lists (negobs_run --list-cameras)",
               (long)c->width, (long)c->height, (long)run_cfg.capture_width,
               (long)run_cfg.capture_height);
        negobs_capture_stop(&run_camera);
        negobs_capture_close(&run_camera);
        return -1;
    }
    return 0;
}

int open_camera(const run_args_t *a)
{
    negobs_capture_config_t cfg;
    negobs_status_t s;
    negobs_capture_config_default(&cfg);
    cfg.left = a->left;
    cfg.right = a->right != NULL ? a->right : a->left;
    cfg.width = run_cfg.width;
    cfg.height = run_cfg.height;
    cfg.fps = run_cfg.fps;
    cfg.pair_tol_ms = run_cfg.pair_tol_ms;
    cfg.frozen_frames = run_cfg.frozen_frames;
    cfg.exposure = run_cfg.exposure;
    cfg.gain = run_cfg.gain;
    cfg.loop = run_cfg.replay_loop;
    cfg.capture_width = run_cfg.capture_width;
    cfg.capture_height = run_cfg.capture_height;
    cfg.side_by_side = side_by_side(a);
    (void)pixel_format_fourcc(&cfg.pixel_format); /* checked at start */
    if (strcmp(camera_kind(a->left), "replay") == 0) {
        if (!run_cfg.size_given) {
            cfg.width = 0; /* take the size of the files */
            cfg.height = 0;
        }
        s = negobs_replay_init(&replay_state, frame_buf, sizeof frame_buf,
                               &run_camera);
    } else if (strcmp(camera_kind(a->left), "libcamera") == 0) {
        s = negobs_libcamera_init(&libcamera_state, frame_buf,
                                  sizeof frame_buf, &run_camera);
    } else {
        s = negobs_v4l2_init(&v4l2_state, v4l2_scratch, sizeof v4l2_scratch,
                             &run_camera);
    }
    if (s == NEGOBS_OK) {
        s = negobs_capture_open(&run_camera, &cfg);
        if (s == NEGOBS_OK) {
            s = negobs_capture_start(&run_camera);
            if (s != NEGOBS_OK) {
                negobs_capture_close(&run_camera);
            }
        }
    }
    if (s != NEGOBS_OK) {
        logmsg(LOG_ERROR, "camera %s: %s (%s)", a->left,
               negobs_capture_errmsg(&run_camera), camera_status_words(s));
        return -1;
    }
    if (strcmp(camera_kind(a->left), "replay") == 0 &&
        negobs_replay_damage(&replay_state)[0] != '\0') {
        logmsg(LOG_WARN, "replay: %s", negobs_replay_damage(&replay_state));
    }
    logmsg(LOG_INFO, "camera: %s backend, %s %s", run_camera.ops->name,
           cfg.left, cfg.side_by_side ? "(side by side)" : cfg.right);
    if (strcmp(camera_kind(a->left), "v4l2") == 0) {
        return check_v4l2_geometry(a);
    }
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
        (void)snprintf(msg, len,
                       "unsupported table version or format "
                       "(this negobs_run reads version %d.x)",
                       NEGOBS_RECTIFY_VERSION_MAJOR);
        return;
    }
    if (calib_bytes < NEGOBS_RECTIFY_HEADER_BYTES) {
        (void)snprintf(msg, len,
                       "truncated: %lu bytes, shorter than the "
                       "%d-byte header",
                       (unsigned long)calib_bytes,
                       NEGOBS_RECTIFY_HEADER_BYTES);
        return;
    }
    if (memcmp(calib_table, NEGOBS_RECTIFY_MAGIC, 8) != 0) {
        (void)snprintf(msg, len,
                       "not a negobs rectification table "
                       "(bad magic)");
        return;
    }
    total = rd_u32le(calib_table + 16);
    if ((size_t)total > calib_bytes) {
        (void)snprintf(msg, len,
                       "truncated: %lu of the %lu bytes its "
                       "header declares",
                       (unsigned long)calib_bytes, (unsigned long)total);
        return;
    }
    (void)snprintf(msg, len,
                   "corrupt: checksum (CRC32) or header values "
                   "do not match");
}

/* Read and check the table, set the geometry and the capture size. */
int load_calib(const char *path)
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
        fprintf(stderr,
                "negobs_run: calibration table %s: larger than %u "
                "bytes (use a coarser negobs_calib --grid-shift)\n",
                path, APP_CALIB_MAX_BYTES);
        return EXIT_CALIB;
    }
    st = negobs_rectify_table_check(calib_table, calib_bytes, 0, 0,
                                    &calib_info);
    if (st != NEGOBS_OK) {
        calib_why(st, why, sizeof why);
        fprintf(stderr, "negobs_run: calibration table %s refused: %s\n", path,
                why);
        return EXIT_CALIB;
    }
    if (calib_info.width > NEGOBS_RUN_MAX_W ||
        calib_info.height > NEGOBS_RUN_MAX_H) {
        fprintf(stderr,
                "negobs_run: calibration table %s refused: it is "
                "for %ldx%ld, larger than %dx%d\n",
                path, (long)calib_info.width, (long)calib_info.height,
                NEGOBS_RUN_MAX_W, NEGOBS_RUN_MAX_H);
        return EXIT_CALIB;
    }
    if (run_cfg.size_given && (run_cfg.width != calib_info.width ||
                               run_cfg.height != calib_info.height)) {
        fprintf(stderr,
                "negobs_run: calibration table %s refused: size "
                "mismatch: the table is for %ldx%ld, the capture "
                "size is %ldx%ld\n",
                path, (long)calib_info.width, (long)calib_info.height,
                (long)run_cfg.width, (long)run_cfg.height);
        return EXIT_CALIB;
    }
    /* The table's size is the capture size (a replay keeps its files'
     * size; the first pair is checked against the table). */
    run_cfg.width = calib_info.width;
    run_cfg.height = calib_info.height;
    /* Measured geometry wins over the config's nominal values. */
    run_cfg.app.focal_q4 = (int32_t)((calib_info.f_q16 + 2048u) >> 12);
    run_cfg.app.baseline_um = (int32_t)calib_info.baseline_um;
    run_cfg.app.cx_q4 = calib_info.cx_q16 >= 0
                            ? (int32_t)((calib_info.cx_q16 + 2048) >> 12)
                            : -1;
    run_cfg.app.cy_q4 = calib_info.cy_q16 >= 0
                            ? (int32_t)((calib_info.cy_q16 + 2048) >> 12)
                            : -1;
    return -1;
}

/* One line with what the table brings (after the log is set up). */
void log_calib(const char *path)
{
    uint32_t f100 = (uint32_t)(((uint64_t)calib_info.f_q16 * 100u + 32768u) >>
                               16);
    int32_t cx100 = (int32_t)(((int64_t)calib_info.cx_q16 * 100 + 32768) /
                              65536);
    int32_t cy100 = (int32_t)(((int64_t)calib_info.cy_q16 * 100 + 32768) /
                              65536);
    logmsg(
        LOG_INFO,
        "calib: %s: %ldx%ld grid 2^%ld f_px=%lu.%02lu baseline_mm=%lu.%03lu "
        "cx=%ld.%02ld cy=%ld.%02ld (replace focal_px=%ld baseline_mm=%ld)",
        path, (long)calib_info.width, (long)calib_info.height,
        (long)calib_info.grid_shift, (unsigned long)(f100 / 100u),
        (unsigned long)(f100 % 100u),
        (unsigned long)(calib_info.baseline_um / 1000u),
        (unsigned long)(calib_info.baseline_um % 1000u), (long)(cx100 / 100),
        (long)(cx100 < 0 ? -cx100 % 100 : cx100 % 100), (long)(cy100 / 100),
        (long)(cy100 < 0 ? -cy100 % 100 : cy100 % 100),
        (long)run_cfg.app.focal_px, (long)run_cfg.app.baseline_mm);
    if (calib_info.doffs_q16 != 0) {
        logmsg(LOG_WARN,
               "calib: the table has a disparity offset "
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
        logmsg(LOG_ERROR,
               "calib: size mismatch: the table is for %ldx%ld, "
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

bool calib_loaded(void)
{
    return calib_bytes > 0;
}

/* Record raw, judge rectified (a recorded session can be replayed with
 * the same table). */
int rectify_pair(const negobs_image_u8_t *l, const negobs_image_u8_t *r,
                 negobs_image_u8_t *out_l, negobs_image_u8_t *out_r)
{
    int32_t w = l->width;
    int32_t h = l->height;
    if (!rect_ready && rectify_setup(w, h) != 0) {
        return EXIT_CALIB;
    }
    out_l->data = rect_buf;
    out_r->data = rect_buf + (size_t)w * (size_t)h;
    out_l->width = out_r->width = w;
    out_l->height = out_r->height = h;
    out_l->stride = out_r->stride = w;
    if (negobs_rectify_process(&rect_ctx, l, r, out_l, out_r, NULL) !=
        NEGOBS_OK) {
        logmsg(LOG_ERROR, "calib: cannot rectify a %ldx%ld pair", (long)w,
               (long)h);
        return EXIT_CALIB;
    }
    return 0;
}

/* Which table this is, for a recorded session's meta.txt: its CRC-32
 * (the table's last 4 bytes, docs/CALIBRATION.md) and length. */
void calib_identity(uint32_t *crc32, size_t *bytes)
{
    uint32_t total = calib_bytes >= NEGOBS_RECTIFY_HEADER_BYTES
                         ? rd_u32le(calib_table + 16)
                         : 0u;
    *crc32 = (total >= 4u && (size_t)total <= calib_bytes)
                 ? rd_u32le(calib_table + total - 4u)
                 : 0u;
    *bytes = calib_bytes;
}
