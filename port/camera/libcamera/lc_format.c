/*
 * libcamera source helpers that need no libcamera: source-name parsing,
 * pixel-format preference and luma extraction. Compiled in every build so
 * they are unit-tested even where libcamera is absent.
 *
 * Formats are DRM fourccs (what libcamera::PixelFormat::fourcc() returns).
 * Note DRM's byte order: RGB888 ('RG24') is B, G, R in memory and BGR888
 * ('BG24') is R, G, B; XRGB8888 ('XR24') is B, G, R, X.
 */
#include <string.h>

#include "negobs_port/camera_libcamera.h"

#define FCC_R8 NEGOBS_DRM_FOURCC('R', '8', ' ', ' ')
#define FCC_NV12 NEGOBS_DRM_FOURCC('N', 'V', '1', '2')
#define FCC_NV21 NEGOBS_DRM_FOURCC('N', 'V', '2', '1')
#define FCC_YU12 NEGOBS_DRM_FOURCC('Y', 'U', '1', '2')
#define FCC_YV12 NEGOBS_DRM_FOURCC('Y', 'V', '1', '2')
#define FCC_NV16 NEGOBS_DRM_FOURCC('N', 'V', '1', '6')
#define FCC_NV61 NEGOBS_DRM_FOURCC('N', 'V', '6', '1')
#define FCC_YUYV NEGOBS_DRM_FOURCC('Y', 'U', 'Y', 'V')
#define FCC_UYVY NEGOBS_DRM_FOURCC('U', 'Y', 'V', 'Y')
#define FCC_YVYU NEGOBS_DRM_FOURCC('Y', 'V', 'Y', 'U')
#define FCC_VYUY NEGOBS_DRM_FOURCC('V', 'Y', 'U', 'Y')
#define FCC_RG24 NEGOBS_DRM_FOURCC('R', 'G', '2', '4')
#define FCC_BG24 NEGOBS_DRM_FOURCC('B', 'G', '2', '4')
#define FCC_XR24 NEGOBS_DRM_FOURCC('X', 'R', '2', '4')
#define FCC_XB24 NEGOBS_DRM_FOURCC('X', 'B', '2', '4')

/* Preference: Y plane in place, then packed YUV (one byte per pixel
 * copied), then RGB (a weighted sum per pixel). */
static const uint32_t format_order[] = {
    FCC_R8,   FCC_NV12, FCC_NV21, FCC_YU12, FCC_YV12,
    FCC_NV16, FCC_NV61, FCC_YUYV, FCC_UYVY, FCC_YVYU,
    FCC_VYUY, FCC_RG24, FCC_BG24, FCC_XR24, FCC_XB24,
};

negobs_status_t negobs_libcamera_parse_source(const char *src, int32_t *index,
                                              const char **id)
{
    const size_t plen = sizeof NEGOBS_LIBCAMERA_PREFIX - 1u;
    const char *p;
    size_t n;
    size_t i;
    if (src == NULL || index == NULL || id == NULL ||
        strncmp(src, NEGOBS_LIBCAMERA_PREFIX, plen) != 0) {
        return NEGOBS_ERR_INVAL;
    }
    p = src + plen;
    n = strlen(p);
    if (n == 0 || n >= NEGOBS_LIBCAMERA_ID_LEN) {
        return NEGOBS_ERR_INVAL;
    }
    for (i = 0; i < n && p[i] >= '0' && p[i] <= '9'; i++) {
    }
    if (i == n) {
        int32_t v = 0;
        if (n > 3) {
            return NEGOBS_ERR_INVAL; /* no rig has a thousand cameras */
        }
        for (i = 0; i < n; i++) {
            v = v * 10 + (int32_t)(p[i] - '0');
        }
        *index = v;
        *id = NULL;
        return NEGOBS_OK;
    }
    *index = -1;
    *id = p;
    return NEGOBS_OK;
}

int negobs_libcamera_format_rank(uint32_t fourcc)
{
    size_t i;
    for (i = 0; i < sizeof format_order / sizeof format_order[0]; i++) {
        if (format_order[i] == fourcc) {
            return (int)i;
        }
    }
    return -1;
}

