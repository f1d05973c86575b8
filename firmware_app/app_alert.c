/*
 * The library's alert state machine as motor-thread schedules (see the
 * header). The look-ahead copies the library context (a plain struct) and
 * calls negobs_alert_update() at each cmd.next_change_ms with no input, so
 * it follows the library's own rules: priorities, minimum pulse, the gap
 * between patterns, the IMMINENT hold, stale_ms -> no-information.
 */
#include <string.h>

#include "app_alert.h"
#include "negobs_port/clock.h"

/* Segments collected before giving up on finding the looped tail. */
#define APP_ALERT_MAX_SEG NEGOBS_MOTOR_MAX_SEGMENTS
/* Library calls per look-ahead; idle wake-ups come every 1000 ms, so the
 * horizon needs about 20 plus two per segment. */
#define APP_ALERT_MAX_CALLS 256

typedef struct sim_seg {
    uint32_t start_ms;
    uint32_t dur_ms;
    uint16_t duty;
    negobs_alert_pattern_t pat;
} sim_seg_t;

static int32_t since(uint32_t now, uint32_t then)
{
    return (int32_t)(now - then);
}

static uint16_t duty_of(const negobs_motor_cmd_t *c)
{
    return c->on ? (uint16_t)c->duty_permille : 0u;
}

static void to_schedule(const sim_seg_t *s, int32_t n, int32_t loop,
                        negobs_motor_schedule_t *out)
{
    int32_t i;
    memset(out, 0, sizeof *out);
    for (i = 0; i < n; i++) {
        uint32_t d = s[i].dur_ms;
        out->seg[i].duty_permille = s[i].duty;
        out->seg[i].duration_ms = (uint16_t)(d > 65535u ? 65535u : d);
    }
    out->count = (uint8_t)n;
    out->loop_start = loop >= 0 ? (uint8_t)loop : NEGOBS_MOTOR_NO_LOOP;
}

/*
 * Run `sim` (a copy) forward from `now`, where it commanded `c0`, with no
 * new verdict, until the settled no-information pulse (then its on + off
 * is the loop). Returns the number of complete segments in s, *loop the
 * loop start or -1 when the budget or the horizon ran out first.
 */
static int32_t simulate(negobs_alert_t *sim, const negobs_motor_cmd_t *c0,
                        uint32_t now, sim_seg_t *s, int32_t *loop_out)
{
    negobs_motor_cmd_t c = *c0;
    int32_t n = 0; /* complete segments */
    int32_t loop = -1;
    int32_t calls;
    int32_t noinfo_on = -1;
    s[0].start_ms = now;
    s[0].duty = duty_of(&c);
    s[0].pat = c.pattern;
    for (calls = 0; calls < APP_ALERT_MAX_CALLS; calls++) {
        uint32_t t = c.next_change_ms;
        if (since(t, now) > (int32_t)APP_ALERT_HORIZON_MS) {
            break;
        }
        (void)negobs_alert_update(sim, t, NULL, &c);
        if (duty_of(&c) == s[n].duty) {
            continue;
        }
        s[n].dur_ms = t - s[n].start_ms;
        n++;
        if (noinfo_on >= 0 && n == noinfo_on + 2) {
            loop = noinfo_on; /* the repeating no-info pulse and its gap */
            break;
        }
        if (n == APP_ALERT_MAX_SEG) {
            break;
        }
        s[n].start_ms = t;
        s[n].duty = duty_of(&c);
        s[n].pat = c.pattern;
        /* Without verdicts nothing outranks the repeating no-info pulse
         * once it has begun: it is the end state. */
        if (noinfo_on < 0 && c.pattern == NEGOBS_PATTERN_NO_INFO && c.on) {
            noinfo_on = n;
        }
    }
    *loop_out = loop;
    return n;
}

static void look_ahead(negobs_alert_t *sim, const negobs_motor_cmd_t *c0,
                       uint32_t now, negobs_motor_schedule_t *out)
{
    sim_seg_t s[APP_ALERT_MAX_SEG + 1];
    negobs_alert_config_t cfg = sim->cfg;
    negobs_motor_schedule_t tail;
    int32_t loop = -1;
    int32_t n = simulate(sim, c0, now, s, &loop);
    int32_t i;
    if (loop >= 0) {
        to_schedule(s, n, loop, out);
        return;
    }
    /*
     * The library would still be playing its current pattern at the end
     * of the segment budget (a stale_ms of several seconds): play what
     * fits, then the no-information pattern at once. Earlier than the
     * library would say it, but never silent and never a hazard pattern
     * that outlives its verdict; the next verdict replaces it anyway.
     */
    if (app_alert_noinfo_schedule(&cfg, 0u, &tail) != NEGOBS_OK) {
        tail.count = 0; /* cannot happen: cfg passed negobs_alert_init */
    }
    if (n > APP_ALERT_MAX_SEG - (int32_t)tail.count) {
        n = APP_ALERT_MAX_SEG - (int32_t)tail.count;
    }
    while (n > 0 && s[n - 1].duty > 0) {
        n--; /* end on a gap: the tail starts with a pulse */
    }
    to_schedule(s, n, -1, out);
    for (i = 0; i < (int32_t)tail.count; i++) {
        out->seg[n + i] = tail.seg[i];
    }
    out->count = (uint8_t)(n + (int32_t)tail.count);
    out->loop_start = tail.count > 0 ? (uint8_t)(n + tail.loop_start)
                                     : NEGOBS_MOTOR_NO_LOOP;
}

