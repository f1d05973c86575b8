/* A 16-byte aligned block for a library workspace, inside a malloc'd one
 * (C99 has no aligned_alloc): the pipeline tests' one allocator. */
#ifndef NEGOBS_TEST_WS_H
#define NEGOBS_TEST_WS_H

#include <stdint.h>
#include <stdlib.h>

#include "cmocka_all.h"

/* bytes usable at the returned address; *raw is what to free(). */
static inline void *test_aligned_ws(size_t bytes, void **raw)
{
    *raw = malloc(bytes + 16u);
    assert_non_null(*raw);
    return (void *)(((uintptr_t)*raw + 15u) & ~(uintptr_t)15u);
}

#endif
