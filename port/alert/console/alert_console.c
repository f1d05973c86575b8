/* Console alert backend: prints every motor level change. */
#include <stdio.h>
#include <string.h>

#include "negobs_port/motor.h"
#include "negobs_port/clock.h"

static negobs_status_t console_set(void *ctx, uint16_t duty)
{
    negobs_motor_out_console_t *st = ctx;
    uint64_t now = negobs_clock_now_ms();
    if (duty > NEGOBS_MOTOR_FULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (!st->started) {
        st->started = true;
        st->t0_ms = now;
    } else if (st->last == duty) {
        return NEGOBS_OK;
    }
    st->last = duty;
    if (fprintf(st->out, "motor %6lu ms: %s %4u permille\n",
                (unsigned long)(now - st->t0_ms), duty > 0 ? "ON " : "off",
                (unsigned)duty) < 0) {
        return NEGOBS_ERR_IO;
    }
    (void)fflush(st->out);
    return NEGOBS_OK;
}

static void console_close(void *ctx)
{
    negobs_motor_out_console_t *st = ctx;
    if (st->out != NULL && st->started && st->last != 0) {
        (void)console_set(ctx, 0);
    }
}

static const negobs_motor_out_ops_t console_ops = {
    .name = "console",
    .set = console_set,
    .close = console_close,
};

negobs_status_t negobs_motor_out_console_open(negobs_motor_out_console_t *st,
                                              FILE *out,
                                              negobs_motor_out_t *alert)
{
    if (st == NULL || out == NULL || alert == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(st, 0, sizeof *st);
    st->out = out;
    alert->ops = &console_ops;
    alert->ctx = st;
    return NEGOBS_OK;
}
