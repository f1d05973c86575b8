#include "negobs/version.h"

#include "simd.h"

const char *negobs_version(void)
{
    return NEGOBS_VERSION_STRING;
}

const char *negobs_simd(void)
{
#if defined(NEGOBS_SIMD_SSE2)
    return "sse2";
#elif defined(NEGOBS_SIMD_NEON)
    return "neon";
#else
    return "none";
#endif
}
