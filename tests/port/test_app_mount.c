/* negobs_run's remembered mounting (firmware_app/app_mount.c): what is
 * kept, when, and what a read refuses. */
#define _XOPEN_SOURCE 700

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cmocka_all.h"
#include "app_mount.h"
#include "negobs/detect.h"

static char dir[64];
static char path[128];

static int setup(void **state)
{
    (void)state;
    strcpy(dir, "/tmp/negobs-mount-XXXXXX");
    if (mkdtemp(dir) == NULL) {
        return -1;
    }
    snprintf(path, sizeof path, "%s/mount", dir);
    return 0;
}

static int teardown(void **state)
{
    char tmp[160];
    (void)state;
    remove(path);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    remove(tmp);
    rmdir(dir);
    return 0;
}

static void write_file(const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void test_mount_round_trip(void **state)
{
    char msg[256] = "";
    int32_t h = 0;
    int32_t p = 0;
    (void)state;
    assert_int_equal(app_mount_load(path, &h, &p, msg, sizeof msg), 0);
    assert_int_equal(app_mount_save(path, 1455, 20141, msg, sizeof msg), 0);
    assert_int_equal(app_mount_load(path, &h, &p, msg, sizeof msg), 1);
    assert_int_equal(h, 1455);
    assert_int_equal(p, 20141);
}

static void test_mount_load_refuses(void **state)
{
    static const char *const bad[] = {
        "cam_height_mm = 1400\n",                          /* no pitch   */
        "cam_height_mm = 99999\ncam_pitch_mdeg = 20000\n", /* priors     */
        "cam_height_mm = 500\ncam_pitch_mdeg = 20000\n",
        "cam_height_mm = 1400\ncam_pitch_mdeg = 70000\n",
        "cam_height_mm = 1400\ncam_pitch_mdeg = 2x\n", /* not a number */
        "cam_height_mm = 1400\nfocal_px = 250\n",      /* other keys */
        "garbage\n",
    };
    char msg[256];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        int32_t h = 7;
        int32_t p = 7;
        write_file(bad[i]);
        msg[0] = '\0';
        assert_int_equal(app_mount_load(path, &h, &p, msg, sizeof msg), -1);
        assert_true(msg[0] != '\0');
        assert_int_equal(h, 7); /* outputs untouched */
        assert_int_equal(p, 7);
    }
    write_file("# comment\n\ncam_pitch_mdeg = 0\ncam_height_mm = 600\n");
    {
        int32_t h = 0;
        int32_t p = 1;
        assert_int_equal(app_mount_load(path, &h, &p, msg, sizeof msg), 1);
        assert_int_equal(h, 600);
        assert_int_equal(p, 0);
    }
}

/* A failed write leaves the old file as it was. */
static void test_mount_save_failure_keeps_the_old_file(void **state)
{
    char msg[256] = "";
    char missing[160];
    int32_t h = 0;
    int32_t p = 0;
    (void)state;
    assert_int_equal(app_mount_save(path, 1300, 25000, msg, sizeof msg), 0);
    snprintf(missing, sizeof missing, "%s/no/such/dir/mount", dir);
    assert_int_equal(app_mount_save(missing, 1500, 30000, msg, sizeof msg),
                     -1);
    assert_non_null(strstr(msg, "no/such/dir"));
    assert_int_equal(app_mount_load(path, &h, &p, msg, sizeof msg), 1);
    assert_int_equal(h, 1300);
    assert_int_equal(p, 25000);
}

/* Only evidence is kept; a reference taken by time alone never is (it
 * may be a lower floor stood before, and would verify the next start in
 * front of the same drop). */
