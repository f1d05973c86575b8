/*
 * Recording on its own thread (negobs_port/record_queue.h): a failing or
 * stalled writer, injected through the write hook, must never hold up the
 * caller, and a failure must stop only the recording.
 */
#define _XOPEN_SOURCE 700

#include <errno.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs_port/clock.h"
#include "negobs_port/record_queue.h"
#include "port_test_util.h"

#define W 32
#define H 16
#define SLOTS 4u

static char dir[256];
static char session[300];
static uint8_t slots[SLOTS * 2u * W * H];
static uint8_t img[2][W * H];
static negobs_record_queue_t q;

/* Writer hooks: fail with ENOSPC after `budget` calls; or block until
 * released (a card that stalls). */
static atomic_int budget;
static atomic_int stall;
static atomic_int calls;

static ssize_t enospc_after_budget(int fd, const void *buf, size_t n)
{
    atomic_fetch_add(&calls, 1);
    if (atomic_fetch_sub(&budget, 1) <= 0) {
        errno = ENOSPC;
        return -1;
    }
    return write(fd, buf, n);
}

static ssize_t stalling(int fd, const void *buf, size_t n)
{
    atomic_fetch_add(&calls, 1);
    while (atomic_load(&stall)) {
        negobs_clock_sleep_ms(1u);
    }
    return write(fd, buf, n);
}

static int setup(void **state)
{
    (void)state;
    memset(&q, 0, sizeof q);
    atomic_store(&calls, 0);
    if (tu_mkdtemp(dir, sizeof dir, "recq") != 0) {
        return -1;
    }
    (void)snprintf(session, sizeof session, "%s/s", dir);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    tu_rm_tree(dir);
    return 0;
}

static void make_pair(negobs_frame_pair_t *p, uint32_t i)
{
    memset(p, 0, sizeof *p);
    memset(img[0], (int)(i & 0xFFu), sizeof img[0]);
    memset(img[1], (int)((i + 100u) & 0xFFu), sizeof img[1]);
    p->left.y.data = img[0];
    p->right.y.data = img[1];
    p->left.y.width = p->right.y.width = W;
    p->left.y.height = p->right.y.height = H;
    p->left.y.stride = p->right.y.stride = W;
    p->left.ts_ns = 1000000u * i;
    p->right.ts_ns = p->left.ts_ns;
    p->left.sequence = p->right.sequence = i;
}

static long file_size(const char *leaf)
{
    char path[400];
    FILE *f;
    long n;
    (void)snprintf(path, sizeof path, "%s/%s", session, leaf);
    f = fopen(path, "rb");
    if (f == NULL) {
        return -1;
    }
    (void)fseek(f, 0, SEEK_END);
    n = ftell(f);
    (void)fclose(f);
    return n;
}

static void test_recq_records_every_pair(void **state)
{
    negobs_frame_pair_t p;
    negobs_recq_stats_t st;
    uint32_t i;
    (void)state;
    assert_int_equal(negobs_recq_start(&q, session, slots, 2u * W * H, SLOTS),
                     NEGOBS_OK);
    for (i = 0; i < 20; i++) {
        make_pair(&p, i);
        while (negobs_recq_push(&q, &p) == 0) {
            negobs_clock_sleep_ms(1u); /* test only: wait for a slot */
        }
    }
    negobs_recq_stop(&q);
    negobs_recq_stats(&q, &st);
    assert_int_equal(st.written, 20);
    assert_int_equal(file_size("left.y"), 20L * W * H);
    assert_int_equal(file_size("right.y"), 20L * W * H);
}

/* Full disk: the first pair's pixels are written, then ENOSPC. The queue
 * stops recording, keeps the message, and every later push returns at
 * once with -1; the caller goes on. */
