/* cmocka needs these system headers first, in this order. */
#ifndef NEGOBS_TEST_CMOCKA_ALL_H
#define NEGOBS_TEST_CMOCKA_ALL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

/* Deterministic generator for test inputs (same on every target). */
static inline uint32_t test_lcg_next(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

#endif
