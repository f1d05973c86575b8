/*
 * Motor schedule checks and the executor.
 *
 * The executor keeps the end time of the current segment and, on every
 * tick, walks forward over all segments that have ended by `now`. End
 * times are computed from the previous end time, not from `now`, so a late
 * tick shortens the segment it arrives in but never shifts the rest of the
 * pattern (no accumulated drift). A looped tail whose total duration is
 * known is skipped over in whole periods, so a tick seconds late costs
 * O(segments), not O(elapsed / period).
 */
#include <string.h>

#include "negobs_port/motor.h"

negobs_status_t negobs_motor_schedule_check(const negobs_motor_schedule_t *s)
{
    uint32_t i;
    uint32_t loop_ms = 0;
    if (s == NULL || s->count > NEGOBS_MOTOR_MAX_SEGMENTS) {
        return NEGOBS_ERR_INVAL;
    }
    if (s->loop_start != NEGOBS_MOTOR_NO_LOOP && s->loop_start >= s->count) {
        return NEGOBS_ERR_INVAL;
    }
    for (i = 0; i < s->count; i++) {
        if (s->seg[i].duty_permille > NEGOBS_MOTOR_FULL) {
            return NEGOBS_ERR_INVAL;
        }
        if (s->loop_start != NEGOBS_MOTOR_NO_LOOP && i >= s->loop_start) {
            loop_ms += s->seg[i].duration_ms;
        }
    }
    if (s->loop_start != NEGOBS_MOTOR_NO_LOOP && loop_ms == 0) {
        return NEGOBS_ERR_INVAL; /* would spin forever */
    }
    return NEGOBS_OK;
}

bool negobs_motor_schedule_equal(const negobs_motor_schedule_t *a,
                                 const negobs_motor_schedule_t *b)
{
    uint32_t i;
    if (a->count != b->count || a->loop_start != b->loop_start) {
        return false;
    }
    for (i = 0; i < a->count; i++) {
        if (a->seg[i].duty_permille != b->seg[i].duty_permille ||
            a->seg[i].duration_ms != b->seg[i].duration_ms) {
            return false;
        }
    }
    return true;
}

static void exec_apply(negobs_motor_exec_t *ex, uint16_t level)
{
    negobs_status_t st;
    if (ex->level == (int32_t)level) {
        return;
    }
    st = negobs_motor_out_set(ex->out, level);
    ex->last_status = st;
    if (st != NEGOBS_OK) {
        /* Leave level unknown so the next tick tries again. */
        ex->set_errors++;
        ex->level = -1;
        return;
    }
    ex->level = (int32_t)level;
}

void negobs_motor_exec_init(negobs_motor_exec_t *ex, negobs_motor_out_t *out)
{
    memset(ex, 0, sizeof *ex);
    ex->out = out;
    ex->level = -1;
    ex->last_status = NEGOBS_OK;
}

negobs_status_t negobs_motor_exec_start(negobs_motor_exec_t *ex,
                                        const negobs_motor_schedule_t *s,
                                        uint64_t now_ms)
{
    if (negobs_motor_schedule_check(s) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    ex->sched = *s;
    ex->active = s->count > 0;
    ex->seg = 0;
    if (!ex->active) {
        exec_apply(ex, 0);
        return NEGOBS_OK;
    }
    ex->seg_end_ms = now_ms + s->seg[0].duration_ms;
    (void)negobs_motor_exec_tick(ex, now_ms);
    return NEGOBS_OK;
}

static uint64_t loop_period_ms(const negobs_motor_schedule_t *s)
{
    uint64_t p = 0;
    uint32_t i;
    for (i = s->loop_start; i < s->count; i++) {
        p += s->seg[i].duration_ms;
    }
    return p;
}

int64_t negobs_motor_exec_tick(negobs_motor_exec_t *ex, uint64_t now_ms)
{
    const negobs_motor_schedule_t *s = &ex->sched;
    if (!ex->active) {
        exec_apply(ex, 0);
        return -1;
    }
    while (now_ms >= ex->seg_end_ms) {
        uint32_t next = (uint32_t)ex->seg + 1u;
        if (next >= s->count) {
            if (s->loop_start == NEGOBS_MOTOR_NO_LOOP) {
                ex->active = false;
                exec_apply(ex, 0);
                return -1;
            }
            next = s->loop_start;
            /* Far behind: jump whole loop periods at once (the period is
             * > 0, negobs_motor_schedule_check() made sure of it). */
            {
                uint64_t p = loop_period_ms(s);
                if (p > 0 && now_ms - ex->seg_end_ms > p) {
                    ex->seg_end_ms += ((now_ms - ex->seg_end_ms) / p) * p;
                }
            }
        }
        ex->seg = (uint8_t)next;
        ex->seg_end_ms += s->seg[next].duration_ms;
    }
    exec_apply(ex, s->seg[ex->seg].duty_permille);
    return (int64_t)(ex->seg_end_ms - now_ms);
}

void negobs_motor_exec_stop(negobs_motor_exec_t *ex)
{
    ex->active = false;
    ex->level = -1; /* force the write */
    exec_apply(ex, 0);
}
