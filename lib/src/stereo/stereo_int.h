/*
 * Disparity engine internals (not installed).
 *
 * One private state block is carved from the caller's workspace by
 * negobs_stereo_carve() (stereo.c), which runs twice: once in measuring
 * mode for negobs_stereo_workspace_size() and once for real in init, so the
 * size query cannot drift from what init consumes.
 *
 * Rows are processed in horizontal strips of `strip_rows` rows: window
 * statistics, Canny, the GCS matching table and the seed queue only exist
 * for one strip at a time, which is what keeps the workspace near
 * 512 KB at 320x240 with 64 disparities. Full-frame state is limited to the
 * low-resolution range maps and the DP stage-2 pointers (H x D bytes).
 *
 * Fixed-point conventions (see docs/DISPARITY.md):
 *   correlation scores  Q14 int32, 16384 = 1.0 (MNCC in [-1, 1])
 *   table scores        Q8 uint8, 255 ~ 1.0, 0 = "none / -inf"
 *   disparities         integer px inside the engine, Q4 on output
 */
#ifndef NEGOBS_STEREO_INT_H
#define NEGOBS_STEREO_INT_H

#include <stddef.h>
#include <stdint.h>

#include "arena.h"

#if defined(__SSE2__) && !defined(NEGOBS_NO_SIMD)
#include <emmintrin.h>
#elif defined(__ARM_NEON) && defined(__aarch64__) && !defined(NEGOBS_NO_SIMD)
#include <arm_neon.h>
#endif
#include "negobs/stereo.h"

#define STX_WIN_R 2                 /* 5x5 window                      */
#define STX_WIN_N 25                /* pixels per window               */
#define STX_ONE_Q14 16384
#define STX_FLAT INT32_MIN          /* "no texture": score undefined   */
#define STX_LOWRES 4                /* elementary map scale (1/4)      */
#define STX_NBUCKET 257             /* bucket queue: c_q14 >> 6        */
#define STX_NONE8 0xFFu             /* empty u8 disparity slot         */
#define STX_CACHE_BITS 11           /* growth score cache: 2048 entries */

/* One cached correlation of the growth stage (key 0 = empty). */
typedef struct stx_cache_entry {
    uint32_t key;   /* stx_pack(u, v - y0, d - dmin) + 1                 */
    int32_t num2;   /* MNCC fraction, den == 0: flat / no score          */
    int32_t den;
} stx_cache_entry_t;

/* ---- bounded bucket queue (queue.c) ---------------------------------- */
typedef struct stx_queue {
    uint32_t *item;   /* packed u:12 | v:12 | d:8                       */
    int32_t *next;    /* singly linked LIFO per bucket / spare list     */
    int32_t *head;    /* STX_NBUCKET heads, -1 = empty                  */
    int32_t free_head;
    int32_t cap;
    int32_t count;
    int32_t top;      /* highest possibly non-empty bucket              */
    uint32_t peak;
    uint32_t overflows;
} stx_queue_t;

void stx_queue_reset(stx_queue_t *q);
/* Push with key (0..STX_NBUCKET-1). When full, the lowest-key entry is
 * evicted if the new key is higher, otherwise the new entry is dropped;
 * either way `overflows` is incremented. Returns 1 if stored. */
int stx_queue_push(stx_queue_t *q, uint32_t item, int32_t key);
/* Pop an entry of the highest non-empty bucket; 0 when empty. */
int stx_queue_pop(stx_queue_t *q, uint32_t *item);

static inline uint32_t stx_pack(int32_t u, int32_t v, int32_t d)
{
    return ((uint32_t)u << 20) | ((uint32_t)v << 8) | (uint32_t)d;
}
static inline int32_t stx_unpack_u(uint32_t p) { return (int32_t)(p >> 20); }
static inline int32_t stx_unpack_v(uint32_t p)
{
    return (int32_t)((p >> 8) & 0xFFFu);
}
static inline int32_t stx_unpack_d(uint32_t p) { return (int32_t)(p & 0xFFu); }

