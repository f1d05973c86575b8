/* negobs_run's main loop: pairs -> pipeline -> alert -> motor thread,
 * the recording, status lines and the summary. */
#define _POSIX_C_SOURCE 200809L

#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "negobs/status.h"
#include "negobs_port/clock.h"
#include "negobs_port/pool.h"
#include "negobs_port/record_queue.h"
#include "app_mount.h"
#include "run_app.h"

static app_pipeline_t pipeline;
static app_alert_t alert_sm;
static app_mount_keep_t mount_keep;
static bool mount_fail_logged;

/* Start from the remembered mounting (app_mount.h) when there is one: it
 * replaces the configured hints. A missing file is the first run; a bad
 * one is reported and ignored: it is a hint, the detector still measures
 * the mounting and verifies the start. */
static void mount_recall(void)
{
    char msg[384];
    int32_t h = 0;
    int32_t p = 0;
    int rc;
    memset(&mount_keep, 0, sizeof mount_keep);
    mount_fail_logged = false;
    if (run_cfg.mount_file[0] == '\0') {
        return;
    }
    rc = app_mount_load(run_cfg.mount_file, &h, &p, msg, sizeof msg);
    if (rc > 0) {
        run_cfg.app.cam_height_mm = h;
        run_cfg.app.cam_pitch_mdeg = p;
        mount_keep.have = 1;
        mount_keep.height_mm = h;
        mount_keep.pitch_mdeg = p;
        logmsg(LOG_INFO, "mounting hint from %s: %ld mm, %ld mdeg",
               run_cfg.mount_file, (long)h, (long)p);
    } else if (rc == 0) {
        logmsg(LOG_INFO, "no remembered mounting in %s yet: hint %ld mm",
               run_cfg.mount_file, (long)run_cfg.app.cam_height_mm);
    } else {
        logmsg(LOG_WARN, "remembered mounting ignored: %s", msg);
    }
}

/* A save runs on a short-lived thread of its own: a card busy with
 * writeback (a recording on the same card) can hold even a 100-byte
 * write or rename for seconds, and the verdicts never wait for an
 * optional output. One save at a time; its result is taken on a later
 * pair (or when the loop ends) and logged then. */
typedef struct mount_job {
    pthread_t thread;
    bool running; /* started, not yet joined */
    pthread_mutex_t lock;
    bool done; /* under lock: the save returned */
    int rc;
    int32_t by;
    int32_t height_mm;
    int32_t pitch_mdeg;
    uint32_t started_ms;
    char msg[384];
} mount_job_t;
static mount_job_t mount_job = {.lock = PTHREAD_MUTEX_INITIALIZER};

static void *mount_save_main(void *arg)
{
    mount_job_t *j = arg;
    int rc = app_mount_save(run_cfg.mount_file, j->height_mm, j->pitch_mdeg,
                            j->msg, sizeof j->msg);
    (void)pthread_mutex_lock(&j->lock);
    j->rc = rc;
    j->done = true;
    (void)pthread_mutex_unlock(&j->lock);
    return NULL;
}

/* The result of the save (j->rc, j->msg), kept and logged. */
static void mount_report(void)
{
    mount_job_t *j = &mount_job;
    if (j->rc == 0) {
        app_mount_saved(&mount_keep, j->height_mm, j->pitch_mdeg,
                        j->started_ms);
        mount_fail_logged = false;
        logmsg(LOG_INFO, "mounting remembered (%s): %ld mm, %ld mdeg",
               app_ground_ref_name(j->by), (long)j->height_mm,
               (long)j->pitch_mdeg);
        return;
    }
    /* try again after the save interval, quietly */
    app_mount_failed(&mount_keep, j->started_ms);
    if (!mount_fail_logged) {
        logmsg(LOG_WARN, "cannot remember the mounting: %s", j->msg);
        mount_fail_logged = true;
    }
}

/* At the end of the run a save in flight gets this long to finish; a
 * card (or a FIFO put in the file's place) that holds it longer does not
 * hold up the exit: the old file then stays, untouched (the save writes
 * a temporary file and renames it). */
#define MOUNT_EXIT_WAIT_MS 2000u

