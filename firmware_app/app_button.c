/* Push-button presses from sampled levels; see app_button.h. */
#include "app_button.h"

#include <string.h>

void app_button_init(app_button_t *b, uint32_t long_ms)
{
    memset(b, 0, sizeof *b);
    b->long_ms = long_ms;
}

app_button_event_t app_button_sample(app_button_t *b, int32_t pressed,
                                     uint32_t now_ms)
{
    int32_t level = pressed ? 1 : 0;
    if (!b->started) {
        b->started = 1;
        b->raw = level;
        b->raw_since = now_ms;
        b->stable = level;
        b->armed = level ? 0 : 1; /* held at start: wait for a release */
        return APP_BUTTON_NONE;
    }
    if (level != b->raw) {
        b->raw = level;
        b->raw_since = now_ms;
    }
    if (b->raw != b->stable &&
        (uint32_t)(now_ms - b->raw_since) >= APP_BUTTON_DEBOUNCE_MS) {
        b->stable = b->raw;
        if (b->stable) {
            /* the press began when the level first changed */
            b->press_start = b->raw_since;
            b->long_sent = 0;
        } else {
            int32_t was_armed = b->armed;
            int32_t was_long = b->long_sent;
            b->armed = 1;
            if (was_armed && !was_long) {
                return APP_BUTTON_SHORT;
            }
            return APP_BUTTON_NONE;
        }
    }
    if (b->stable && b->armed && !b->long_sent &&
        (uint32_t)(now_ms - b->press_start) >= b->long_ms) {
        b->long_sent = 1;
        return APP_BUTTON_LONG;
    }
    return APP_BUTTON_NONE;
}

app_verdict_t app_button_filter(int32_t preset, app_verdict_t v,
                                int32_t nearest_mm, int32_t mid_mm)
{
    if (v != APP_VERDICT_CAUTION) {
        return v;
    }
    if (preset == APP_PRESET_IMMINENT ||
        (preset == APP_PRESET_NEAR && nearest_mm >= 0 &&
         nearest_mm >= mid_mm)) {
        return APP_VERDICT_CLEAR;
    }
    return v;
}

negobs_status_t app_button_confirm_schedule(
    app_button_confirm_t kind, int32_t preset, uint16_t level_permille,
    const negobs_motor_schedule_t *tail, negobs_motor_schedule_t *out,
    uint32_t *pattern_ms)
{
    uint32_t n;
    uint16_t on_ms;
    uint16_t off_ms;
    uint32_t i;
    uint32_t total = 0;
    if (out == NULL || tail == NULL || pattern_ms == NULL ||
        level_permille == 0u || level_permille > NEGOBS_MOTOR_FULL) {
        return NEGOBS_ERR_INVAL;
    }
    /* lengths no alert pattern uses (those are 80-400 ms pulses in their
     * own rhythms; docs/RUNNING.md "Motor patterns") */
    switch (kind) {
    case APP_CONFIRM_PAUSE:
        n = 1u;
        on_ms = 700u;
        off_ms = 0u;
        break;
    case APP_CONFIRM_RESUME:
        n = 2u;
        on_ms = 300u;
        off_ms = 200u;
        break;
    case APP_CONFIRM_PRESET:
        if (preset < 0 || preset >= APP_PRESET_COUNT) {
            return NEGOBS_ERR_INVAL;
        }
        n = (uint32_t)preset + 1u;
        on_ms = 120u;
        off_ms = 180u;
        break;
    default: return NEGOBS_ERR_INVAL;
    }
    if (2u * n + tail->count > NEGOBS_MOTOR_MAX_SEGMENTS) {
        return NEGOBS_ERR_INVAL;
    }
    memset(out, 0, sizeof *out);
    for (i = 0; i < n; i++) {
        out->seg[out->count].duty_permille = level_permille;
        out->seg[out->count++].duration_ms = on_ms;
        out->seg[out->count].duty_permille = 0;
        /* the last gap is the closing silence */
        out->seg[out->count++].duration_ms =
            (uint16_t)(i + 1u < n ? off_ms : APP_CONFIRM_GAP_MS);
        total += on_ms + (i + 1u < n ? off_ms : APP_CONFIRM_GAP_MS);
    }
    out->loop_start = NEGOBS_MOTOR_NO_LOOP;
    if (tail->loop_start != NEGOBS_MOTOR_NO_LOOP) {
        out->loop_start = (uint8_t)(out->count + tail->loop_start);
    }
    for (i = 0; i < tail->count; i++) {
        out->seg[out->count++] = tail->seg[i];
    }
    *pattern_ms = total;
    return negobs_motor_schedule_check(out);
}

void app_button_paused_schedule(uint16_t level_permille,
                                negobs_motor_schedule_t *out)
{
    memset(out, 0, sizeof *out);
    out->seg[0].duty_permille = 0;
    out->seg[0].duration_ms = (uint16_t)APP_PAUSED_PERIOD_MS;
    out->seg[1].duty_permille = level_permille;
    out->seg[1].duration_ms = (uint16_t)APP_PAUSED_PULSE_MS;
    out->count = 2;
    out->loop_start = 0;
}
