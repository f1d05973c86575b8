/*
 * The two steps of Canny that the image edges (stereo seeds) and the
 * disparity edges (detect support) share (internal): non-maximum
 * suppression along the quantised gradient direction, and one sweep of
 * the hysteresis done by raster sweeps (no recursion).
 */
#ifndef NEGOBS_CANNY_CORE_H
#define NEGOBS_CANNY_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/fixed.h"

/*
 * Whether magnitude m at column x, with Sobel gradients gx, gy, is a local
 * maximum across the edge. mu, mc, md are the magnitude rows above, at and
 * below it (columns x - 1 .. x + 1 readable). The direction is quantised
 * to 4 sectors by the slope test |gy| * 1000 < |gx| * 414 (tan 22.5 deg =
 * 0.4142); |gx|, |gy| <= 2^21 keep the products in int32. Of a plateau two
 * pixels wide along the direction the first pixel is kept (>= / >).
 */
static inline int canny_nms_keep(int32_t m, int32_t gx, int32_t gy,
                                 const uint16_t *mu, const uint16_t *mc,
                                 const uint16_t *md, ptrdiff_t x)
{
    int32_t ax = negobs_abs_s32(gx);
    int32_t ay = negobs_abs_s32(gy);
    int32_t n1;
    int32_t n2;
    if (ay * 1000 < ax * 414) {
        n1 = mc[x - 1];
        n2 = mc[x + 1];
    } else if (ay * 414 > ax * 1000) {
        n1 = mu[x];
        n2 = md[x];
    } else if ((gx > 0) == (gy > 0)) {
        n1 = mu[x - 1];
        n2 = md[x + 1];
    } else {
        n1 = mu[x + 1];
        n2 = md[x - 1];
    }
    return m >= n1 && m > n2;
}

/*
 * One raster sweep of hysteresis over labels (0 none, 1 weak, 2 edge) of
 * nr rows of nc: a weak pixel with an 8-neighbour edge becomes an edge, in
 * place, so a chain running with the sweep is followed in one go. Forward
 * or backward; returns the number of pixels promoted.
 */
static inline int32_t canny_hyst_sweep(uint8_t *lab, int32_t nr, int32_t nc,
                                       int backward)
{
    int32_t promoted = 0;
    int32_t total = nr * nc;
    int32_t i;
    for (i = 0; i < total; i++) {
        int32_t p = backward ? total - 1 - i : i;
        int32_t r = p / nc;
        int32_t c = p - r * nc;
        int32_t dr;
        if (lab[p] != 1u) {
            continue;
        }
        for (dr = -1; dr <= 1 && lab[p] == 1u; dr++) {
            int32_t dc;
            if (r + dr < 0 || r + dr >= nr) {
                continue;
            }
            for (dc = -1; dc <= 1; dc++) {
                if (c + dc >= 0 && c + dc < nc &&
                    lab[p + dr * nc + dc] == 2u) {
                    lab[p] = 2u;
                    promoted++;
                    break;
                }
            }
        }
    }
    return promoted;
}

#endif
