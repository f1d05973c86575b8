/*
 * 5x5 window statistics of one row, 8 centres per step (SSE2 or NEON; see
 * stereo_simd.h for the contract and ncc.c for the reference).
 *
 * Centres x .. x + 7 need the columns x - 2 .. x + 9. Column sums of the 5
 * rows are formed 8 columns at a time from 8-byte loads (S: u16, <= 1 275;
 * Q: u32, <= 325 125) and each block's upper 8 columns serve as the next
 * block's lower ones; then the 5-tap horizontal sums come from the two
 * blocks shifted by 1..4 lanes:
 *   S <= 6 375 (u16), Q <= 1 625 625 (u32), S^2 < 2^26, 25 Q < 2^26,
 * so V = 25 Q - S^2 is exact in u32, as in the reference.
 */
#include "stereo/stereo_simd.h"

#include "stereo/stereo_state.h"

#if defined(NEGOBS_SIMD)
/* The reference formula at one centre (tail columns). */
static void stats_at(const uint8_t *const rows[5], int32_t x, uint16_t *so,
                     uint32_t *vo)
{
    uint32_t s = 0;
    uint32_t q = 0;
    int32_t k;
    int32_t j;
    for (k = 0; k < 5; k++) {
        for (j = x - STX_WIN_R; j <= x + STX_WIN_R; j++) {
            uint32_t p = rows[k][j];
            s += p;
            q += p * p;
        }
    }
    so[x] = (uint16_t)s;
    vo[x] = (uint32_t)STX_WIN_N * q - s * s;
}
#endif

#if defined(NEGOBS_SIMD_SSE2)
/* Lanes k .. k + 7 of the 16-lane u16 pair (lo, hi) (and the u32 form).
 * Macros, not inline functions: the byte shifts take an immediate, which
 * a function parameter is not in an unoptimised build. */
#define STX_CAT16(lo, hi, k)                                                  \
    _mm_or_si128(_mm_srli_si128((lo), 2 * (k)),                               \
                 _mm_slli_si128((hi), 16 - 2 * (k)))
#define STX_CAT32(lo, hi, k)                                                  \
    _mm_or_si128(_mm_srli_si128((lo), 4 * (k)),                               \
                 _mm_slli_si128((hi), 16 - 4 * (k)))

/* Column sums of 8 columns: S (u16) and Q (u32, columns 0-3 and 4-7). */
typedef struct cols8 {
    __m128i c, qa, qb;
} cols8_t;

static inline cols8_t cols8(const uint8_t *const rows[5], int32_t col)
{
    const __m128i z = _mm_setzero_si128();
    cols8_t r;
    int32_t k;
    r.c = z;
    r.qa = z;
    r.qb = z;
    for (k = 0; k < 5; k++) {
        __m128i v = _mm_unpacklo_epi8(
            _mm_loadl_epi64((const __m128i *)(rows[k] + col)), z);
        __m128i q = _mm_mullo_epi16(v, v); /* <= 65 025: exact in u16 */
        r.c = _mm_add_epi16(r.c, v);
        r.qa = _mm_add_epi32(r.qa, _mm_unpacklo_epi16(q, z));
        r.qb = _mm_add_epi32(r.qb, _mm_unpackhi_epi16(q, z));
    }
    return r;
}

/* Centres x .. x + 7 from the columns x - 2 .. x + 5 (lo) and x + 6 ..
 * x + 13 (hi). */
static inline void stats8(cols8_t lo, cols8_t hi, int32_t x, uint16_t *so,
                          uint32_t *vo)
{
    __m128i s;
    __m128i qa;
    __m128i qb;
    __m128i sl;
    __m128i sh;
    s = _mm_add_epi16(
        _mm_add_epi16(lo.c, STX_CAT16(lo.c, hi.c, 1)),
        _mm_add_epi16(STX_CAT16(lo.c, hi.c, 2), STX_CAT16(lo.c, hi.c, 3)));
    s = _mm_add_epi16(s, STX_CAT16(lo.c, hi.c, 4));
    qa = _mm_add_epi32(
        _mm_add_epi32(lo.qa, STX_CAT32(lo.qa, lo.qb, 1)),
        _mm_add_epi32(STX_CAT32(lo.qa, lo.qb, 2), STX_CAT32(lo.qa, lo.qb, 3)));
    qa = _mm_add_epi32(qa, lo.qb);
    qb = _mm_add_epi32(
        _mm_add_epi32(lo.qb, STX_CAT32(lo.qb, hi.qa, 1)),
        _mm_add_epi32(STX_CAT32(lo.qb, hi.qa, 2), STX_CAT32(lo.qb, hi.qa, 3)));
    qb = _mm_add_epi32(qb, hi.qa);
    /* S^2 as 32-bit lanes from the low and high halves of the products */
    sl = _mm_mullo_epi16(s, s);
    sh = _mm_mulhi_epu16(s, s);
    /* 25 Q = 16 Q + 8 Q + Q */
    qa = _mm_add_epi32(
        _mm_add_epi32(_mm_slli_epi32(qa, 4), _mm_slli_epi32(qa, 3)), qa);
    qb = _mm_add_epi32(
        _mm_add_epi32(_mm_slli_epi32(qb, 4), _mm_slli_epi32(qb, 3)), qb);
    _mm_storeu_si128((__m128i *)(so + x), s);
    _mm_storeu_si128((__m128i *)(vo + x),
                     _mm_sub_epi32(qa, _mm_unpacklo_epi16(sl, sh)));
    _mm_storeu_si128((__m128i *)(vo + x + 4),
                     _mm_sub_epi32(qb, _mm_unpackhi_epi16(sl, sh)));
}
#elif defined(NEGOBS_SIMD_NEON)
/* Column sums of 8 columns: S (u16) and Q (u32, columns 0-3 and 4-7). */
typedef struct cols8 {
    uint16x8_t c;
    uint32x4_t qa, qb;
} cols8_t;

