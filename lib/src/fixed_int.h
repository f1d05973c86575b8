/*
 * Integer square roots (internal: the library and its tests only).
 */
#ifndef NEGOBS_FIXED_INT_H
#define NEGOBS_FIXED_INT_H

#include <stdint.h>

/**
 * @brief Integer square root of a 64-bit value: largest r with r * r <= x.
 *
 * Bit-by-bit method: at most 32 iterations, no division, same result
 * everywhere.
 */
static inline uint64_t negobs_isqrt_u64(uint64_t x)
{
    uint64_t r = 0;
    uint64_t bit = (uint64_t)1 << 62;
    while (bit > x) {
        bit >>= 2;
    }
    while (bit != 0) {
        if (x >= r + bit) {
            x -= r + bit;
            r = (r >> 1) + bit;
        } else {
            r >>= 1;
        }
        bit >>= 2;
    }
    return r;
}

/** @brief Integer square root: largest r with r * r <= x (32-bit). */
static inline uint32_t negobs_isqrt_u32(uint32_t x)
{
    return (uint32_t)negobs_isqrt_u64(x);
}

#endif /* NEGOBS_FIXED_INT_H */
