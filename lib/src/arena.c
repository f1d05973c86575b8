#include "arena.h"

#include <string.h>

#ifdef NEGOBS_ARENA_GUARDS
#define GUARD_HEAD 16u
#define GUARD_TAIL 16u
#define GUARD_MAGIC 0x4E474F42u /* "NGOB" */
#define GUARD_BYTE 0xA5u
#else
#define GUARD_HEAD 0u
#define GUARD_TAIL 0u
#endif

static size_t round_up16(size_t n)
{
    return (n + (NEGOBS_ARENA_ALIGN - 1u)) &
           ~(size_t)(NEGOBS_ARENA_ALIGN - 1u);
}

void negobs_arena_init(negobs_arena_t *a, void *base, size_t capacity)
{
    a->base = (uint8_t *)base;
    a->capacity = (base == NULL) ? 0u : capacity;
    a->used = 0;
    a->err = NEGOBS_OK;
    if (base != NULL && !negobs_arena_aligned(base)) {
        a->err = NEGOBS_ERR_ALIGN;
    }
}

void *negobs_arena_take(negobs_arena_t *a, size_t bytes)
{
    size_t need;
    uint8_t *block;

    /* Refuse sizes whose rounding would wrap size_t. */
    if (bytes > (SIZE_MAX / 2u)) {
        a->err = NEGOBS_ERR_NOSPACE;
        return NULL;
    }
    need = GUARD_HEAD + round_up16(bytes) + GUARD_TAIL;
    if (a->err != NEGOBS_OK) {
        return NULL;
    }
    if (a->base == NULL) {
        if (need > SIZE_MAX - a->used) {
            a->err = NEGOBS_ERR_NOSPACE;
            return NULL;
        }
        a->used += need;
        return NULL;
    }
    if (need > a->capacity - a->used) {
        a->err = NEGOBS_ERR_NOSPACE;
        return NULL;
    }
    block = a->base + a->used;
    a->used += need;
#ifdef NEGOBS_ARENA_GUARDS
    {
        uint32_t head[4];
        head[0] = GUARD_MAGIC;
        head[1] = (uint32_t)bytes;
        head[2] = (uint32_t)((uint64_t)bytes >> 32);
        head[3] = ~GUARD_MAGIC;
        memcpy(block, head, sizeof head);
        memset(block + GUARD_HEAD + bytes, GUARD_BYTE,
               need - GUARD_HEAD - bytes);
    }
#endif
    return block + GUARD_HEAD;
}

negobs_status_t negobs_arena_check(const negobs_arena_t *a)
{
#ifdef NEGOBS_ARENA_GUARDS
    size_t pos = 0;
    if (a->base == NULL) {
        return NEGOBS_OK;
    }
    while (pos < a->used) {
        uint32_t head[4];
        size_t bytes;
        size_t need;
        size_t i;
        const uint8_t *block = a->base + pos;

        memcpy(head, block, sizeof head);
        if (head[0] != GUARD_MAGIC || head[3] != ~GUARD_MAGIC) {
            return NEGOBS_ERR_CORRUPT;
        }
        bytes = (size_t)((uint64_t)head[1] | ((uint64_t)head[2] << 32));
        need = GUARD_HEAD + round_up16(bytes) + GUARD_TAIL;
        if (bytes > SIZE_MAX / 2u || need > a->used - pos) {
            return NEGOBS_ERR_CORRUPT;
        }
        for (i = GUARD_HEAD + bytes; i < need; i++) {
            if (block[i] != GUARD_BYTE) {
                return NEGOBS_ERR_CORRUPT;
            }
        }
        pos += need;
    }
    return NEGOBS_OK;
#else
    (void)a;
    return NEGOBS_OK;
#endif
}
