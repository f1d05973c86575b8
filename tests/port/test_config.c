/* Table-driven key = value parser. */
#define _XOPEN_SOURCE 700

#include <stdbool.h>
#include <string.h>

#include "cmocka_all.h"
#include "app_config.h"
#include "port_test_util.h"

static int32_t fps;
static int32_t gain;
static bool flip;
static char alert[16];

static const app_cfg_key_t table[] = {
    {"fps", APP_CFG_INT, &fps, 1, 120, "frame rate"},
    {"gain", APP_CFG_INT, &gain, -1, 1000, "sensor gain, -1 auto"},
    {"flip", APP_CFG_BOOL, &flip, 0, 1, "mirror images"},
    {"alert", APP_CFG_STRING, alert, 0, sizeof alert, "output"},
};
#define N (sizeof table / sizeof table[0])

static int reset(void **state)
{
    (void)state;
    fps = 30;
    gain = -1;
    flip = false;
    strcpy(alert, "console");
    return 0;
}

static void test_config_parses_values_comments_and_blanks(void **state)
{
    app_cfg_error_t err;
    (void)state;
    assert_int_equal(app_config_parse_text(table, N,
                                           "# camera\n"
                                           "\n"
                                           "  fps=15  \n"
                                           "gain = -1 # automatic\n"
                                           "flip = yes\r\n"
                                           "alert = pwm:0:1\n"
                                           "fps = 20",
                                           &err),
                     NEGOBS_OK);
    assert_int_equal(fps, 20); /* a later line wins */
    assert_int_equal(gain, -1);
    assert_true(flip);
    assert_string_equal(alert, "pwm:0:1");
}

static void expect_error(const char *text, int32_t line, const char *needle)
{
    app_cfg_error_t err;
    memset(&err, 0, sizeof err);
    assert_int_equal(app_config_parse_text(table, N, text, &err),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(err.line, line);
    assert_non_null(strstr(err.msg, needle));
}

static void test_config_bad_lines_name_line_and_reason(void **state)
{
    char msg[32];
    (void)state;
    expect_error("fps = 10\n\nfsp = 10\n", 3, "unknown key 'fsp'");
    expect_error("fps = 12x\n", 1, "not an integer");
    expect_error("fps =\n", 1, "not an integer");
    expect_error("fps = 0\n", 1, "outside [1, 120]");
    expect_error("fps = 99999999999999999999\n", 1, "not an integer");
    expect_error("# ok\nfps 10\n", 2, "expected 'key = value'");
    expect_error("= 10\n", 1, "missing key");
    expect_error("flip = maybe\n", 1, "not a boolean");
    expect_error("alert = 0123456789abcdef\n", 1, "longer than 15");
    (void)snprintf(msg, sizeof msg, "line %d:", 3);
    expect_error("fps = 10\n\nfsp = 10\n", 3, msg);
    /* The variables before the bad line were set; others keep defaults. */
    reset(NULL);
    expect_error("gain = 5\nflip = 2\n", 2, "flip");
    assert_int_equal(gain, 5);
    assert_false(flip);
}

static void test_config_rejects_overlong_line(void **state)
{
    char text[400];
    (void)state;
    memset(text, 'a', sizeof text);
    memcpy(text, "alert = ", 8);
    text[sizeof text - 1] = '\0';
    expect_error(text, 1, "longer than");
}

static void test_config_file_and_override(void **state)
{
    char dir[256];
    char path[300];
    app_cfg_error_t err;
    (void)state;
    assert_int_equal(tu_mkdtemp(dir, sizeof dir, "cfg"), 0);
    assert_int_equal(tu_write_str(dir, "a.conf", "fps = 25\nflip = on\n"), 0);
    (void)snprintf(path, sizeof path, "%s/a.conf", dir);
    assert_int_equal(app_config_parse_file(path, table, N, &err), NEGOBS_OK);
    assert_int_equal(fps, 25);
    assert_true(flip);
    /* Command-line style override through the same table. */
    err.line = 0;
    assert_int_equal(app_config_set(table, N, "fps", "60", &err), NEGOBS_OK);
    assert_int_equal(fps, 60);
    assert_int_equal(app_config_set(table, N, "nope", "1", &err),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(tu_write_str(dir, "b.conf", "fps = 25\ngain = 2000\n"),
                     0);
    (void)snprintf(path, sizeof path, "%s/b.conf", dir);
    assert_int_equal(app_config_parse_file(path, table, N, &err),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.msg, "line 2: gain"));
    (void)snprintf(path, sizeof path, "%s/missing.conf", dir);
    assert_int_equal(app_config_parse_file(path, table, N, &err),
                     NEGOBS_ERR_NODEV);
    assert_non_null(strstr(err.msg, "missing.conf"));
    tu_rm_tree(dir);
}

/* A NUL byte cuts a C string short: the file reader must say "NUL byte",
 * not "longer than" (what fgets + strlen made of it). */
static void test_config_file_line_with_nul_byte(void **state)
{
    static const char text[] = "fps = 25\nfl\0ip = on\ngain = 3\n";
    char dir[256];
    char path[300];
    app_cfg_error_t err;
    (void)state;
    assert_int_equal(tu_mkdtemp(dir, sizeof dir, "cfg"), 0);
    assert_int_equal(tu_write(dir, "nul.conf", text, sizeof text - 1u), 0);
    (void)snprintf(path, sizeof path, "%s/nul.conf", dir);
    assert_int_equal(app_config_parse_file(path, table, N, &err),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.msg, "line 2: NUL byte"));
    /* a line of exactly APP_CONFIG_LINE_MAX characters still fits, one
     * more does not */
    {
        char line[APP_CONFIG_LINE_MAX + 3];
        memset(line, ' ', sizeof line);
        memcpy(line, "fps = 7", 7);
        line[APP_CONFIG_LINE_MAX] = '\n';
        assert_int_equal(
            tu_write(dir, "max.conf", line, APP_CONFIG_LINE_MAX + 1u), 0);
        (void)snprintf(path, sizeof path, "%s/max.conf", dir);
        assert_int_equal(app_config_parse_file(path, table, N, &err),
                         NEGOBS_OK);
        assert_int_equal(fps, 7);
        line[APP_CONFIG_LINE_MAX] = ' ';
        line[APP_CONFIG_LINE_MAX + 1] = '\n';
        assert_int_equal(
            tu_write(dir, "long.conf", line, APP_CONFIG_LINE_MAX + 2u), 0);
        (void)snprintf(path, sizeof path, "%s/long.conf", dir);
        assert_int_equal(app_config_parse_file(path, table, N, &err),
                         NEGOBS_ERR_INVAL);
        assert_non_null(strstr(err.msg, "line 1: line longer than"));
    }
    tu_rm_tree(dir);
}

