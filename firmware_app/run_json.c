/*
 * negobs_run's optional outputs beside the warnings: the per-pair JSON
 * lines log (--log-json FILE) and meta.txt in a recorded session.
 *
 * Both follow the recording's rule: an optional output never stops the
 * warnings. A file that cannot be opened or written is logged once, the
 * output is switched off, and detection and alerting go on.
 *
 * The JSON lines carry negobs_png's fields (tools/detect: frame, file,
 * stereo_status, state, reasons, level, nearest_range_mm, clear_to_mm,
 * short_sight, noise_vouch_mm, range_near_mm, pooled_permille, pattern,
 * motor_on,
 * duty_permille, hazards,
 * candidates, stereo, ground, mount, ms) so that one reader serves both,
 * plus what only the device knows (timestamps, the app's verdict and
 * gate reason, latency, sensitivity preset). docs/RUNNING.md lists them.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "negobs/version.h"
#include "app_logout.h"
#include "app_mount.h"
#include "run_app.h"

/* The log's descriptor, written without waiting (app_logout.h): a reader
 * that stops reading loses lines, counted and reported, and never holds
 * up a verdict. Each line is built whole in json_line first. */
static app_logout_t json_out;
static bool json_on;
static char json_line[APP_LOGOUT_LINE_MAX];
static char json_path[256];

void json_log_open(const char *path)
{
    /* O_NONBLOCK: a FIFO nobody reads fails at once (ENXIO) instead of
     * holding up the start, and stays on for the writes; O_APPEND: a
     * restarted service adds to it. */
    int fd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_NONBLOCK | O_CLOEXEC,
                  0644);
    (void)snprintf(json_path, sizeof json_path, "%s", path);
    if (fd < 0) {
        logmsg(LOG_ERROR, "log-json: %s: %s; running without it", path,
               strerror(errno));
        return;
    }
    app_logout_init(&json_out, fd, true);
    json_on = true;
    logmsg(LOG_INFO, "log-json: one line per pair to %s", path);
}

/* Lines dropped since the last report, said once lines flow again (and
 * at the end). */
static void json_report_dropped(void)
{
    unsigned long n = app_logout_take_dropped(&json_out);
    if (n > 0u) {
        logmsg(LOG_WARN,
               "log-json: %s: %lu line(s) dropped: the reader was not "
               "taking them",
               json_path, n);
    }
}

void json_log_close(void)
{
    if (json_on) {
        json_report_dropped();
        if (app_logout_flush(&json_out) == 0) {
            logmsg(LOG_WARN, "log-json: %s: the last line left unfinished",
                   json_path);
        }
        if (close(json_out.fd) != 0) {
            logmsg(LOG_ERROR, "log-json: %s: %s (last lines lost)", json_path,
                   strerror(errno));
        }
        json_on = false;
    }
}

unsigned long json_lines_dropped(void)
{
    return json_out.dropped_total;
}

static const char *state_name(negobs_detect_state_t s)
{
    switch (s) {
    case NEGOBS_DETECT_CLEAR: return "CLEAR";
    case NEGOBS_DETECT_HAZARD: return "HAZARD";
    case NEGOBS_DETECT_NO_INFO: return "NO_INFO";
    default: return "?";
    }
}

static const char *level_name(negobs_alert_level_t l)
{
    switch (l) {
    case NEGOBS_LEVEL_NONE: return "NONE";
    case NEGOBS_LEVEL_CAUTION: return "CAUTION";
    case NEGOBS_LEVEL_IMMINENT: return "IMMINENT";
    default: return "?";
    }
}

/* negobs_png's upper-case pattern names (tools/detect). */
static const char *pattern_name(int p)
{
    static const char *const names[] = {
        "NONE",     "READY",       "LOW_BATTERY", "NO_INFO_ENTRY",
        "NO_INFO",  "CAUTION_FAR", "CAUTION_MID", "CAUTION_NEAR",
        "IMMINENT", "SHORT_SIGHT"};
    return (p >= 0 && p < (int)(sizeof names / sizeof names[0])) ? names[p]
                                                                 : "?";
}

