/*
 * Vectorised hot kernels of the disparity engine beside their plain C
 * references (the 5x5 cross sum lives in stereo_ncc.h). The SIMD forms
 * exist only where simd.h selects an instruction set (NEGOBS_SIMD);
 * tests/stereo/test_stereo_simd.c checks each bit for bit against its
 * reference. Internal to lib/src/stereo.
 */
#ifndef NEGOBS_STEREO_SIMD_H
#define NEGOBS_STEREO_SIMD_H

#include <stddef.h>
#include <stdint.h>

#include "simd.h"

/* ---- 5x5 window statistics of one image row (ncc.c, stats_simd.c) ---- */
/* rows[k] = image row y - 2 + k (k = 0..4), each w >= 5 pixels. For every
 * centre x in [2, w - 3]: so[x] = S (sum of the 25 grey values), vo[x] =
 * 25 Q - S^2 (Q the sum of squares; exact, < 2^24). Other entries are not
 * written. Plain C reference. */
void stx_stats_row_ref(const uint8_t *const rows[5], int32_t w, uint16_t *so,
                       uint32_t *vo);
/* Same contract and results; 16-byte loads for centres [2, w - 14] and the
 * reference formula for the rest, so it reads no byte outside the rows. */
void stx_stats_row(const uint8_t *const rows[5], int32_t w, uint16_t *so,
                   uint32_t *vo);

/* ---- adaptive-mean taps of 8 lanes (refine.c, amean_simd.c) ---------- */
/* tap[4] points to 8 centre values (Q4, NEGOBS_DISP_INVALID = hole),
 * tap[4 - j] and tap[4 + j] to the 8 values j steps before and after
 * (left/right or up/down). The line ends kl steps before and kr steps
 * after the centres (0..4 each; taps beyond are not read), so min(kl, kr)
 * pairs of taps count and the hole search looks kl back and kr forward.
 * out[l] is what refine.c's per-line filter gives at lane l. */
void stx_amean8_ref(const int16_t *const tap[9], int32_t kl, int32_t kr,
                    int16_t *out);
#if defined(NEGOBS_SIMD)
void stx_amean8_simd(const int16_t *const tap[9], int32_t kl, int32_t kr,
                     int16_t *out);
#endif

/* ---- 1/4-scale matching: zero-mean 3x3 SAD along a row (lowres.c,
 * zsad_simd.c) ------------------------------------------------------- */
/* out[l] = sum over the 3x3 window of |9 (a - b_l) - (Sa - Sb_l)| for the
 * fixed window centred at a and the n windows centred at b + l (S the
 * window sums; all windows inside their images, row stride `stride`).
 * Each cost is <= 9 * (9 * 255 + 2 295) = 41 310. Plain C reference. */
void stx_zsad3_run_ref(const uint8_t *a, const uint8_t *b, int32_t stride,
                       int32_t n, int32_t *out);
/* Same results; 8 windows per step (their loads stay inside the windows
 * of the run). */
void stx_zsad3_run(const uint8_t *a, const uint8_t *b, int32_t stride,
                   int32_t n, int32_t *out);

/* sd / sw rounded half away from zero (|sd| < 2^25, sw > 0): the adaptive
 * mean's division, shared by the reference and the SIMD forms. */
static inline int32_t stx_div_round_pos(int32_t sd, int32_t sw)
{
    if (sd >= 0) {
        return (sd + sw / 2) / sw;
    }
    return -((-sd + sw / 2) / sw);
}

#endif /* NEGOBS_STEREO_SIMD_H */
