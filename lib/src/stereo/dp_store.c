/*
 * The DP's pointer store (dp.c): scratch idle while the DP runs, lent to
 * it by carve() (stereo.c): worker 0's memo in the fast profile, its strip
 * scratch otherwise. Each row band takes records for its rows, in order,
 * from its part of the store; pass 1 takes the same records again, so a
 * row that got one in pass 0 is back-tracked from it.
 */
#include <string.h>

#include "stereo/stereo_int.h"

/* Rows [y0, y1)'s part [*a, *b) of the store: shares proportional to the
 * rows, so the parts depend on the band layout only; whole 32-bit words
 * (the lent memo's), so no band's record shares a word with another's. */
static void store_part(const stx_t *s, int32_t y0, int32_t y1, size_t *a,
                       size_t *b)
{
    uint64_t cap = (uint64_t)s->dps_cap;
    *a = (size_t)(cap * (uint64_t)y0 / (uint64_t)s->h) & ~(size_t)3;
    *b = (size_t)(cap * (uint64_t)y1 / (uint64_t)s->h) & ~(size_t)3;
}

void stx_dp_store_begin(stx_t *s, int32_t y0, int32_t y1, size_t limit)
{
    size_t a;
    size_t b;
    store_part(s, y0, y1, &a, &b);
    s->dps_start = a;
    s->dps_pos = a;
    s->dps_end = (b - a < limit) ? b : a + limit;
}

size_t stx_dp_store_used(const stx_t *s)
{
    return s->dps_pos - s->dps_start;
}

void stx_dp_store_release(stx_t *s, int32_t y0, int32_t y1, size_t used)
{
    size_t a;
    size_t b;
    if (s->dps == NULL || used == 0 || !s->dps_memo) {
        return; /* (the growth's strip scratch is set up every strip) */
    }
    store_part(s, y0, y1, &a, &b);
    /* the lent memo: a zero word reads as empty (stx_memo_pack); a word
     * the records only began must not keep its old stamp */
    memset(s->dps + a, 0, (used + 3u) & ~(size_t)3);
}