static const char *type_name(negobs_hazard_type_t t)
{
    switch (t) {
    case NEGOBS_HAZARD_UNKNOWN: return "UNKNOWN";
    case NEGOBS_HAZARD_DROP: return "DROP";
    case NEGOBS_HAZARD_STAIRS: return "STAIRS";
    case NEGOBS_HAZARD_HOLE: return "HOLE";
    default: return "?";
    }
}

static void bit_names(FILE *f, uint32_t bits, const char *const *names,
                      unsigned n)
{
    unsigned b;
    bool first = true;
    fputc('[', f);
    for (b = 0; b < n; b++) {
        if (bits & (1u << b)) {
            fprintf(f, "%s\"%s\"", first ? "" : ",", names[b]);
            first = false;
        }
    }
    fputc(']', f);
}

static void reasons_json(FILE *f, uint32_t reasons)
{
    static const char *const names[] = {
        "TOO_DARK",          "SATURATED",       "LOW_TEXTURE",
        "FEW_GROUND",        "GROUND_REJECTED", "STALE",
        "UNSYNCED",          "NOISY",           "BAD_INPUT",
        "GROUND_UNVERIFIED", "NEAR_UNSEEN"};
    bit_names(f, reasons, names, sizeof names / sizeof names[0]);
}

/* Signed value / div with `dec` decimals, without floating point. */
static void fixed(FILE *f, int64_t v, int64_t div, int dec)
{
    int64_t scale = dec == 1 ? 10 : dec == 2 ? 100 : 1000;
    int64_t a = v < 0 ? -v : v;
    int64_t q = (a * scale + div / 2) / div;
    fprintf(f, "%s%lld.%0*lld", v < 0 && q != 0 ? "-" : "",
            (long long)(q / scale), dec, (long long)(q % scale));
}

static void hazard_json(FILE *f, const negobs_hazard_t *h)
{
    static const char *const flags[] = {
        "CONFIRMED", "HELD", "H_LOWER", "CANNY", "GROUND_DROP", "TEXTURED"};
    fprintf(f,
            "{\"type\":\"%s\",\"level\":\"%s\",\"track\":%lu,\"range_mm\":%ld,"
            "\"lateral_mm\":%ld,\"bearing_deg\":",
            type_name(h->type), level_name(h->level),
            (unsigned long)h->track_id, (long)h->range_mm,
            (long)h->lateral_mm);
    fixed(f, h->bearing_mdeg, 1000, 1);
    fprintf(f, ",\"drop_mm\":%ld,\"box\":[%d,%d,%d,%d],\"confidence\":",
            (long)h->drop_mm, h->u0, h->v0, h->u1, h->v1);
    fixed(f, h->conf_q15, 32767, 3);
    fprintf(f, ",\"strips\":%d,\"flags\":", h->strips);
    bit_names(f, h->flags, flags, sizeof flags / sizeof flags[0]);
    fputc('}', f);
}

static void hazards_json(FILE *f, const char *key, const negobs_hazard_t *h,
                         uint32_t n)
{
    uint32_t k;
    fprintf(f, ",\"%s\":[", key);
    for (k = 0; k < n && k < NEGOBS_DETECT_MAX_HAZARDS; k++) {
        if (k > 0) {
            fputc(',', f);
        }
        hazard_json(f, &h[k]);
    }
    fputc(']', f);
}

