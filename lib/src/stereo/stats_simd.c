/*
 * 5x5 window statistics of one row, 8 centres per step (SSE2 or NEON; see
 * stereo_simd.h for the contract and ncc.c for the reference).
 *
 * One 16-byte load per window row covers the columns x - 2 .. x + 13 of
 * the centres x .. x + 7 (12 columns are used). Column sums of the 5 rows
 * are formed first (S: u16, <= 1 275; Q: u32, <= 325 125), then the 5-tap
 * horizontal sums from the same registers shifted by 1..4 lanes:
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

static inline void stats8(const uint8_t *const rows[5], int32_t x,
                          uint16_t *so, uint32_t *vo)
{
    const __m128i z = _mm_setzero_si128();
    __m128i c0 = z; /* column sums, columns 0-7 / 8-15 */
    __m128i c1 = z;
    __m128i q0 = z; /* column sums of squares, columns 0-3 / 4-7 / 8-11 */
    __m128i q1 = z;
    __m128i q2 = z;
    __m128i s;
    __m128i qa;
    __m128i qb;
    __m128i sl;
    __m128i sh;
    int32_t k;
    for (k = 0; k < 5; k++) {
        __m128i p = _mm_loadu_si128(
            (const __m128i *)(rows[k] + x - STX_WIN_R));
        __m128i lo = _mm_unpacklo_epi8(p, z);
        __m128i hi = _mm_unpackhi_epi8(p, z);
        __m128i lq = _mm_mullo_epi16(lo, lo); /* <= 65 025: exact in u16 */
        __m128i hq = _mm_mullo_epi16(hi, hi);
        c0 = _mm_add_epi16(c0, lo);
        c1 = _mm_add_epi16(c1, hi);
        q0 = _mm_add_epi32(q0, _mm_unpacklo_epi16(lq, z));
        q1 = _mm_add_epi32(q1, _mm_unpackhi_epi16(lq, z));
        q2 = _mm_add_epi32(q2, _mm_unpacklo_epi16(hq, z));
    }
    s = _mm_add_epi16(
        _mm_add_epi16(c0, STX_CAT16(c0, c1, 1)),
        _mm_add_epi16(STX_CAT16(c0, c1, 2), STX_CAT16(c0, c1, 3)));
    s = _mm_add_epi16(s, STX_CAT16(c0, c1, 4));
    qa = _mm_add_epi32(
        _mm_add_epi32(q0, STX_CAT32(q0, q1, 1)),
        _mm_add_epi32(STX_CAT32(q0, q1, 2), STX_CAT32(q0, q1, 3)));
    qa = _mm_add_epi32(qa, q1);
    qb = _mm_add_epi32(
        _mm_add_epi32(q1, STX_CAT32(q1, q2, 1)),
        _mm_add_epi32(STX_CAT32(q1, q2, 2), STX_CAT32(q1, q2, 3)));
    qb = _mm_add_epi32(qb, q2);
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
static inline void stats8(const uint8_t *const rows[5], int32_t x,
                          uint16_t *so, uint32_t *vo)
{
    uint16x8_t c0 = vdupq_n_u16(0);
    uint16x8_t c1 = vdupq_n_u16(0);
    uint32x4_t q0 = vdupq_n_u32(0);
    uint32x4_t q1 = vdupq_n_u32(0);
    uint32x4_t q2 = vdupq_n_u32(0);
    uint16x8_t s;
    uint32x4_t qa;
    uint32x4_t qb;
    int32_t k;
    for (k = 0; k < 5; k++) {
        uint8x16_t p = vld1q_u8(rows[k] + x - STX_WIN_R);
        uint8x8_t lo = vget_low_u8(p);
        uint8x8_t hi = vget_high_u8(p);
        uint16x8_t lq = vmull_u8(lo, lo);
        c0 = vaddw_u8(c0, lo);
        c1 = vaddw_u8(c1, hi);
        q0 = vaddw_u16(q0, vget_low_u16(lq));
        q1 = vaddw_u16(q1, vget_high_u16(lq));
        q2 = vaddw_u16(q2, vget_low_u16(vmull_u8(hi, hi)));
    }
    s = vaddq_u16(vaddq_u16(c0, vextq_u16(c0, c1, 1)),
                  vaddq_u16(vextq_u16(c0, c1, 2), vextq_u16(c0, c1, 3)));
    s = vaddq_u16(s, vextq_u16(c0, c1, 4));
    qa = vaddq_u32(vaddq_u32(q0, vextq_u32(q0, q1, 1)),
                   vaddq_u32(vextq_u32(q0, q1, 2), vextq_u32(q0, q1, 3)));
    qa = vaddq_u32(qa, q1);
    qb = vaddq_u32(vaddq_u32(q1, vextq_u32(q1, q2, 1)),
                   vaddq_u32(vextq_u32(q1, q2, 2), vextq_u32(q1, q2, 3)));
    qb = vaddq_u32(qb, q2);
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
    /* the load of centre x ends at column x + 13 */
    for (; x + 13 < w; x += 8) {
        stats8(rows, x, so, vo);
    }
    /* one more block ending at the last column, overlapping the previous
     * one (it writes the same values) */
    if (x < w - 6 && w - 14 >= STX_WIN_R) {
        x = w - 14;
        stats8(rows, x, so, vo);
        x += 8;
    }
    for (; x < w - STX_WIN_R; x++) {
        stats_at(rows, x, so, vo);
    }
#else
    stx_stats_row_ref(rows, w, so, vo);
#endif
}
