/* A drop's depth over one whole pixel of floor disparity past its edge
 * (docs/DETECTION.md 5, "One pixel of floor"). */
#include "detect_internal.h"

/*
 * The drop past an edge over one whole pixel of floor disparity.
 *
 * The matcher's sub-pixel estimate errs with the fraction of the
 * disparity (pixel locking, docs/DISPARITY.md stage 5): on a floor the
 * fraction runs through a whole cycle every pixel of ground disparity, so
 * the error alternates in sign along the rows, about half a pixel of
 * disparity one way, half the other. On average over the floor that
 * ripple is 0.04-0.07 px peak to peak, but over the smooth interiors of
 * paving tiles it reached -0.15 and +0.1 px within a strip on a 6 cm rig
 * (OpenCV's SGBM read the same wave at the same rows, larger), and its
 * negative half then passed the rule as a 40-70 mm "drop". A lower
 * surface keeps its deficit over the whole cycle; the ripple averages
 * out over it. So the deficit is measured again as the mean of the
 * strip's row medians over the rows past the edge where the ground
 * disparity falls by one pixel (16 in Q4), as the same-ray height H (d_g
 * - d) / d. -1 when fewer than half of those rows can vote or the cycle
 * runs out of the scan (past range_max_mm, or the image's top). A stair's
 * deeper tread or a hole's far rim inside the cycle move the mean as
 * they move the floor: deeper, or back up towards the ground.
 */
int32_t det_unit_drop_mm(const scan_ctx_t *s, int32_t u0, int32_t u1,
                         int32_t edge_v)
{
    const int32_t uc = (u0 + u1) / 2;
    const int32_t dg0 = negobs_ground_disp_q4(s->plane, uc, edge_v);
    const uint8_t min_conf = (uint8_t)s->cfg->min_confidence;
    int64_t sum_r = 0;
    int64_t sum_g = 0;
    int32_t rows = 0;
    int32_t seen = 0;
    int32_t v;
    for (v = edge_v - 1; v >= 0; v--) {
        const int32_t dgc = negobs_ground_disp_q4(s->plane, uc, v);
        const int16_t *row = negobs_image_s16_row(s->disp, v);
        const uint8_t *crow = (s->conf != NULL)
                                  ? negobs_image_u8_row(s->conf, v)
                                  : NULL;
        int32_t r[MAX_STRIP_PX];
        int32_t n = 0;
        int32_t u;
        if (dg0 - dgc >= NEGOBS_DISP_ONE) {
            break; /* a whole cycle */
        }
        if (dgc < s->d_min_q4 || dgc <= 0) {
            return -1;
        }
        rows++;
        for (u = u0; u < u1; u++) {
            const int32_t d = row[u];
            if (d == NEGOBS_DISP_INVALID || d < 0 ||
                (crow != NULL && crow[u] < min_conf)) {
                continue;
            }
            /* a lower surface reads down to d = 0; a wild match above
             * the floor weighs as 2 px, as in the band noise */
            r[n++] = negobs_clamp_s32(
                d - negobs_ground_disp_q4(s->plane, u, v), -dgc,
                2 * NEGOBS_DISP_ONE);
        }
        if (n * 4 < (u1 - u0) || n < 3) {
            continue;
        }
        /* twice the median, so an even count needs no halving */
        sum_r += det_median2_s32(r, n);
        sum_g += 2 * (int64_t)dgc;
        seen++;
    }
    if (v < 0 || rows == 0 || seen * 2 < rows || sum_g + sum_r <= 0) {
        return -1;
    }
    if (sum_r >= 0) {
        return 0;
    }
    return (int32_t)geom_clamp_s64(
        ((int64_t)s->frame->height_mm * -sum_r) / (sum_g + sum_r), 0, 100000);
}