static void test_recq_write_failure_stops_only_the_recording(void **state)
{
    negobs_frame_pair_t p;
    negobs_recq_stats_t st;
    uint32_t i;
    int pushed_after_failure = 0;
    (void)state;
    atomic_store(&budget, 3); /* pair 0: left, right, its index line */
    q.write_fn = enospc_after_budget;
    assert_int_equal(negobs_recq_start(&q, session, slots, 2u * W * H, SLOTS),
                     NEGOBS_OK);
    for (i = 0; i < 60; i++) {
        int r;
        make_pair(&p, i);
        r = negobs_recq_push(&q, &p);
        assert_true(r >= -1 && r <= 1);
        negobs_recq_stats(&q, &st);
        if (st.state == NEGOBS_RECQ_FAILED) {
            pushed_after_failure++;
            assert_int_equal(negobs_recq_push(&q, &p), -1);
        }
        negobs_clock_sleep_ms(1u);
    }
    assert_true(pushed_after_failure > 0);
    negobs_recq_stats(&q, &st);
    assert_int_equal(st.state, NEGOBS_RECQ_FAILED);
    assert_int_equal(st.written, 1);
    assert_non_null(strstr(st.errmsg, "write failed at pair 1"));
    assert_non_null(strstr(st.errmsg, strerror(ENOSPC)));
    negobs_recq_stop(&q);
    /* the index holds the one pair that was written */
    assert_int_equal(file_size("left.y"), (long)W * H);
}

/* A card that stalls: push never waits for it. With every slot taken the
 * newest pair is dropped (counted), the queued ones are written in order
 * once the card comes back. */
static void test_recq_stalled_writer_drops_newest_without_waiting(void **state)
{
    negobs_frame_pair_t p;
    negobs_recq_stats_t st;
    uint32_t i;
    uint32_t queued = 0;
    uint32_t dropped = 0;
    uint64_t t0;
    uint64_t worst = 0;
    char idx[4096];
    (void)state;
    atomic_store(&stall, 1);
    q.write_fn = stalling;
    assert_int_equal(negobs_recq_start(&q, session, slots, 2u * W * H, SLOTS),
                     NEGOBS_OK);
    for (i = 0; i < 30; i++) {
        int r;
        uint64_t dt;
        make_pair(&p, i);
        t0 = negobs_clock_now_ns();
        r = negobs_recq_push(&q, &p);
        dt = negobs_clock_now_ns() - t0;
        worst = dt > worst ? dt : worst;
        if (r == 1) {
            queued++;
        } else {
            assert_int_equal(r, 0);
            dropped++;
        }
    }
    /* the writer holds pair 0 (stalled); SLOTS pairs were queued */
    assert_int_equal(queued, SLOTS);
    assert_int_equal(dropped, 30u - SLOTS);
    /* a stalled card costs the caller no wait (a copy and a lock only;
     * 50 ms would mean it waited for the writer) */
    assert_true(worst < 50000000u);
    atomic_store(&stall, 0);
    negobs_recq_stop(&q);
    negobs_recq_stats(&q, &st);
    assert_int_equal(st.written, SLOTS);
    assert_int_equal(st.dropped, 30u - SLOTS);
    /* the oldest pairs, in order: sequences 0..SLOTS-1 */
    (void)snprintf(idx, sizeof idx, "%s", session);
    assert_true(tu_read(session, "frames.txt", idx, sizeof idx) > 0);
    assert_non_null(strstr(idx, "\n0 0 0 0\n1 1000000 1000000 1\n"));
    assert_non_null(strstr(idx, "\n3 3000000 3000000 3\n"));
    assert_null(strstr(idx, "\n4 "));
}

/* An existing session is refused by the writer thread too (O_EXCL), and
 * left as it was. */
static void test_recq_never_writes_over_a_session(void **state)
{
    negobs_frame_pair_t p;
    negobs_recq_stats_t st;
    char txt[64];
    (void)state;
    assert_int_equal(mkdir(session, 0755), 0);
    assert_int_equal(tu_write_str(session, "frames.txt", "precious\n"), 0);
    assert_int_equal(negobs_recq_start(&q, session, slots, 2u * W * H, SLOTS),
                     NEGOBS_OK);
    make_pair(&p, 0);
    assert_int_equal(negobs_recq_push(&q, &p), 1);
    negobs_recq_stop(&q);
    negobs_recq_stats(&q, &st);
    assert_int_equal(st.state, NEGOBS_RECQ_FAILED);
    assert_non_null(strstr(st.errmsg, "already holds a session"));
    assert_true(tu_read(session, "frames.txt", txt, sizeof txt) > 0);
    assert_string_equal(txt, "precious\n");
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(test_recq_records_every_pair),
        T(test_recq_write_failure_stops_only_the_recording),
        T(test_recq_stalled_writer_drops_newest_without_waiting),
        T(test_recq_never_writes_over_a_session),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
