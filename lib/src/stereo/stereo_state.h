/*
 * The disparity engine's private state (stx_t), carved from the caller's
 * workspace by stereo.c: carve(), and the constants every stage shares.
 * Internal to lib/src/stereo.
 *
 * Rows are processed in horizontal strips of `strip_rows` rows: window
 * statistics, Canny, the GCS matching table and the seed queue only exist
 * for one strip at a time, which is what keeps the compact profile's
 * workspace near 512 KB at 320x240 with 64 disparities. Full-frame state is
 * limited to the low-resolution range maps and the DP stage-2 pointers
 * (H x D bytes). The fast profile adds the strip's correlation memo.
 *
 * Fixed-point conventions (see docs/DISPARITY.md):
 *   correlation scores  Q14 int32, 16384 = 1.0 (MNCC in [-1, 1])
 *   table scores        Q8 uint8, 255 ~ 1.0, 0 = "none / -inf"
 *   disparities         integer px inside the engine, Q4 on output
 */
#ifndef NEGOBS_STEREO_STATE_H
#define NEGOBS_STEREO_STATE_H

#include <stddef.h>
#include <stdint.h>

#include "arena.h"
#include "negobs/stereo.h"
#include "stereo/stereo_queue.h"

#define STX_WIN_R 2  /* 5x5 window                      */
#define STX_WIN_N 25 /* pixels per window               */
#define STX_ONE_Q14 16384
#define STX_FLAT INT32_MIN /* "no texture": score undefined   */
#define STX_LOWRES 4       /* elementary map scale (1/4)      */
#define STX_NONE8 0xFFu    /* empty u8 disparity slot         */
#define STX_CACHE_BITS 11  /* growth score cache: 2048 entries */
/* The cache's slot of key k is (k * STX_CACHE_HASH) >> (32 - STX_CACHE_BITS)
 * (Fibonacci hashing). The product is taken mod 2^32, so it distributes over
 * a sum of keys: the growth adds a neighbour's premultiplied offset to the
 * popped cell's premultiplied key instead of multiplying per neighbour. */
#define STX_CACHE_HASH 2654435761u
#define STX_VSEARCH_MAX 4 /* largest vertical_search (rows)   */

/* One cached correlation of the growth stage (key 0 = empty). */
typedef struct stx_cache_entry {
    uint32_t key; /* stx_pack(u, v - y0, d - dmin) + 1                 */
    int32_t num2; /* MNCC fraction, den == 0: flat / no score          */
    int32_t den;
} stx_cache_entry_t;

/* What one band's growth found (bands.c), so a band grown again at the
 * seam counts once in the statistics. */
typedef struct stx_band_result {
    uint32_t seeds, grown, gcs_matched, edges;
} stx_band_result_t;

