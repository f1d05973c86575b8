/* The start-up SIMD check (negobs_port/cpu.h): a NEON library on a 32-bit
 * ARM CPU without NEON is refused with a message; everything else runs. */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/version.h"
#include "negobs_port/cpu.h"

static void test_neon_library_needs_neon_on_arm32(void **state)
{
    char msg[256];
    (void)state;
    msg[0] = '\0';
    assert_int_equal(
        negobs_port_cpu_check_hwcap("neon", 1, 0x1F7ul, msg, sizeof msg),
        NEGOBS_ERR_UNSUPPORTED);
    assert_non_null(strstr(msg, "NEON"));
    assert_int_equal(
        negobs_port_cpu_check_hwcap(
            "neon", 1, 0x1F7ul | NEGOBS_PORT_HWCAP_ARM_NEON, NULL, 0),
        NEGOBS_OK);
    /* a NULL message buffer is allowed on failure too */
    assert_int_equal(negobs_port_cpu_check_hwcap("neon", 1, 0ul, NULL, 0),
                     NEGOBS_ERR_UNSUPPORTED);
}

static void test_other_builds_always_run(void **state)
{
    (void)state;
    assert_int_equal(negobs_port_cpu_check_hwcap("none", 1, 0ul, NULL, 0),
                     NEGOBS_OK);
    assert_int_equal(negobs_port_cpu_check_hwcap("sse2", 0, 0ul, NULL, 0),
                     NEGOBS_OK);
    /* aarch64: NEON is in the baseline, hwcap is not consulted */
    assert_int_equal(negobs_port_cpu_check_hwcap("neon", 0, 0ul, NULL, 0),
                     NEGOBS_OK);
}

/* The library under test runs here, so the check on this CPU passes. */
static void test_this_cpu_passes(void **state)
{
    char msg[256];
    (void)state;
    assert_int_equal(negobs_port_cpu_check(msg, sizeof msg), NEGOBS_OK);
    assert_true(strcmp(negobs_simd(), "sse2") == 0 ||
                strcmp(negobs_simd(), "neon") == 0 ||
                strcmp(negobs_simd(), "none") == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_neon_library_needs_neon_on_arm32),
        cmocka_unit_test(test_other_builds_always_run),
        cmocka_unit_test(test_this_cpu_passes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