/* ---- private state ---------------------------------------------------- */
typedef struct stx {
    negobs_stereo_config_t cfg;
    int32_t w, h;          /* frame being matched (h: a crop's height)   */
    int32_t first_row;     /* negobs_stereo_set_first_row (0 = all rows) */
    int32_t dmin, ndisp;   /* configured range: dmin .. dmin+ndisp-1     */
    int32_t sh;            /* strip rows                                 */

    /* frame inputs (set by process) */
    const negobs_image_u8_t *left;
    const negobs_image_u8_t *right;
    int32_t voff;          /* right row = left row + voff                */
    int32_t gdmin, gdmax;  /* global search range of this frame          */

    /* strip window statistics, strip-relative rows */
    int32_t y0, y1;        /* strip rows [y0, y1)                        */
    uint16_t *sl, *sr;     /* 5x5 sums                                   */
    uint32_t *vl, *vr;     /* 25*Q - S^2 (= n^2 var), 0 = no window      */

    /* Canny (strip + 1 halo row each side) */
    uint16_t *mag;
    uint8_t *edge;

    /* GCS matching table for one strip (u8 Q8 scores, d - dmin) */
    uint8_t *ld, *lc, *lc2;
    uint8_t *rd, *rc, *rc2;
    uint8_t *tbits;        /* (v, u, d) triple membership, 1 bit each    */
    stx_queue_t q;
    stx_cache_entry_t *cache; /* direct-mapped, 1 << STX_CACHE_BITS       */
    /* fast profile: cross-sum memo of the strip (NULL in compact) */
    uint32_t *memo;        /* (strip pixel, level) -> gen << 21 | sum    */
    uint8_t *memo_base;    /* strip pixel: first memoised d - dmin       */
    int32_t memo_k;        /* levels per pixel (0 = no memo)             */
    uint32_t memo_gen;     /* stamp of the current strip, 1 .. 2047      */

    /* elementary low-resolution map and per-tile ranges */
    int32_t lw, lh;        /* low-res size                               */
    uint8_t *lo_l, *lo_r;
    uint8_t *lo_d;         /* low-res disparity (d4 - dmin4), 0xFF none   */
    int32_t tile, tw, th;  /* tile size (px) and tile grid               */
    int16_t *tile_lo, *tile_hi;
    uint32_t *hist;        /* ndisp/4 + 2 bins                           */

    /* DP */
    int32_t *yprev, *ycur; /* ndisp + 2 scores each (stage 1)            */
    int64_t *zprev, *zcur; /* ndisp (stage 2)                            */
    uint8_t *p1;           /* w x ndisp stage-1 pointers of one row      */
    int16_t *cost;         /* w x ndisp Q14 costs of one row (sub-pixel) */
    int16_t *jump_to;      /* w: argmax of previous column               */
    int16_t *blo, *bhi;    /* w: band per column                         */
    uint8_t *bscored;      /* w: 1 = band cells scored (GCS match)       */
    int16_t *rowd;         /* w: GCS disparities of the current row      */
    const int16_t *gcs_cur; /* GCS row being processed by the DP          */
    uint8_t *p2;           /* h x ndisp stage-2 pointers                 */
    int16_t *dend;         /* h: stage-2 end disparity per row          */
    int16_t *zarg;         /* h: argmax of stage-2 scores per row       */
    int32_t zrows;         /* rows fed to stage 2 so far                */

    /* refinement */
    int16_t *line;         /* max(w, h) + 16 scratch                     */
    int16_t *line2;
    uint8_t *vis;          /* w*h bits: speckle visited                  */
    uint8_t *keep;         /* w*h bits: speckle "big region"             */
    uint32_t *flood;       /* speckle_size + 1 entries                   */

    /* optional profiling clock (negobs_stereo_set_clock) */
    negobs_stereo_clock_fn clock;
    void *clock_user;
    uint32_t lap;          /* clock value at the end of the last stage   */
    /* optional observer of intermediate maps (negobs_stereo_set_observer) */
    negobs_stereo_observer_fn observer;
    void *observer_user;

    negobs_stereo_stats_t st;
    negobs_arena_t arena;  /* the carve, for negobs_arena_check()        */
} stx_t;

/* ---- ncc.c ------------------------------------------------------------ */
/* Window statistics of image rows [ya, ya+n): S and V per pixel; windows
 * leaving the image get V = 0 (no window). */
void stx_stats_rows(const negobs_image_u8_t *img, int32_t ya, int32_t n,
                    uint16_t *s, uint32_t *v);
/* MNCC of 5x5 windows in Q14 from sums: 2*num/(VL+VR). STX_FLAT when
 * VL+VR < tex_min. */
int32_t stx_mncc_q14(uint32_t sum_lr, uint32_t sl, uint32_t vl, uint32_t sr,
                     uint32_t vr, uint32_t tex_min);