/* Bytes per pixel of plane 0 and, for packed formats, where luma is. */
typedef struct lc_layout {
    uint32_t bpp;   /* bytes per pixel in plane 0 (YUYV: 2 per pixel) */
    bool packed;    /* luma must be computed                          */
    bool rgb;       /* weighted sum of three channels                 */
    uint32_t y_off; /* packed YUV: offset of luma in a pixel           */
    uint32_t r_off; /* RGB: offsets of R, G, B in a pixel              */
    uint32_t g_off;
    uint32_t b_off;
} lc_layout_t;

static bool layout_of(uint32_t fourcc, lc_layout_t *l)
{
    memset(l, 0, sizeof *l);
    l->bpp = 1;
    switch (fourcc) {
    case FCC_R8:
    case FCC_NV12:
    case FCC_NV21:
    case FCC_YU12:
    case FCC_YV12:
    case FCC_NV16:
    case FCC_NV61: return true;
    case FCC_YUYV:
    case FCC_YVYU:
        l->bpp = 2;
        l->packed = true;
        return true;
    case FCC_UYVY:
    case FCC_VYUY:
        l->bpp = 2;
        l->packed = true;
        l->y_off = 1;
        return true;
    case FCC_RG24: /* B G R */
    case FCC_XR24: /* B G R X */
        l->bpp = fourcc == FCC_RG24 ? 3u : 4u;
        l->packed = true;
        l->rgb = true;
        l->r_off = 2;
        l->g_off = 1;
        l->b_off = 0;
        return true;
    case FCC_BG24: /* R G B */
    case FCC_XB24: /* R G B X */
        l->bpp = fourcc == FCC_BG24 ? 3u : 4u;
        l->packed = true;
        l->rgb = true;
        l->r_off = 0;
        l->g_off = 1;
        l->b_off = 2;
        return true;
    default: return false;
    }
}

bool negobs_libcamera_format_packed(uint32_t fourcc)
{
    lc_layout_t l;
    return layout_of(fourcc, &l) && l.packed;
}

/* BT.601 luma in 1/256: 77 R + 150 G + 29 B sums to 256, so white stays
 * 255 and the result never overflows a byte. */
static inline uint8_t luma_601(uint32_t r, uint32_t g, uint32_t b)
{
    return (uint8_t)((77u * r + 150u * g + 29u * b + 128u) >> 8);
}

negobs_status_t negobs_libcamera_luma(uint32_t fourcc, uint8_t *base,
                                      size_t bytesused, int32_t width,
                                      int32_t height, uint32_t stride,
                                      uint8_t *scratch, size_t scratch_bytes,
                                      negobs_image_u8_t *out)
{
    lc_layout_t l;
    size_t need;
    int32_t x;
    int32_t y;
    if (base == NULL || out == NULL || width <= 0 || height <= 0 ||
        width > NEGOBS_MAX_DIM || height > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    if (!layout_of(fourcc, &l)) {
        return NEGOBS_ERR_UNSUPPORTED;
    }
    if ((size_t)stride < (size_t)width * l.bpp) {
        return NEGOBS_ERR_INVAL;
    }
    /* the last row need not be padded to the stride */
    need = (size_t)stride * (size_t)(height - 1) + (size_t)width * l.bpp;
    if (bytesused < need) {
        return NEGOBS_ERR_CORRUPT;
    }
    if (!l.packed) {
        if (stride > (uint32_t)INT32_MAX) {
            return NEGOBS_ERR_INVAL;
        }
        out->data = base;
        out->width = width;
        out->height = height;
        out->stride = (int32_t)stride;
        return NEGOBS_OK;
    }
    if (scratch == NULL || scratch_bytes < (size_t)width * (size_t)height) {
        return NEGOBS_ERR_NOSPACE;
    }
    for (y = 0; y < height; y++) {
        const uint8_t *src = base + (size_t)y * stride;
        uint8_t *dst = scratch + (size_t)y * (size_t)width;
        for (x = 0; x < width; x++) {
            const uint8_t *px = src + (size_t)x * l.bpp;
            dst[x] = l.rgb ? luma_601(px[l.r_off], px[l.g_off], px[l.b_off])
                           : px[l.y_off];
        }
    }
    out->data = scratch;
    out->width = width;
    out->height = height;
    out->stride = width;
    return NEGOBS_OK;
}
