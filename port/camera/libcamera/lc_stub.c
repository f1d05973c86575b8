/*
 * The libcamera source in builds without libcamera: init() fills the
 * handle with ops that refuse with a clear message and returns
 * NEGOBS_ERR_UNSUPPORTED, so negobs_run can name the backend in every build
 * and fail with a sentence instead of a link error or a NULL ops table.
 */
#include <stdio.h>
#include <string.h>

#include "negobs_port/camera_libcamera.h"

static const char not_built[] =
    "libcamera backend not built in (no libcamera-dev at configure time, "
    "or -Dlibcamera=disabled)";

static negobs_status_t stub_open(void *ctx, const negobs_capture_config_t *cfg)
{
    (void)ctx;
    (void)cfg;
    return NEGOBS_ERR_UNSUPPORTED;
}

static negobs_status_t stub_start(void *ctx)
{
    (void)ctx;
    return NEGOBS_ERR_STATE;
}

static int stub_get_pair(void *ctx, negobs_frame_pair_t *pair,
                         int32_t timeout_ms)
{
    (void)ctx;
    (void)pair;
    (void)timeout_ms;
    return NEGOBS_ERR_STATE;
}

static void stub_release(void *ctx, negobs_frame_pair_t *pair)
{
    (void)ctx;
    (void)pair;
}

static void stub_void(void *ctx)
{
    (void)ctx;
}

static void stub_stats(void *ctx, negobs_capture_stats_t *out)
{
    (void)ctx;
    memset(out, 0, sizeof *out);
}

static const char *stub_errmsg(void *ctx)
{
    (void)ctx;
    return not_built;
}

static const negobs_capture_ops_t stub_ops = {
    .name = "libcamera",
    .open = stub_open,
    .start = stub_start,
    .get_pair = stub_get_pair,
    .release = stub_release,
    .stop = stub_void,
    .close = stub_void,
    .stats = stub_stats,
    .errmsg = stub_errmsg,
};

negobs_status_t negobs_libcamera_init(negobs_libcamera_t *st, uint8_t *scratch,
                                      size_t scratch_bytes,
                                      negobs_capture_t *cam)
{
    (void)scratch;
    (void)scratch_bytes;
    if (st == NULL || cam == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(st, 0, sizeof *st);
    (void)snprintf(st->errmsg, sizeof st->errmsg, "%s", not_built);
    cam->ops = &stub_ops;
    cam->ctx = st;
    return NEGOBS_ERR_UNSUPPORTED;
}

bool negobs_libcamera_available(void)
{
    return false;
}
