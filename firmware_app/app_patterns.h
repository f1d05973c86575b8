/*
 * Motor patterns of negobs_run: a PLACEHOLDER table taken from the
 * proposal in DOMAIN.md 2.2, to be replaced by the core library's alert
 * state machine (which will choose patterns and priorities itself).
 */
#ifndef NEGOBS_APP_PATTERNS_H
#define NEGOBS_APP_PATTERNS_H

#include "app_pipeline.h"
#include "negobs_port/alert.h"

/** Two short pulses at start-up: proves motor and driver work. */
const negobs_motor_schedule_t *app_pattern_ready(void);

/** The pattern for a verdict (CLEAR is silence). */
const negobs_motor_schedule_t *app_pattern_for(app_verdict_t v);

#endif
