/* Small file helpers for the port tests (temporary trees, file contents). */
#ifndef NEGOBS_PORT_TEST_UTIL_H
#define NEGOBS_PORT_TEST_UTIL_H

#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* mkdtemp under $TMPDIR or /tmp; `out` gets the path. 0 on success. */
static inline int tu_mkdtemp(char *out, size_t len, const char *tag)
{
    const char *base = getenv("TMPDIR");
    int n;
    if (base == NULL || base[0] == '\0') {
        base = "/tmp";
    }
    n = snprintf(out, len, "%s/negobs-%s-XXXXXX", base, tag);
    if (n < 0 || (size_t)n >= len) {
        return -1;
    }
    return mkdtemp(out) != NULL ? 0 : -1;
}

static inline int tu_rm_one(const char *path, const struct stat *sb, int flag,
                            struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

static inline void tu_rm_tree(const char *path)
{
    (void)nftw(path, tu_rm_one, 16, FTW_DEPTH | FTW_PHYS);
}

/* Write `len` bytes to DIR/LEAF. 0 on success. */
static inline int tu_write(const char *dir, const char *leaf, const void *data,
                           size_t len)
{
    char path[512];
    FILE *f;
    size_t w;
    if (snprintf(path, sizeof path, "%s/%s", dir, leaf) >= (int)sizeof path) {
        return -1;
    }
    f = fopen(path, "wb");
    if (f == NULL) {
        return -1;
    }
    w = fwrite(data, 1, len, f);
    return (fclose(f) == 0 && w == len) ? 0 : -1;
}

static inline int tu_write_str(const char *dir, const char *leaf,
                               const char *s)
{
    return tu_write(dir, leaf, s, strlen(s));
}

/* Read DIR/LEAF as text into buf (NUL-terminated). Returns bytes or -1. */
static inline long tu_read(const char *dir, const char *leaf, char *buf,
                           size_t len)
{
    char path[512];
    FILE *f;
    size_t r;
    if (snprintf(path, sizeof path, "%s/%s", dir, leaf) >= (int)sizeof path) {
        return -1;
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        return -1;
    }
    r = fread(buf, 1, len - 1, f);
    buf[r] = '\0';
    (void)fclose(f);
    return (long)r;
}

static inline int tu_mkdir(const char *dir, const char *leaf)
{
    char path[512];
    if (snprintf(path, sizeof path, "%s/%s", dir, leaf) >= (int)sizeof path) {
        return -1;
    }
    return mkdir(path, 0755);
}

#endif
