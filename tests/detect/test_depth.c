/*
 * Integer stereo geometry: depth <-> disparity round trips, rounding,
 * invalid and saturated values, lateral offset, CORDIC angles.
 */
#include <math.h>
#include <stdlib.h>

#include "cmocka_all.h"
#include "negobs/depth.h"
#include "negobs/fixed.h"
#include "detect/detect_int.h"

#define TEST_PI 3.14159265358979323846

static negobs_rig_t cam;

static void setup_cam(void)
{
    negobs_rig_default(&cam, 320, 240);
}

static void test_depth_known_values(void **state)
{
    (void)state;
    setup_cam();
    assert_int_equal(cam.focal_q4, 4000);
    assert_int_equal(cam.baseline_um, 120000);
    /* f*B = 250 px * 120 mm = 30000 px*mm. */
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, 10 * 16), 3000);
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, 30 * 16), 1000);
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, 1), 480000);
    /* 7.5 px -> 4000 mm exactly; 7.4375 px -> 4033.6 -> 4034. */
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, 120), 4000);
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, 119), 4034);
    assert_int_equal(negobs_disp_q4_from_depth_mm(&cam, 3000), 160);
    assert_int_equal(negobs_disp_q4_from_depth_mm(&cam, 4000), 120);
}

static void test_depth_invalid_and_saturation(void **state)
{
    (void)state;
    setup_cam();
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, 0),
                     NEGOBS_DEPTH_NONE_MM);
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, -16),
                     NEGOBS_DEPTH_NONE_MM);
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, NEGOBS_DISP_INVALID),
                     NEGOBS_DEPTH_NONE_MM);
    cam.focal_q4 = 8192 * 16;
    cam.baseline_um = 1000000;
    assert_int_equal(negobs_depth_mm_from_disp_q4(&cam, 1),
                     NEGOBS_DEPTH_MAX_MM);
    assert_int_equal(negobs_disp_q4_from_depth_mm(&cam, 0), 0);
    assert_int_equal(negobs_disp_q4_from_depth_mm(&cam, 1), INT16_MAX);
}

static void test_depth_round_trip_error_within_one_step(void **state)
{
    int32_t z;
    (void)state;
    setup_cam();
    for (z = 500; z <= 20000; z += 7) {
        int32_t d = negobs_disp_q4_from_depth_mm(&cam, z);
        int32_t z2 = negobs_depth_mm_from_disp_q4(&cam, d);
        /* d is rounded to 1/32 px at worst: |dZ| <= Z * 0.5 / (d - 0.5),
         * plus 1 mm for the rounding of Z itself. */
        double bound = z * 0.5 / (d - 0.5) + 1.0;
        assert_true(abs(z2 - z) <= bound);
    }
}

static void test_depth_matches_double_reference(void **state)
{
    int32_t d;
    (void)state;
    setup_cam();
    cam.focal_q4 = 4013; /* 250.8125 px */
    cam.baseline_um = 119870;
    for (d = 1; d < 2048; d += 3) {
        double ref = (cam.focal_q4 / 16.0) * (cam.baseline_um / 1000.0) /
                     (d / 16.0);
        int32_t z = negobs_depth_mm_from_disp_q4(&cam, d);
        assert_true(fabs(z - ref) <= 0.5 + 1e-9);
    }
}

static void test_depth_lateral(void **state)
{
    (void)state;
    setup_cam();
    /* 100 px right of the centre at 2 m: 2000 * 100 / 250 = 800 mm. */
    assert_int_equal(negobs_lateral_mm(&cam, cam.cx_q4 + 1600, 2000), 800);
    assert_int_equal(negobs_lateral_mm(&cam, cam.cx_q4 - 1600, 2000), -800);
    assert_int_equal(negobs_lateral_mm(&cam, cam.cx_q4, 5000), 0);
}

static void test_depth_camera_check(void **state)
{
    (void)state;
    setup_cam();
    assert_int_equal(negobs_rig_check(&cam), NEGOBS_OK);
    assert_int_equal(negobs_rig_check(NULL), NEGOBS_ERR_INVAL);
    cam.width = 8;
    assert_int_equal(negobs_rig_check(&cam), NEGOBS_ERR_INVAL);
    setup_cam();
    cam.cx_q4 = 400 * 16;
    assert_int_equal(negobs_rig_check(&cam), NEGOBS_ERR_INVAL);
    setup_cam();
    cam.focal_q4 = 0;
    assert_int_equal(negobs_rig_check(&cam), NEGOBS_ERR_INVAL);
}

static void test_depth_atan2_accuracy(void **state)
{
    int32_t i;
    uint32_t rng = 5;
    (void)state;
    assert_int_equal(negobs_atan2_mdeg(1, 1), 45000);
    assert_int_equal(negobs_atan2_mdeg(0, 5), 0);
    assert_int_equal(negobs_atan2_mdeg(5, 0), 90000);
    assert_int_equal(negobs_atan2_mdeg(0, -5), 180000);
    assert_int_equal(negobs_atan2_mdeg(-5, 0), -90000);
    assert_int_equal(negobs_atan2_mdeg(0, 0), 0);
    for (i = 0; i < 5000; i++) {
        int64_t y = (int64_t)(test_lcg_next(&rng) % 2000001u) - 1000000;
        int64_t x = (int64_t)(test_lcg_next(&rng) % 2000001u) - 1000000;
        double ref = atan2((double)y, (double)x) * 180000.0 / TEST_PI;
        int32_t got;
        if (x == 0 && y == 0) {
            continue;
        }
        got = negobs_atan2_mdeg(y, x);
        if (fabs(ref) > 179990.0) {
            continue; /* +-180 wraps */
        }
        assert_true(fabs(got - ref) <= 2.0);
    }
    /* Large magnitudes are normalised, not overflowed. */
    assert_int_equal(negobs_atan2_mdeg((int64_t)1 << 50, (int64_t)1 << 50),
                     45000);
}

static void test_depth_sincos_accuracy(void **state)
{
    int32_t a;
    (void)state;
    for (a = -360000; a <= 360000; a += 1237) {
        int32_t s;
        int32_t c;
        double r = a * TEST_PI / 180000.0;
        negobs_sincos_q30(a, &s, &c);
        assert_true(fabs(s / 1073741824.0 - sin(r)) < 4e-7);
        assert_true(fabs(c / 1073741824.0 - cos(r)) < 4e-7);
    }
}

static void test_depth_isqrt64(void **state)
{
    uint64_t x;
    (void)state;
    assert_int_equal(negobs_isqrt_u64(0), 0);
    assert_int_equal(negobs_isqrt_u64(UINT64_MAX), 4294967295u);
    for (x = 1; x < 100000; x = x * 3 + 1) {
        uint64_t r = negobs_isqrt_u64(x);
        assert_true(r * r <= x && (r + 1) * (r + 1) > x);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_depth_known_values),
        cmocka_unit_test(test_depth_invalid_and_saturation),
        cmocka_unit_test(test_depth_round_trip_error_within_one_step),
        cmocka_unit_test(test_depth_matches_double_reference),
        cmocka_unit_test(test_depth_lateral),
        cmocka_unit_test(test_depth_camera_check),
        cmocka_unit_test(test_depth_atan2_accuracy),
        cmocka_unit_test(test_depth_sincos_accuracy),
        cmocka_unit_test(test_depth_isqrt64),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
