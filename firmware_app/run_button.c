/*
 * negobs_run's push button: a thread samples the GPIO line every
 * APP_BUTTON_POLL_MS and classifies presses (app_button.h); the main loop
 * applies them between pairs (button_poll()).
 *
 *   long press   pause / resume. Paused, pairs are still taken from the
 *                cameras (so the watchdogs stay fed and a lost camera is
 *                still noticed) but not judged; the motor plays one short
 *                reminder pulse every APP_PAUSED_PERIOD_MS, so a paused
 *                device never feels like a dead one or a clear path.
 *   short press  next sensitivity preset:
 *                  0 "all"       every warning (the default);
 *                  1 "near"      cautions only nearer than caution_mid_mm;
 *                  2 "imminent"  imminent warnings only.
 *                Presets quiet far cautions in a crowd; they never hide an
 *                imminent warning nor the no-information pattern.
 *
 * Each press is confirmed on the motor, with patterns no alert uses (the
 * alert patterns are 80-200 ms pulses, docs/RUNNING.md "Motor patterns"):
 *   pause     one 700 ms pulse;
 *   resume    two 300 ms pulses;
 *   preset N  N+1 pulses of 120 ms, 180 ms apart (1, 2 or 3).
 * A confirmation ends in the no-information loop: if the main loop died
 * while it played, the wearer is told, never left in silence. Verdicts
 * wait until it has played (button_confirming()).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "app_button.h"
#include "negobs_port/clock.h"
#include "negobs_port/input.h"
#include "run_app.h"

static negobs_input_gpio_t button_in;
/* button = file:PATH: the first byte of PATH, '1' pressed (a developer
 * aid, as replay is for cameras: tests press it from a script) */
static char button_file[sizeof run_cfg.button];
static char button_file_err[NEGOBS_INPUT_ERRMSG_LEN];
static app_button_t button_sm;
static pthread_t button_thread;
static pthread_mutex_t button_lock = PTHREAD_MUTEX_INITIALIZER;
static bool button_running;
static volatile bool button_quit;
static uint32_t shorts_pending;
static uint32_t longs_pending;
static int button_errno_seen; /* read failure the main loop logs once */
static char button_err[NEGOBS_INPUT_ERRMSG_LEN];

static bool paused;
static int32_t preset;
static uint64_t confirm_until_ms;
static negobs_motor_schedule_t noinfo_tail;

static int read_file_level(void)
{
    char c = '0';
    FILE *f = fopen(button_file, "r");
    if (f == NULL) {
        (void)snprintf(button_file_err, sizeof button_file_err, "%.100s: %s",
                       button_file, strerror(errno));
        return NEGOBS_ERR_IO;
    }
    if (fread(&c, 1, 1, f) != 1) {
        c = '0';
    }
    (void)fclose(f);
    return c == '1' ? 1 : 0;
}

static void *button_main(void *arg)
{
    uint64_t next = negobs_clock_now_ms();
    (void)arg;
    while (!button_quit) {
        int v = button_file[0] != '\0' ? read_file_level()
                                       : negobs_input_gpio_read(&button_in);
        app_button_event_t ev = APP_BUTTON_NONE;
        if (v >= 0) {
            ev = app_button_sample(&button_sm, v, (uint32_t)next);
        }
        (void)pthread_mutex_lock(&button_lock);
        if (v < 0 && button_errno_seen == 0) {
            button_errno_seen = 1;
            (void)snprintf(button_err, sizeof button_err, "%s",
                           button_file[0] != '\0' ? button_file_err
                                                  : button_in.errmsg);
        }
        if (ev == APP_BUTTON_SHORT) {
            shorts_pending++;
        } else if (ev == APP_BUTTON_LONG) {
            longs_pending++;
        }
        (void)pthread_mutex_unlock(&button_lock);
        /* a failing line is tried again once a second */
        next += v < 0 ? 1000u : APP_BUTTON_POLL_MS;
        negobs_clock_sleep_until_ns(next * 1000000u, NULL);
    }
    return NULL;
}

