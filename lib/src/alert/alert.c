/*
 * Alert state machine. Every pattern is a fixed list of (duration, on)
 * segments, played once or repeated; the state is only the pattern and its
 * start time, so the output at any instant is a pure function of the
 * clock. See negobs/alert.h for the table and the priority rules.
 */
#include "negobs/alert.h"

#include <string.h>

#include "negobs/detect.h" /* negobs_alert_input_from_result */

#define ALERT_MAGIC 0x4E47414Cu /* "NGAL" */

typedef struct seg {
    uint16_t dur_ms;
    uint8_t on;
} seg_t;

typedef struct pat {
    const seg_t *s;
    uint8_t n;
    uint8_t repeat;
    uint8_t prio;
} pat_t;

static const seg_t seg_ready[] = {{100, 1}, {100, 0}, {100, 1}, {100, 0}};
static const seg_t seg_batt[] = {{80, 1}, {120, 0}, {80, 1}, {120, 0},
                                 {80, 1}, {120, 0}, {80, 1}, {120, 0}};
static const seg_t seg_noinfo_entry[] = {{400, 1}, {200, 0}, {400, 1},
                                         {200, 0}, {400, 1}, {200, 0}};
static const seg_t seg_noinfo[] = {{600, 1}, {2400, 0}};
static const seg_t seg_caution_far[] = {{80, 1}, {80, 0}, {80, 1}, {760, 0}};
static const seg_t seg_caution_mid[] = {{80, 1}, {80, 0}, {80, 1}, {360, 0}};
static const seg_t seg_caution_near[] = {{80, 1}, {80, 0}, {80, 1}, {160, 0}};
static const seg_t seg_imminent[] = {{300, 1}, {100, 0}};
/* Short sight: one pulse (caution is always a pair) of 160 ms (a quarter
 * of the NO_INFO pulse, twice a caution pulse) every 2 s (slower than
 * any caution band): "clear, but only for a short way". */
static const seg_t seg_short_sight[] = {{160, 1}, {1840, 0}};

#define NSEG(a) ((uint8_t)(sizeof(a) / sizeof((a)[0])))

/* Priorities: IMMINENT 7 > CAUTION 6 > SHORT_SIGHT 5 > READY 4 (power-on
 * self-test, once, 400 ms) > NO_INFO 3 > LOW_BATTERY 2 > NONE 0. Short
 * sight ranks below every hazard pattern: it says "clear". */
static const pat_t pats[NEGOBS_PATTERN_COUNT] = {
    {NULL, 0, 0, 0},
    {seg_ready, NSEG(seg_ready), 0, 4},
    {seg_batt, NSEG(seg_batt), 0, 2},
    {seg_noinfo_entry, NSEG(seg_noinfo_entry), 0, 3},
    {seg_noinfo, NSEG(seg_noinfo), 1, 3},
    {seg_caution_far, NSEG(seg_caution_far), 1, 6},
    {seg_caution_mid, NSEG(seg_caution_mid), 1, 6},
    {seg_caution_near, NSEG(seg_caution_near), 1, 6},
    {seg_imminent, NSEG(seg_imminent), 1, 7},
    {seg_short_sight, NSEG(seg_short_sight), 1, 5},
};

/* The heartbeat is the NONE ("clear") pattern when it is on: a silent gap
 * of heartbeat_period_ms - heartbeat_pulse_ms, then one pulse, repeated.
 * Its durations come from the config, the others from the table above. */
static int heartbeat_on(const negobs_alert_t *c)
{
    return c->cfg.heartbeat_period_ms > 0;
}

static int32_t pat_n(const negobs_alert_t *c, negobs_alert_pattern_t p)
{
    if (p == NEGOBS_PATTERN_NONE) {
        return heartbeat_on(c) ? 2 : 0;
    }
    return pats[p].n;
}

static int pat_repeat(negobs_alert_pattern_t p)
{
    return p == NEGOBS_PATTERN_NONE ? 1 : pats[p].repeat;
}

static int32_t seg_dur(const negobs_alert_t *c, negobs_alert_pattern_t p,
                       int32_t i)
{
    if (p == NEGOBS_PATTERN_NONE) {
        return i == 0 ? c->cfg.heartbeat_period_ms - c->cfg.heartbeat_pulse_ms
                      : c->cfg.heartbeat_pulse_ms;
    }
    return pats[p].s[i].dur_ms;
}