/* Take the result of the save in flight once it is done, waiting up to
 * wait_ms for it. */
static void mount_collect(uint32_t wait_ms)
{
    mount_job_t *j = &mount_job;
    uint64_t until = negobs_clock_now_ms() + wait_ms;
    bool done;
    if (!j->running) {
        return;
    }
    for (;;) {
        (void)pthread_mutex_lock(&j->lock);
        done = j->done;
        (void)pthread_mutex_unlock(&j->lock);
        if (done || negobs_clock_now_ms() >= until) {
            break;
        }
        negobs_clock_sleep_ms(10);
    }
    if (!done) {
        if (wait_ms > 0u) {
            (void)pthread_detach(j->thread);
            j->running = false;
            logmsg(LOG_WARN,
                   "cannot remember the mounting: %s still not written "
                   "after %u ms; the old one stays",
                   run_cfg.mount_file, (unsigned)wait_ms);
        }
        return;
    }
    (void)pthread_join(j->thread, NULL);
    j->running = false;
    mount_report();
}

/* Keep the ground under the feet once the detector established it with
 * evidence; a failed write is logged once and never stops the warnings. */
static void mount_remember(uint32_t now_ms)
{
    mount_job_t *j = &mount_job;
    const app_frame_stats_t *st = &pipeline.last;
    if (run_cfg.mount_file[0] == '\0') {
        return;
    }
    mount_collect(0u);
    if (j->running || !app_mount_due(&mount_keep, st->ground_ref_by,
                                     st->ground_ref_height_mm,
                                     st->ground_ref_pitch_mdeg, now_ms)) {
        return;
    }
    j->by = st->ground_ref_by;
    j->height_mm = st->ground_ref_height_mm;
    j->pitch_mdeg = st->ground_ref_pitch_mdeg;
    j->started_ms = now_ms;
    j->done = false;
    j->rc = -1;
    (void)snprintf(j->msg, sizeof j->msg, "%s", "no thread for the save");
    if (run_thread_start(&j->thread, mount_save_main, j) != 0) {
        mount_report(); /* rc -1, "no thread for the save" */
        return;
    }
    j->running = true;
}

/* The matcher's stage clock: monotonic ns modulo 2^32 (it takes
 * differences of successive reads). */
static uint32_t stage_clock_ns(void *user)
{
    (void)user;
    return (uint32_t)negobs_clock_now_ns();
}

int loop_setup(negobs_motor_schedule_t *noinfo_sched)
{
    /* The detector must accept every pair the capture layer pairs. */
    run_cfg.app.sync_tol_ms = run_cfg.pair_tol_ms;
    run_cfg.app.vertical_align = run_cfg.vertical_align ? 1 : 0;
    run_cfg.app.row_crop = run_cfg.row_crop ? 1 : 0;
    run_cfg.app.threads = run_cfg.threads > 0 ? run_cfg.threads
                                              : negobs_pool_online_cores();
    mount_recall();
    if (app_pipeline_init(&pipeline, &run_cfg.app) != NEGOBS_OK) {
        if (calib_loaded()) {
            fprintf(stderr,
                    "negobs_run: calibration table %s refused: its "
                    "geometry is outside the detector's range\n",
                    run_cfg.calib);
            return EXIT_CALIB;
        }
        fprintf(stderr, "negobs_run: bad image-quality thresholds\n");
        return EXIT_CONFIG;
    }
    if (run_log_level >= LOG_DEBUG) {
        /* where the matcher's time goes, on the device itself */
        app_pipeline_set_clock(&pipeline, stage_clock_ns, NULL);
    }
    /* One staleness limit: the library's and the watchdog's. */
    run_cfg.alert_cfg.stale_ms = run_cfg.watchdog_ms;
    run_cfg.alert_cfg.binary_mode = run_cfg.alert_binary ? 1 : 0;
    if (app_alert_init(&alert_sm, &run_cfg.alert_cfg) != NEGOBS_OK ||
        app_alert_noinfo_schedule(&run_cfg.alert_cfg, 0u, noinfo_sched) !=
            NEGOBS_OK) {
        fprintf(stderr, "negobs_run: bad alert settings (caution_mid_mm "
                        "must not exceed caution_far_mm; heartbeat_period_ms "
                        "0 or 1000..60000, heartbeat_pulse_ms 80 .. a quarter "
                        "of it)\n");
        return EXIT_CONFIG;
    }
    return -1;
}

