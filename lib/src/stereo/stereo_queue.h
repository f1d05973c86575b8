/*
 * Bounded bucket queue of the growth stage (queue.c) and the packed
 * (u, v, d) items it holds. Internal to lib/src/stereo.
 */
#ifndef NEGOBS_STEREO_QUEUE_H
#define NEGOBS_STEREO_QUEUE_H

#include <stdint.h>

#define STX_NBUCKET 257 /* bucket queue: c_q14 >> 6        */

typedef struct stx_queue {
    uint32_t *item; /* packed u:12 | v:12 | d:8                       */
    int32_t *next;  /* singly linked LIFO per bucket / spare list     */
    int32_t *head;  /* STX_NBUCKET heads, -1 = empty                  */
    int32_t free_head;
    int32_t cap;
    int32_t count;
    int32_t top; /* highest possibly non-empty bucket              */
    uint32_t peak;
    uint32_t overflows;
} stx_queue_t;

void stx_queue_reset(stx_queue_t *q);
/* stx_queue_push() when every slot is used (queue.c). */
int stx_queue_push_full(stx_queue_t *q, uint32_t item, int32_t key);

/* Push with key (clamped to 0..STX_NBUCKET-1). When full, the lowest-key
 * entry is evicted if the new key is higher, otherwise the new entry is
 * dropped; either way `overflows` is incremented. Returns 1 if stored.
 * Inline: the growth pushes once per accepted cell. */
static inline int stx_queue_push(stx_queue_t *q, uint32_t item, int32_t key)
{
    int32_t slot;
    key = (key < 0) ? 0 : ((key >= STX_NBUCKET) ? STX_NBUCKET - 1 : key);
    if (q->free_head < 0) {
        return stx_queue_push_full(q, item, key);
    }
    slot = q->free_head;
    q->free_head = q->next[slot];
    q->item[slot] = item;
    q->next[slot] = q->head[key];
    q->head[key] = slot;
    q->count++;
    if ((uint32_t)q->count > q->peak) {
        q->peak = (uint32_t)q->count;
    }
    if (key > q->top) {
        q->top = key;
    }
    return 1;
}

/* Pop an entry of the highest non-empty bucket; 0 (and item 0) when
 * empty. */
static inline int stx_queue_pop(stx_queue_t *q, uint32_t *item)
{
    int32_t slot;
    while (q->top >= 0 && q->head[q->top] < 0) {
        q->top--;
    }
    if (q->top < 0) {
        *item = 0u; /* defined on every path */
        return 0;
    }
    slot = q->head[q->top];
    q->head[q->top] = q->next[slot];
    *item = q->item[slot];
    q->next[slot] = q->free_head;
    q->free_head = slot;
    q->count--;
    return 1;
}

static inline uint32_t stx_pack(int32_t u, int32_t v, int32_t d)
{
    return ((uint32_t)u << 20) | ((uint32_t)v << 8) | (uint32_t)d;
}
static inline int32_t stx_unpack_u(uint32_t p)
{
    return (int32_t)(p >> 20);
}
static inline int32_t stx_unpack_v(uint32_t p)
{
    return (int32_t)((p >> 8) & 0xFFFu);
}
static inline int32_t stx_unpack_d(uint32_t p)
{
    return (int32_t)(p & 0xFFu);
}

#endif /* NEGOBS_STEREO_QUEUE_H */
