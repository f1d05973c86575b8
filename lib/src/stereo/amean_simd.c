/*
 * The adaptive mean's taps for 8 lanes at once (SSE2 or NEON); contract in
 * stereo_simd.h, reference in refine.c.
 *
 * Per lane, as the reference: a pair of taps counts only when both are
 * valid; its weights are max(0, 64 - |v - c|). The difference is taken
 * with 16-bit saturation: a saturated |v - c| is >= 32 767, whose weight
 * is 0 as the exact one's, so the weights are exact (0..64). The weighted
 * sum uses 16 x 16 -> 32-bit multiply-adds, |sd| <= 9 * 64 * 32 768 < 2^25;
 * sw <= 576 fits 16 bits. The division (one per lane) stays scalar
 * (stx_div_round_pos), since neither SSE2 nor NEON divides integers.
 * A hole takes (a + b) / 2 of its nearest valid neighbours within kl / kr
 * when they agree to 1 px, computed in 32 bits and truncated towards zero
 * as C's division.
 */
#include "stereo/stereo_simd.h"

#include "negobs/fixed.h"

#if defined(NEGOBS_SIMD)

/* The kernel body is inlined twice (stx_amean8_simd): forced, since the
 * specialisation is the point. */
#if defined(__GNUC__)
#define STX_AMEAN_INLINE static inline __attribute__((always_inline))
#else
#define STX_AMEAN_INLINE static inline
#endif

/* The per-lane end: the division for valid centres, the hole value
 * otherwise. */
static inline void amean_finish(const int16_t *c, const int32_t *sd,
                                const int16_t *sw, const int16_t *hole,
                                int16_t *out)
{
    int32_t l;
    for (l = 0; l < 8; l++) {
        if (c[l] != NEGOBS_DISP_INVALID) {
            out[l] = (int16_t)stx_div_round_pos(sd[l], sw[l]);
        } else {
            out[l] = hole[l];
        }
    }
}

#if defined(NEGOBS_SIMD_SSE2)
/* |a - b| with 16-bit saturation */
static inline __m128i absdiff_sat(__m128i a, __m128i b)
{
    __m128i d = _mm_subs_epi16(a, b);
    return _mm_max_epi16(d, _mm_subs_epi16(_mm_setzero_si128(), d));
}

/* (a + b) / 2 in 32 bits, truncated towards zero, for 4 lanes */
static inline __m128i half_sum(__m128i a, __m128i b)
{
    __m128i s = _mm_add_epi32(a, b);
    s = _mm_sub_epi32(s, _mm_srai_epi32(s, 31));
    return _mm_srai_epi32(s, 1);
}

/* sign-extended low / high 4 lanes */
static inline __m128i lo32(__m128i v)
{
    return _mm_srai_epi32(_mm_unpacklo_epi16(v, v), 16);
}
static inline __m128i hi32(__m128i v)
{
    return _mm_srai_epi32(_mm_unpackhi_epi16(v, v), 16);
}