void button_start(const negobs_motor_schedule_t *noinfo)
{
    char kind[16];
    char chip[64];
    char line[16];
    uint32_t off = 0;
    preset = run_cfg.sensitivity;
    noinfo_tail = *noinfo;
    if (run_cfg.button[0] == '\0') {
        return;
    }
    app_button_init(&button_sm, (uint32_t)run_cfg.button_long_ms);
    if (strncmp(run_cfg.button, "file:", 5) == 0) {
        size_t n = strlen(run_cfg.button + 5); /* < sizeof button_file */
        memcpy(button_file, run_cfg.button + 5, n + 1u);
    } else {
        (void)split_spec(run_cfg.button, kind, sizeof kind, chip, sizeof chip,
                         line, sizeof line);
        (void)parse_u32(line, &off);
    }
    if (button_file[0] == '\0' &&
        negobs_input_gpio_open(&button_in, chip, off,
                               run_cfg.button_active_low) != NEGOBS_OK) {
        logmsg(LOG_ERROR, "button %s: %s; running without the button",
               run_cfg.button, button_in.errmsg);
        return;
    }
    button_quit = false;
    button_running = run_thread_start(&button_thread, button_main, NULL) == 0;
    if (!button_running) {
        negobs_input_gpio_close(&button_in);
        logmsg(LOG_ERROR, "button: cannot start its thread; running "
                          "without the button");
        return;
    }
    logmsg(LOG_INFO, "button: %s (%s, long press %ld ms)%s", run_cfg.button,
           run_cfg.button_active_low ? "pressed = low" : "pressed = high",
           (long)run_cfg.button_long_ms,
           (button_file[0] != '\0' || button_in.biased)
               ? ""
               : "; no internal pull resistor");
}

void button_stop(void)
{
    if (button_running) {
        button_quit = true;
        (void)pthread_join(button_thread, NULL);
        button_running = false;
    }
    negobs_input_gpio_close(&button_in);
}

/* Play a confirmation; verdicts (or the paused pattern) take over 50 ms
 * into its closing gap, before the no-information tail could start. */
static void confirm(app_button_confirm_t kind)
{
    negobs_motor_schedule_t s;
    uint32_t ms = 0;
    if (app_button_confirm_schedule(
            kind, preset, (uint16_t)run_cfg.alert_cfg.intensity_permille,
            &noinfo_tail, &s, &ms) != NEGOBS_OK) {
        return; /* cannot happen: the tail is the checked no-info schedule */
    }
    negobs_motor_thread_post_restart(&run_motor, &s);
    confirm_until_ms = negobs_clock_now_ms() + ms - (APP_CONFIRM_GAP_MS - 50u);
}

/* Silence with a reminder pulse, looped: what a paused device plays. */
static void post_paused(void)
{
    negobs_motor_schedule_t s;
    app_button_paused_schedule((uint16_t)run_cfg.alert_cfg.intensity_permille,
                               &s);
    negobs_motor_thread_post(&run_motor, &s);
}

static const char *const preset_names[APP_PRESET_COUNT] = {"all", "near",
                                                           "imminent"};

const char *button_preset_name(void)
{
    return preset_names[preset >= 0 && preset < APP_PRESET_COUNT ? preset : 0];
}

bool button_poll(void)
{
    uint32_t shorts;
    uint32_t longs;
    int err_new;
    (void)pthread_mutex_lock(&button_lock);
    shorts = shorts_pending;
    longs = longs_pending;
    shorts_pending = longs_pending = 0;
    err_new = button_errno_seen == 1;
    if (err_new) {
        button_errno_seen = 2; /* logged; not again */
    }
    (void)pthread_mutex_unlock(&button_lock);
    if (err_new) {
        logmsg(LOG_ERROR, "button: %s; retrying every second", button_err);
    }
    for (; longs > 0u; longs--) {
        paused = !paused;
        logmsg(LOG_INFO, "button: long press: %s",
               paused ? "paused" : "resumed");
        service_status(paused ? "paused by the wearer" : "judging pairs");
        if (paused) {
            confirm(APP_CONFIRM_PAUSE);
        } else {
            alert_restart();
            confirm(APP_CONFIRM_RESUME);
        }
    }
    for (; shorts > 0u; shorts--) {
        preset = (preset + 1) % APP_PRESET_COUNT;
        logmsg(LOG_INFO, "button: short press: sensitivity preset %ld (%s)",
               (long)preset, button_preset_name());
        confirm(APP_CONFIRM_PRESET);
    }
    if (paused && !button_confirming()) {
        post_paused();
    }
    return paused;
}

bool button_confirming(void)
{
    return negobs_clock_now_ms() < confirm_until_ms;
}

app_verdict_t button_filter(app_verdict_t v, const app_frame_stats_t *st)
{
    return app_button_filter(preset, v, st->nearest_range_mm,
                             run_cfg.alert_cfg.band_mid_mm);
}
