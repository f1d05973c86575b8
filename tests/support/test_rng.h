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

#endif
