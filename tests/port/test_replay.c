/* Replay source and session recorder on generated files. */
#define _XOPEN_SOURCE 700

#include <stdio.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs_port/camera_replay.h"
#include "negobs_port/clock.h"
#include "port_test_util.h"

#define W 16
#define H 8

static uint8_t pix[2 * 64 * 64];
static char dir[256];

static int setup(void **state)
{
    (void)state;
    return tu_mkdtemp(dir, sizeof dir, "replay");
}

static int teardown(void **state)
{
    (void)state;
    tu_rm_tree(dir);
    return 0;
}

static uint8_t value_at(uint32_t idx, int side, int32_t x, int32_t y)
{
    return (uint8_t)(idx * 31u + (uint32_t)side * 101u + (uint32_t)x * 7u +
                     (uint32_t)y * 13u);
}

static void write_pair(uint32_t idx, int32_t w, int32_t h)
{
    uint8_t img[64 * 64];
    negobs_image_u8_t d = {img, w, h, w};
    char path[400];
    int side;
    int32_t x;
    int32_t y;
    for (side = 0; side < 2; side++) {
        for (y = 0; y < h; y++) {
            for (x = 0; x < w; x++) {
                img[y * w + x] = value_at(idx, side, x, y);
            }
        }
        (void)snprintf(path, sizeof path, "%s/%s_%04u.pgm", dir,
                       side == 0 ? "left" : "right", (unsigned)idx);
        assert_int_equal(negobs_pgm_write(path, &d), NEGOBS_OK);
    }
}

static void open_replay(negobs_replay_t *rp, negobs_capture_t *cam,
                        negobs_status_t want)
{
    negobs_capture_config_t cfg;
    char arg[300];
    negobs_capture_config_default(&cfg);
    cfg.width = 0;
    cfg.height = 0;
    cfg.fps = 0;
    (void)snprintf(arg, sizeof arg, "replay:%s", dir);
    cfg.left = arg;
    assert_int_equal(negobs_replay_init(rp, pix, sizeof pix, cam), NEGOBS_OK);
    assert_int_equal(negobs_capture_open(cam, &cfg), want);
    if (want == NEGOBS_OK) {
        assert_int_equal(negobs_capture_start(cam), NEGOBS_OK);
    }
}

static void check_pair(const negobs_frame_pair_t *p, uint32_t idx)
{
    int32_t x;
    int32_t y;
    assert_int_equal(p->left.y.width, W);
    assert_int_equal(p->left.y.height, H);
    assert_true(p->left.y.stride >= W);
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            assert_int_equal(negobs_image_u8_row(&p->left.y, y)[x],
                             value_at(idx, 0, x, y));
            assert_int_equal(negobs_image_u8_row(&p->right.y, y)[x],
                             value_at(idx, 1, x, y));
        }
    }
}

static void test_replay_reads_pgm_pairs_until_end(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    negobs_capture_stats_t stats;
    uint32_t i;
    (void)state;
    for (i = 0; i < 3; i++) {
        write_pair(i, W, H);
    }
    open_replay(&rp, &cam, NEGOBS_OK);
    for (i = 0; i < 3; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
        assert_int_equal(p.index, i);
        assert_int_equal(p.left.sequence, i);
        check_pair(&p, i);
        negobs_capture_release(&cam, &p);
    }
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_CAPTURE_END);
    negobs_capture_get_stats(&cam, &stats);
    assert_int_equal(stats.pairs, 3);
    negobs_capture_stop(&cam);
    negobs_capture_close(&cam);
}