/* num2 / den in Q14, rounded towards zero (den > 0, |num2| <= den). */
int32_t stx_frac_q14(int32_t num2, int32_t den);

/* The common scale of stx_frac_q14: |num2| and den shifted right together
 * by the fewest bits that bring den below 2^17, in fixed steps of 8, 4, 2,
 * 1, 1 instead of a loop. A step is taken only when den stays >= 2^17
 * after it, so the total is the least shift; each step leaves den below
 * the next step's bound, so the last one ends below 2^17 for any den. */
static inline void stx_frac_scale(uint32_t *a, uint32_t *d)
{
    if (*d >= (1u << 25)) {
        *d >>= 8;
        *a >>= 8;
    }
    if (*d >= (1u << 21)) {
        *d >>= 4;
        *a >>= 4;
    }
    if (*d >= (1u << 19)) {
        *d >>= 2;
        *a >>= 2;
    }
    if (*d >= (1u << 18)) {
        *d >>= 1;
        *a >>= 1;
    }
    if (*d >= (1u << 17)) {
        *d >>= 1;
        *a >>= 1;
    }
}

/* stx_frac_q14(num2, den) >= t_q14 without the division (den > 0,
 * t_q14 <= 16384): the quotient is floored, so q >= t exactly when
 * (a << 14) >= t d, and t d < 2^31 after the scaling. */
static inline int stx_frac_reaches(int32_t num2, int32_t den, int32_t t_q14)
{
    uint32_t a;
    uint32_t d;
    if (t_q14 <= 0) {
        return stx_frac_q14(num2, den) >= t_q14;
    }
    if (num2 <= 0) {
        return 0; /* the fraction is <= 0 < t */
    }
    a = (uint32_t)num2;
    d = (uint32_t)den;
    stx_frac_scale(&a, &d);
    if (a > d) {
        a = d;
    }
    return (a << 14) >= (uint32_t)t_q14 * d;
}
/* MNCC of candidate (u, v, d) with statistics of the current strip; v is an
 * image row inside the strip. STX_FLAT when out of bounds or flat. */
int32_t stx_mncc_strip(const stx_t *s, int32_t u, int32_t v, int32_t d);
/* Same from the images only (window sums computed directly). */
int32_t stx_mncc_direct(const stx_t *s, int32_t u, int32_t v, int32_t d,
                        int32_t voff);
/* S and V of the 5x5 window at (x, y), straight from the image (the window
 * must be inside). */
void stx_sums5(const negobs_image_u8_t *img, int32_t x, int32_t y,
               uint32_t *sum, uint32_t *var);
/* Compute strip statistics for rows [y0, y1) (right uses s->voff). */
void stx_strip_stats(stx_t *s, int32_t y0, int32_t y1);

/* ---- hot MNCC kernels (inline: called millions of times) ---------- */
/* 2*num and den of the MNCC (no division); 0 when flat. */
static inline int stx_mncc_num_den(uint32_t sum_lr, uint32_t sl, uint32_t vl, uint32_t sr,
                     uint32_t vr, uint32_t tex_min, int32_t *num2,
                     int32_t *den)
{
    uint32_t d = vl + vr;
    int32_t num;
    if (d < tex_min || d == 0u) {
        return 0;
    }
    num = (int32_t)((uint32_t)STX_WIN_N * sum_lr) - (int32_t)(sl * sr);
    *num2 = 2 * num; /* |2 num| <= VL + VR < 2^25 */
    *den = (int32_t)d;
    return 1;
}

/* Raw 5x5 cross sum of the windows at a (left) and b (right), pointers to
 * their top-left pixels: the plain C reference of every variant below. */
static inline uint32_t stx_cross5_ref(const uint8_t *a, ptrdiff_t sa,
                                      const uint8_t *b, ptrdiff_t sb)
{
    uint32_t acc = 0;
    int32_t k;
    for (k = 0; k < 5; k++) {
        acc += (uint32_t)a[0] * b[0] + (uint32_t)a[1] * b[1] +
               (uint32_t)a[2] * b[2] + (uint32_t)a[3] * b[3] +
               (uint32_t)a[4] * b[4];
        a += sa;
        b += sb;
    }
    return acc;
}

