/* Start-up SIMD check (negobs_port/cpu.h). */
#include "negobs_port/cpu.h"

#include <stdio.h>
#include <string.h>

#include "negobs/version.h"

#if defined(__linux__) && defined(__arm__) && !defined(__aarch64__)
#include <sys/auxv.h>
#define NEGOBS_PORT_ARM32 1
#endif

negobs_status_t negobs_port_cpu_check_hwcap(const char *lib_simd, int arm32,
                                            unsigned long hwcap, char *msg,
                                            size_t cap)
{
    if (lib_simd == NULL || !arm32 || strcmp(lib_simd, "neon") != 0 ||
        (hwcap & NEGOBS_PORT_HWCAP_ARM_NEON) != 0u) {
        return NEGOBS_OK;
    }
    if (msg != NULL && cap > 0u) {
        snprintf(msg, cap,
                 "this negobs library was built with NEON (-Darm_neon=true) "
                 "but the CPU does not report NEON (AT_HWCAP 0x%lx); use a "
                 "build without -Darm_neon",
                 hwcap);
    }
    return NEGOBS_ERR_UNSUPPORTED;
}

negobs_status_t negobs_port_cpu_check(char *msg, size_t cap)
{
#if defined(NEGOBS_PORT_ARM32)
    return negobs_port_cpu_check_hwcap(negobs_simd(), 1, getauxval(AT_HWCAP),
                                       msg, cap);
#else
    return negobs_port_cpu_check_hwcap(negobs_simd(), 0, 0ul, msg, cap);
#endif
}