/* negobs_png's fields from the library's result. */
static void library_json(FILE *f, const negobs_pipeline_result_t *r, int32_t w,
                         int32_t h)
{
    const negobs_detect_result_t *d = &r->detect;
    uint64_t npix = (uint64_t)w * (uint64_t)h;
    fprintf(f, ",\"stereo_status\":\"%s\",\"state\":\"%s\",\"reasons\":",
            negobs_status_str(r->stereo_status), state_name(d->state));
    reasons_json(f, d->reasons);
    fprintf(f,
            ",\"level\":\"%s\",\"nearest_range_mm\":%ld,\"clear_to_mm\":%ld,"
            "\"short_sight\":%ld,\"noise_vouch_mm\":%ld,\"range_near_mm\":%ld,"
            "\"pooled_permille\":%ld",
            level_name(d->level), (long)d->nearest_range_mm,
            (long)d->clear_to_mm, (long)d->short_sight,
            (long)d->noise_vouch_mm, (long)d->range_near_mm,
            (long)d->pooled_permille);
    fprintf(f, ",\"motor_on\":%ld,\"duty_permille\":%ld", (long)r->motor.on,
            (long)r->motor.duty_permille);
    hazards_json(f, "hazards", d->hazards, d->n_hazards);
    hazards_json(f, "candidates", d->candidates, d->n_candidates);
    fprintf(f, ",\"stereo\":{\"valid\":%lu,\"valid_pct\":",
            (unsigned long)r->stereo.valid);
    fixed(f, npix > 0 ? (int64_t)r->stereo.valid * 100 : 0,
          npix > 0 ? (int64_t)npix : 1, 1);
    fprintf(f,
            ",\"seeds\":%lu,\"range\":[%ld,%ld],\"vertical_offset\":%ld,"
            "\"first_row\":%ld},\"ground\":{\"valid\":%ld,"
            "\"valid_permille\":%ld,\"inliers\":%ld,\"sigma_px\":",
            (unsigned long)r->stereo.seeds, (long)r->stereo.range_min,
            (long)r->stereo.range_max, (long)r->stereo.vertical_offset,
            (long)r->stereo.first_row, (long)d->ground_valid,
            (long)d->ground_valid_permille, (long)d->ground_inliers);
    fixed(f, d->sigma_q4, 16, 3);
    fprintf(f, ",\"height_mm\":%ld,\"pitch_deg\":", (long)d->pose.height_mm);
    fixed(f, d->pose.pitch_mdeg, 1000, 2);
    fprintf(f,
            "},\"mount\":{\"height_mm\":%ld,\"pitch_mdeg\":%ld,"
            "\"roll_mdeg\":%ld,\"source\":\"%s\"}",
            (long)d->mount.height_mm, (long)d->mount.pitch_mdeg,
            (long)d->mount.roll_mdeg,
            d->mount.source == NEGOBS_MOUNT_CONFIG      ? "config"
            : d->mount.source == NEGOBS_MOUNT_ESTIMATED ? "estimated"
            : d->mount.source == NEGOBS_MOUNT_HELD      ? "held"
                                                        : "?");
    fprintf(f,
            ",\"ground_ref\":{\"by\":\"%s\",\"height_mm\":%ld,"
            "\"pitch_mdeg\":%ld}",
            app_ground_ref_name(d->ground_ref_by),
            (long)d->ground_ref_height_mm, (long)d->ground_ref_pitch_mdeg);
}

