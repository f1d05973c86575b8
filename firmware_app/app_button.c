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
