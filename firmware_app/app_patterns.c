/* Placeholder pattern table (DOMAIN.md 2.2); see app_patterns.h. */
#include "app_patterns.h"

#define ON NEGOBS_MOTOR_FULL
#define NO_LOOP NEGOBS_MOTOR_NO_LOOP

/* READY: 100 on / 100 off / 100 on, once. */
static const negobs_motor_schedule_t ready = {
    {{ON, 100}, {0, 100}, {ON, 100}}, 3, NO_LOOP};

/* CLEAR: motor off (one long off segment, repeated). */
static const negobs_motor_schedule_t silence = {{{0, 1000}}, 1, 0};

/* CAUTION: double pulse 80/80/80, repeated every 1.0 s (one band only
 * until the detector reports distance). */
static const negobs_motor_schedule_t caution = {
    {{ON, 80}, {0, 80}, {ON, 80}, {0, 760}}, 4, 0};

/* IMMINENT: 300 on / 100 off, continuous. */
static const negobs_motor_schedule_t imminent = {{{ON, 300}, {0, 100}}, 2, 0};

/* NO_INFO: on entry 3 x 400 ms, then one 600 ms pulse every 3 s. */
static const negobs_motor_schedule_t no_info = {
    {{ON, 400}, {0, 200}, {ON, 400}, {0, 200}, {ON, 400}, {0, 400},
     {ON, 600}, {0, 2400}},
    8, 6};

const negobs_motor_schedule_t *app_pattern_ready(void)
{
    return &ready;
}

const negobs_motor_schedule_t *app_pattern_for(app_verdict_t v)
{
    switch (v) {
    case APP_VERDICT_CLEAR: return &silence;
    case APP_VERDICT_CAUTION: return &caution;
    case APP_VERDICT_IMMINENT: return &imminent;
    case APP_VERDICT_NO_INFO:
    default: return &no_info;
    }
}
