/* Small int64 helpers shared by the detect stage (internal). */
#ifndef NEGOBS_DETECT_GEOM_INTERNAL_H
#define NEGOBS_DETECT_GEOM_INTERNAL_H

#include <stdint.h>

/* Floor shift of a signed 64-bit value (defined for negatives). */
static inline int64_t geom_asr_s64(int64_t x, int n)
{
    if (x >= 0) {
        return x >> n;
    }
    return -(int64_t)((uint64_t)(-(x + 1)) >> n) - 1;
}

/* x / 2^n rounded to nearest (ties up); |x| < 2^62. */
static inline int64_t geom_rshift_round_s64(int64_t x, int n)
{
    return geom_asr_s64(x + ((int64_t)1 << (n - 1)), n);
}

static inline int64_t geom_clamp_s64(int64_t x, int64_t lo, int64_t hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

static inline int32_t geom_min_s32(int32_t a, int32_t b)
{
    return (a < b) ? a : b;
}

static inline int32_t geom_max_s32(int32_t a, int32_t b)
{
    return (a > b) ? a : b;
}

#endif
