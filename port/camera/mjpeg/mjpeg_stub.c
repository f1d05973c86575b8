/* MJPEG decoding in a build without libturbojpeg: refused, clearly. */
#include "negobs_port/mjpeg.h"

bool negobs_mjpeg_available(void)
{
    return false;
}

negobs_status_t negobs_mjpeg_size(const uint8_t *jpeg, size_t bytes,
                                  int32_t *width, int32_t *height)
{
    (void)jpeg;
    (void)bytes;
    (void)width;
    (void)height;
    return NEGOBS_ERR_UNSUPPORTED;
}

negobs_status_t negobs_mjpeg_decode_grey(const uint8_t *jpeg, size_t bytes,
                                         int32_t width, int32_t height,
                                         uint8_t *dst, size_t stride)
{
    (void)jpeg;
    (void)bytes;
    (void)width;
    (void)height;
    (void)dst;
    (void)stride;
    return NEGOBS_ERR_UNSUPPORTED;
}
