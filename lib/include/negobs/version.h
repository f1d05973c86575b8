/* negobs library version. */
#ifndef NEGOBS_VERSION_H
#define NEGOBS_VERSION_H

#ifdef __cplusplus
extern "C" {
#endif

#define NEGOBS_VERSION_MAJOR 0
#define NEGOBS_VERSION_MINOR 1
#define NEGOBS_VERSION_PATCH 0
#define NEGOBS_VERSION_STRING "0.1.0"

/** @brief Version of the linked library, e.g. "0.1.0". */
const char *negobs_version(void);

/**
 * @brief SIMD instruction set the library's hot kernels were compiled for:
 *        "sse2", "neon" or "none" (docs/SIMD.md). A 32-bit ARM library
 *        built with NEON needs a CPU that has it; port/ checks that at
 *        start-up (negobs_port/cpu.h).
 */
const char *negobs_simd(void);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_VERSION_H */