static int check_alert(void *user, const char *key, const char *value,
                       char *why, size_t why_len)
{
    ++*(int *)user;
    if (strcmp(key, "alert") == 0 && strcmp(value, "console") != 0 &&
        strcmp(value, "none") != 0) {
        (void)snprintf(why, why_len, "no such output '%s'", value);
        return 1;
    }
    return 0;
}

/* Values the table cannot judge are vetted by the program's check, and a
 * refusal names the line like any other bad line. */
static void test_config_file_checked_values_name_the_line(void **state)
{
    char dir[256];
    char path[300];
    app_cfg_error_t err;
    int calls = 0;
    (void)state;
    assert_int_equal(tu_mkdtemp(dir, sizeof dir, "cfg"), 0);
    assert_int_equal(tu_write_str(dir, "c.conf",
                                  "# x\nfps = 20\n"
                                  "alert = none\n"),
                     0);
    (void)snprintf(path, sizeof path, "%s/c.conf", dir);
    assert_int_equal(app_config_parse_file_checked(path, table, N, check_alert,
                                                   &calls, &err),
                     NEGOBS_OK);
    assert_int_equal(calls, 2);
    assert_string_equal(alert, "none");
    assert_int_equal(tu_write_str(dir, "d.conf",
                                  "fps = 20\n\n"
                                  "alert = siren\n"),
                     0);
    (void)snprintf(path, sizeof path, "%s/d.conf", dir);
    assert_int_equal(app_config_parse_file_checked(path, table, N, check_alert,
                                                   &calls, &err),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(err.line, 3);
    assert_non_null(strstr(err.msg, "line 3: alert: no such output 'siren'"));
    tu_rm_tree(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_config_parses_values_comments_and_blanks,
                               reset),
        cmocka_unit_test_setup(test_config_bad_lines_name_line_and_reason,
                               reset),
        cmocka_unit_test_setup(test_config_rejects_overlong_line, reset),
        cmocka_unit_test_setup(test_config_file_and_override, reset),
        cmocka_unit_test_setup(test_config_file_line_with_nul_byte, reset),
        cmocka_unit_test_setup(test_config_file_checked_values_name_the_line,
                               reset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