negobs_status_t app_alert_init(app_alert_t *a,
                               const negobs_alert_config_t *cfg)
{
    negobs_status_t st;
    if (a == NULL || cfg == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(a, 0, sizeof *a);
    st = negobs_alert_init(&a->lib, cfg, NULL, 0);
    return st;
}

negobs_status_t app_alert_step(app_alert_t *a, uint32_t now_ms,
                               const negobs_alert_input_t *in,
                               negobs_motor_schedule_t *sched)
{
    negobs_alert_t sim;
    negobs_status_t st;
    int32_t k;
    if (a == NULL || sched == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    /* Replay the wake-ups the library asked for and nobody made, at their
     * own times (bounded: after a long stall the rest is skipped, the
     * library only needs times that do not go back). */
    for (k = 0;
         a->started && k < 64 && since(now_ms, a->cmd.next_change_ms) > 0;
         k++) {
        st = negobs_alert_update(&a->lib, a->cmd.next_change_ms, NULL,
                                 &a->cmd);
        if (st != NEGOBS_OK) {
            return st;
        }
    }
    st = negobs_alert_update(&a->lib, now_ms, in, &a->cmd);
    if (st != NEGOBS_OK) {
        return st;
    }
    a->started = 1;
    sim = a->lib;
    look_ahead(&sim, &a->cmd, now_ms, sched);
    return NEGOBS_OK;
}

negobs_status_t app_alert_post(app_alert_t *a, negobs_motor_thread_t *motor,
                               const negobs_alert_input_t *in,
                               negobs_alert_pattern_t *before)
{
    negobs_motor_schedule_t sched;
    negobs_alert_input_t v;
    uint32_t now;
    negobs_status_t st;
    if (a == NULL || motor == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (before != NULL) {
        *before = a->cmd.pattern;
    }
    now = (uint32_t)negobs_clock_now_ms();
    if (in != NULL) {
        v = *in;
        v.verdict_ms = now;
        in = &v;
    }
    st = app_alert_step(a, now, in, &sched);
    if (st == NEGOBS_OK) {
        /* The schedule starts now: an equal one posted earlier started
         * earlier, so it must start again (not keep playing). */
        negobs_motor_thread_post_restart(motor, &sched);
    }
    return st;
}

negobs_status_t app_alert_noinfo_schedule(const negobs_alert_config_t *cfg,
                                          uint32_t lead_ms,
                                          negobs_motor_schedule_t *sched)
{
    negobs_alert_config_t c;
    negobs_alert_t sim;
    negobs_motor_cmd_t cmd;
    if (cfg == NULL || sched == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    c = *cfg;
    c.ready_on_start = 0;
    if (negobs_alert_init(&sim, &c, NULL, 0) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    /* No verdict ever: the library plays no-information from t = 0. */
    if (negobs_alert_update(&sim, 0u, NULL, &cmd) != NEGOBS_OK || !cmd.on) {
        return NEGOBS_ERR_INVAL;
    }
    {
        sim_seg_t s[APP_ALERT_MAX_SEG + 1];
        int32_t loop = -1;
        int32_t n = simulate(&sim, &cmd, 0u, s, &loop);
        if (loop < 0) {
            return NEGOBS_ERR_INVAL; /* the pattern table changed shape */
        }
        to_schedule(s, n, loop, sched);
    }
    if (sched->seg[0].duration_ms >= lead_ms + (uint32_t)c.min_pulse_ms) {
        sched->seg[0].duration_ms = (uint16_t)(sched->seg[0].duration_ms -
                                               lead_ms);
    }
    return NEGOBS_OK;
}

void app_alert_input(app_verdict_t v, const app_frame_stats_t *st,
                     uint32_t verdict_ms, negobs_alert_input_t *in)
{
    memset(in, 0, sizeof *in);
    in->verdict_ms = verdict_ms;
    in->battery_low = 0; /* no battery gauge in this port yet */
    in->no_info = v == APP_VERDICT_NO_INFO ? 1 : 0;
    in->level = v == APP_VERDICT_IMMINENT  ? NEGOBS_LEVEL_IMMINENT
                : v == APP_VERDICT_CAUTION ? NEGOBS_LEVEL_CAUTION
                                           : NEGOBS_LEVEL_NONE;
    in->range_mm = st != NULL ? st->nearest_range_mm : -1;
    in->short_sight = (v == APP_VERDICT_CLEAR && st != NULL && st->short_sight)
                          ? 1
                          : 0;
}

negobs_alert_pattern_t app_alert_pattern(const app_alert_t *a)
{
    return a->cmd.pattern;
}

const char *app_alert_pattern_name(negobs_alert_pattern_t p)
{
    switch (p) {
    case NEGOBS_PATTERN_NONE: return "off";
    case NEGOBS_PATTERN_READY: return "ready";
    case NEGOBS_PATTERN_LOW_BATTERY: return "low-battery";
    case NEGOBS_PATTERN_NO_INFO_ENTRY: return "no-info-entry";
    case NEGOBS_PATTERN_NO_INFO: return "no-info";
    case NEGOBS_PATTERN_CAUTION_FAR: return "caution-far";
    case NEGOBS_PATTERN_CAUTION_MID: return "caution-mid";
    case NEGOBS_PATTERN_CAUTION_NEAR: return "caution-near";
    case NEGOBS_PATTERN_IMMINENT: return "imminent";
    case NEGOBS_PATTERN_SHORT_SIGHT: return "short-sight";
    default: return "?";
    }
}
