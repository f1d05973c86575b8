/* Bounded bucket queue: order, bound and overflow policy. */
#include "cmocka_all.h"
#include "stereo/stereo_int.h"

#define CAP 32

static uint32_t items[CAP];
static int32_t nexts[CAP];
static int32_t heads[STX_NBUCKET];

static stx_queue_t make(void)
{
    stx_queue_t q;
    q.item = items;
    q.next = nexts;
    q.head = heads;
    q.cap = CAP;
    stx_queue_reset(&q);
    return q;
}

static void test_queue_pops_highest_key_first(void **state)
{
    stx_queue_t q = make();
    uint32_t it;
    int32_t last = STX_NBUCKET;
    uint32_t seed = 3u;
    int32_t i;
    (void)state;
    for (i = 0; i < CAP; i++) {
        int32_t key = (int32_t)(test_lcg_next(&seed) % STX_NBUCKET);
        assert_int_equal(stx_queue_push(&q, (uint32_t)key, key), 1);
    }
    assert_int_equal(q.peak, CAP);
    for (i = 0; i < CAP; i++) {
        assert_int_equal(stx_queue_pop(&q, &it), 1);
        assert_true((int32_t)it <= last);
        last = (int32_t)it;
    }
    assert_int_equal(stx_queue_pop(&q, &it), 0);
    assert_int_equal(q.overflows, 0);
}

static void test_queue_full_evicts_lowest_and_counts(void **state)
{
    stx_queue_t q = make();
    uint32_t it;
    int32_t i;
    (void)state;
    for (i = 0; i < CAP; i++) {
        stx_queue_push(&q, (uint32_t)(100 + i), 100 + i);
    }
    /* higher key: evicts one of key 100 */
    assert_int_equal(stx_queue_push(&q, 250u, 250), 1);
    assert_int_equal(q.overflows, 1);
    assert_int_equal(q.count, CAP);
    /* lower or equal to the lowest: the newcomer is dropped */
    assert_int_equal(stx_queue_push(&q, 5u, 5), 0);
    assert_int_equal(stx_queue_push(&q, 101u, 101), 0);
    assert_int_equal(q.overflows, 3);
    assert_int_equal(q.count, CAP);
    assert_int_equal(q.peak, CAP);
    assert_int_equal(stx_queue_pop(&q, &it), 1);
    assert_int_equal(it, 250u);
    for (i = 1; i < CAP; i++) {
        assert_int_equal(stx_queue_pop(&q, &it), 1);
        assert_true(it != 100u); /* the evicted one is gone */
    }
    assert_int_equal(stx_queue_pop(&q, &it), 0);
}

static void test_queue_keys_are_clamped(void **state)
{
    stx_queue_t q = make();
    uint32_t it;
    (void)state;
    assert_int_equal(stx_queue_push(&q, 1u, -50), 1);
    assert_int_equal(stx_queue_push(&q, 2u, 100000), 1);
    assert_int_equal(stx_queue_pop(&q, &it), 1);
    assert_int_equal(it, 2u);
    assert_int_equal(stx_queue_pop(&q, &it), 1);
    assert_int_equal(it, 1u);
}

static void test_pack_round_trips(void **state)
{
    uint32_t p = stx_pack(4095, 4095, 255);
    (void)state;
    assert_int_equal(stx_unpack_u(p), 4095);
    assert_int_equal(stx_unpack_v(p), 4095);
    assert_int_equal(stx_unpack_d(p), 255);
    p = stx_pack(17, 3, 42);
    assert_int_equal(stx_unpack_u(p), 17);
    assert_int_equal(stx_unpack_v(p), 3);
    assert_int_equal(stx_unpack_d(p), 42);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_queue_pops_highest_key_first),
        cmocka_unit_test(test_queue_full_evicts_lowest_and_counts),
        cmocka_unit_test(test_queue_keys_are_clamped),
        cmocka_unit_test(test_pack_round_trips),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
