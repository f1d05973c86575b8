#include "cmocka_all.h"
#include "negobs/image.h"

static uint8_t pixels[64 * 48];
static int16_t pixels16[64 * 48];

static negobs_image_u8_t make(int32_t w, int32_t h, int32_t stride)
{
    negobs_image_u8_t img;
    img.data = pixels;
    img.width = w;
    img.height = h;
    img.stride = stride;
    return img;
}

static void test_image_accepts_padded_rows(void **state)
{
    negobs_image_u8_t img = make(60, 48, 64);
    (void)state;
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_OK);
    pixels[2 * 64 + 5] = 77;
    assert_int_equal(negobs_image_u8_row(&img, 2)[5], 77);
}

static void test_image_rejects_stride_below_width(void **state)
{
    negobs_image_u8_t img = make(64, 48, 63);
    (void)state;
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_ERR_INVAL);
}

static void test_image_rejects_null_and_empty(void **state)
{
    negobs_image_u8_t img = make(64, 48, 64);
    (void)state;
    assert_int_equal(negobs_image_u8_check(NULL), NEGOBS_ERR_INVAL);
    img.data = NULL;
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_ERR_INVAL);
    img = make(0, 48, 64);
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_ERR_INVAL);
    img = make(64, -1, 64);
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_ERR_INVAL);
}

static void test_image_rejects_huge_sizes(void **state)
{
    negobs_image_u8_t img = make(NEGOBS_MAX_DIM + 1, 2, NEGOBS_MAX_DIM + 1);
    (void)state;
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_ERR_INVAL);
    img = make(4, 4, 4 * NEGOBS_MAX_DIM + 1);
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_ERR_INVAL);
    img = make(NEGOBS_MAX_DIM, 1, NEGOBS_MAX_DIM);
    assert_int_equal(negobs_image_u8_check(&img), NEGOBS_OK);
}

static void test_image_min_size_is_enforced(void **state)
{
    negobs_image_u8_t img = make(4, 4, 4);
    (void)state;
    assert_int_equal(negobs_image_u8_check_min(&img, 5, 5), NEGOBS_ERR_INVAL);
    img = make(5, 5, 5);
    assert_int_equal(negobs_image_u8_check_min(&img, 5, 5), NEGOBS_OK);
}

static void test_image_s16_rules(void **state)
{
    negobs_image_s16_t img;
    (void)state;
    img.data = pixels16;
    img.width = 64;
    img.height = 48;
    img.stride = 64;
    assert_int_equal(negobs_image_s16_check(&img), NEGOBS_OK);
    negobs_image_s16_row(&img, 3)[1] = -5;
    assert_int_equal(pixels16[3 * 64 + 1], -5);
    img.stride = 10;
    assert_int_equal(negobs_image_s16_check(&img), NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_image_accepts_padded_rows),
        cmocka_unit_test(test_image_rejects_stride_below_width),
        cmocka_unit_test(test_image_rejects_null_and_empty),
        cmocka_unit_test(test_image_rejects_huge_sizes),
        cmocka_unit_test(test_image_min_size_is_enforced),
        cmocka_unit_test(test_image_s16_rules),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