STX_AMEAN_INLINE void amean8(const int16_t *const tap[9], int32_t kl,
                             int32_t kr, int16_t *out)
{
    const __m128i inv = _mm_set1_epi16(NEGOBS_DISP_INVALID);
    const __m128i w64 = _mm_set1_epi16(64);
    const __m128i z = _mm_setzero_si128();
    __m128i c = _mm_loadu_si128((const __m128i *)tap[4]);
    __m128i sw = w64;
    __m128i sdl = _mm_slli_epi32(lo32(c), 6);
    __m128i sdh = _mm_slli_epi32(hi32(c), 6);
    __m128i a = inv;
    __m128i b = inv;
    __m128i fill;
    __m128i hole;
    int32_t np = (kl < kr) ? kl : kr;
    int32_t j;
    int32_t sd[8];
    int16_t swv[8];
    int16_t cv[8];
    int16_t hv[8];

    for (j = 1; j <= np; j++) {
        __m128i vl = _mm_loadu_si128((const __m128i *)tap[4 - j]);
        __m128i vr = _mm_loadu_si128((const __m128i *)tap[4 + j]);
        __m128i both = _mm_andnot_si128(
            _mm_or_si128(_mm_cmpeq_epi16(vl, inv), _mm_cmpeq_epi16(vr, inv)),
            _mm_cmpeq_epi16(z, z));
        __m128i wl = _mm_and_si128(
            _mm_max_epi16(_mm_subs_epi16(w64, absdiff_sat(vl, c)), z), both);
        __m128i wr = _mm_and_si128(
            _mm_max_epi16(_mm_subs_epi16(w64, absdiff_sat(vr, c)), z), both);
        sw = _mm_add_epi16(sw, _mm_add_epi16(wl, wr));
        sdl = _mm_add_epi32(sdl, _mm_madd_epi16(_mm_unpacklo_epi16(wl, wr),
                                                _mm_unpacklo_epi16(vl, vr)));
        sdh = _mm_add_epi32(sdh, _mm_madd_epi16(_mm_unpackhi_epi16(wl, wr),
                                                _mm_unpackhi_epi16(vl, vr)));
    }
    hole = inv;
    /* holes are the exception: their part only when a centre is one */
    if (_mm_movemask_epi8(_mm_cmpeq_epi16(c, inv)) != 0) {
        /* nearest valid neighbour on each side: the farthest first, so the
         * nearest valid one is the last written */
        for (j = kl; j >= 1; j--) {
            __m128i v = _mm_loadu_si128((const __m128i *)tap[4 - j]);
            __m128i bad = _mm_cmpeq_epi16(v, inv);
            a = _mm_or_si128(_mm_and_si128(bad, a), _mm_andnot_si128(bad, v));
        }
        for (j = kr; j >= 1; j--) {
            __m128i v = _mm_loadu_si128((const __m128i *)tap[4 + j]);
            __m128i bad = _mm_cmpeq_epi16(v, inv);
            b = _mm_or_si128(_mm_and_si128(bad, b), _mm_andnot_si128(bad, v));
        }
        fill = _mm_andnot_si128(
            _mm_or_si128(
                _mm_or_si128(_mm_cmpeq_epi16(a, inv), _mm_cmpeq_epi16(b, inv)),
                _mm_cmpgt_epi16(absdiff_sat(a, b),
                                _mm_set1_epi16(NEGOBS_DISP_ONE))),
            _mm_cmpeq_epi16(z, z));
        hole = _mm_packs_epi32(half_sum(lo32(a), lo32(b)),
                               half_sum(hi32(a), hi32(b)));
        hole = _mm_or_si128(_mm_and_si128(fill, hole),
                            _mm_andnot_si128(fill, inv));
    }
    _mm_storeu_si128((__m128i *)sd, sdl);
    _mm_storeu_si128((__m128i *)(sd + 4), sdh);
    _mm_storeu_si128((__m128i *)swv, sw);
    _mm_storeu_si128((__m128i *)cv, c);
    _mm_storeu_si128((__m128i *)hv, hole);
    amean_finish(cv, sd, swv, hv, out);
}

#elif defined(NEGOBS_SIMD_NEON)
/* whether any lane of a comparison result is set */
static inline int any_u16(uint16x8_t m)
{
    uint16x4_t h = vorr_u16(vget_low_u16(m), vget_high_u16(m));
    return vget_lane_u64(vreinterpret_u64_u16(h), 0) != 0u;
}

