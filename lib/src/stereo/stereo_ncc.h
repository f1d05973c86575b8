/*
 * 5x5 MNCC kernels of the disparity engine: window statistics (ncc.c), the
 * exact fraction helpers, and the inline hot kernels with their plain C
 * reference (stx_cross5_ref) and SIMD forms (SSE2, NEON), which
 * tests/stereo/test_stereo_ncc.c checks bit for bit against it.
 * STX_CROSS5_SIMD is defined (to 1) only where a SIMD form is compiled.
 * Internal to lib/src/stereo.
 */
#ifndef NEGOBS_STEREO_NCC_H
#define NEGOBS_STEREO_NCC_H

#include <stddef.h>
#include <stdint.h>

#include "simd.h"
#include "stereo/stereo_state.h"

/* ---- ncc.c ------------------------------------------------------------ */
/* Window statistics of image rows [ya, ya+n): S and V per pixel; windows
 * leaving the image get V = 0 (no window). */
void stx_stats_rows(const negobs_image_u8_t *img, int32_t ya, int32_t n,
                    uint16_t *s, uint32_t *v);
/* MNCC of 5x5 windows in Q14 from sums: 2*num/(VL+VR). STX_FLAT when
 * VL+VR < tex_min. */
int32_t stx_mncc_q14(uint32_t sum_lr, uint32_t sl, uint32_t vl, uint32_t sr,
                     uint32_t vr, uint32_t tex_min);
/* The common scale of stx_frac_q14: |num2| and den shifted right together
 * by the fewest bits that bring den below 2^17. Shifting by s1 then s2
 * floors like one shift by s1 + s2, so the count can be taken in one go:
 * from the leading zeros where the compiler has them, else in fixed steps
 * of 8, 4, 2, 1, 1 (a step is taken only when den stays >= 2^17 after it,
 * so the total is the least shift; each step leaves den below the next
 * step's bound, so the last one ends below 2^17 for any den). */
static inline void stx_frac_scale(uint32_t *a, uint32_t *d)
{
#if defined(__GNUC__)
    if (*d >= (1u << 17)) {
        /* 32 - clz = bit length; keep 17 bits */
        unsigned sh = (unsigned)(15 - __builtin_clz(*d));
        *d >>= sh;
        *a >>= sh;
    }
#else
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
#endif
}

/* num2 / den in Q14, rounded towards zero (den > 0, |num2| <= den).
 * Inline: the growth, the seeds and the DP call it about a million times
 * a frame. */
static inline int32_t stx_frac_q14(int32_t num2, int32_t den)
{
    uint32_t a = (uint32_t)((num2 < 0) ? -num2 : num2);
    uint32_t d = (uint32_t)den;
    uint32_t q;
    stx_frac_scale(&a, &d);
    if (a > d) {
        a = d; /* cannot happen mathematically; keeps |c| <= 1 */
    }
    q = (a << 14) / d;
    return (num2 < 0) ? -(int32_t)q : (int32_t)q;
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
static inline int stx_mncc_num_den(uint32_t sum_lr, uint32_t sl, uint32_t vl,
                                   uint32_t sr, uint32_t vr, uint32_t tex_min,
                                   int32_t *num2, int32_t *den)
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

/* Plain C reference of stx_cross5x3_simd: the left window at a against
 * the right windows at b, b + 1, b + 2. */
static inline void stx_cross5x3_ref(const uint8_t *a, ptrdiff_t sa,
                                    const uint8_t *b, ptrdiff_t sb,
                                    uint32_t out[3])
{
    int32_t k;
    for (k = 0; k < 3; k++) {
        out[k] = stx_cross5_ref(a, sa, b + k, sb);
    }
}
#if defined(NEGOBS_SIMD_SSE2)
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
    x = _mm_and_si128(
        _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)a),
                           _mm_loadl_epi64((const __m128i *)(a + sa))),
        m5);
    y = _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)b),
                           _mm_loadl_epi64((const __m128i *)(b + sb)));
    acc = _mm_add_epi32(
        _mm_madd_epi16(_mm_unpacklo_epi8(x, z), _mm_unpacklo_epi8(y, z)),
        _mm_madd_epi16(_mm_unpackhi_epi8(x, z), _mm_unpackhi_epi8(y, z)));
    a += 2 * sa;
    b += 2 * sb;
    x = _mm_and_si128(
        _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)a),
                           _mm_loadl_epi64((const __m128i *)(a + sa))),
        m5);
    y = _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)b),
                           _mm_loadl_epi64((const __m128i *)(b + sb)));
    acc = _mm_add_epi32(
        acc, _mm_madd_epi16(_mm_unpacklo_epi8(x, z), _mm_unpacklo_epi8(y, z)));
    acc = _mm_add_epi32(
        acc, _mm_madd_epi16(_mm_unpackhi_epi8(x, z), _mm_unpackhi_epi8(y, z)));
    a += 2 * sa;
    b += 2 * sb;
    x = _mm_and_si128(_mm_loadl_epi64((const __m128i *)a), m5);
    y = _mm_loadl_epi64((const __m128i *)b);
    acc = _mm_add_epi32(
        acc, _mm_madd_epi16(_mm_unpacklo_epi8(x, z), _mm_unpacklo_epi8(y, z)));
    acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, 0x4E));
    acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, 0xB1));
    return (uint32_t)_mm_cvtsi128_si32(acc);
}
#define STX_CROSS5X3_SIMD 1
/* Three cross sums of one left window (top-left a) against the right
 * windows at b, b + 1 and b + 2 (three consecutive disparities), as
 * out[k] = stx_cross5_ref(a, sa, b + k, sb). Each right row is one 8-byte
 * load (b .. b + 7: the caller guarantees b + 7 is inside the row) shifted
 * by 0, 1 and 2 pixels after widening, so the left row is loaded and
 * widened once for the three; the left load has stx_cross5_simd's
 * contract. Bit-exact: integer sums in any order, each PMADDWD lane <=
 * 130 050. */