void json_log_pair(uint32_t index, uint64_t ts_left_ns, uint64_t ts_right_ns,
                   int32_t w, int32_t h, app_verdict_t v,
                   const app_pipeline_t *p, negobs_alert_pattern_t pattern,
                   const char *preset)
{
    FILE *f;
    const app_frame_stats_t *st = &p->last;
    long len;
    int rc;
    if (!json_on) {
        return;
    }
    f = fmemopen(json_line, sizeof json_line, "w");
    if (f == NULL) {
        return; /* no memory stream: this line only */
    }
    fprintf(f, "{\"frame\":%lu,\"file\":\"pair_%06lu\"", (unsigned long)index,
            (unsigned long)index);
    if (p->res_valid) {
        library_json(f, &p->res, w, h);
    } else {
        /* the image-quality gate answered before the library ran */
        fprintf(f, ",\"stereo_status\":\"not run\",\"state\":\"NO_INFO\","
                   "\"reasons\":[],\"level\":\"NONE\",\"nearest_range_mm\":-1,"
                   "\"clear_to_mm\":0,\"short_sight\":0,\"noise_vouch_mm\":0,"
                   "\"range_near_mm\":0,\"pooled_permille\":0,"
                   "\"motor_on\":0,\"duty_permille\":0,\"hazards\":[],"
                   "\"candidates\":[]");
    }
    fprintf(f, ",\"pattern\":\"%s\",\"ms\":{", pattern_name((int)pattern));
    if (st->stereo_us > 0u) {
        fputs("\"stereo\":", f);
        fixed(f, st->stereo_us, 1000, 2);
        fputc(',', f);
    }
    fprintf(f, "\"total\":%ld}", (long)st->latency_ms);
    fprintf(f,
            ",\"ts_left_ns\":%llu,\"ts_right_ns\":%llu,\"verdict\":\"%s\","
            "\"app_reason\":\"%s\",\"mean\":[%ld,%ld],"
            "\"texture_q4\":[%ld,%ld],\"preset\":\"%s\"}\n",
            (unsigned long long)ts_left_ns, (unsigned long long)ts_right_ns,
            app_verdict_name(v), app_reason_name(st->reason),
            (long)st->mean[0], (long)st->mean[1], (long)st->texture_q4[0],
            (long)st->texture_q4[1], preset);
    len = (fflush(f) == 0 && !ferror(f)) ? ftell(f) : -1;
    (void)fclose(f);
    if (len <= 0 || (size_t)len >= sizeof json_line - 1u ||
        json_line[len - 1] != '\n') {
        /* longer than the buffer (hundreds of candidates): not cut */
        json_out.dropped++;
        json_out.dropped_total++;
        return;
    }
    rc = app_logout_line(&json_out, json_line, (size_t)len);
    if (rc == 1 && json_out.dropped > 0u) {
        json_report_dropped();
    } else if (rc < 0) {
        logmsg(LOG_ERROR,
               "log-json: %s: write failed: %s; the log stops here, "
               "detection and alerting go on",
               json_path, strerror(json_out.err));
        (void)close(json_out.fd);
        json_on = false;
    }
}

/* ---- meta.txt ------------------------------------------------------- */

void session_meta_write(const char *dir, const app_pipeline_config_t *app)
{
    char path[320];
    int fd;
    FILE *f;
    uint32_t crc = 0;
    size_t bytes = 0;
    bool ok;
    /* the recorder makes the folder on its first pair; a failure here is
     * its to report (once), so say nothing */
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        return;
    }
    (void)snprintf(path, sizeof path, "%s/meta.txt", dir);
    /* negobs_recorder_check_dir() found no session here: a meta.txt left
     * by a run that recorded nothing is replaced */
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (f == NULL) {
        logmsg(LOG_WARN, "record: %s: %s; recording without it", path,
               strerror(errno));
        if (fd >= 0) {
            (void)close(fd);
        }
        return;
    }
    fprintf(f,
            "# negobs recorded-session metadata (docs/RUNNING.md)\n"
            "negobs_meta = 1\n"
            "negobs_version = %s\n",
            NEGOBS_VERSION_STRING);
    /* the geometry the detector used: the table's, else the config's */
    fprintf(f, "geometry_source = %s\n",
            calib_loaded()                                    ? "calib"
            : (run_cfg.focal_given && run_cfg.baseline_given) ? "config"
                                                              : "default");
    fprintf(f, "focal_q4 = %ld\nbaseline_um = %ld\ncx_q4 = %ld\ncy_q4 = %ld\n",
            (long)(app->focal_q4 > 0 ? app->focal_q4 : app->focal_px * 16),
            (long)(app->baseline_um > 0 ? app->baseline_um
                                        : app->baseline_mm * 1000),
            (long)app->cx_q4, (long)app->cy_q4);
    if (calib_loaded()) {
        calib_identity(&crc, &bytes);
        fprintf(f,
                "calib_file = %s\ncalib_crc32 = 0x%08lx\ncalib_bytes = %lu\n",
                run_cfg.calib, (unsigned long)crc, (unsigned long)bytes);
    } else {
        fprintf(f, "calib_file =\n");
    }
    fprintf(f, "# the run's settings (negobs_run --help lists the keys)\n");
    settings_write_prefixed(f, "config.");
    ok = fflush(f) == 0 && ferror(f) == 0;
    ok = (fclose(f) == 0) && ok;
    if (!ok) {
        logmsg(LOG_WARN, "record: %s: write failed: %s; recording without it",
               path, strerror(errno));
    }
}
