/* "none" alert backend: accepts every level and does nothing. */
#include <stddef.h>

#include "negobs_port/motor.h"

static negobs_status_t none_set(void *ctx, uint16_t duty)
{
    (void)ctx;
    return duty > NEGOBS_MOTOR_FULL ? NEGOBS_ERR_INVAL : NEGOBS_OK;
}

static void none_close(void *ctx)
{
    (void)ctx;
}

static const negobs_motor_out_ops_t none_ops = {
    .name = "none",
    .set = none_set,
    .close = none_close,
};

negobs_status_t negobs_motor_out_none_open(negobs_motor_out_t *alert)
{
    if (alert == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    alert->ops = &none_ops;
    alert->ctx = NULL;
    return NEGOBS_OK;
}
