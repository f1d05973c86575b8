/*
 * Fixed-point types and saturating helpers.
 *
 * The core never uses floating point. Quantities carry their format in
 * their names: `_q15` is Q1.15 (int16, [-1, 1)), `disp_q4` is disparity in
 * 1/16 pixel (int16), `_mm` is integer millimetres. docs/FIXED_POINT.md
 * lists every format used by the library.
 */
#ifndef NEGOBS_FIXED_H
#define NEGOBS_FIXED_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NEGOBS_Q15_MAX INT16_MAX
#define NEGOBS_Q15_MIN INT16_MIN

/** Fractional bits of a disparity in 1/16 px. */
#define NEGOBS_DISP_FRAC_BITS 4
/** One pixel of disparity in disp_q4 units. */
#define NEGOBS_DISP_ONE 16
/** Marker for "no disparity here" in disp_q4 images. */
#define NEGOBS_DISP_INVALID INT16_MIN

/*
 * Right shifts of negative signed values are implementation-defined in C99
 * (6.5.7p5). Parts of the library shift negative int32/int64 sums and
 * products directly (the detector's and the ground fit's accumulators, for
 * speed and for a floor that division does not give) and so assume the
 * shift is arithmetic: the sign propagates, x >> n == floor(x / 2^n). GCC,
 * Clang, armcc/armclang, IAR and MSVC all shift that way on every target
 * we build for. C99 has no _Static_assert, so these typedefs check it when
 * the header is compiled: on a compiler that shifts any other way the array
 * size is -1 and the build stops here instead of giving other results.
 * New code should prefer the helpers below (negobs_rshift_round_s32, ...),
 * which do not depend on it.
 */
typedef char negobs_assert_arithmetic_rshift_s32
    [(((int32_t)-5 >> 1) == -3 && ((int32_t)-1 >> 31) == -1) ? 1 : -1];
typedef char
    negobs_assert_arithmetic_rshift_s64[(((int64_t)-5 >> 1) == -3 &&
                                         ((int64_t)-1 >> 63) == -1 &&
                                         ((int64_t)INT64_MIN >> 62) == -2)
                                            ? 1
                                            : -1];

/** @brief Clamp a 32-bit value into [lo, hi]. */
static inline int32_t negobs_clamp_s32(int32_t x, int32_t lo, int32_t hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

/** @brief Saturate an int32 to int16 (also the Q31->Q15 clip after >> 16). */
static inline int16_t negobs_sat_s32_to_s16(int32_t x)
{
    return (int16_t)negobs_clamp_s32(x, INT16_MIN, INT16_MAX);
}

/**
 * @brief Arithmetic right shift by n (1..31) with round-half-up.
 *
 * Scaling and overflow: adds 2^(n-1) first, so x must be at most
 * INT32_MAX - 2^(n-1). Negative values round towards +infinity on ties
 * (-1.5 -> -1), which keeps the result the same on every compiler because
 * the shift of a negative value is done on the biased magnitude.
 */
static inline int32_t negobs_rshift_round_s32(int32_t x, int n)
{
    int32_t half = (int32_t)1 << (n - 1);
    int32_t y = x + half;
    /* C99 leaves >> of negatives implementation-defined: use division. */
    if (y >= 0) {
        return y >> n;
    }
    return -(int32_t)(((uint32_t)(-(y + 1)) >> n) + 1u);
}

/** @brief |x| for int32 without the INT32_MIN trap (saturates to MAX). */
static inline int32_t negobs_abs_s32(int32_t x)
{
    if (x == INT32_MIN) {
        return INT32_MAX;
    }
    return (x < 0) ? -x : x;
}

/**
 * @brief Signed division rounded to nearest (ties away from zero).
 * @param den must be non-zero; the caller guarantees it.
 */
static inline int64_t negobs_div_round_s64(int64_t num, int64_t den)
{
    if (den < 0) {
        num = -num;
        den = -den;
    }
    if (num >= 0) {
        return (num + den / 2) / den;
    }
    return -((-num + den / 2) / den);
}

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_FIXED_H */
