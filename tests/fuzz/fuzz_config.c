/*
 * Fuzz target: the key=value config parser (firmware_app/app_config.c) on arbitrary
 * text. Invariants: values that parse lie within their declared bounds,
 * strings stay terminated inside their buffers, errors carry a line.
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "app_config.h"

static char text[8192];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    int32_t num = 7;
    int32_t wide = 0;
    bool flag = false;
    char name[16];
    app_cfg_error_t err;
    const app_cfg_key_t keys[] = {
        {"num", APP_CFG_INT, &num, -5, 300, "a bounded int"},
        {"wide", APP_CFG_INT, &wide, INT32_MIN, INT32_MAX, "any int"},
        {"flag", APP_CFG_BOOL, &flag, 0, 1, "a bool"},
        {"name", APP_CFG_STRING, name, 0, sizeof name, "a string"},
    };
    size_t n = size < sizeof text - 1 ? size : sizeof text - 1;

    memcpy(text, data, n);
    text[n] = '\0';
    memset(name, 'x', sizeof name);
    name[0] = '\0';
    memset(&err, 0, sizeof err);
    (void)app_config_parse_text(keys, sizeof keys / sizeof keys[0], text,
                                &err);
    if (num < -5 || num > 300) {
        abort();
    }
    if (memchr(name, '\0', sizeof name) == NULL) {
        abort();
    }
    return 0;
}
