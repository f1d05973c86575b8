/*
 * MJPEG to grey through libjpeg-turbo's TurboJPEG API (turbojpeg.h of
 * libjpeg-turbo 2.1: tjDecompressHeader3, tjDecompress2).
 */
#include <limits.h>

#include <turbojpeg.h>

#include "negobs/image.h"
#include "negobs_port/mjpeg.h"

bool negobs_mjpeg_available(void)
{
    return true;
}

/* A JPEG starts with SOI (FF D8); the header parse needs a few segments. */
static bool looks_like_jpeg(const uint8_t *p, size_t n)
{
    return n >= 4u && p[0] == 0xFFu && p[1] == 0xD8u;
}

negobs_status_t negobs_mjpeg_size(const uint8_t *jpeg, size_t bytes,
                                  int32_t *width, int32_t *height)
{
    tjhandle h;
    int w = 0;
    int ht = 0;
    int sub = 0;
    int cs = 0;
    int rc;
    if (jpeg == NULL || width == NULL || height == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (!looks_like_jpeg(jpeg, bytes) || bytes > (size_t)ULONG_MAX) {
        return NEGOBS_ERR_CORRUPT;
    }
    h = tjInitDecompress();
    if (h == NULL) {
        return NEGOBS_ERR_IO;
    }
    rc = tjDecompressHeader3(h, jpeg, (unsigned long)bytes, &w, &ht, &sub,
                             &cs);
    (void)tjDestroy(h);
    if (rc != 0 || w < 1 || ht < 1 || w > NEGOBS_MAX_DIM ||
        ht > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_CORRUPT;
    }
    *width = (int32_t)w;
    *height = (int32_t)ht;
    return NEGOBS_OK;
}

negobs_status_t negobs_mjpeg_decode_grey(const uint8_t *jpeg, size_t bytes,
                                         int32_t width, int32_t height,
                                         uint8_t *dst, size_t stride)
{
    tjhandle h;
    int w = 0;
    int ht = 0;
    int sub = 0;
    int cs = 0;
    int rc;
    if (jpeg == NULL || dst == NULL || width < 1 || height < 1 ||
        width > NEGOBS_MAX_DIM || height > NEGOBS_MAX_DIM ||
        stride < (size_t)width || stride > (size_t)INT_MAX) {
        return NEGOBS_ERR_INVAL;
    }
    if (!looks_like_jpeg(jpeg, bytes) || bytes > (size_t)ULONG_MAX) {
        return NEGOBS_ERR_CORRUPT;
    }
    h = tjInitDecompress();
    if (h == NULL) {
        return NEGOBS_ERR_IO;
    }
    rc = tjDecompressHeader3(h, jpeg, (unsigned long)bytes, &w, &ht, &sub,
                             &cs);
    if (rc != 0 || w != (int)width || ht != (int)height) {
        (void)tjDestroy(h);
        return NEGOBS_ERR_CORRUPT;
    }
    /* Full size (scaling factor 1/1: the width and height asked are the
     * picture's). TJFLAG_STOPONWARNING: a truncated frame is an error,
     * not a picture with grey rows at the bottom. */
    rc = tjDecompress2(h, jpeg, (unsigned long)bytes, dst, w, (int)stride, ht,
                       TJPF_GRAY, TJFLAG_STOPONWARNING);
    (void)tjDestroy(h);
    return rc == 0 ? NEGOBS_OK : NEGOBS_ERR_CORRUPT;
}