static void test_replay_loop_restarts_at_first_pair(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_capture_config_t cfg;
    negobs_frame_pair_t p;
    (void)state;
    write_pair(0, W, H);
    write_pair(1, W, H);
    negobs_capture_config_default(&cfg);
    cfg.left = dir;
    cfg.width = W;
    cfg.height = H;
    cfg.fps = 0;
    cfg.loop = true;
    assert_int_equal(negobs_replay_init(&rp, pix, sizeof pix, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_OK);
    assert_int_equal(negobs_capture_start(&cam), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    check_pair(&p, 0);
    assert_int_equal(p.index, 2);
    negobs_capture_close(&cam);
}

static void test_replay_requested_size_must_match(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_capture_config_t cfg;
    negobs_frame_pair_t p;
    (void)state;
    write_pair(0, W, H);
    negobs_capture_config_default(&cfg); /* asks for 640x480 */
    cfg.left = dir;
    cfg.fps = 0;
    assert_int_equal(negobs_replay_init(&rp, pix, sizeof pix, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_OK);
    assert_int_equal(negobs_capture_start(&cam), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_ERR_INVAL);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "640x480 requested"));
    negobs_capture_close(&cam);
}

static void test_replay_paces_at_fps(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_capture_config_t cfg;
    negobs_frame_pair_t p;
    uint64_t t0;
    int i;
    (void)state;
    for (i = 0; i < 4; i++) {
        write_pair((uint32_t)i, W, H);
    }
    negobs_capture_config_default(&cfg);
    cfg.left = dir;
    cfg.width = 0;
    cfg.height = 0;
    cfg.fps = 10; /* 100 ms apart: 4 pairs take >= 300 ms */
    assert_int_equal(negobs_replay_init(&rp, pix, sizeof pix, &cam),
                     NEGOBS_OK);
    assert_int_equal(negobs_capture_open(&cam, &cfg), NEGOBS_OK);
    assert_int_equal(negobs_capture_start(&cam), NEGOBS_OK);
    t0 = negobs_clock_now_ms();
    /* A 5 ms timeout cannot wait for the 2nd pair: TIMEOUT, kept. */
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 5), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 5), NEGOBS_ERR_TIMEOUT);
    for (i = 1; i < 4; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 200), NEGOBS_OK);
        assert_int_equal(p.left.sequence, (uint32_t)i);
    }
    assert_true(negobs_clock_now_ms() - t0 >= 299);
    negobs_capture_close(&cam);
}

static void test_replay_rejects_truncated_pgm(void **state)
{
    static const char hdr[] = "P5\n16 8\n255\n";
    uint8_t buf[sizeof hdr - 1 + 50];
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    (void)state;
    write_pair(0, W, H);
    memcpy(buf, hdr, sizeof hdr - 1);
    memset(buf + sizeof hdr - 1, 9, 50); /* 50 of 128 pixels */
    assert_int_equal(tu_write(dir, "right_0000.pgm", buf, sizeof buf), 0);
    open_replay(&rp, &cam, NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_ERR_CORRUPT);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "truncated"));
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "right_0000.pgm"));
    negobs_capture_close(&cam);
}

static void test_pgm_reader_rejects_corrupt_headers(void **state)
{
    static const char *const bad[] = {
        "P2\n16 8\n255\n",         /* ASCII PGM                 */
        "P5\n16\n",                /* missing height            */
        "P5\n-16 8\n255\n",        /* sign                      */
        "P5\n16 8\n65535\n",       /* 16-bit PGM                */
        "P5\n99999 8\n255\n",      /* above NEGOBS_MAX_DIM      */
        "P5\n9999999999 8\n255\n", /* overflowing number        */
        "P5 16 8 255x",            /* no whitespace after maxval */
        "",                        /* empty                     */
    };
    char path[400];
    char err[160];
    int32_t w;
    int32_t h;
    size_t i;
    (void)state;
    (void)snprintf(path, sizeof path, "%s/x.pgm", dir);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(tu_write_str(dir, "x.pgm", bad[i]), 0);
        err[0] = '\0';
        assert_int_equal(
            negobs_pgm_read(path, pix, sizeof pix, &w, &h, err, sizeof err),
            NEGOBS_ERR_CORRUPT);
        assert_true(strlen(err) > 0);
    }
    /* Comments in the header are legal. */
    {
        char ok[64 + 128];
        int n = snprintf(ok, 64, "P5\n# made by a test\n16 8\n255\n");
        memset(ok + n, 3, 128);
        assert_int_equal(tu_write(dir, "x.pgm", ok, (size_t)n + 128), 0);
        assert_int_equal(
            negobs_pgm_read(path, pix, sizeof pix, &w, &h, err, sizeof err),
            NEGOBS_OK);
        assert_int_equal(w, 16);
        assert_int_equal(h, 8);
        /* Too small a buffer is NOSPACE, not an overflow. */
        assert_int_equal(
            negobs_pgm_read(path, pix, 127, &w, &h, err, sizeof err),
            NEGOBS_ERR_NOSPACE);
    }
    (void)snprintf(path, sizeof path, "%s/none.pgm", dir);
    assert_int_equal(
        negobs_pgm_read(path, pix, sizeof pix, &w, &h, err, sizeof err),
        NEGOBS_ERR_NODEV);
}

