/* Table-driven key = value parser; see app_config.h. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_config.h"

static void cfg_fail(app_cfg_error_t *err, const char *fmt, ...)
{
    va_list ap;
    int n = 0;
    if (err == NULL) {
        return;
    }
    if (err->line > 0) {
        n = snprintf(err->msg, sizeof err->msg, "line %ld: ", (long)err->line);
        if (n < 0 || (size_t)n >= sizeof err->msg) {
            n = 0;
        }
    }
    va_start(ap, fmt);
    /* va_start() is above; clang-tidy 14 reports this false positive
     * only when it analyses several files in one run. */
    /* NOLINTNEXTLINE(clang-analyzer-valist.Uninitialized) */
    (void)vsnprintf(err->msg + n, sizeof err->msg - (size_t)n, fmt, ap);
    va_end(ap);
}

static bool is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' ||
           c == '\f';
}

static int parse_bool(const char *v, bool *out)
{
    static const char *const yes[] = {"1", "true", "yes", "on"};
    static const char *const no[] = {"0", "false", "no", "off"};
    size_t i;
    for (i = 0; i < 4; i++) {
        if (strcmp(v, yes[i]) == 0) {
            *out = true;
            return 0;
        }
        if (strcmp(v, no[i]) == 0) {
            *out = false;
            return 0;
        }
    }
    return -1;
}