#if defined(__SSE2__) && !defined(NEGOBS_NO_SIMD)
#define STX_CROSS5_SIMD 1
/* SSE2 form of stx_cross5_ref (bit-exact: integer sums in any order).
 * Each row is an 8-byte load whose last 3 left bytes are masked to zero, so
 * it reads 3 bytes past the window on the right: the caller guarantees
 * they are inside the row. Two rows share one register; PMADDWD of the
 * zero-extended bytes gives pairs of products (<= 130 050, no overflow). */
static inline uint32_t stx_cross5_simd(const uint8_t *a, ptrdiff_t sa,
                                       const uint8_t *b, ptrdiff_t sb)
{
    const __m128i z = _mm_setzero_si128();
    const __m128i m5 = _mm_set_epi32(0xFF, -1, 0xFF, -1);
    __m128i x;
    __m128i y;
    __m128i acc;
    x = _mm_and_si128(_mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)a),
                                         _mm_loadl_epi64((const __m128i *)(a + sa))),
                      m5);
    y = _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)b),
                           _mm_loadl_epi64((const __m128i *)(b + sb)));
    acc = _mm_add_epi32(
        _mm_madd_epi16(_mm_unpacklo_epi8(x, z), _mm_unpacklo_epi8(y, z)),
        _mm_madd_epi16(_mm_unpackhi_epi8(x, z), _mm_unpackhi_epi8(y, z)));
    a += 2 * sa;
    b += 2 * sb;
    x = _mm_and_si128(_mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)a),
                                         _mm_loadl_epi64((const __m128i *)(a + sa))),
                      m5);
    y = _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)b),
                           _mm_loadl_epi64((const __m128i *)(b + sb)));
    acc = _mm_add_epi32(
        acc,
        _mm_madd_epi16(_mm_unpacklo_epi8(x, z), _mm_unpacklo_epi8(y, z)));
    acc = _mm_add_epi32(
        acc,
        _mm_madd_epi16(_mm_unpackhi_epi8(x, z), _mm_unpackhi_epi8(y, z)));
    a += 2 * sa;
    b += 2 * sb;
    x = _mm_and_si128(_mm_loadl_epi64((const __m128i *)a), m5);
    y = _mm_loadl_epi64((const __m128i *)b);
    acc = _mm_add_epi32(
        acc,
        _mm_madd_epi16(_mm_unpacklo_epi8(x, z), _mm_unpacklo_epi8(y, z)));
    acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, 0x4E));
    acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, 0xB1));
    return (uint32_t)_mm_cvtsi128_si32(acc);
}
#elif defined(__ARM_NEON) && defined(__aarch64__) && !defined(NEGOBS_NO_SIMD)
#define STX_CROSS5_SIMD 1
/* AArch64 NEON form of stx_cross5_ref (bit-exact, same load contract as
 * the SSE2 form: 8-byte row loads, the 3 bytes past the window masked to
 * zero on the left). VMULL.U8 gives exact 16-bit products (<= 65 025),
 * VPADAL adds their pairs into 32-bit lanes (<= 130 050 per row and lane),
 * the lanes are summed once at the end (<= 1 625 625). Not built under
 * -mgeneral-regs-only (__ARM_NEON is then undefined), so the integer-only
 * hygiene check compiles the reference path. */
static inline uint32_t stx_cross5_simd(const uint8_t *a, ptrdiff_t sa,
                                       const uint8_t *b, ptrdiff_t sb)
{
    const uint8x8_t m5 = vcreate_u8(UINT64_C(0x000000FFFFFFFFFF));
    uint32x4_t acc = vdupq_n_u32(0);
    int32_t k;
    for (k = 0; k < 5; k++) {
        acc = vpadalq_u16(acc, vmull_u8(vand_u8(vld1_u8(a), m5),
                                        vld1_u8(b)));
        a += sa;
        b += sb;
    }
    return vaddvq_u32(acc);
}
#endif /* STX_CROSS5_SIMD: defined only where a SIMD form exists */

/* Raw 5x5 cross sum at left (u, yl) and right (ur, yr); both windows
 * inside their images, ur <= u. */
static inline uint32_t stx_cross5(const negobs_image_u8_t *l, int32_t u, int32_t yl,
                    const negobs_image_u8_t *r, int32_t ur, int32_t yr)
{
    const uint8_t *a = negobs_image_u8_row(l, yl - STX_WIN_R) + u - STX_WIN_R;
    const uint8_t *b = negobs_image_u8_row(r, yr - STX_WIN_R) + ur - STX_WIN_R;
#if defined(STX_CROSS5_SIMD)
    /* the 8-byte loads end at column x + 5: inside the row for both */
    if (u + 5 < l->width && ur + 5 < r->width) {
        return stx_cross5_simd(a, l->stride, b, r->stride);
    }
#endif
    return stx_cross5_ref(a, l->stride, b, r->stride);
}