static void test_replay_missing_right_or_size_change_is_corrupt(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    char path[400];
    (void)state;
    write_pair(0, W, H);
    write_pair(1, W + 2, H);
    write_pair(2, W, H);
    (void)snprintf(path, sizeof path, "%s/right_0002.pgm", dir);
    assert_int_equal(remove(path), 0);
    open_replay(&rp, &cam, NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_ERR_CORRUPT);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "size"));
    negobs_capture_close(&cam);
    /* A folder with neither layout. */
    tu_rm_tree(dir);
    assert_int_equal(mkdir(dir, 0755), 0);
    open_replay(&rp, &cam, NEGOBS_ERR_NODEV);
}

static void record_session(uint32_t n)
{
    static uint8_t img[2][H][W + 5]; /* padded rows: stride W + 5 */
    negobs_recorder_t rec;
    negobs_frame_pair_t p;
    uint32_t i;
    int32_t x;
    int32_t y;
    assert_int_equal(negobs_recorder_open(&rec, dir, W, H), NEGOBS_OK);
    for (i = 0; i < n; i++) {
        for (y = 0; y < H; y++) {
            for (x = 0; x < W + 5; x++) {
                img[0][y][x] = x < W ? value_at(i, 0, x, y) : 0xEE;
                img[1][y][x] = x < W ? value_at(i, 1, x, y) : 0xEE;
            }
        }
        p.left.y.data = &img[0][0][0];
        p.right.y.data = &img[1][0][0];
        p.left.y.width = p.right.y.width = W;
        p.left.y.height = p.right.y.height = H;
        p.left.y.stride = p.right.y.stride = W + 5;
        p.left.ts_ns = 1000000000u + i * 33000000u;
        p.right.ts_ns = p.left.ts_ns + 2000000u;
        p.left.sequence = p.right.sequence = 40 + i;
        p.index = i;
        assert_int_equal(negobs_recorder_write(&rec, &p), NEGOBS_OK);
    }
    p.left.y.width = W - 1;
    assert_int_equal(negobs_recorder_write(&rec, &p), NEGOBS_ERR_INVAL);
    negobs_recorder_close(&rec);
}

static void test_session_round_trip(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    uint32_t i;
    (void)state;
    record_session(3);
    open_replay(&rp, &cam, NEGOBS_OK);
    for (i = 0; i < 3; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
        check_pair(&p, i);
        assert_int_equal(p.left.sequence, 40 + i);
        assert_int_equal(p.right.ts_ns - p.left.ts_ns, 2000000u);
    }
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_CAPTURE_END);
    negobs_capture_close(&cam);
}

static void test_session_truncated_frames_are_corrupt(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    char path[400];
    FILE *f;
    (void)state;
    record_session(2);
    /* Cut right.y in the middle of the second frame. */
    (void)snprintf(path, sizeof path, "%s/right.y", dir);
    f = fopen(path, "r+b");
    assert_non_null(f);
    assert_int_equal(ftruncate(fileno(f), W * H + 10), 0);
    (void)fclose(f);
    open_replay(&rp, &cam, NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_ERR_CORRUPT);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "damaged session"));
    assert_non_null(strstr(negobs_replay_damage(&rp), "right.y 1 complete"));
    negobs_capture_close(&cam);
}