void alert_restart(void)
{
    negobs_alert_config_t c = run_cfg.alert_cfg;
    c.ready_on_start = 0;
    (void)app_alert_init(&alert_sm, &c); /* checked by loop_setup() */
}

negobs_alert_pattern_t alert_pattern_now(void)
{
    return app_alert_pattern(&alert_sm);
}

/* ---- alert ---------------------------------------------------------- */

/* Advance the library's alert state machine (NULL: no new verdict) and
 * hand the motor thread what it should play from now on. */
void alert_post(const negobs_alert_input_t *in)
{
    negobs_alert_pattern_t before = NEGOBS_PATTERN_NONE;
    if (app_alert_post(&alert_sm, &run_motor, in, &before) != NEGOBS_OK) {
        return; /* cannot happen after a successful init */
    }
    if (app_alert_pattern(&alert_sm) != before) {
        logmsg(LOG_INFO, "pattern %s -> %s", app_alert_pattern_name(before),
               app_alert_pattern_name(app_alert_pattern(&alert_sm)));
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
    uint32_t verdicts[4]; /* pairs per verdict over the whole run */
} run_status_t;

/* negobs_mount_source_t as the log writes it. */
static const char *mount_source_name(int32_t source)
{
    static const char *const names[] = {"config", "estimated", "held"};
    return (source >= 0 && source < 3) ? names[source] : "?";
}

static void status_line(run_status_t *st, uint64_t now)
{
    negobs_capture_stats_t cs;
    uint64_t span = now - st->window_start_ms;
    unsigned long fps10 = span > 0 ? (unsigned long)((uint64_t)st->pairs *
                                                     10000u / span)
                                   : 0;
    unsigned long lat = st->pairs > 0 ? (unsigned long)(st->lat_sum_us /
                                                        st->pairs / 100u)
                                      : 0;
    negobs_capture_get_stats(&run_camera, &cs);
    logmsg(LOG_INFO,
           "status fps=%lu.%lu latency_ms=%lu.%lu max=%lu dropped=%lu "
           "timeouts=%lu reopens=%lu verdict=%s reason=%s mean=%ld/%ld "
           "texture_q4=%ld/%ld watchdog=%lu pattern=%s mount=%ld/%ld/%ld/%s",
           fps10 / 10u, fps10 % 10u, lat / 10u, lat % 10u,
           (unsigned long)(st->lat_max_us / 1000u),
           (unsigned long)cs.dropped_pairs, (unsigned long)cs.timeouts,
           (unsigned long)cs.reopens, app_verdict_name(st->verdict),
           app_reason_name(pipeline.last.reason), (long)pipeline.last.mean[0],
           (long)pipeline.last.mean[1], (long)pipeline.last.texture_q4[0],
           (long)pipeline.last.texture_q4[1],
           (unsigned long)negobs_motor_thread_watchdog_fires(&run_motor),
           app_alert_pattern_name(app_alert_pattern(&alert_sm)),
           (long)pipeline.last.mount.height_mm,
           (long)pipeline.last.mount.pitch_mdeg,
           (long)pipeline.last.mount.roll_mdeg,
           mount_source_name(pipeline.last.mount.source));
    st->window_start_ms = now;
    st->next_ms = now + (uint64_t)run_cfg.status_interval_ms;
    st->pairs = 0;
    st->lat_sum_us = 0;
    st->lat_max_us = 0;
}

/* Motor output faults (the motor thread retries and plays no-info;
 * port/alert): say when writes start failing and when they work again. */
static void check_motor_output(bool *was_failing)
{
    bool failing = false;
    uint32_t faults = negobs_motor_thread_output_faults(&run_motor, &failing);
    char why[NEGOBS_PORT_ERRMSG_LEN];
    /* the motor thread writes the backend's message: copy under its lock */
    negobs_motor_thread_copy_msg(&run_motor, alert_errmsg(), why, sizeof why);
    if (failing && !*was_failing) {
        logmsg(LOG_WARN,
               "motor: output failing (%s), retrying; no-info "
               "once it is back (fault %lu)",
               why, (unsigned long)faults);
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
static uint8_t
    rec_buf[APP_RECORD_SLOTS * 2u * NEGOBS_RUN_MAX_W * NEGOBS_RUN_MAX_H];
static negobs_record_queue_t recq;
static char record_refused[NEGOBS_PORT_ERRMSG_LEN];
static bool record_fail_logged;

static void record_summary(char *out, size_t len);

/* Before anything runs: an existing session is never recorded over. The
 * refusal stops the recording only; the device still warns. */
void record_start(void)
{
    char why[NEGOBS_PORT_ERRMSG_LEN];
    if (run_cfg.record[0] == '\0') {
        return;
    }
    if (negobs_recorder_check_dir(run_cfg.record, why, sizeof why) !=
        NEGOBS_OK) {
        (void)snprintf(record_refused, sizeof record_refused, "%s", why);
        logmsg(LOG_ERROR, "record: %s; running without recording", why);
        return;
    }
    if (negobs_recq_start(&recq, run_cfg.record, rec_buf,
                          2u * NEGOBS_RUN_MAX_W * NEGOBS_RUN_MAX_H,
                          APP_RECORD_SLOTS) != NEGOBS_OK) {
        (void)snprintf(record_refused, sizeof record_refused,
                       "cannot start the recording thread");
        logmsg(LOG_ERROR, "record: %s; running without recording",
               record_refused);
        return;
    }
    logmsg(LOG_INFO, "recording to %s", run_cfg.record);
    session_meta_write(run_cfg.record, &run_cfg.app);
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
        logmsg(LOG_ERROR,
               "record: stopped: %s (%lu pairs recorded); "
               "detection and alerting go on",
               rs.errmsg, (unsigned long)rs.written);
    }
}

void record_stop(void)
{
    char rec[NEGOBS_PORT_ERRMSG_LEN + 64];
    bool was_running = recq.running;
    negobs_recq_stop(&recq);
    if (was_running) {
        /* the summary line is written while the writer may still drain its
         * queue; this is the count once every queued pair is on the card */
        record_summary(rec, sizeof rec);
        logmsg(LOG_INFO, "record: closed, %s", rec);
    }
}

/* "record=off", "record=recording written=.. dropped=..", ... */
static void record_summary(char *out, size_t len)
{
    negobs_recq_stats_t rs;
    if (run_cfg.record[0] == '\0') {
        (void)snprintf(out, len, "record=off");
        return;
    }
    if (record_refused[0] != '\0') {
        (void)snprintf(out, len, "record=refused (%s)", record_refused);
        return;
    }
    negobs_recq_stats(&recq, &rs);
    (void)snprintf(out, len, "record=%s written=%lu dropped=%lu%s%s%s",
                   negobs_recq_state_name(rs.state), (unsigned long)rs.written,
                   (unsigned long)(rs.dropped + rs.discarded),
                   rs.state == NEGOBS_RECQ_FAILED ? " (" : "",
                   rs.state == NEGOBS_RECQ_FAILED ? rs.errmsg : "",
                   rs.state == NEGOBS_RECQ_FAILED ? ")" : "");
}

static void log_summary(uint32_t done, const run_status_t *st)
{
    negobs_capture_stats_t cs;
    char rec[NEGOBS_PORT_ERRMSG_LEN + 64];
    negobs_capture_get_stats(&run_camera, &cs);
    record_summary(rec, sizeof rec);
    logmsg(LOG_INFO,
           "summary pairs=%lu no-info=%lu clear=%lu caution=%lu "
           "imminent=%lu last_reason=%s dropped=%lu timeouts=%lu "
           "log_dropped=%lu json_dropped=%lu notify_dropped=%lu %s",
           (unsigned long)done, (unsigned long)st->verdicts[0],
           (unsigned long)st->verdicts[1], (unsigned long)st->verdicts[2],
           (unsigned long)st->verdicts[3],
           app_reason_name(pipeline.last.reason),
           (unsigned long)cs.dropped_pairs, (unsigned long)cs.timeouts,
           log_lines_dropped(), json_lines_dropped(), service_notify_dropped(),
           rec);
}

/* Once per frame size (and whenever it changes): the threads and the
 * memory profile the matcher runs with, which depend on what the static
 * workspace holds at that size (app_pipeline.c). */
static void log_matcher_setup(const app_frame_stats_t *st,
                              const negobs_image_u8_t *img)
{
    static int32_t logged_w;
    static int32_t logged_h;
    static int32_t logged_threads;
    if (st->matcher_threads <= 0 ||
        (img->width == logged_w && img->height == logged_h &&
         st->matcher_threads == logged_threads)) {
        return;
    }
    logged_w = img->width;
    logged_h = img->height;
    logged_threads = st->matcher_threads;
    logmsg(LOG_INFO, "matcher at %ldx%ld: %ld thread(s), %s memory profile",
           (long)img->width, (long)img->height, (long)st->matcher_threads,
           st->memory_profile == NEGOBS_STEREO_PROFILE_FAST
               ? "fast (growth memo)"
               : "compact");
}

/* One pair: [rectify] -> pipeline -> latency gate -> alert; the pair is
 * released here. -1 to go on, else an exit code. */
static int judge_pair(negobs_frame_pair_t *pair, uint64_t now, uint32_t done,
                      run_status_t *st)
{
    app_verdict_t v;
    uint64_t lat_us;
    negobs_alert_input_t in;
    const negobs_image_u8_t *img_l = &pair->left.y;
    const negobs_image_u8_t *img_r = &pair->right.y;
    negobs_image_u8_t rect_l;
    negobs_image_u8_t rect_r;
    record_pair(pair);
    if (calib_loaded()) {
        int erc = rectify_pair(img_l, img_r, &rect_l, &rect_r);
        if (erc != 0) {
            negobs_capture_release(&run_camera, pair);
            return erc;
        }
        img_l = &rect_l;
        img_r = &rect_r;
    }
    v = app_process_pair_at(
        &pipeline, img_l, img_r, (uint32_t)(pair->left.ts_ns / 1000000u),
        (uint32_t)(pair->right.ts_ns / 1000000u), (uint32_t)now);
    {
        /* the verdict is about the moment of capture: a clear one
         * that took too long to reach is not trusted */
        uint64_t t_done = negobs_clock_now_ns();
        uint64_t age_ms = (t_done > pair->left.ts_ns)
                              ? (t_done - pair->left.ts_ns) / 1000000u
                              : 0u;
        v = app_pipeline_latency_gate(
            &pipeline, v, (int32_t)((age_ms > 600000u) ? 600000u : age_ms));
    }
    v = button_filter(v, &pipeline.last);
    app_alert_input(v, &pipeline.last, 0u, &in);
    if (!button_confirming()) {
        alert_post(&in);
    }
    /* after the post: the pattern this verdict set */
    json_log_pair(done, pair->left.ts_ns, pair->right.ts_ns, img_l->width,
                  img_l->height, v, &pipeline, alert_pattern_now(),
                  button_preset_name());
    mount_remember((uint32_t)now);
    log_matcher_setup(&pipeline.last, img_l);
    logmsg(LOG_DEBUG, "pair %lu verdict %s first_row %ld", (unsigned long)done,
           app_verdict_name(v), (long)pipeline.last.first_row);
    if (run_log_level >= LOG_DEBUG && pipeline.last.stereo_us > 0u) {
        const uint32_t *us = pipeline.last.stage_us;
        logmsg(LOG_DEBUG,
               "stage times of pair %lu: stereo_us %lu (gcs %lu dp %lu "
               "other %lu)",
               (unsigned long)done, (unsigned long)pipeline.last.stereo_us,
               (unsigned long)us[NEGOBS_STEREO_STAGE_GCS],
               (unsigned long)us[NEGOBS_STEREO_STAGE_DP],
               (unsigned long)(pipeline.last.stereo_us -
                               us[NEGOBS_STEREO_STAGE_GCS] -
                               us[NEGOBS_STEREO_STAGE_DP]));
    }
    lat_us = (negobs_clock_now_ns() - pair->left.ts_ns) / 1000u;
    negobs_capture_release(&run_camera, pair);
    if (v != st->verdict) {
        /* For "detector", say which NEGOBS_DEGRADED_* bits
         * (negobs/detect.h) made it blind: stale or unsynced
         * frames read very differently from a bad ground fit. */
        if (pipeline.last.reason == APP_REASON_DETECTOR) {
            logmsg(LOG_INFO, "verdict %s -> %s (detector 0x%lx)",
                   app_verdict_name(st->verdict), app_verdict_name(v),
                   (unsigned long)pipeline.last.detect_reasons);
        } else {
            logmsg(LOG_INFO, "verdict %s -> %s (%s)",
                   app_verdict_name(st->verdict), app_verdict_name(v),
                   app_reason_name(pipeline.last.reason));
        }
    }
    st->verdict = v;
    st->verdicts[v & 3]++;
    st->pairs++;
    st->lat_sum_us += lat_us;
    if (lat_us > st->lat_max_us) {
        st->lat_max_us = lat_us;
    }
    return -1;
}

static int run_pairs(void);

int run_loop(void)
{
    int rc = run_pairs();
    mount_collect(MOUNT_EXIT_WAIT_MS); /* a save in flight, then said */
    return rc;
}

static int run_pairs(void)
{
    run_status_t st;
    negobs_frame_pair_t pair;
    uint32_t done = 0;
    int last_err = NEGOBS_OK;
    bool motor_failing = false;
    bool paused = false;
    memset(&st, 0, sizeof st);
    st.window_start_ms = negobs_clock_now_ms();
    st.next_ms = st.window_start_ms + (uint64_t)run_cfg.status_interval_ms;
    st.verdict = APP_VERDICT_NO_INFO;

    while (!run_stop_requested) {
        uint64_t now;
        int rc = negobs_capture_get_pair(&run_camera, &pair,
                                         run_cfg.watchdog_ms);
        now = negobs_clock_now_ms();
        paused = button_poll();
        if (rc == NEGOBS_OK && paused) {
            /* taken, not judged: the cameras and this loop are alive */
            negobs_capture_release(&run_camera, &pair);
            service_pair_done();
        } else if (rc == NEGOBS_OK) {
            int erc = judge_pair(&pair, now, done, &st);
            if (erc >= 0) {
                return erc;
            }
            service_pair_done();
            last_err = NEGOBS_OK;
            done++;
            if (run_cfg.frames > 0 && done >= (uint32_t)run_cfg.frames) {
                logmsg(LOG_INFO, "%lu pairs processed", (unsigned long)done);
                break;
            }
        } else if (rc == NEGOBS_CAPTURE_END) {
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
            if (!paused && !button_confirming()) {
                alert_post(&in);
            }
            if (rc != last_err) {
                logmsg(LOG_WARN, "camera: %s%s%s",
                       negobs_status_str((negobs_status_t)rc),
                       negobs_capture_errmsg(&run_camera)[0] != '\0' ? ": "
                                                                     : "",
                       negobs_capture_errmsg(&run_camera));
            }
            if (st.verdict != APP_VERDICT_NO_INFO) {
                logmsg(LOG_INFO, "verdict %s -> no-info (camera)",
                       app_verdict_name(st.verdict));
            }
            st.verdict = APP_VERDICT_NO_INFO;
            last_err = rc;
        } else {
            logmsg(LOG_ERROR, "camera: %s (%s)",
                   negobs_capture_errmsg(&run_camera),
                   camera_status_words(rc));
            log_summary(done, &st);
            return EXIT_RUNTIME;
        }
        check_motor_output(&motor_failing);
        if (now >= st.next_ms) {
            status_line(&st, now);
        }
    }
    if (run_stop_requested) {
        logmsg(LOG_INFO, "stop requested (%s), shutting down",
               signal_name((int)run_stop_signal));
    }
    log_summary(done, &st);
    if (run_stop_requested && !is_stop_request((int)run_stop_signal)) {
        return 128 + (int)run_stop_signal;
    }
    return EXIT_OK;
}
