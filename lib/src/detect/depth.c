/*
 * Stereo geometry: depth from disparity and CORDIC angle helpers.
 */
#include "negobs/depth.h"

#include <stddef.h>

#include "negobs/fixed.h"
#include "negobs/image.h"
#include "detect_int.h"

#define CORDIC_ITERS 24
/* CORDIC gain 1/prod(sqrt(1 + 2^-2i)) for 24 iterations, Q30. */
#define CORDIC_K_Q30 652032874

/* atan(2^-i) in 1/256 millidegree. */
static const int32_t cordic_atan_tab[CORDIC_ITERS] = {
    11520000, 6800653, 3593278, 1824004, 915542, 458217, 229164, 114589,
    57295,    28648,   14324,   7162,    3581,   1790,   895,    448,
    224,      112,     56,      28,      14,     7,      3,      2};

/* Floor shift of a signed value, defined for negatives (C99 leaves >> of
 * negative values implementation-defined). */
static int64_t asr64(int64_t x, int n)
{
    if (x >= 0) {
        return x >> n;
    }
    return -(int64_t)((uint64_t)(-(x + 1)) >> n) - 1;
}

void negobs_rig_default(negobs_rig_t *rig, int32_t width, int32_t height)
{
    rig->width = width;
    rig->height = height;
    /* f = 250 px at 320 px width, scaled with the width. */
    rig->focal_q4 = (int32_t)(((int64_t)250 * 16 * width + 160) / 320);
    rig->cx_q4 = (width - 1) * 8;
    rig->cy_q4 = (height - 1) * 8;
    rig->baseline_um = 120000;
}

negobs_status_t negobs_rig_check(const negobs_rig_t *rig)
{
    if (rig == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (rig->width < 16 || rig->height < 16 || rig->width > NEGOBS_MAX_DIM ||
        rig->height > NEGOBS_MAX_DIM) {
        return NEGOBS_ERR_INVAL;
    }
    if (rig->focal_q4 < 16 || rig->focal_q4 > 8192 * 16) {
        return NEGOBS_ERR_INVAL;
    }
    if (rig->cx_q4 < 0 || rig->cx_q4 > rig->width * 16 || rig->cy_q4 < 0 ||
        rig->cy_q4 > rig->height * 16) {
        return NEGOBS_ERR_INVAL;
    }
    if (rig->baseline_um < 1000 || rig->baseline_um > 1000000) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

int32_t negobs_depth_mm_from_disp_q4(const negobs_rig_t *rig, int32_t disp_q4)
{
    int64_t num;
    int64_t den;
    int64_t z;

    if (disp_q4 <= 0 || disp_q4 == NEGOBS_DISP_INVALID) {
        return NEGOBS_DEPTH_NONE_MM;
    }
    num = (int64_t)rig->focal_q4 * rig->baseline_um;
    den = (int64_t)disp_q4 * 1000;
    z = (num + den / 2) / den;
    if (z > NEGOBS_DEPTH_MAX_MM) {
        z = NEGOBS_DEPTH_MAX_MM;
    }
    return (int32_t)z;
}

int32_t negobs_disp_q4_from_depth_mm(const negobs_rig_t *rig, int32_t depth_mm)
{
    int64_t num;
    int64_t den;
    int64_t d;

    if (depth_mm <= 0) {
        return 0;
    }
    num = (int64_t)rig->focal_q4 * rig->baseline_um;
    den = (int64_t)depth_mm * 1000;
    d = (num + den / 2) / den;
    if (d > INT16_MAX) {
        d = INT16_MAX;
    }
    return (int32_t)d;
}

int32_t negobs_lateral_mm(const negobs_rig_t *rig, int32_t u_q4,
                          int32_t depth_mm)
{
    int64_t num = ((int64_t)u_q4 - rig->cx_q4) * depth_mm;
    int64_t x = negobs_div_round_s64(num, rig->focal_q4);
    if (x > INT32_MAX) {
        x = INT32_MAX;
    } else if (x < -INT32_MAX) {
        x = -INT32_MAX;
    }
    return (int32_t)x;
}

int32_t negobs_atan2_mdeg(int64_t y, int64_t x)
{
    int64_t z = 0;
    int64_t ax;
    int64_t ay;
    int64_t m;
    int i;
    int32_t offset = 0;

    if (x == 0 && y == 0) {
        return 0;
    }
    /* Keep the vector in the right half-plane; remember the half-turn. */
    if (x < 0) {
        offset = (y >= 0) ? 180000 : -180000;
        x = -x;
        y = -y;
    }
    /* Normalise the magnitude into [2^28, 2^29) so the iterations have
     * guard bits for the 1.65 CORDIC growth and full precision. */
    ax = x;
    ay = (y < 0) ? -y : y;
    m = (ax > ay) ? ax : ay;
    while (m >= ((int64_t)1 << 29)) {
        x = asr64(x, 1);
        y = asr64(y, 1);
        m >>= 1;
    }
    while (m < ((int64_t)1 << 28)) {
        x *= 2;
        y *= 2;
        m *= 2;
    }
    for (i = 0; i < CORDIC_ITERS; i++) {
        int64_t xs = asr64(x, i);
        int64_t ys = asr64(y, i);
        if (y > 0) {
            x += ys;
            y -= xs;
            z += cordic_atan_tab[i];
        } else {
            x -= ys;
            y += xs;
            z -= cordic_atan_tab[i];
        }
    }
    /* z is in 1/256 mdeg; round to mdeg. */
    z = asr64(z + 128, 8);
    z += offset;
    if (z <= -180000) {
        z += 360000;
    }
    if (z > 180000) {
        z -= 360000;
    }
    return (int32_t)z;
}

void negobs_sincos_q30(int32_t angle_mdeg, int32_t *sin_q30, int32_t *cos_q30)
{
    int64_t a = angle_mdeg % 360000;
    int64_t x = CORDIC_K_Q30;
    int64_t y = 0;
    int64_t z;
    int negate = 0;
    int i;

    if (a > 180000) {
        a -= 360000;
    } else if (a <= -180000) {
        a += 360000;
    }
    if (a > 90000) {
        a -= 180000;
        negate = 1;
    } else if (a < -90000) {
        a += 180000;
        negate = 1;
    }
    z = a * 256;
    for (i = 0; i < CORDIC_ITERS; i++) {
        int64_t xs = asr64(x, i);
        int64_t ys = asr64(y, i);
        if (z >= 0) {
            x -= ys;
            y += xs;
            z -= cordic_atan_tab[i];
        } else {
            x += ys;
            y -= xs;
            z += cordic_atan_tab[i];
        }
    }
    if (negate) {
        x = -x;
        y = -y;
    }
    if (x > ((int64_t)1 << 30)) {
        x = (int64_t)1 << 30;
    }
    if (y > ((int64_t)1 << 30)) {
        y = (int64_t)1 << 30;
    }
    if (sin_q30 != NULL) {
        *sin_q30 = (int32_t)y;
    }
    if (cos_q30 != NULL) {
        *cos_q30 = (int32_t)x;
    }
}