/* A session whose frames.txt never reached the disk (stdio buffer lost
 * to SIGKILL or a power cut) while left.y/right.y hold the frames: every
 * frame is replayed, with synthesised timestamps, then the end is an
 * error that says so; never "0 pairs" and a clean end. */
static void test_session_without_index_is_recovered(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    uint64_t t_prev = 0;
    uint32_t i;
    (void)state;
    record_session(5);
    assert_int_equal(tu_write_str(dir, "frames.txt", ""), 0);
    open_replay(&rp, &cam, NEGOBS_OK);
    assert_non_null(strstr(negobs_replay_damage(&rp), "lists 0 pairs"));
    assert_non_null(
        strstr(negobs_replay_damage(&rp), "5 with synthesised timestamps"));
    for (i = 0; i < 5; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
        check_pair(&p, i);
        assert_true(i == 0 || p.left.ts_ns >= t_prev);
        t_prev = p.left.ts_ns;
    }
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_ERR_CORRUPT);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "5 recoverable"));
    negobs_capture_close(&cam);
}

/* frames.txt cut in its last line (and one record short), left.y with a
 * partial frame: the complete pairs are replayed, recorded timestamps
 * where there is a record. */
static void test_session_cut_index_line_is_recovered(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    char path[400];
    FILE *f;
    uint32_t i;
    (void)state;
    record_session(3);
    assert_int_equal(tu_write_str(dir, "frames.txt",
                                  "# index left_ts_ns right_ts_ns sequence\n"
                                  "0 1000000000 1002000000 40\n"
                                  "1 1033000000 10"),
                     0);
    (void)snprintf(path, sizeof path, "%s/left.y", dir);
    f = fopen(path, "ab");
    assert_non_null(f);
    assert_int_equal(fwrite("xyz", 1, 3, f), 3);
    (void)fclose(f);
    open_replay(&rp, &cam, NEGOBS_OK);
    assert_non_null(strstr(negobs_replay_damage(&rp), "a cut line"));
    assert_non_null(strstr(negobs_replay_damage(&rp), "(+3/+0 bytes)"));
    for (i = 0; i < 3; i++) {
        assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
        check_pair(&p, i);
        assert_int_equal(p.left.sequence, 40 + i);
    }
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_ERR_CORRUPT);
    negobs_capture_close(&cam);
}

/* Nothing to recover, or a file missing: open() fails, each with its own
 * status and a message naming the file. */
static void test_session_unrecoverable_or_missing_file(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    char path[400];
    (void)state;
    record_session(2);
    assert_int_equal(tu_write_str(dir, "left.y", "short"), 0);
    open_replay(&rp, &cam, NEGOBS_ERR_CORRUPT);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "no complete pair"));
    (void)snprintf(path, sizeof path, "%s/left.y", dir);
    assert_int_equal(remove(path), 0);
    open_replay(&rp, &cam, NEGOBS_ERR_NODEV);
    assert_non_null(strstr(negobs_capture_errmsg(&cam), "left.y"));
}

/* The recorder never writes over an earlier session, whatever the file
 * that is already there. */
static void test_recorder_refuses_existing_session(void **state)
{
    negobs_recorder_t rec;
    char msg[200];
    char path[400];
    FILE *f;
    long size;
    (void)state;
    assert_int_equal(negobs_recorder_check_dir(dir, msg, sizeof msg),
                     NEGOBS_OK);
    record_session(2);
    assert_int_equal(negobs_recorder_check_dir(dir, msg, sizeof msg),
                     NEGOBS_ERR_INVAL);
    assert_non_null(strstr(msg, "already holds a session"));
    assert_int_equal(negobs_recorder_open(&rec, dir, W, H), NEGOBS_ERR_INVAL);
    assert_non_null(strstr(rec.errmsg, "already holds a session"));
    negobs_recorder_close(&rec);
    (void)snprintf(path, sizeof path, "%s/left.y", dir);
    f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    size = ftell(f);
    (void)fclose(f);
    assert_int_equal(size, 2 * W * H);
    /* only right.y left over: still refused */
    (void)snprintf(path, sizeof path, "%s/session.txt", dir);
    assert_int_equal(remove(path), 0);
    (void)snprintf(path, sizeof path, "%s/frames.txt", dir);
    assert_int_equal(remove(path), 0);
    (void)snprintf(path, sizeof path, "%s/left.y", dir);
    assert_int_equal(remove(path), 0);
    assert_int_equal(negobs_recorder_check_dir(dir, msg, sizeof msg),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_recorder_open(&rec, dir, W, H), NEGOBS_ERR_INVAL);
    negobs_recorder_close(&rec);
}

