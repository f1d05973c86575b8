/*
 * The libcamera source in builds without libcamera: init() says so, so
 * negobs_run can name the backend in every build and fail with a clear
 * message instead of a link error.
 */
#include <stddef.h>

#include "negobs_port/camera_libcamera.h"

negobs_status_t negobs_libcamera_init(negobs_libcamera_t *st,
                                      uint8_t *scratch, size_t scratch_bytes,
                                      negobs_capture_t *cam)
{
    (void)scratch;
    (void)scratch_bytes;
    if (st == NULL || cam == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_ERR_UNSUPPORTED;
}

bool negobs_libcamera_available(void)
{
    return false;
}
