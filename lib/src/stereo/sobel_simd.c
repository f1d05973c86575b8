/*
 * Canny's gradient magnitude |Gx| + |Gy| of one row, 8 pixels per step
 * (SSE2 or NEON); contract in stereo_simd.h, reference in canny.c.
 *
 * Pixels x .. x + 7 need columns x - 1 .. x + 8 of the three rows: three
 * 8-byte loads per row at x - 1, x and x + 1, widened to 16 bits. Each
 * Sobel sum is in [-1 020, 1 020] and the magnitude <= 2 040, so 16-bit
 * lanes are exact.
 */
#include "stereo/stereo_simd.h"

#if defined(NEGOBS_SIMD_SSE2)
static inline __m128i ld8(const uint8_t *p)
{
    return _mm_unpacklo_epi8(_mm_loadl_epi64((const __m128i *)p),
                             _mm_setzero_si128());
}

static inline __m128i abs16(__m128i v)
{
    return _mm_max_epi16(v, _mm_sub_epi16(_mm_setzero_si128(), v));
}

static inline void mag8(const uint8_t *a, const uint8_t *b, const uint8_t *c,
                        int32_t x, uint16_t *m)
{
    __m128i a0 = ld8(a + x - 1);
    __m128i a1 = ld8(a + x);
    __m128i a2 = ld8(a + x + 1);
    __m128i c0 = ld8(c + x - 1);
    __m128i c1 = ld8(c + x);
    __m128i c2 = ld8(c + x + 1);
    __m128i b0 = ld8(b + x - 1);
    __m128i b2 = ld8(b + x + 1);
    __m128i gx = _mm_sub_epi16(
        _mm_add_epi16(_mm_add_epi16(a2, c2), _mm_add_epi16(b2, b2)),
        _mm_add_epi16(_mm_add_epi16(a0, c0), _mm_add_epi16(b0, b0)));
    __m128i gy = _mm_sub_epi16(
        _mm_add_epi16(_mm_add_epi16(c0, c2), _mm_add_epi16(c1, c1)),
        _mm_add_epi16(_mm_add_epi16(a0, a2), _mm_add_epi16(a1, a1)));
    _mm_storeu_si128((__m128i *)(m + x), _mm_add_epi16(abs16(gx), abs16(gy)));
}
#elif defined(NEGOBS_SIMD_NEON)
static inline int16x8_t ld8(const uint8_t *p)
{
    return vreinterpretq_s16_u16(vmovl_u8(vld1_u8(p)));
}

static inline void mag8(const uint8_t *a, const uint8_t *b, const uint8_t *c,
                        int32_t x, uint16_t *m)
{
    int16x8_t a0 = ld8(a + x - 1);
    int16x8_t a1 = ld8(a + x);
    int16x8_t a2 = ld8(a + x + 1);
    int16x8_t c0 = ld8(c + x - 1);
    int16x8_t c1 = ld8(c + x);
    int16x8_t c2 = ld8(c + x + 1);
    int16x8_t b0 = ld8(b + x - 1);
    int16x8_t b2 = ld8(b + x + 1);
    int16x8_t gx = vsubq_s16(vaddq_s16(vaddq_s16(a2, c2), vshlq_n_s16(b2, 1)),
                             vaddq_s16(vaddq_s16(a0, c0), vshlq_n_s16(b0, 1)));
    int16x8_t gy = vsubq_s16(vaddq_s16(vaddq_s16(c0, c2), vshlq_n_s16(c1, 1)),
                             vaddq_s16(vaddq_s16(a0, a2), vshlq_n_s16(a1, 1)));
    vst1q_u16(m + x,
              vreinterpretq_u16_s16(vaddq_s16(vabsq_s16(gx), vabsq_s16(gy))));
}
#endif

void stx_sobel_mag_row(const uint8_t *a, const uint8_t *b, const uint8_t *c,
                       int32_t w, uint16_t *m)
{
#if defined(NEGOBS_SIMD)
    int32_t x = 1;
    /* the loads of pixels x .. x + 7 end at column x + 8 */
    for (; x + 8 < w; x += 8) {
        mag8(a, b, c, x, m);
    }
    /* the last pixels: one more block ending at column w - 1 (w - 2 the
     * last pixel), overlapping the previous one (same values) */
    if (x < w - 1 && w - 9 >= 1) {
        mag8(a, b, c, w - 9, m);
        x = w - 1;
    }
    if (x < w - 1) {
        /* narrower than one block: the reference from x on */
        stx_sobel_mag_row_ref(a + x - 1, b + x - 1, c + x - 1, w - x + 1,
                              m + x - 1);
    }
#else
    stx_sobel_mag_row_ref(a, b, c, w, m);
#endif
}