static int seg_on(negobs_alert_pattern_t p, int32_t i)
{
    return p == NEGOBS_PATTERN_NONE ? i == 1 : pats[p].s[i].on;
}

static int32_t since(uint32_t now, uint32_t then)
{
    return (int32_t)(now - then);
}

void negobs_alert_config_default(negobs_alert_config_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->min_pulse_ms = 80;
    cfg->intensity_permille = 1000;
    cfg->band_far_mm = 3000;
    cfg->band_mid_mm = 2200;
    cfg->binary_mode = 0;
    cfg->stale_ms = 300;
    cfg->noinfo_rearm_ms = 10000;
    cfg->battery_period_ms = 60000;
    cfg->imminent_hold_ms = 1000;
    cfg->ready_on_start = 1;
    cfg->heartbeat_period_ms = 5000;
    cfg->heartbeat_pulse_ms = 80;
}

static int32_t shortest_pulse(void)
{
    int32_t m = 1 << 30;
    int i;
    int j;
    for (i = 1; i < NEGOBS_PATTERN_COUNT; i++) {
        for (j = 0; j < pats[i].n; j++) {
            if (pats[i].s[j].on && pats[i].s[j].dur_ms < m) {
                m = pats[i].s[j].dur_ms;
            }
        }
    }
    return m;
}