negobs_status_t app_config_set(const app_cfg_key_t *table, size_t n,
                               const char *key, const char *value,
                               app_cfg_error_t *err)
{
    size_t i;
    const app_cfg_key_t *k = NULL;
    if (table == NULL || key == NULL || value == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    for (i = 0; i < n; i++) {
        if (strcmp(table[i].key, key) == 0) {
            k = &table[i];
            break;
        }
    }
    if (k == NULL) {
        cfg_fail(err, "unknown key '%s'", key);
        return NEGOBS_ERR_INVAL;
    }
    switch (k->type) {
    case APP_CFG_INT: {
        char *end = NULL;
        long long v;
        errno = 0;
        v = strtoll(value, &end, 10);
        if (value[0] == '\0' || end == NULL || *end != '\0' || errno != 0) {
            cfg_fail(err, "%s: '%s' is not an integer", key, value);
            return NEGOBS_ERR_INVAL;
        }
        if (v < k->min || v > k->max) {
            cfg_fail(err, "%s: %lld is outside [%lld, %lld]", key, v,
                     (long long)k->min, (long long)k->max);
            return NEGOBS_ERR_INVAL;
        }
        *(int32_t *)k->ptr = (int32_t)v;
        return NEGOBS_OK;
    }
    case APP_CFG_BOOL:
        if (parse_bool(value, (bool *)k->ptr) != 0) {
            cfg_fail(err, "%s: '%s' is not a boolean (true/false)", key,
                     value);
            return NEGOBS_ERR_INVAL;
        }
        return NEGOBS_OK;
    case APP_CFG_STRING: {
        size_t len = strlen(value);
        if (k->max < 1 || len >= (size_t)k->max) {
            cfg_fail(err, "%s: value longer than %lld characters", key,
                     (long long)(k->max - 1));
            return NEGOBS_ERR_INVAL;
        }
        memcpy(k->ptr, value, len + 1);
        return NEGOBS_OK;
    }
    default:
        cfg_fail(err, "%s: bad table entry", key);
        return NEGOBS_ERR_INVAL;
    }
}

/* Parse one line (modified in place); `check` (may be NULL) vets the
 * value of a key once the table accepted it. */
static negobs_status_t parse_line(const app_cfg_key_t *table, size_t n,
                                  char *line, app_cfg_check_fn check,
                                  void *user, app_cfg_error_t *err)
{
    char *hash = strchr(line, '#');
    char *eq;
    char *key = line;
    char *val;
    char *end;
    if (hash != NULL) {
        *hash = '\0';
    }
    while (is_blank(*key)) {
        key++;
    }
    if (*key == '\0') {
        return NEGOBS_OK;
    }
    eq = strchr(key, '=');
    if (eq == NULL) {
        cfg_fail(err, "expected 'key = value', got '%s'", key);
        return NEGOBS_ERR_INVAL;
    }
    end = eq;
    while (end > key && is_blank(end[-1])) {
        end--;
    }
    *end = '\0';
    if (*key == '\0') {
        cfg_fail(err, "missing key before '='");
        return NEGOBS_ERR_INVAL;
    }
    val = eq + 1;
    while (is_blank(*val)) {
        val++;
    }
    end = val + strlen(val);
    while (end > val && is_blank(end[-1])) {
        end--;
    }
    *end = '\0';
    if (app_config_set(table, n, key, val, err) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    if (check != NULL) {
        char why[128];
        why[0] = '\0';
        if (check(user, key, val, why, sizeof why) != 0) {
            cfg_fail(err, "%s: %s", key, why);
            return NEGOBS_ERR_INVAL;
        }
    }
    return NEGOBS_OK;
}

negobs_status_t app_config_parse_text(const app_cfg_key_t *table, size_t n,
                                      const char *text, app_cfg_error_t *err)
{
    char line[APP_CONFIG_LINE_MAX + 1];
    int32_t lineno = 0;
    if (table == NULL || text == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    while (*text != '\0') {
        const char *nl = strchr(text, '\n');
        size_t len = nl != NULL ? (size_t)(nl - text) : strlen(text);
        negobs_status_t s;
        lineno++;
        if (err != NULL) {
            err->line = lineno;
        }
        if (len > APP_CONFIG_LINE_MAX) {
            cfg_fail(err, "line longer than %d characters",
                     APP_CONFIG_LINE_MAX);
            return NEGOBS_ERR_INVAL;
        }
        memcpy(line, text, len);
        line[len] = '\0';
        s = parse_line(table, n, line, NULL, NULL, err);
        if (s != NEGOBS_OK) {
            return s;
        }
        text += len + (nl != NULL ? 1u : 0u);
    }
    if (err != NULL) {
        err->line = 0;
        err->msg[0] = '\0';
    }
    return NEGOBS_OK;
}

/* One line into buf (without its newline). Returns 0 at end of file,
 * 1 for a line, -1 for a line longer than APP_CONFIG_LINE_MAX, -2 for a
 * line holding a NUL byte (a binary file, or a text editor's accident: it
 * would silently cut the line short). The rest of a bad line is read. */
static int read_line(FILE *f, char *buf, size_t cap)
{
    size_t len = 0;
    int rc = 1;
    int c = getc(f);
    if (c == EOF) {
        return 0;
    }
    while (c != EOF && c != '\n') {
        if (c == '\0') {
            rc = -2;
        } else if (len + 1u >= cap) {
            rc = rc == 1 ? -1 : rc;
        } else {
            buf[len++] = (char)c;
        }
        c = getc(f);
    }
    buf[len] = '\0';
    return rc;
}

negobs_status_t app_config_parse_file(const char *path,
                                      const app_cfg_key_t *table, size_t n,
                                      app_cfg_error_t *err)
{
    return app_config_parse_file_checked(path, table, n, NULL, NULL, err);
}

negobs_status_t app_config_parse_file_checked(const char *path,
                                              const app_cfg_key_t *table,
                                              size_t n, app_cfg_check_fn check,
                                              void *user, app_cfg_error_t *err)
{
    char line[APP_CONFIG_LINE_MAX + 1];
    FILE *f;
    int32_t lineno = 0;
    int r;
    negobs_status_t s = NEGOBS_OK;
    if (path == NULL || table == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (err != NULL) {
        err->line = 0;
        err->msg[0] = '\0';
    }
    f = fopen(path, "r");
    if (f == NULL) {
        cfg_fail(err, "%s: %s", path, strerror(errno));
        return NEGOBS_ERR_NODEV;
    }
    while ((r = read_line(f, line, sizeof line)) != 0) {
        lineno++;
        if (err != NULL) {
            err->line = lineno;
        }
        if (r == -2) {
            cfg_fail(err, "NUL byte in the line (not a text file?)");
            s = NEGOBS_ERR_INVAL;
            break;
        }
        if (r == -1) {
            cfg_fail(err, "line longer than %d characters",
                     APP_CONFIG_LINE_MAX);
            s = NEGOBS_ERR_INVAL;
            break;
        }
        s = parse_line(table, n, line, check, user, err);
        if (s != NEGOBS_OK) {
            break;
        }
    }
    if (s == NEGOBS_OK && ferror(f)) {
        cfg_fail(err, "%s: read error", path);
        s = NEGOBS_ERR_IO;
    }
    (void)fclose(f);
    if (s == NEGOBS_OK && err != NULL) {
        err->line = 0;
    }
    return s;
}

void app_config_print_keys(FILE *out, const app_cfg_key_t *table, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        const app_cfg_key_t *k = &table[i];
        switch (k->type) {
        case APP_CFG_INT:
            fprintf(out, "  %-20s int %lld..%lld  %s\n", k->key,
                    (long long)k->min, (long long)k->max, k->help);
            break;
        case APP_CFG_BOOL:
            fprintf(out, "  %-20s bool  %s\n", k->key, k->help);
            break;
        default: fprintf(out, "  %-20s text  %s\n", k->key, k->help); break;
        }
    }
}
