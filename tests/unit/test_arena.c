/*
 * Arena tests. This executable compiles arena.c with NEGOBS_ARENA_GUARDS
 * so the canary walk is tested whatever the build type.
 */
#include <string.h>

#include "arena.h"
#include "cmocka_all.h"

/* A module-style carve: the same function measures and allocates. */
typedef struct carved {
    uint8_t *a;
    int16_t *b;
    uint32_t *c;
} carved_t;

static negobs_status_t carve(negobs_arena_t *ar, carved_t *out)
{
    out->a = negobs_arena_take(ar, 13);
    out->b = negobs_arena_take(ar, 100 * sizeof(int16_t));
    out->c = negobs_arena_take(ar, 7 * sizeof(uint32_t));
    return negobs_arena_status(ar);
}

static size_t measure(void)
{
    negobs_arena_t ar;
    carved_t c;
    negobs_arena_init(&ar, NULL, 0);
    assert_int_equal(carve(&ar, &c), NEGOBS_OK);
    assert_null(c.a);
    return negobs_arena_used(&ar);
}

/* 16-byte aligned backing store; the union forces the alignment. */
static union {
    uint8_t bytes[4096];
    uint64_t align[2];
} store __attribute__((aligned(16)));

static void test_arena_measure_is_exact(void **state)
{
    size_t need = measure();
    negobs_arena_t ar;
    carved_t c;
    (void)state;
    assert_true(need > 13 + 200 + 28);
    negobs_arena_init(&ar, store.bytes, need);
    assert_int_equal(carve(&ar, &c), NEGOBS_OK);
    assert_int_equal(negobs_arena_used(&ar), need);
    assert_non_null(c.a);
    assert_non_null(c.b);
    assert_non_null(c.c);
}

static void test_arena_one_byte_short_fails_cleanly(void **state)
{
    size_t need = measure();
    negobs_arena_t ar;
    carved_t c;
    (void)state;
    negobs_arena_init(&ar, store.bytes, need - 1);
    assert_int_equal(carve(&ar, &c), NEGOBS_ERR_NOSPACE);
    assert_null(c.c);
    /* The failure is sticky: nothing more is handed out. */
    assert_null(negobs_arena_take(&ar, 1));
}

static void test_arena_blocks_are_16_byte_aligned(void **state)
{
    negobs_arena_t ar;
    carved_t c;
    (void)state;
    negobs_arena_init(&ar, store.bytes, sizeof store.bytes);
    assert_int_equal(carve(&ar, &c), NEGOBS_OK);
    assert_true(negobs_arena_aligned(c.a));
    assert_true(negobs_arena_aligned(c.b));
    assert_true(negobs_arena_aligned(c.c));
    assert_true((uint8_t *)c.b >= c.a + 13);
}

static void test_arena_rejects_misaligned_base(void **state)
{
    negobs_arena_t ar;
    (void)state;
    negobs_arena_init(&ar, store.bytes + 1, 1000);
    assert_int_equal(negobs_arena_status(&ar), NEGOBS_ERR_ALIGN);
    assert_null(negobs_arena_take(&ar, 4));
}

static void test_arena_guards_catch_one_byte_overrun(void **state)
{
    negobs_arena_t ar;
    carved_t c;
    (void)state;
    negobs_arena_init(&ar, store.bytes, sizeof store.bytes);
    assert_int_equal(carve(&ar, &c), NEGOBS_OK);
    memset(c.a, 0x11, 13);
    memset(c.b, 0x22, 200);
    assert_int_equal(negobs_arena_check(&ar), NEGOBS_OK);
    c.a[13] = 0; /* one byte past the 13 requested */
    assert_int_equal(negobs_arena_check(&ar), NEGOBS_ERR_CORRUPT);
}

static void test_arena_guards_catch_underrun(void **state)
{
    negobs_arena_t ar;
    carved_t c;
    (void)state;
    negobs_arena_init(&ar, store.bytes, sizeof store.bytes);
    assert_int_equal(carve(&ar, &c), NEGOBS_OK);
    ((uint8_t *)c.c)[-1] = 0; /* clobbers the header of the last block */
    assert_int_equal(negobs_arena_check(&ar), NEGOBS_ERR_CORRUPT);
}

static void test_arena_huge_request_is_refused(void **state)
{
    negobs_arena_t ar;
    (void)state;
    negobs_arena_init(&ar, NULL, 0);
    assert_null(negobs_arena_take(&ar, SIZE_MAX - 3));
    assert_int_equal(negobs_arena_status(&ar), NEGOBS_ERR_NOSPACE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arena_measure_is_exact),
        cmocka_unit_test(test_arena_one_byte_short_fails_cleanly),
        cmocka_unit_test(test_arena_blocks_are_16_byte_aligned),
        cmocka_unit_test(test_arena_rejects_misaligned_base),
        cmocka_unit_test(test_arena_guards_catch_one_byte_overrun),
        cmocka_unit_test(test_arena_guards_catch_underrun),
        cmocka_unit_test(test_arena_huge_request_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