/* Private state of one context (negobs_stereo_t.priv). */
typedef struct stx {
    negobs_stereo_config_t cfg;
    int32_t w, h;        /* frame being matched (h: a crop's height)   */
    int32_t first_row;   /* negobs_stereo_set_first_row (0 = all rows) */
    int32_t vhold;       /* negobs_stereo_hold_vertical_offset: rows */
    int32_t vhold_set;   /* 1: the next frame uses vhold, no search   */
    int32_t dmin, ndisp; /* configured range: dmin .. dmin+ndisp-1     */
    int32_t sh;          /* strip rows                                 */

    /* frame inputs (set by process) */
    const negobs_image_u8_t *left;
    const negobs_image_u8_t *right;
    int32_t voff;         /* right row = left row + voff                */
    int32_t gdmin, gdmax; /* global search range of this frame          */

    /* strip window statistics, strip-relative rows */
    int32_t y0, y1;    /* strip rows [y0, y1)                        */
    uint16_t *sl, *sr; /* 5x5 sums                                   */
    uint32_t *vl, *vr; /* 25*Q - S^2 (= n^2 var), 0 = no window      */

    /* Canny (strip + 1 halo row each side) */
    uint16_t *mag;
    uint8_t *edge;

    /* GCS matching table for one strip (u8 Q8 scores, d - dmin) */
    uint8_t *ld, *lc, *lc2;
    uint8_t *rd, *rc, *rc2;
    uint8_t *tbits; /* (v, u, d) triple membership, 1 bit each    */
    stx_queue_t q;
    stx_cache_entry_t *cache; /* direct-mapped, 1 << STX_CACHE_BITS       */
    /* fast profile: correlation memo of the strip (NULL in compact) */
    uint32_t *memo;     /* (strip pixel, level) -> stamp | numerator  */
    uint8_t *memo_base; /* strip pixel: first memoised d - dmin       */
    int32_t memo_k;     /* levels per pixel (0 = no memo)             */
    uint32_t memo_gen;  /* stamp of the current strip, 1 .. 63        */

    /* elementary low-resolution map and per-tile ranges */
    int32_t lw, lh; /* low-res size                               */
    uint8_t *lo_l, *lo_r;
    uint8_t *lo_d;        /* low-res disparity (d4 - dmin4), 0xFF none   */
    int32_t tile, tw, th; /* tile size (px) and tile grid               */
    int16_t *tile_lo, *tile_hi;
    uint32_t *hist; /* ndisp/4 + 2 bins                           */

    /* partial results of the band jobs of stages 6 and 1 (bands.c;
     * NULL with one worker) */
    int64_t *vscore; /* bands x (2 STX_VSEARCH_MAX + 1) offset scores */
    uint32_t *lhist; /* bands x (ndisp/4 + 2) low-res histograms     */
    uint32_t *lkept; /* bands: low-res values kept                   */

    /* DP */
    int32_t *yprev, *ycur;  /* ndisp + 2 scores each (stage 1)            */
    int64_t *zprev, *zcur;  /* ndisp (stage 2)                            */
    uint8_t *p1;            /* w x ndisp stage-1 pointers of one row      */
    int16_t *cost;          /* w x ndisp Q14 costs of one row (sub-pixel) */
    int16_t *jump_to;       /* w: argmax of previous column               */
    int16_t *blo, *bhi;     /* w: band per column                         */
    uint8_t *bscored;       /* w: 1 = band cells scored (GCS match)       */
    int16_t *rowd;          /* w: GCS disparities of the current row      */
    const int16_t *gcs_cur; /* GCS row being processed by the DP          */
    uint8_t *p2;            /* h x ndisp stage-2 pointers                 */
    int16_t *dend;          /* h: stage-2 end disparity per row          */
    int16_t *zarg;          /* h: argmax of stage-2 scores per row       */
    int32_t zrows;          /* rows fed to stage 2 so far                */
    /* stage-1 pointer store (dp.c): scratch lent to the DP (the growth's
     * memo or its strip scratch, worker 0's), NULL: none */
    uint8_t *dps;
    size_t dps_cap;
    size_t dps_start, dps_pos, dps_end; /* the band's part, next record */
    uint32_t dps_used[NEGOBS_STEREO_MAX_BANDS]; /* bytes, by pass 0    */

    /* row bands (bands.c): per-row stage-1 end scores when several
     * workers run pass 0 at once (NULL with one worker: the rows then
     * reach stage 2 in order and are fed to it directly) */
    int32_t band_y0; /* first row of the band being grown            */
    int32_t *yend;   /* h x ndisp stage-1 end scores                 */
    uint8_t *yhave;  /* h: 1 = the row had a GCS match               */
    struct stx *wk;  /* band_workers - 1 worker states (bands.c)     */
    stx_band_result_t band_res[NEGOBS_STEREO_MAX_BANDS];
    uint8_t band_done[NEGOBS_STEREO_MAX_BANDS]; /* jobs of the last run */
    /* dispatch order (bands.c: stx_bands_order): job j of a run is band
     * band_order[j], costliest first by the last frame's work counts */
    uint8_t band_order[NEGOBS_STEREO_MAX_BANDS];
    uint32_t band_work[NEGOBS_STEREO_MAX_BANDS]; /* cells scored */
    int32_t band_work_h;  /* rows of the frame band_work is of    */
    int32_t band_work_nb; /* its band count (0: no frame yet)     */
    int exec_failed;      /* an executor skipped a job or named a bad worker */
    int dps_memo;         /* 1: the DP's store is the memo (dp.c)   */
    negobs_executor_t exec; /* run == NULL: the caller's thread       */

    /* refinement */
    int16_t *line; /* max(w, h) + 16 scratch                     */
    int16_t *line2;
    uint8_t *vis;        /* h rows of (w + 7) / 8 bytes: speckle visited */
    uint8_t *keep;       /* the same: speckle "big region"               */
    uint32_t *flood;     /* speckle_size + 2 entries (per worker)      */
    uint32_t *flood_out; /* the same: a band flood's pixels outside it */

    /* optional profiling clock (negobs_stereo_set_clock) */
    negobs_stereo_clock_fn clock;
    void *clock_user;
    uint32_t lap; /* clock value at the end of the last stage   */
    /* optional observer of intermediate maps (negobs_stereo_set_observer) */
    negobs_stereo_observer_fn observer;
    void *observer_user;

    negobs_stereo_stats_t st;
    negobs_arena_t arena; /* the carve, for negobs_arena_check()        */
} stx_t;

/* Fast profile: the growth's memo word (gcs.c). It holds the numerator
 * of a cell's exact MNCC fraction num2 / den as num2 + 2^25 in its low 26
 * bits (|num2| <= den = VL + VR <= 2 * 625 * 255^2 / 4 < 2^25, so a real
 * value is never 0; 0 marks a flat window), and the strip's stamp
 * (1 .. STX_MEMO_GEN_MAX) above them, so a word written for an earlier
 * strip reads as empty without clearing the table each strip. The
 * denominator is rebuilt from the window statistics (two loads). */
#define STX_MEMO_NUM_BITS 26
#define STX_MEMO_NUM_MASK ((1u << STX_MEMO_NUM_BITS) - 1u)
#define STX_MEMO_NUM_BIAS (1 << (STX_MEMO_NUM_BITS - 1))
#define STX_MEMO_GEN_MAX ((1u << (32 - STX_MEMO_NUM_BITS)) - 1u)

/* Word of stamp gen for the fraction num2 / den (den == 0: flat). */
static inline uint32_t stx_memo_pack(uint32_t gen, int32_t num2, int32_t den)
{
    return (gen << STX_MEMO_NUM_BITS) |
           ((den != 0) ? (uint32_t)(num2 + STX_MEMO_NUM_BIAS) : 0u);
}

/* num2 of a word's non-zero low bits nb. */
static inline int32_t stx_memo_num2(uint32_t nb)
{
    return (int32_t)nb - STX_MEMO_NUM_BIAS;
}

#endif /* NEGOBS_STEREO_STATE_H */