static inline cols8_t cols8(const uint8_t *const rows[5], int32_t col)
{
    cols8_t r;
    int32_t k;
    r.c = vdupq_n_u16(0);
    r.qa = vdupq_n_u32(0);
    r.qb = vdupq_n_u32(0);
    for (k = 0; k < 5; k++) {
        uint8x8_t v = vld1_u8(rows[k] + col);
        uint16x8_t q = vmull_u8(v, v);
        r.c = vaddw_u8(r.c, v);
        r.qa = vaddw_u16(r.qa, vget_low_u16(q));
        r.qb = vaddw_u16(r.qb, vget_high_u16(q));
    }
    return r;
}

/* Centres x .. x + 7 from the columns x - 2 .. x + 5 (lo) and x + 6 ..
 * x + 13 (hi). */
static inline void stats8(cols8_t lo, cols8_t hi, int32_t x, uint16_t *so,
                          uint32_t *vo)
{
    uint16x8_t s;
    uint32x4_t qa;
    uint32x4_t qb;
    s = vaddq_u16(
        vaddq_u16(lo.c, vextq_u16(lo.c, hi.c, 1)),
        vaddq_u16(vextq_u16(lo.c, hi.c, 2), vextq_u16(lo.c, hi.c, 3)));
    s = vaddq_u16(s, vextq_u16(lo.c, hi.c, 4));
    qa = vaddq_u32(
        vaddq_u32(lo.qa, vextq_u32(lo.qa, lo.qb, 1)),
        vaddq_u32(vextq_u32(lo.qa, lo.qb, 2), vextq_u32(lo.qa, lo.qb, 3)));
    qa = vaddq_u32(qa, lo.qb);
    qb = vaddq_u32(
        vaddq_u32(lo.qb, vextq_u32(lo.qb, hi.qa, 1)),
        vaddq_u32(vextq_u32(lo.qb, hi.qa, 2), vextq_u32(lo.qb, hi.qa, 3)));
    qb = vaddq_u32(qb, hi.qa);
    vst1q_u16(so + x, s);
    vst1q_u32(vo + x, vmlsl_u16(vmulq_n_u32(qa, STX_WIN_N), vget_low_u16(s),
                                vget_low_u16(s)));
    vst1q_u32(vo + x + 4, vmlsl_u16(vmulq_n_u32(qb, STX_WIN_N),
                                    vget_high_u16(s), vget_high_u16(s)));
}
#endif

void stx_stats_row(const uint8_t *const rows[5], int32_t w, uint16_t *so,
                   uint32_t *vo)
{
#if defined(NEGOBS_SIMD)
    int32_t x = STX_WIN_R;
    if (x + 13 < w) {
        /* the columns of centres x .. x + 7 end at x + 13; each block's
         * upper 8 columns are the next block's lower ones */
        cols8_t lo = cols8(rows, x - STX_WIN_R);
        for (; x + 13 < w; x += 8) {
            cols8_t hi = cols8(rows, x + 6);
            stats8(lo, hi, x, so, vo);
            lo = hi;
        }
        /* one more block ending at the last column, overlapping the
         * previous one (it writes the same values) */
        if (x < w - 6) {
            x = w - 14;
            stats8(cols8(rows, x - STX_WIN_R), cols8(rows, x + 6), x, so, vo);
            x += 8;
        }
    }
    for (; x < w - STX_WIN_R; x++) {
        stats_at(rows, x, so, vo);
    }
#else
    stx_stats_row_ref(rows, w, so, vo);
#endif
}
