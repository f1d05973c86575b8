/*
 * Key = value configuration files.
 *
 * Generic: the program describes its settings in a table of
 * {key, type, pointer, min, max, help} and the parser fills the pointed-to
 * variables. Syntax: one `key = value` per line, blanks around both
 * ignored, '#' starts a comment (anywhere on a line, so values cannot
 * contain '#'), empty lines ignored, a later line overrides an earlier one.
 * An unknown key, a missing '=', a value of the wrong type or outside
 * [min, max] stops parsing with NEGOBS_ERR_INVAL and a message naming the
 * line number. Variables keep their values for keys not in the file, so
 * defaults are simply the values set before parsing.
 */
#ifndef NEGOBS_APP_CONFIG_H
#define NEGOBS_APP_CONFIG_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest accepted line, in bytes, without the newline. */
#define APP_CONFIG_LINE_MAX 255

typedef enum app_cfg_type {
    APP_CFG_INT = 0,   /**< int32_t; value in [min, max]                */
    APP_CFG_BOOL = 1,  /**< bool; 0/1, true/false, yes/no, on/off       */
    APP_CFG_STRING = 2 /**< char[max]; text up to max-1 bytes (min unused) */
} app_cfg_type_t;

/** One setting. */
typedef struct app_cfg_key {
    const char *key; /**< name as written in the file            */
    app_cfg_type_t type;
    void *ptr;        /**< int32_t *, bool * or char[max]         */
    int64_t min;      /**< INT: smallest value                    */
    int64_t max;      /**< INT: largest value; STRING: buffer size */
    const char *help; /**< one line for --help and docs           */
} app_cfg_key_t;

/** Where and why parsing failed. */
typedef struct app_cfg_error {
    int32_t line;  /**< 1-based line number, 0 when not line-related */
    char msg[192]; /**< "line 3: unknown key 'fsp'"                  */
} app_cfg_error_t;

/**
 * @brief Set one key from its text value (used for lines and for
 *        command-line overrides).
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL (err->msg says why).
 */
negobs_status_t app_config_set(const app_cfg_key_t *table, size_t n,
                               const char *key, const char *value,
                               app_cfg_error_t *err);

/**
 * @brief Parse a whole text (lines separated by '\n').
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL at the first bad line.
 */
negobs_status_t app_config_parse_text(const app_cfg_key_t *table, size_t n,
                                      const char *text, app_cfg_error_t *err);

/**
 * @brief Parse a file.
 * @return NEGOBS_OK, NEGOBS_ERR_NODEV (cannot open), NEGOBS_ERR_INVAL
 *         (bad line; err->line set), NEGOBS_ERR_IO (read error).
 */
negobs_status_t app_config_parse_file(const char *path,
                                      const app_cfg_key_t *table, size_t n,
                                      app_cfg_error_t *err);

/**
 * Vets a value the table accepted (e.g. the syntax of a device spec):
 * return 0 to accept, non-zero to refuse with a reason in `why`.
 */
typedef int (*app_cfg_check_fn)(void *user, const char *key, const char *value,
                                char *why, size_t why_len);

/**
 * @brief app_config_parse_file() with `check` (may be NULL) called for
 *        every key = value line after the table accepted it, so that a
 *        value the program cannot use is reported with its line number.
 *        A line holding a NUL byte is refused as such.
 * @return as app_config_parse_file().
 */
negobs_status_t app_config_parse_file_checked(const char *path,
                                              const app_cfg_key_t *table,
                                              size_t n, app_cfg_check_fn check,
                                              void *user,
                                              app_cfg_error_t *err);

/** @brief Print "key  (type, range)  help" for every entry. */
void app_config_print_keys(FILE *out, const app_cfg_key_t *table, size_t n);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_APP_CONFIG_H */
