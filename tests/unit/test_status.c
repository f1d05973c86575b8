#include <string.h>

#include "cmocka_all.h"
#include "negobs/status.h"

static void test_status_codes_are_negative_and_distinct(void **state)
{
    static const negobs_status_t all[] = {
        NEGOBS_ERR_INVAL,       NEGOBS_ERR_NOSPACE, NEGOBS_ERR_RANGE,
        NEGOBS_ERR_UNSUPPORTED, NEGOBS_ERR_IO,      NEGOBS_ERR_TIMEOUT,
        NEGOBS_ERR_AGAIN,       NEGOBS_ERR_NODEV,   NEGOBS_ERR_ALIGN,
        NEGOBS_ERR_CORRUPT,     NEGOBS_ERR_STATE,
    };
    size_t i;
    size_t j;
    (void)state;
    assert_int_equal(NEGOBS_OK, 0);
    for (i = 0; i < sizeof all / sizeof all[0]; i++) {
        assert_true(all[i] < 0);
        for (j = i + 1; j < sizeof all / sizeof all[0]; j++) {
            assert_int_not_equal(all[i], all[j]);
        }
    }
}

static void test_status_str_describes_each_code(void **state)
{
    int s;
    (void)state;
    assert_string_equal(negobs_status_str(NEGOBS_OK), "ok");
    assert_string_equal(negobs_status_str(NEGOBS_ERR_NOSPACE),
                        "not enough space");
    /* Every defined code has its own text, none falls to the default. */
    for (s = NEGOBS_ERR_STATE; s < 0; s++) {
        const char *txt = negobs_status_str((negobs_status_t)s);
        assert_non_null(txt);
        assert_true(strlen(txt) > 0);
        assert_string_not_equal(txt, "unknown status");
    }
}

static void test_status_str_unknown_value(void **state)
{
    (void)state;
    assert_string_equal(negobs_status_str((negobs_status_t)-999),
                        "unknown status");
    assert_string_equal(negobs_status_str((negobs_status_t)7),
                        "unknown status");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_codes_are_negative_and_distinct),
        cmocka_unit_test(test_status_str_describes_each_code),
        cmocka_unit_test(test_status_str_unknown_value),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