static inline void stx_cross5x3_simd(const uint8_t *a, ptrdiff_t sa,
                                     const uint8_t *b, ptrdiff_t sb,
                                     uint32_t out[3])
{
    const __m128i z = _mm_setzero_si128();
    const __m128i m5 = _mm_set_epi32(0, 0, 0xFF, -1);
    __m128i acc0 = z;
    __m128i acc1 = z;
    __m128i acc2 = z;
    int32_t k;
    for (k = 0; k < 5; k++) {
        __m128i l = _mm_unpacklo_epi8(
            _mm_and_si128(_mm_loadl_epi64((const __m128i *)a), m5), z);
        __m128i r = _mm_unpacklo_epi8(_mm_loadl_epi64((const __m128i *)b), z);
        acc0 = _mm_add_epi32(acc0, _mm_madd_epi16(l, r));
        acc1 = _mm_add_epi32(acc1, _mm_madd_epi16(l, _mm_srli_si128(r, 2)));
        acc2 = _mm_add_epi32(acc2, _mm_madd_epi16(l, _mm_srli_si128(r, 4)));
        a += sa;
        b += sb;
    }
    acc0 = _mm_add_epi32(acc0, _mm_shuffle_epi32(acc0, 0x4E));
    acc1 = _mm_add_epi32(acc1, _mm_shuffle_epi32(acc1, 0x4E));
    acc2 = _mm_add_epi32(acc2, _mm_shuffle_epi32(acc2, 0x4E));
    acc0 = _mm_add_epi32(acc0, _mm_shuffle_epi32(acc0, 0xB1));
    acc1 = _mm_add_epi32(acc1, _mm_shuffle_epi32(acc1, 0xB1));
    acc2 = _mm_add_epi32(acc2, _mm_shuffle_epi32(acc2, 0xB1));
    out[0] = (uint32_t)_mm_cvtsi128_si32(acc0);
    out[1] = (uint32_t)_mm_cvtsi128_si32(acc1);
    out[2] = (uint32_t)_mm_cvtsi128_si32(acc2);
}
#elif defined(NEGOBS_SIMD_NEON)
#define STX_CROSS5_SIMD 1
/* NEON form (AArch64, and ARMv7 built with -mfpu=neon) of stx_cross5_ref (bit-exact, same load contract as
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
        acc = vpadalq_u16(acc, vmull_u8(vand_u8(vld1_u8(a), m5), vld1_u8(b)));
        a += sa;
        b += sb;
    }
    return negobs_neon_addv_u32(acc);
}
#define STX_CROSS5X3_SIMD 1
/* NEON form of stx_cross5x3_ref, same contract as the SSE2 one: the right
 * row's 8 bytes shifted by 0, 1, 2 pixels with VEXT (zeros shifted in sit
 * under the left row's masked bytes), products and pair sums as in
 * stx_cross5_simd. */
static inline void stx_cross5x3_simd(const uint8_t *a, ptrdiff_t sa,
                                     const uint8_t *b, ptrdiff_t sb,
                                     uint32_t out[3])
{
    const uint8x8_t m5 = vcreate_u8(UINT64_C(0x000000FFFFFFFFFF));
    const uint8x8_t z = vdup_n_u8(0);
    uint32x4_t acc0 = vdupq_n_u32(0);
    uint32x4_t acc1 = vdupq_n_u32(0);
    uint32x4_t acc2 = vdupq_n_u32(0);
    int32_t k;
    for (k = 0; k < 5; k++) {
        uint8x8_t l = vand_u8(vld1_u8(a), m5);
        uint8x8_t r = vld1_u8(b);
        acc0 = vpadalq_u16(acc0, vmull_u8(l, r));
        acc1 = vpadalq_u16(acc1, vmull_u8(l, vext_u8(r, z, 1)));
        acc2 = vpadalq_u16(acc2, vmull_u8(l, vext_u8(r, z, 2)));
        a += sa;
        b += sb;
    }
    out[0] = negobs_neon_addv_u32(acc0);
    out[1] = negobs_neon_addv_u32(acc1);
    out[2] = negobs_neon_addv_u32(acc2);
}
#endif /* STX_CROSS5_SIMD: defined only where a SIMD form exists */

/* Raw 5x5 cross sum at left (u, yl) and right (ur, yr); both windows
 * inside their images, ur <= u. */
static inline uint32_t stx_cross5(const negobs_image_u8_t *l, int32_t u,
                                  int32_t yl, const negobs_image_u8_t *r,
                                  int32_t ur, int32_t yr)
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
static inline int stx_mncc_frac(const stx_t *s, int32_t u, int32_t v,
                                int32_t d, int32_t *num2, int32_t *den)
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

#endif /* NEGOBS_STEREO_NCC_H */