static void test_mount_due_only_on_evidence(void **state)
{
    static const struct {
        int32_t by;
        int32_t height_mm;
        int due;
    } cases[] = {
        {NEGOBS_GROUND_REF_NONE, 1400, 0},
        {NEGOBS_GROUND_REF_TIME, 1400, 0},
        {NEGOBS_GROUND_REF_HINT, 1400, 1},
        {NEGOBS_GROUND_REF_FEET, 1400, 1},
        {NEGOBS_GROUND_REF_WALK, 1400, 1},
        {NEGOBS_GROUND_REF_WALK, 2400, 0}, /* outside the priors: never */
    };
    app_mount_keep_t k;
    size_t i;
    (void)state;
    memset(&k, 0, sizeof k);
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        assert_int_equal(
            app_mount_due(&k, cases[i].by, cases[i].height_mm, 20000, 0u),
            cases[i].due);
    }
}

/* After a save: not within APP_MOUNT_SAVE_EVERY_MS, and then only when
 * the reference moved 20 mm or 2 deg. A loaded file counts as kept but
 * does not hold the first save back. */
static void test_mount_due_rate_and_change(void **state)
{
    app_mount_keep_t k;
    const uint32_t t0 = 4000000000u; /* the clock wraps in between */
    (void)state;
    memset(&k, 0, sizeof k);
    app_mount_saved(&k, 1400, 20000, t0);
    assert_int_equal(
        app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1500, 20000, t0 + 1000u), 0);
    assert_int_equal(app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1419, 21999,
                                   t0 + APP_MOUNT_SAVE_EVERY_MS),
                     0);
    assert_int_equal(app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1420, 20000,
                                   t0 + APP_MOUNT_SAVE_EVERY_MS),
                     1);
    assert_int_equal(app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1380, 20000,
                                   t0 + APP_MOUNT_SAVE_EVERY_MS),
                     1);
    assert_int_equal(app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1400, 22000,
                                   t0 + APP_MOUNT_SAVE_EVERY_MS),
                     1);
    memset(&k, 0, sizeof k);
    k.have = 1; /* loaded, not yet saved by this run */
    k.height_mm = 1400;
    k.pitch_mdeg = 20000;
    assert_int_equal(
        app_mount_due(&k, NEGOBS_GROUND_REF_HINT, 1405, 20100, 5u), 0);
    assert_int_equal(
        app_mount_due(&k, NEGOBS_GROUND_REF_HINT, 1430, 20100, 5u), 1);
}

/* A failed save holds the next try back like a save, and keeps what
 * was remembered: the change rule still reads against the loaded value,
 * and with nothing remembered the first success is still due. */
static void test_mount_failed_save_waits_and_keeps(void **state)
{
    app_mount_keep_t k;
    const uint32_t t0 = 1000u;
    (void)state;
    memset(&k, 0, sizeof k);
    app_mount_failed(&k, t0);
    assert_int_equal(k.have, 0);
    assert_int_equal(
        app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1400, 20000, t0 + 1000u), 0);
    assert_int_equal(app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1400, 20000,
                                   t0 + APP_MOUNT_SAVE_EVERY_MS),
                     1);
    memset(&k, 0, sizeof k);
    k.have = 1; /* loaded */
    k.height_mm = 1400;
    k.pitch_mdeg = 20000;
    app_mount_failed(&k, t0);
    assert_int_equal(k.have, 1);
    assert_int_equal(k.height_mm, 1400);
    assert_int_equal(k.pitch_mdeg, 20000);
    assert_int_equal(app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1410, 20000,
                                   t0 + APP_MOUNT_SAVE_EVERY_MS),
                     0);
    assert_int_equal(app_mount_due(&k, NEGOBS_GROUND_REF_WALK, 1420, 20000,
                                   t0 + APP_MOUNT_SAVE_EVERY_MS),
                     1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_mount_round_trip, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_mount_load_refuses, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(
            test_mount_save_failure_keeps_the_old_file, setup, teardown),
        cmocka_unit_test(test_mount_due_only_on_evidence),
        cmocka_unit_test(test_mount_due_rate_and_change),
        cmocka_unit_test(test_mount_failed_save_waits_and_keeps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
