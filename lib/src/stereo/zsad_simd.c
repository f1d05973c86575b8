/*
 * Zero-mean 3x3 SAD of one fixed window against a run of windows along a
 * row, 8 windows per step (SSE2 or NEON); contract in stereo_simd.h,
 * reference in lowres.c.
 *
 * Lane l holds the window centred at b + l. The 9 taps of 8 neighbouring
 * windows are 9 loads of 8 bytes (rows -1..1, columns -1..1 from b), so
 * no byte outside the run's windows is read. With the fixed window's
 * terms ta_k = 9 a_k - Sa and the lane's u_k = 9 b_k - Sb (both in
 * [-2 295, 2 295]), each term |ta_k - u_k| <= 4 590 fits int16 and the
 * 9-term sum <= 41 310 fits u16; it is widened to 32 bits on store.
 */
#include "stereo/stereo_simd.h"

#if defined(NEGOBS_SIMD)
/* 9 a_k - Sa of the fixed window, k = 3 (row + 1) + (column + 1) */
static inline void fixed_terms(const uint8_t *a, int32_t stride, int16_t *ta)
{
    int32_t s = 0;
    int32_t k;
    for (k = 0; k < 9; k++) {
        s += a[(ptrdiff_t)(k / 3 - 1) * stride + (k % 3 - 1)];
    }
    for (k = 0; k < 9; k++) {
        ta[k] = (int16_t)(9 * (int32_t)a[(ptrdiff_t)(k / 3 - 1) * stride +
                                         (k % 3 - 1)] -
                          s);
    }
}
#endif

#if defined(NEGOBS_SIMD_SSE2)
static inline void zsad8(const int16_t *ta, const uint8_t *b, int32_t stride,
                         int32_t *out)
{
    const __m128i z = _mm_setzero_si128();
    __m128i bv[9];
    __m128i sb = z;
    __m128i acc = z;
    int32_t k;
    for (k = 0; k < 9; k++) {
        bv[k] = _mm_unpacklo_epi8(
            _mm_loadl_epi64((const __m128i *)(b +
                                              (ptrdiff_t)(k / 3 - 1) * stride +
                                              (k % 3 - 1))),
            z);
        sb = _mm_add_epi16(sb, bv[k]);
    }
    for (k = 0; k < 9; k++) {
        __m128i u = _mm_sub_epi16(
            _mm_add_epi16(_mm_slli_epi16(bv[k], 3), bv[k]), sb);
        __m128i t = _mm_sub_epi16(_mm_set1_epi16(ta[k]), u);
        acc = _mm_add_epi16(acc, _mm_max_epi16(t, _mm_sub_epi16(z, t)));
    }
    _mm_storeu_si128((__m128i *)out, _mm_unpacklo_epi16(acc, z));
    _mm_storeu_si128((__m128i *)(out + 4), _mm_unpackhi_epi16(acc, z));
}
#elif defined(NEGOBS_SIMD_NEON)
static inline void zsad8(const int16_t *ta, const uint8_t *b, int32_t stride,
                         int32_t *out)
{
    int16x8_t bv[9];
    int16x8_t sb = vdupq_n_s16(0);
    uint16x8_t acc = vdupq_n_u16(0);
    int32_t k;
    for (k = 0; k < 9; k++) {
        bv[k] = vreinterpretq_s16_u16(vmovl_u8(
            vld1_u8(b + (ptrdiff_t)(k / 3 - 1) * stride + (k % 3 - 1))));
        sb = vaddq_s16(sb, bv[k]);
    }
    for (k = 0; k < 9; k++) {
        int16x8_t u = vsubq_s16(vmulq_n_s16(bv[k], 9), sb);
        int16x8_t t = vsubq_s16(vdupq_n_s16(ta[k]), u);
        acc = vaddq_u16(acc, vreinterpretq_u16_s16(vabsq_s16(t)));
    }
    vst1q_s32(out, vreinterpretq_s32_u32(vmovl_u16(vget_low_u16(acc))));
    vst1q_s32(out + 4, vreinterpretq_s32_u32(vmovl_u16(vget_high_u16(acc))));
}
#endif

void stx_zsad3_run(const uint8_t *a, const uint8_t *b, int32_t stride,
                   int32_t n, int32_t *out)
{
#if defined(NEGOBS_SIMD)
    int16_t ta[9];
    int32_t l = 0;
    fixed_terms(a, stride, ta);
    for (; l + 8 <= n; l += 8) {
        zsad8(ta, b + l, stride, out + l);
    }
    /* the last windows: one more block ending at the run's end,
     * overlapping the previous one (same values) */
    if (l < n && n >= 8) {
        zsad8(ta, b + n - 8, stride, out + n - 8);
        l = n;
    }
    if (l < n) {
        stx_zsad3_run_ref(a, b + l, stride, n - l, out + l);
    }
#else
    stx_zsad3_run_ref(a, b, stride, n, out);
#endif
}