/* Strip-statistics MNCC as a fraction; 0 when out of bounds or flat. */
static inline int stx_mncc_frac(const stx_t *s, int32_t u, int32_t v, int32_t d,
                  int32_t *num2, int32_t *den)
{
    int32_t ur = u - d;
    ptrdiff_t il;
    ptrdiff_t ir;
    uint32_t vl;
    uint32_t vr;

    if (u < STX_WIN_R || u >= s->w - STX_WIN_R || ur < STX_WIN_R ||
        ur >= s->w - STX_WIN_R || v < s->y0 || v >= s->y1) {
        return 0;
    }
    il = (ptrdiff_t)(v - s->y0) * s->w + u;
    ir = (ptrdiff_t)(v - s->y0) * s->w + ur;
    vl = s->vl[il];
    vr = s->vr[ir];
    if (vl == 0u || vr == 0u) {
        return 0; /* window outside the image or perfectly flat */
    }
    return stx_mncc_num_den(
        stx_cross5(s->left, u, v, s->right, ur, v + s->voff), s->sl[il], vl,
        s->sr[ir], vr, (uint32_t)s->cfg.texture_min, num2, den);
}

/* ---- fast profile: cross-sum memo (gcs.c) ------------------------- */
/* A raw 5x5 cross sum is at most 25 * 255^2 = 1 625 625 < 2^21, so a memo
 * word holds it in its low 21 bits and the strip's stamp above them:
 * a word from an earlier strip reads as empty without clearing the table
 * (which would cost more than the sums it saves). */
#define STX_MEMO_SUM_BITS 21
#define STX_MEMO_SUM_MASK ((1u << STX_MEMO_SUM_BITS) - 1u)
#define STX_MEMO_GEN_MAX ((1u << (32 - STX_MEMO_SUM_BITS)) - 1u)

/* ---- canny.c ---------------------------------------------------------- */
/* Edge map of strip rows [y0, y1) into s->edge (1 = edge). Returns count. */
uint32_t stx_canny_strip(stx_t *s, int32_t y0, int32_t y1);

/* ---- lowres.c --------------------------------------------------------- */
/* Elementary 1/4-scale disparity and search ranges (global + per tile). */
void stx_lowres_range(stx_t *s);
/* Estimate the vertical offset in [-n, n]; returns the chosen offset. */
int32_t stx_vertical_estimate(stx_t *s, int32_t n);
/* Tile range for pixel (x, y). */
void stx_tile_range(const stx_t *s, int32_t x, int32_t y, int32_t *lo,
                    int32_t *hi);

/* ---- gcs.c ------------------------------------------------------------ */
/* Seeds + growth + stable selection for the current strip; writes integer
 * disparities (or NEGOBS_DISP_INVALID) into rows [y0, y1) of out. */
void stx_gcs_strip(stx_t *s, negobs_image_s16_t *out);
/* Fast profile: empty the memo (init) so stamps start afresh. */
void stx_memo_clear(stx_t *s);

/* ---- dp.c ------------------------------------------------------------- */
/* Stage 1 of one row (needs the strip statistics of row y). With
 * pass == 0 the end column feeds stage 2; with pass == 1 the row is
 * back-tracked from s->dend[y] and written (integer px) to out, costs kept
 * in s->cost for sub-pixel refinement. `gcsrow` holds the GCS result. */
void stx_dp_row(stx_t *s, int32_t y, const int16_t *gcsrow, int pass,
                int16_t *outrow, uint8_t *confrow);
void stx_dp_stage2_reset(stx_t *s);
void stx_dp_stage2_finish(stx_t *s);

/* ---- refine.c --------------------------------------------------------- */
void stx_lr_check(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                  int32_t conf_stride);
void stx_speckle(stx_t *s, negobs_image_s16_t *disp);
/* Filled pixels get NEGOBS_STEREO_CONF_FILLED (negobs/stereo.h). */
void stx_gap_fill(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                  int32_t conf_stride);
void stx_adaptive_mean(stx_t *s, negobs_image_s16_t *disp, uint8_t *conf,
                       int32_t conf_stride);

#endif /* NEGOBS_STEREO_INT_H */