/* frames.txt is in the kernel after every pair (no stdio buffer): read
 * back while the recorder is still open, as after a SIGKILL. */
static void test_recorder_index_written_per_pair(void **state)
{
    static uint8_t img[W * H];
    negobs_recorder_t rec;
    negobs_frame_pair_t p;
    char path[400];
    char text[256];
    FILE *f;
    size_t n;
    (void)state;
    memset(&p, 0, sizeof p);
    p.left.y.data = p.right.y.data = img;
    p.left.y.width = p.right.y.width = W;
    p.left.y.height = p.right.y.height = H;
    p.left.y.stride = p.right.y.stride = W;
    p.left.ts_ns = 7;
    assert_int_equal(negobs_recorder_open(&rec, dir, W, H), NEGOBS_OK);
    assert_int_equal(negobs_recorder_write(&rec, &p), NEGOBS_OK);
    (void)snprintf(path, sizeof path, "%s/frames.txt", dir);
    f = fopen(path, "r");
    assert_non_null(f);
    n = fread(text, 1, sizeof text - 1, f);
    (void)fclose(f);
    text[n] = '\0';
    assert_non_null(strstr(text, "\n0 7 0 0\n"));
    negobs_recorder_close(&rec);
}

static void test_session_bad_header_or_record_is_corrupt(void **state)
{
    negobs_replay_t rp;
    negobs_capture_t cam;
    negobs_frame_pair_t p;
    (void)state;
    record_session(2);
    assert_int_equal(tu_write_str(dir, "frames.txt", "0 1 2 3\n7 x y z\n"), 0);
    open_replay(&rp, &cam, NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100), NEGOBS_OK);
    assert_int_equal(negobs_capture_get_pair(&cam, &p, 100),
                     NEGOBS_ERR_CORRUPT);
    negobs_capture_close(&cam);
    assert_int_equal(
        tu_write_str(dir, "session.txt", "negobs-session 1\nwidth 0\n"), 0);
    open_replay(&rp, &cam, NEGOBS_ERR_CORRUPT);
    assert_int_equal(tu_write_str(dir, "session.txt", "garbage\n"), 0);
    open_replay(&rp, &cam, NEGOBS_ERR_CORRUPT);
    assert_int_equal(tu_write_str(dir, "session.txt",
                                  "negobs-session 1\nwidth 4096\n"
                                  "height 4096\n"),
                     0);
    open_replay(&rp, &cam, NEGOBS_ERR_NOSPACE);
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(test_replay_reads_pgm_pairs_until_end),
        T(test_replay_loop_restarts_at_first_pair),
        T(test_replay_requested_size_must_match),
        T(test_replay_paces_at_fps),
        T(test_replay_rejects_truncated_pgm),
        T(test_pgm_reader_rejects_corrupt_headers),
        T(test_replay_missing_right_or_size_change_is_corrupt),
        T(test_session_round_trip),
        T(test_session_truncated_frames_are_corrupt),
        T(test_session_bad_header_or_record_is_corrupt),
        T(test_session_without_index_is_recovered),
        T(test_session_cut_index_line_is_recovered),
        T(test_session_unrecoverable_or_missing_file),
        T(test_recorder_refuses_existing_session),
        T(test_recorder_index_written_per_pair),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
