#include "cmocka_all.h"
#include "negobs/fixed.h"
#include "fixed_int.h"

static void test_isqrt_is_floor_sqrt(void **state)
{
    uint32_t x;
    uint32_t seed = 1;
    int i;
    (void)state;
    for (x = 0; x < 70000; x++) {
        uint32_t r = negobs_isqrt_u32(x);
        assert_true((uint64_t)r * r <= x);
        assert_true((uint64_t)(r + 1) * (r + 1) > x);
    }
    for (i = 0; i < 20000; i++) {
        uint32_t v = test_lcg_next(&seed) * 257u + (uint32_t)i;
        uint32_t r = negobs_isqrt_u32(v);
        assert_true((uint64_t)r * r <= v);
        assert_true((uint64_t)(r + 1) * (r + 1) > v);
    }
    assert_int_equal(negobs_isqrt_u32(UINT32_MAX), 65535);
}

static void test_rshift_round_matches_floor_of_half_up(void **state)
{
    int32_t x;
    (void)state;
    /* round(x / 4) with ties up: floor((x + 2) / 4). */
    for (x = -1000; x <= 1000; x++) {
        int32_t num = x + 2;
        int32_t expect = (num >= 0) ? num / 4 : -((-num + 3) / 4);
        assert_int_equal(negobs_rshift_round_s32(x, 2), expect);
    }
    assert_int_equal(negobs_rshift_round_s32(-6, 2), -1); /* -1.5 -> -1 */
    assert_int_equal(negobs_rshift_round_s32(6, 2), 2);   /*  1.5 ->  2 */
}

static void test_saturation_and_abs(void **state)
{
    (void)state;
    assert_int_equal(negobs_sat_s32_to_s16(40000), INT16_MAX);
    assert_int_equal(negobs_sat_s32_to_s16(-40000), INT16_MIN);
    assert_int_equal(negobs_sat_s32_to_s16(-123), -123);
    assert_int_equal(negobs_abs_s32(INT32_MIN), INT32_MAX);
    assert_int_equal(negobs_abs_s32(-7), 7);
    assert_int_equal(negobs_clamp_s32(5, 6, 9), 6);
}

static void test_div_round(void **state)
{
    (void)state;
    assert_int_equal(negobs_div_round_s64(7, 2), 4);
    assert_int_equal(negobs_div_round_s64(-7, 2), -4);
    assert_int_equal(negobs_div_round_s64(7, -2), -4);
    assert_int_equal(negobs_div_round_s64(5, 3), 2);
    assert_int_equal(negobs_div_round_s64(4, 3), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_isqrt_is_floor_sqrt),
        cmocka_unit_test(test_rshift_round_matches_floor_of_half_up),
        cmocka_unit_test(test_saturation_and_abs),
        cmocka_unit_test(test_div_round),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
