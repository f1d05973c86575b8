/*
 * The push button's presses from sampled levels (pure logic, fake-clock
 * testable; run_button.c samples the line every APP_BUTTON_POLL_MS).
 *
 * - Debounce: a level counts once it has held APP_BUTTON_DEBOUNCE_MS
 *   (tactile switches bounce for well under 10 ms; 30 ms leaves margin and
 *   is still far below a deliberate press of about 100 ms).
 * - Long press: reported as soon as the button has been held long_ms, so
 *   the wearer feels the confirmation while still holding it; its release
 *   reports nothing more.
 * - Short press: reported at release when it was held less than long_ms.
 * - A button already held at start (or stuck, e.g. a shorted wire) reports
 *   nothing until it has been released once: a fault must not pause the
 *   device.
 */
#ifndef NEGOBS_APP_BUTTON_H
#define NEGOBS_APP_BUTTON_H

#include <stdint.h>

#define APP_BUTTON_DEBOUNCE_MS 30u
#define APP_BUTTON_POLL_MS 10u

typedef enum app_button_event {
    APP_BUTTON_NONE = 0,
    APP_BUTTON_SHORT = 1, /**< next sensitivity preset */
    APP_BUTTON_LONG = 2   /**< pause / resume          */
} app_button_event_t;

typedef struct app_button {
    uint32_t long_ms;
    int32_t started;      /**< first sample seen                        */
    int32_t raw;          /**< last sampled level                       */
    uint32_t raw_since;   /**< when it took that level                  */
    int32_t stable;       /**< debounced level (1 pressed)              */
    uint32_t press_start; /**< when the debounced press began           */
    int32_t long_sent;    /**< this press already reported as long      */
    int32_t armed;        /**< a release has been seen since start      */
} app_button_t;

/** @brief Reset; `long_ms` is the long-press threshold (> debounce). */
void app_button_init(app_button_t *b, uint32_t long_ms);

/**
 * @brief Feed one sample (pressed 1 / released 0) taken at now_ms
 *        (wrap-safe uint32 ms, not going back).
 * @return the press completed by this sample, or APP_BUTTON_NONE.
 */
app_button_event_t app_button_sample(app_button_t *b, int32_t pressed,
                                     uint32_t now_ms);

#endif /* NEGOBS_APP_BUTTON_H */