negobs_status_t negobs_alert_workspace_size(const negobs_alert_config_t *cfg,
                                            size_t *bytes_out)
{
    if (cfg == NULL || bytes_out == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    *bytes_out = 0;
    return NEGOBS_OK;
}

negobs_status_t negobs_alert_init(negobs_alert_t *ctx,
                                  const negobs_alert_config_t *cfg,
                                  void *workspace, size_t workspace_bytes)
{
    (void)workspace;
    (void)workspace_bytes;
    if (ctx == NULL || cfg == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (cfg->min_pulse_ms < 30 || cfg->min_pulse_ms > shortest_pulse() ||
        cfg->intensity_permille < 1 || cfg->intensity_permille > 1000 ||
        cfg->band_mid_mm < 0 || cfg->band_far_mm < cfg->band_mid_mm ||
        cfg->stale_ms < 1 || cfg->stale_ms > 60000 ||
        cfg->noinfo_rearm_ms < 0 || cfg->battery_period_ms < 1000 ||
        cfg->imminent_hold_ms < 0 || cfg->imminent_hold_ms > 60000) {
        return NEGOBS_ERR_INVAL;
    }
    /* A heartbeat is one brief pulse: at least the shortest pulse that is
     * felt, at most a quarter of its period (longer reads as a pattern). */
    if (cfg->heartbeat_period_ms != 0 &&
        (cfg->heartbeat_period_ms < 1000 || cfg->heartbeat_period_ms > 60000 ||
         cfg->heartbeat_pulse_ms < cfg->min_pulse_ms ||
         cfg->heartbeat_pulse_ms > cfg->heartbeat_period_ms / 4)) {
        return NEGOBS_ERR_INVAL;
    }
    memset(ctx, 0, sizeof *ctx);
    ctx->cfg = *cfg;
    ctx->ready_pending = cfg->ready_on_start ? 1 : 0;
    ctx->pat = NEGOBS_PATTERN_NONE;
    ctx->magic = ALERT_MAGIC;
    return NEGOBS_OK;
}

static int is_caution(negobs_alert_pattern_t p)
{
    return p == NEGOBS_PATTERN_CAUTION_FAR ||
           p == NEGOBS_PATTERN_CAUTION_MID || p == NEGOBS_PATTERN_CAUTION_NEAR;
}

static int is_noinfo(negobs_alert_pattern_t p)
{
    return p == NEGOBS_PATTERN_NO_INFO_ENTRY || p == NEGOBS_PATTERN_NO_INFO;
}

/* Segment of pattern p (started at start) playing at now. Returns 0 when
 * a one-shot pattern has finished (then *end is its end time). */
static int locate(const negobs_alert_t *c, negobs_alert_pattern_t p,
                  uint32_t start, uint32_t now, int32_t *idx,
                  uint32_t *seg_start, uint32_t *end)
{
    int32_t n = pat_n(c, p);
    int32_t total = 0;
    int32_t el = since(now, start);
    int32_t base;
    int32_t i;
    if (n == 0) {
        return 0;
    }
    for (i = 0; i < n; i++) {
        total += seg_dur(c, p, i);
    }
    if (el < 0) {
        /* Scheduled to start later: a silent gap until then. */
        *idx = -1;
        *seg_start = now;
        *end = start;
        return 1;
    }
    if (!pat_repeat(p) && el >= total) {
        *end = start + (uint32_t)total;
        return 0;
    }
    base = pat_repeat(p) ? (el / total) * total : 0;
    el -= base;
    for (i = 0; i < n; i++) {
        if (el < seg_dur(c, p, i)) {
            break;
        }
        el -= seg_dur(c, p, i);
        base += seg_dur(c, p, i);
    }
    *idx = i;
    *seg_start = start + (uint32_t)base;
    *end = *seg_start + (uint32_t)seg_dur(c, p, i);
    return 1;
}

static negobs_alert_pattern_t desired(negobs_alert_t *c, uint32_t now)
{
    const negobs_alert_config_t *cfg = &c->cfg;
    int stale = !c->have_input || since(now, c->in.verdict_ms) > cfg->stale_ms;
    if (!stale && c->in.level == NEGOBS_LEVEL_IMMINENT) {
        c->imminent_seen = 1;
        c->last_imminent_ms = now;
    }
    if (c->imminent_seen &&
        since(now, c->last_imminent_ms) <= cfg->imminent_hold_ms) {
        return NEGOBS_PATTERN_IMMINENT;
    }
    if (!stale && c->in.level == NEGOBS_LEVEL_CAUTION) {
        if (cfg->binary_mode) {
            return NEGOBS_PATTERN_CAUTION_MID;
        }
        if (c->in.range_mm >= cfg->band_far_mm) {
            return NEGOBS_PATTERN_CAUTION_FAR;
        }
        if (c->in.range_mm >= cfg->band_mid_mm) {
            return NEGOBS_PATTERN_CAUTION_MID;
        }
        return NEGOBS_PATTERN_CAUTION_NEAR;
    }
    if (!stale && !c->in.no_info && c->in.short_sight) {
        return NEGOBS_PATTERN_SHORT_SIGHT;
    }
    if (c->ready_pending) {
        return NEGOBS_PATTERN_READY;
    }
    if (stale || c->in.no_info) {
        return NEGOBS_PATTERN_NO_INFO;
    }
    if (c->in.battery_low &&
        (c->pat == NEGOBS_PATTERN_LOW_BATTERY || !c->battery_played ||
         since(now, c->battery_start_ms) >= cfg->battery_period_ms)) {
        return NEGOBS_PATTERN_LOW_BATTERY;
    }
    return NEGOBS_PATTERN_NONE;
}

static void start_pattern(negobs_alert_t *c, negobs_alert_pattern_t p,
                          uint32_t now)
{
    if (c->pat == NEGOBS_PATTERN_READY) {
        c->ready_pending = 0;
    }
    if (is_noinfo(p)) {
        p = (!c->noinfo_seen ||
             since(now, c->last_noinfo_ms) > c->cfg.noinfo_rearm_ms)
                ? NEGOBS_PATTERN_NO_INFO_ENTRY
                : NEGOBS_PATTERN_NO_INFO;
    }
    if (p == NEGOBS_PATTERN_LOW_BATTERY) {
        c->battery_played = 1;
        c->battery_start_ms = now;
    }
    c->pat = p;
    c->pat_start_ms = now;
}

static uint32_t earlier(uint32_t now, uint32_t a, uint32_t b)
{
    return (since(a, now) <= since(b, now)) ? a : b;
}

/* Where the current pattern stands at the time of an update. */
typedef struct {
    int playing;        /* 0 once a one-shot pattern has finished    */
    int32_t idx;        /* segment index, -1 in a delayed start's gap */
    uint32_t seg_start; /* ms, start of that segment                 */
    uint32_t seg_end;   /* ms, end of that segment                   */
    int on;             /* the segment drives the motor              */
} play_t;

static void play_locate(const negobs_alert_t *c, uint32_t now, play_t *ps)
{
    ps->playing = locate(c, c->pat, c->pat_start_ms, now, &ps->idx,
                         &ps->seg_start, &ps->seg_end);
}

/* The heartbeat and the staleness watchdog need a time origin even when no
 * verdict has arrived yet. */
static void first_update(negobs_alert_t *c, uint32_t now)
{
    c->started = 1;
    c->pat_start_ms = now; /* the heartbeat counts from here */
    /* Before any verdict, staleness counts from the first update. */
    if (!c->have_input) {
        c->in.verdict_ms = now;
        c->in.no_info = 1;
        c->have_input = 1;
    }
}

/* Finish one-shot patterns (the NO_INFO burst chains into NO_INFO), so the
 * pattern in c->pat is always one that plays at now. */
static void finish_one_shot(negobs_alert_t *c, uint32_t now, play_t *ps)
{
    play_locate(c, now, ps);
    if (!ps->playing && c->pat != NEGOBS_PATTERN_NONE) {
        if (c->pat == NEGOBS_PATTERN_READY) {
            c->ready_pending = 0;
        }
        if (c->pat == NEGOBS_PATTERN_NO_INFO_ENTRY) {
            c->pat = NEGOBS_PATTERN_NO_INFO;
        } else {
            c->pat = NEGOBS_PATTERN_NONE; /* heartbeat: its gap first */
        }
        c->pat_start_ms = ps->seg_end;
        play_locate(c, now, ps);
    }
    ps->on = (ps->playing && ps->idx >= 0) ? seg_on(c->pat, ps->idx) : 0;
}

/* Switch to the wanted pattern only where the switch cannot be felt as a
 * broken or fused pulse, unless the wanted one is more urgent. */
static void switch_pattern(negobs_alert_t *c, uint32_t now, play_t *ps)
{
    negobs_alert_pattern_t want = desired(c, now);
    int sw;
    negobs_alert_pattern_t old = c->pat;
    if (want == c->pat || (is_noinfo(want) && is_noinfo(c->pat))) {
        return;
    }
    if (pats[want].prio > pats[c->pat].prio) {
        sw = 1; /* pre-empt now (the min-pulse guard protects a pulse) */
    } else if (is_caution(want) && is_caution(c->pat)) {
        /* Band change: in the long gap after the two-pulse burst. */
        sw = !ps->on && ps->idx == pat_n(c, c->pat) - 1;
    } else {
        sw = !ps->on; /* lower priority: never cut a pulse */
    }
    if (sw) {
        /* A pending READY pre-empted by a hazard is dropped. */
        start_pattern(c, want, now);
        /* After a pulse that just ended, keep a gap so two patterns
         * never fuse into one long pulse. TUNABLE: 100 ms. */
        if (pats[want].prio <= pats[old].prio && c->motor_on) {
            c->pat_start_ms = now + 100u;
        }
        play_locate(c, now, ps);
        ps->on = (ps->playing && ps->idx >= 0) ? seg_on(c->pat, ps->idx) : 0;
    }
}

/* Wake up for the watchdog deadline, the end of an IMMINENT hold and the
 * next low-battery reminder, which no segment boundary announces. */
static uint32_t wake_deadlines(const negobs_alert_t *c, uint32_t now,
                               uint32_t next)
{
    if (since(now, c->in.verdict_ms) <= c->cfg.stale_ms) {
        next = earlier(now, next,
                       c->in.verdict_ms + (uint32_t)c->cfg.stale_ms + 1u);
    }
    if (c->pat == NEGOBS_PATTERN_IMMINENT && c->imminent_seen &&
        since(now, c->last_imminent_ms) <= c->cfg.imminent_hold_ms) {
        next = earlier(now, next,
                       c->last_imminent_ms +
                           (uint32_t)c->cfg.imminent_hold_ms + 1u);
    }
    if (c->in.battery_low && c->battery_played) {
        uint32_t due = c->battery_start_ms +
                       (uint32_t)c->cfg.battery_period_ms;
        if (since(due, now) > 0) {
            next = earlier(now, next, due);
        }
    }
    if (since(next, now) <= 0) {
        next = now + 1u;
    }
    return next;
}

/* Upcoming schedule of the current pattern, assuming no new input, so a
 * driver can play it without waking the caller for every segment. */
static void fill_schedule(const negobs_alert_t *c, uint32_t now,
                          const play_t *ps, uint32_t next,
                          negobs_motor_cmd_t *cmd)
{
    uint32_t i;
    cmd->n_segments = 1;
    cmd->segments[0].start_ms = now;
    cmd->segments[0].on = ps->on;
    cmd->segments[0].duty_permille = cmd->duty_permille;
    if (ps->playing) {
        int32_t n = pat_n(c, c->pat);
        uint32_t t = ps->seg_end;
        int32_t k = ps->idx;
        if (ps->idx < 0 || (ps->on && !seg_on(c->pat, ps->idx))) {
            t = next; /* guard extension or delayed start */
        }
        for (i = 1; i < NEGOBS_ALERT_MAX_SEGMENTS; i++) {
            k++;
            if (k >= n) {
                if (!pat_repeat(c->pat)) {
                    cmd->segments[i].start_ms = t;
                    cmd->segments[i].on = 0;
                    cmd->segments[i].duty_permille = 0;
                    cmd->n_segments = i + 1;
                    break;
                }
                k = 0;
            }
            cmd->segments[i].start_ms = t;
            cmd->segments[i].on = seg_on(c->pat, k);
            cmd->segments[i].duty_permille = seg_on(c->pat, k)
                                                 ? c->cfg.intensity_permille
                                                 : 0;
            cmd->n_segments = i + 1;
            t += (uint32_t)seg_dur(c, c->pat, k);
        }
    }
}

negobs_status_t negobs_alert_update(negobs_alert_t *c, uint32_t now,
                                    const negobs_alert_input_t *input,
                                    negobs_motor_cmd_t *cmd)
{
    play_t ps;
    uint32_t next;

    if (c == NULL || cmd == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (c->magic != ALERT_MAGIC) {
        return NEGOBS_ERR_STATE;
    }
    if (input != NULL) {
        c->in = *input;
        c->have_input = 1;
    }
    if (!c->started) {
        first_update(c, now);
    }
    ps.playing = 0;
    ps.idx = 0;
    ps.seg_start = now;
    ps.seg_end = now;
    ps.on = 0;

    finish_one_shot(c, now, &ps);
    switch_pattern(c, now, &ps);

    /* Remembered while it plays, so the entry burst sees the gap. */
    if (is_noinfo(c->pat)) {
        c->noinfo_seen = 1;
        c->last_noinfo_ms = now;
    }

    next = ps.playing ? ps.seg_end : now + 1000u;
    /* Minimum pulse: never switch off earlier than min_pulse_ms. */
    if (!ps.on && c->motor_on &&
        since(now, c->on_since_ms) < c->cfg.min_pulse_ms) {
        ps.on = 1;
        next = c->on_since_ms + (uint32_t)c->cfg.min_pulse_ms;
    }
    if (ps.on && !c->motor_on) {
        c->on_since_ms = now;
    }
    c->motor_on = ps.on;
    next = wake_deadlines(c, now, next);

    cmd->on = ps.on;
    cmd->duty_permille = ps.on ? c->cfg.intensity_permille : 0;
    cmd->next_change_ms = next;
    cmd->pattern = c->pat;
    fill_schedule(c, now, &ps, next, cmd);
    return NEGOBS_OK;
}

void negobs_alert_input_from_result(const negobs_detect_result_t *res,
                                    int32_t battery_low, uint32_t verdict_ms,
                                    negobs_alert_input_t *in)
{
    memset(in, 0, sizeof *in);
    in->verdict_ms = verdict_ms;
    in->battery_low = battery_low;
    if (res == NULL) {
        in->no_info = 1;
        return;
    }
    in->level = res->level;
    in->range_mm = res->nearest_range_mm;
    in->no_info = (res->state == NEGOBS_DETECT_NO_INFO) ? 1 : 0;
    in->short_sight = (res->state == NEGOBS_DETECT_CLEAR && res->short_sight)
                          ? 1
                          : 0;
}
