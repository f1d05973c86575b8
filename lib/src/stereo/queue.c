/*
 * Bounded bucket priority queue for the growing stage (docs/DISPARITY.md).
 *
 * Keys are correlation scores c_q14 >> 6 (257 buckets over [0, 1]); each
 * bucket is a LIFO list threaded through one fixed array of `cap` slots, so
 * push and pop are O(1) and the memory is 8 bytes per slot. Order inside a
 * bucket is approximate (1/256 in correlation), which is harmless: the final
 * stable selection, not the growth order, decides the matches.
 *
 * Overflow policy (defined, counted): when all slots are used, a push with a
 * key above the lowest non-empty bucket evicts one entry of that bucket;
 * otherwise the new entry is dropped. Every eviction or drop increments
 * `overflows`. The lowest candidates are the least likely to win, so this
 * loses the least.
 */
#include "stereo/stereo_int.h"

void stx_queue_reset(stx_queue_t *q)
{
    int32_t i;
    for (i = 0; i < STX_NBUCKET; i++) {
        q->head[i] = -1;
    }
    for (i = 0; i < q->cap; i++) {
        q->next[i] = (i + 1 < q->cap) ? i + 1 : -1;
    }
    q->free_head = (q->cap > 0) ? 0 : -1;
    q->count = 0;
    q->top = -1;
    q->peak = 0;
    q->overflows = 0;
}

int stx_queue_push_full(stx_queue_t *q, uint32_t item, int32_t key)
{
    int32_t slot;
    int32_t lo = 0;
    q->overflows++;
    while (lo < STX_NBUCKET && q->head[lo] < 0) {
        lo++;
    }
    if (lo >= STX_NBUCKET || key <= lo) {
        return 0; /* drop the newcomer */
    }
    slot = q->head[lo]; /* evict one of the lowest */
    q->head[lo] = q->next[slot];
    q->item[slot] = item;
    q->next[slot] = q->head[key];
    q->head[key] = slot;
    if (key > q->top) {
        q->top = key;
    }
    return 1;
}
