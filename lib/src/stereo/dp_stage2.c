/*
 * Stage 4, second DP stage (Sun 2002; dp.c runs the first along the rows):
 * down the end column x = W-1 over each row's normalised end scores
 * Y(W-1, y, d) - max_d Y(W-1, y, d), with the same |dd| <= 1 plus
 * penalised jump recurrence, then back-tracked to one end disparity per
 * row (s->dend), from which dp.c back-tracks the row. h x ndisp steps,
 * about 1 % of the frame.
 */
#include <string.h>

#include "stereo/stereo_int.h"

#define NEG32 STX_DP_NEG32
#define NEG64 (INT64_MIN / 4)

void stx_dp_stage2_reset(stx_t *s)
{
    s->zrows = 0;
}

void stx_dp_stage2_feed(stx_t *s, int32_t y, int have, const int32_t *ye)
{
    int32_t nd = s->ndisp;
    int32_t jump = s->cfg.dp_jump_q14;
    int32_t ymax = NEG32;
    int64_t zbest = NEG64;
    int32_t zarg = 0;
    int32_t i;
    uint8_t *p = s->p2 + (ptrdiff_t)y * nd;
    int64_t pbest = NEG64;
    int32_t parg = 0;

    if (have) {
        for (i = 0; i < nd; i++) {
            if (ye[i] > ymax) {
                ymax = ye[i];
            }
        }
    }
    if (s->zrows > 0) {
        for (i = 0; i < nd; i++) {
            if (s->zprev[i] > pbest) {
                pbest = s->zprev[i];
                parg = i;
            }
        }
        s->zarg[y - 1] = (int16_t)parg;
    }
    for (i = 0; i < nd; i++) {
        int64_t e;
        int64_t m;
        int t = 1;
        if (!have) {
            e = 0; /* a row without matches says nothing */
        } else if (ye[i] <= NEG32) {
            s->zcur[i] = NEG64;
            p[i] = 1u;
            continue;
        } else {
            e = (int64_t)ye[i] - ymax;
        }
        if (s->zrows == 0) {
            m = 0;
        } else {
            m = s->zprev[i];
            if (i > 0 && s->zprev[i - 1] > m) {
                m = s->zprev[i - 1];
                t = 0;
            }
            if (i + 1 < nd && s->zprev[i + 1] > m) {
                m = s->zprev[i + 1];
                t = 2;
            }
            if (pbest - jump > m) {
                m = pbest - jump;
                t = 3;
            }
        }
        s->zcur[i] = m + e;
        p[i] = (uint8_t)t;
        if (s->zcur[i] > zbest) {
            zbest = s->zcur[i];
            zarg = i;
        }
    }
    (void)zarg;
    memcpy(s->zprev, s->zcur, (size_t)nd * sizeof *s->zprev);
    s->zrows++;
}

void stx_dp_stage2_feed_stored(stx_t *s)
{
    int32_t y;
    for (y = 0; y < s->h; y++) {
        stx_dp_stage2_feed(s, y, s->yhave[y],
                           s->yend + (ptrdiff_t)y * s->ndisp);
    }
}

void stx_dp_stage2_finish(stx_t *s)
{
    int32_t nd = s->ndisp;
    int32_t y;
    int32_t d = 0;
    int64_t best = NEG64;
    int32_t i;
    if (s->zrows == 0) {
        return;
    }
    for (i = 0; i < nd; i++) {
        if (s->zprev[i] > best) {
            best = s->zprev[i];
            d = i;
        }
    }
    for (y = s->zrows - 1; y >= 0; y--) {
        int t;
        s->dend[y] = (int16_t)(d + s->dmin);
        if (y == 0) {
            break;
        }
        t = s->p2[(ptrdiff_t)y * nd + d];
        if (t == 3) {
            d = s->zarg[y - 1];
        } else {
            d = negobs_clamp_s32(d + t - 1, 0, nd - 1);
        }
    }
}
