/*
 * Start-up check that the CPU runs the SIMD the library was built for.
 *
 * x86-64 (SSE2) and aarch64 (NEON) have their SIMD in the baseline, so
 * only a 32-bit ARM library built with -Darm_neon=true can meet a CPU it
 * cannot run on (Debian's armhf baseline has no NEON): such a library
 * would die with SIGILL in the first frame. The check reads the kernel's
 * hardware capabilities (getauxval(AT_HWCAP)) on Linux; lib/ has no OS, so
 * it lives here (docs/SIMD.md).
 */
#ifndef NEGOBS_PORT_CPU_H
#define NEGOBS_PORT_CPU_H

#include <stddef.h>

#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** HWCAP_NEON of 32-bit ARM Linux (bit 12 of AT_HWCAP). */
#define NEGOBS_PORT_HWCAP_ARM_NEON (1ul << 12)

/**
 * @brief The decision from its inputs (any host can test it).
 * @param lib_simd  negobs_simd() of the linked library
 * @param arm32     non-zero when the program runs on 32-bit ARM
 * @param hwcap     AT_HWCAP of the running CPU (read only when arm32)
 * @param msg       receives a one-line reason on failure (may be NULL)
 * @param cap       bytes at msg
 * @return NEGOBS_OK, or NEGOBS_ERR_UNSUPPORTED when the library needs
 *         NEON and the CPU does not report it.
 */
negobs_status_t negobs_port_cpu_check_hwcap(const char *lib_simd, int arm32,
                                            unsigned long hwcap, char *msg,
                                            size_t cap);

/** @brief negobs_port_cpu_check_hwcap() for this program and this CPU. */
negobs_status_t negobs_port_cpu_check(char *msg, size_t cap);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CPU_H */
