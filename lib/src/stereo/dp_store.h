/*
 * The DP's pointer store, the part dp.c inlines: the records' layout and
 * the taking of the next record (dp_store.c has the parts of the store and
 * their release), and the two-bit writer.
 */
#ifndef NEGOBS_STEREO_DP_STORE_H
#define NEGOBS_STEREO_DP_STORE_H

#include <stddef.h>
#include <stdint.h>

#include "stereo/stereo_state.h"

/* Where stage 1 puts a row's pointers: the row buffer s->p1 (stride
 * ndisp, int16 jump targets), or a store record with a byte or two bits
 * per band cell, packed column after column (byte jump targets). */
#define STX_P1_STRIDED 0
#define STX_P1_BYTES 1
#define STX_P1_BITS 2

/* Two-bit fields appended to a byte stream, the first in the low bits of
 * the first byte (no byte order involved): collected in a 64-bit word and
 * written out every 28 fields, so a write spans at most 8 bytes. */
typedef struct stx_bitw {
    uint8_t *base;
    size_t pos; /* bits written out */
    uint64_t word;
    int32_t n; /* bits in word */
} stx_bitw_t;

static inline __attribute__((always_inline)) void stx_bitw_flush(stx_bitw_t *b)
{
    uint8_t *p = b->base + (b->pos >> 3);
    uint32_t sh = (uint32_t)(b->pos & 7u);
    uint64_t v = b->word << sh;
    int32_t left = b->n + (int32_t)sh - 8;
    /* keep the fields already in the first byte; the rest is overwritten */
    *p = (uint8_t)((*p & ((1u << sh) - 1u)) | (uint8_t)v);
    while (left > 0) {
        v >>= 8;
        *++p = (uint8_t)v;
        left -= 8;
    }
    b->pos += (size_t)b->n;
    b->word = 0;
    b->n = 0;
}

static inline __attribute__((always_inline)) void stx_bitw_put(stx_bitw_t *b,
                                                               uint32_t t)
{
    b->word |= (uint64_t)t << b->n;
    b->n += 2;
    if (b->n == 56) {
        stx_bitw_flush(b);
    }
}

/* The layout of the store's records: a byte per cell in the memo (it
 * has the room, and bytes are cheaper to write), two bits in the strip
 * scratch (about 2.4 bytes per pixel instead of 6.5, so most rows fit). */
static inline int stx_dp_store_layout(const stx_t *s)
{
    return s->dps_memo ? STX_P1_BYTES : STX_P1_BITS;
}

/* The next record of the band's part of the store for a row of `cells`
 * band cells: jump targets of columns 0..w (a byte each; entry w: the last
 * column's argmax), then the pointers (stx_dp_store_layout()). NULL when
 * there is no store, with dp_rescore (its back-track needs the cost row,
 * which is not kept), or when the record does not fit; such a row runs
 * stage 1 in both passes. Both passes make the same decisions: the same
 * cell counts in the same order, pass 1 limited to what pass 0 used. */
static inline uint8_t *stx_dp_store_take(stx_t *s, int32_t cells)
{
    size_t need = (size_t)s->w + 1u +
                  ((stx_dp_store_layout(s) == STX_P1_BITS)
                       ? ((size_t)cells * 2u + 7u) / 8u
                       : (size_t)cells);
    uint8_t *rec;
    if (s->dps == NULL || s->cfg.dp_rescore ||
        need > s->dps_end - s->dps_pos) {
        return NULL;
    }
    rec = s->dps + s->dps_pos;
    s->dps_pos += need;
    return rec;
}

#endif /* NEGOBS_STEREO_DP_STORE_H */