STX_AMEAN_INLINE void amean8(const int16_t *const tap[9], int32_t kl,
                             int32_t kr, int16_t *out)
{
    const int16x8_t inv = vdupq_n_s16(NEGOBS_DISP_INVALID);
    const int16x8_t w64 = vdupq_n_s16(64);
    const int16x8_t z = vdupq_n_s16(0);
    int16x8_t c = vld1q_s16(tap[4]);
    int16x8_t sw = w64;
    int32x4_t sdl = vshll_n_s16(vget_low_s16(c), 6);
    int32x4_t sdh = vshll_n_s16(vget_high_s16(c), 6);
    int16x8_t a = inv;
    int16x8_t b = inv;
    uint16x8_t bad;
    int32x4_t sl;
    int32x4_t sh;
    int16x8_t hole;
    int32_t np = (kl < kr) ? kl : kr;
    int32_t j;
    int32_t sd[8];
    int16_t swv[8];
    int16_t cv[8];
    int16_t hv[8];

    for (j = 1; j <= np; j++) {
        int16x8_t vl = vld1q_s16(tap[4 - j]);
        int16x8_t vr = vld1q_s16(tap[4 + j]);
        uint16x8_t both = vmvnq_u16(
            vorrq_u16(vceqq_s16(vl, inv), vceqq_s16(vr, inv)));
        int16x8_t wl = vandq_s16(
            vmaxq_s16(vqsubq_s16(w64, vqabsq_s16(vqsubq_s16(vl, c))), z),
            vreinterpretq_s16_u16(both));
        int16x8_t wr = vandq_s16(
            vmaxq_s16(vqsubq_s16(w64, vqabsq_s16(vqsubq_s16(vr, c))), z),
            vreinterpretq_s16_u16(both));
        sw = vaddq_s16(sw, vaddq_s16(wl, wr));
        sdl = vmlal_s16(sdl, vget_low_s16(wl), vget_low_s16(vl));
        sdl = vmlal_s16(sdl, vget_low_s16(wr), vget_low_s16(vr));
        sdh = vmlal_s16(sdh, vget_high_s16(wl), vget_high_s16(vl));
        sdh = vmlal_s16(sdh, vget_high_s16(wr), vget_high_s16(vr));
    }
    hole = inv;
    /* holes are the exception: their part only when a centre is one */
    if (any_u16(vceqq_s16(c, inv))) {
        for (j = kl; j >= 1; j--) {
            int16x8_t v = vld1q_s16(tap[4 - j]);
            a = vbslq_s16(vceqq_s16(v, inv), a, v);
        }
        for (j = kr; j >= 1; j--) {
            int16x8_t v = vld1q_s16(tap[4 + j]);
            b = vbslq_s16(vceqq_s16(v, inv), b, v);
        }
        bad = vorrq_u16(vorrq_u16(vceqq_s16(a, inv), vceqq_s16(b, inv)),
                        vcgtq_s16(vqabsq_s16(vqsubq_s16(a, b)),
                                  vdupq_n_s16(NEGOBS_DISP_ONE)));
        sl = vaddl_s16(vget_low_s16(a), vget_low_s16(b));
        sh = vaddl_s16(vget_high_s16(a), vget_high_s16(b));
        /* s - (s >> 31) adds 1 to negative sums: truncation towards zero */
        sl = vshrq_n_s32(vsubq_s32(sl, vshrq_n_s32(sl, 31)), 1);
        sh = vshrq_n_s32(vsubq_s32(sh, vshrq_n_s32(sh, 31)), 1);
        hole = vcombine_s16(vmovn_s32(sl), vmovn_s32(sh));
        hole = vbslq_s16(bad, inv, hole);
    }
    vst1q_s32(sd, sdl);
    vst1q_s32(sd + 4, sdh);
    vst1q_s16(swv, sw);
    vst1q_s16(cv, c);
    vst1q_s16(hv, hole);
    amean_finish(cv, sd, swv, hv, out);
}
#endif

void stx_amean8_simd(const int16_t *const tap[9], int32_t kl, int32_t kr,
                     int16_t *out)
{
    /* the interior (both line ends 4 or more away) with literal bounds,
     * so that its loops unroll */
    if (kl == 4 && kr == 4) {
        amean8(tap, 4, 4, out);
    } else {
        amean8(tap, kl, kr, out);
    }
}

#endif /* NEGOBS_SIMD */
