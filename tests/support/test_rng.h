/* The tests' one pseudo-random generator: a 32-bit LCG in integers, so
 * generated inputs and scenes are the same bytes on every target. */
#ifndef NEGOBS_TEST_RNG_H
#define NEGOBS_TEST_RNG_H

#include <stdint.h>

/* Advances *state; returns its top 24 bits (the low bits of an LCG have
 * short periods). */
static inline uint32_t test_lcg_next(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

/* Approximately standard normal: the sum of 12 uniforms from the LCG,
 * minus 6 (deterministic; for test images with a known noise). */
static inline double test_gauss12(uint32_t *state)
{
    double s = 0.0;
    int i;
    for (i = 0; i < 12; i++) {
        s += (double)test_lcg_next(state) / 16777216.0;
    }
    return s - 6.0;
}

#endif
