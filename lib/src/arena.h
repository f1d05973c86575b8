/*
 * Workspace arena: a bump allocator over caller memory (internal).
 *
 * Every module carves its buffers with the same function in two modes: with
 * a NULL base it only counts bytes (this is how *_workspace_size() gets an
 * exact answer), with a real base it hands out 16-byte aligned blocks. As the
 * same carving code runs in both modes, the size query cannot drift from
 * what init needs.
 *
 * With NEGOBS_ARENA_GUARDS (debug builds) each block is framed by a 16-byte
 * header and a tail of canary bytes up to the next 16-byte boundary plus 16;
 * negobs_arena_check() walks the blocks and reports an overrun as
 * NEGOBS_ERR_CORRUPT.
 */
#ifndef NEGOBS_ARENA_H
#define NEGOBS_ARENA_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/status.h"

#define NEGOBS_ARENA_ALIGN 16u

typedef struct negobs_arena {
    uint8_t *base;       /* NULL: measuring mode                      */
    size_t capacity;     /* bytes available at base                   */
    size_t used;         /* bytes handed out (with guards)            */
    negobs_status_t err; /* first error seen, sticky                  */
} negobs_arena_t;

/* base may be NULL (measure only); a non-NULL base must be 16-aligned. */
void negobs_arena_init(negobs_arena_t *a, void *base, size_t capacity);

/*
 * Take `bytes` (may be 0) aligned to 16. Returns NULL in measuring mode or
 * when the arena is exhausted; exhaustion sets a->err = NEGOBS_ERR_NOSPACE and
 * every later take fails too, so a carve function can check once at the end.
 */
void *negobs_arena_take(negobs_arena_t *a, size_t bytes);

/* NEGOBS_OK, or the first error of a take. */
static inline negobs_status_t negobs_arena_status(const negobs_arena_t *a)
{
    return a->err;
}

/* Bytes a real arena would need for the takes made so far. */
static inline size_t negobs_arena_used(const negobs_arena_t *a)
{
    return a->used;
}

/* NEGOBS_OK if every guard is intact (always OK without guards). */
negobs_status_t negobs_arena_check(const negobs_arena_t *a);

/* True when a pointer is aligned for the workspace. */
static inline int negobs_arena_aligned(const void *p)
{
    return ((uintptr_t)p % NEGOBS_ARENA_ALIGN) == 0u;
}

#endif /* NEGOBS_ARENA_H */
