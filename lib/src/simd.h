/*
 * Which SIMD instruction set the library's hot kernels are compiled for.
 * Internal to lib/.
 *
 * The choice is made at compile time, from the compiler's own macros:
 *   NEGOBS_SIMD_SSE2  x86-64 (SSE2 is part of the x86-64 baseline)
 *   NEGOBS_SIMD_NEON  AArch64 (NEON is part of the baseline), or 32-bit
 *                     ARM compiled with -mfpu=neon (meson -Darm_neon=true:
 *                     Debian's armhf baseline does not guarantee NEON, so
 *                     an armhf build uses the plain C kernels unless asked;
 *                     docs/SIMD.md)
 * NEGOBS_NO_SIMD (meson -Dsimd=false) keeps every kernel on its plain C
 * reference. Under -mgeneral-regs-only (the integer-only hygiene check)
 * __ARM_NEON is undefined, so the reference paths are what it compiles.
 */
#ifndef NEGOBS_SIMD_H
#define NEGOBS_SIMD_H

#include <stdint.h>

#if !defined(NEGOBS_NO_SIMD)
#if defined(__SSE2__)
#define NEGOBS_SIMD_SSE2 1
#include <emmintrin.h>
#elif defined(__ARM_NEON)
#define NEGOBS_SIMD_NEON 1
#include <arm_neon.h>
#endif
#endif

#if defined(NEGOBS_SIMD_SSE2) || defined(NEGOBS_SIMD_NEON)
#define NEGOBS_SIMD 1
#endif

#if defined(NEGOBS_SIMD_NEON)
/* Sum of the four lanes (AArch64 has one instruction; ARMv7 pairs). */
static inline uint32_t negobs_neon_addv_u32(uint32x4_t v)
{
#if defined(__aarch64__)
    return vaddvq_u32(v);
#else
    uint32x2_t t = vadd_u32(vget_low_u32(v), vget_high_u32(v));
    return vget_lane_u32(vpadd_u32(t, t), 0);
#endif
}
#endif

#endif /* NEGOBS_SIMD_H */
