#include "negobs/boxsum.h"

#include "integral.h"

#include <string.h>

negobs_status_t negobs_integral_u8(const negobs_image_u8_t *img, uint32_t *sum,
                                   uint32_t *sumsq, size_t elems)
{
    int32_t x;
    int32_t y;
    int32_t is;

    if (negobs_image_u8_check(img) != NEGOBS_OK || sum == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (elems < negobs_integral_elems(img->width, img->height)) {
        return NEGOBS_ERR_NOSPACE;
    }
    is = img->width + 1;
    memset(sum, 0, (size_t)is * sizeof *sum);
    if (sumsq != NULL) {
        memset(sumsq, 0, (size_t)is * sizeof *sumsq);
    }
    for (y = 0; y < img->height; y++) {
        const uint8_t *row = negobs_image_u8_row(img, y);
        uint32_t *prev = sum + (ptrdiff_t)y * is;
        uint32_t *cur = prev + is;
        uint32_t run = 0;
        uint32_t runsq = 0;
        cur[0] = 0;
        for (x = 0; x < img->width; x++) {
            run += row[x];
            cur[x + 1] = prev[x + 1] + run; /* wraps mod 2^32 by design */
        }
        if (sumsq != NULL) {
            uint32_t *prevq = sumsq + (ptrdiff_t)y * is;
            uint32_t *curq = prevq + is;
            curq[0] = 0;
            for (x = 0; x < img->width; x++) {
                uint32_t v = row[x];
                runsq += v * v;
                curq[x + 1] = prevq[x + 1] + runsq;
            }
        }
    }
    return NEGOBS_OK;
}

negobs_status_t negobs_boxsum_u8(const negobs_image_u8_t *img, int32_t radius,
                                 uint16_t *sum, int32_t sum_stride,
                                 uint32_t *sumsq, int32_t sq_stride,
                                 uint32_t *colbuf)
{
    int32_t w;
    int32_t h;
    int32_t x;
    int32_t y;
    int32_t win;
    uint32_t *col;
    uint32_t *colq;

    if (negobs_image_u8_check(img) != NEGOBS_OK || sum == NULL ||
        colbuf == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (radius < 1 || radius > NEGOBS_BOXSUM_MAX_RADIUS) {
        return NEGOBS_ERR_INVAL;
    }
    w = img->width;
    h = img->height;
    win = 2 * radius + 1;
    if (w < win || h < win || sum_stride < w ||
        (sumsq != NULL && sq_stride < w)) {
        return NEGOBS_ERR_INVAL;
    }
    col = colbuf;
    colq = colbuf + w;
    memset(colbuf, 0, 2u * (size_t)w * sizeof *colbuf);

    /*
     * Column sums are kept for the window of rows [y - r, y + r]; each step
     * adds the row entering at the bottom and removes the one leaving at the
     * top, so a pixel costs O(1) whatever the radius.
     */
    for (y = 0; y < 2 * radius; y++) {
        const uint8_t *row = negobs_image_u8_row(img, y);
        for (x = 0; x < w; x++) {
            uint32_t v = row[x];
            col[x] += v;
            colq[x] += v * v;
        }
    }
    for (y = 0; y < h; y++) {
        uint16_t *srow = sum + (ptrdiff_t)y * sum_stride;
        uint32_t *qrow = (sumsq != NULL) ? sumsq + (ptrdiff_t)y * sq_stride
                                         : NULL;
        if (y < radius || y >= h - radius) {
            memset(srow, 0, (size_t)w * sizeof *srow);
            if (qrow != NULL) {
                memset(qrow, 0, (size_t)w * sizeof *qrow);
            }
            continue;
        }
        {
            const uint8_t *in = negobs_image_u8_row(img, y + radius);
            uint32_t s = 0;
            uint32_t q = 0;
            for (x = 0; x < w; x++) {
                uint32_t v = in[x];
                col[x] += v;
                colq[x] += v * v;
            }
            for (x = 0; x < win - 1; x++) {
                s += col[x];
                q += colq[x];
            }
            for (x = 0; x < radius; x++) {
                srow[x] = 0;
                srow[w - 1 - x] = 0;
                if (qrow != NULL) {
                    qrow[x] = 0;
                    qrow[w - 1 - x] = 0;
                }
            }
            for (x = radius; x < w - radius; x++) {
                s += col[x + radius];
                q += colq[x + radius];
                srow[x] = (uint16_t)s;
                if (qrow != NULL) {
                    qrow[x] = q;
                }
                s -= col[x - radius];
                q -= colq[x - radius];
            }
            {
                const uint8_t *out = negobs_image_u8_row(img, y - radius);
                for (x = 0; x < w; x++) {
                    uint32_t v = out[x];
                    col[x] -= v;
                    colq[x] -= v * v;
                }
            }
        }
    }
    return NEGOBS_OK;
}
