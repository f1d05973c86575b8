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

#include "app_pipeline.h"
#include "negobs/status.h"
#include "negobs_port/motor.h"

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

/* ---- what a press does ------------------------------------------------ */

/** Sensitivity presets (a short press moves to the next). */
enum {
    APP_PRESET_ALL = 0,      /**< every warning                          */
    APP_PRESET_NEAR = 1,     /**< cautions only nearer than caution_mid  */
    APP_PRESET_IMMINENT = 2, /**< imminent warnings only                 */
    APP_PRESET_COUNT = 3
};

/**
 * @brief The verdict the motor gets under a preset. Only CAUTION is ever
 *        lowered (to CLEAR): imminent warnings and no-information always
 *        pass, whatever the preset.
 * @param nearest_mm  range of the nearest confirmed hazard, -1 unknown
 *                    (an unknown range is never quieted)
 * @param mid_mm      caution_mid_mm: the NEAR preset's limit
 */
app_verdict_t app_button_filter(int32_t preset, app_verdict_t v,
                                int32_t nearest_mm, int32_t mid_mm);

/** Confirmation patterns of a press. */
typedef enum app_button_confirm {
    APP_CONFIRM_PAUSE = 0,  /**< one 700 ms pulse                       */
    APP_CONFIRM_RESUME = 1, /**< two 300 ms pulses                      */
    APP_CONFIRM_PRESET = 2  /**< preset + 1 pulses of 120 ms            */
} app_button_confirm_t;

/** Silence after a confirmation before anything else may play (ms). */
#define APP_CONFIRM_GAP_MS 400u

/**
 * @brief The motor schedule confirming a press: its pulses at
 *        `level_permille`, APP_CONFIRM_GAP_MS of silence, then `tail`
 *        (negobs_run: the no-information loop, so that a main loop that
 *        dies while it plays never leaves the wearer in silence).
 * @param[out] pattern_ms  length of pulses and gap, before the tail
 * @return NEGOBS_OK, or NEGOBS_ERR_INVAL (bad kind/preset/level, tail too
 *         long for the segment budget).
 */
negobs_status_t app_button_confirm_schedule(
    app_button_confirm_t kind, int32_t preset, uint16_t level_permille,
    const negobs_motor_schedule_t *tail, negobs_motor_schedule_t *out,
    uint32_t *pattern_ms);

/** Reminder pulse of a paused device, and how often (ms). */
#define APP_PAUSED_PULSE_MS 120u
#define APP_PAUSED_PERIOD_MS 10000u

/** @brief Looped silence with one reminder pulse every 10 s. */
void app_button_paused_schedule(uint16_t level_permille,
                                negobs_motor_schedule_t *out);

#endif /* NEGOBS_APP_BUTTON_H */
