/*
 * Digital inputs: a push button on a GPIO line.
 *
 * The backend only samples the line's level; what a press means (debounce,
 * long or short) is the program's business (firmware_app/app_button.h), so
 * the classification is testable without hardware. State in a
 * caller-owned struct, no heap.
 */
#ifndef NEGOBS_PORT_INPUT_H
#define NEGOBS_PORT_INPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Size of the diagnostic message. */
#define NEGOBS_INPUT_ERRMSG_LEN 160

/** GPIO character-device input state (fields private). */
typedef struct negobs_input_gpio {
    int chip_fd;
    int line_fd;
    uint32_t line;
    bool active_low;
    bool biased; /**< the pull resistor was accepted by the chip */
    int last_errno;
    char errmsg[NEGOBS_INPUT_ERRMSG_LEN];
} negobs_input_gpio_t;

/**
 * @brief Request one input line through the GPIO chardev (uAPI v2, Linux
 *        5.10 or later).
 *
 * With `active_low` the button connects the line to ground: the internal
 * pull-up is asked for, and a low line reads as pressed; otherwise a
 * pull-down and high = pressed. Chips without configurable bias refuse
 * it; the line is then requested without (an external resistor is needed,
 * docs/RUNNING.md).
 * @param chip  "/dev/gpiochip0", "gpiochip0" or "0"
 * @return NEGOBS_OK, NEGOBS_ERR_NODEV (no chip), NEGOBS_ERR_IO (request
 *         refused, e.g. line busy; see st->errmsg), NEGOBS_ERR_INVAL.
 */
negobs_status_t negobs_input_gpio_open(negobs_input_gpio_t *st,
                                       const char *chip, uint32_t line,
                                       bool active_low);

/**
 * @brief Sample the line.
 * @return 1 pressed, 0 released, or NEGOBS_ERR_IO / NEGOBS_ERR_NODEV
 *         (the chip went away; st->errmsg says why).
 */
int negobs_input_gpio_read(negobs_input_gpio_t *st);

/** @brief Release the line. Safe to call twice. */
void negobs_input_gpio_close(negobs_input_gpio_t *st);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_INPUT_H */
