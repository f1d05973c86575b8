/*
 * Binary PGM (P5) reader and writer.
 *
 * The header is parsed byte by byte with hard limits on every number, so
 * a corrupt or hostile file can at worst be rejected: sizes are checked
 * against NEGOBS_MAX_DIM and the caller's buffer before any pixel is read.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "negobs_port/camera_replay.h"

static void set_err(char *err, size_t len, const char *path, const char *what)
{
    if (err != NULL && len > 0) {
        (void)snprintf(err, len, "%s: %s", path, what);
    }
}

/* Skip whitespace and '#' comments; return the next byte or EOF. */
static int skip_space(FILE *f)
{
    int c = fgetc(f);
    for (;;) {
        if (c == '#') {
            while (c != '\n' && c != EOF) {
                c = fgetc(f);
            }
        } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r' ||
                   c == '\v' || c == '\f') {
            c = fgetc(f);
        } else {
            return c;
        }
    }
}

/* Parse one header number (at most 6 digits). -1 on error. */
static int32_t read_number(FILE *f)
{
    int32_t v = 0;
    int digits = 0;
    int c = skip_space(f);
    while (c >= '0' && c <= '9') {
        if (++digits > 6) {
            return -1;
        }
        v = v * 10 + (int32_t)(c - '0');
        c = fgetc(f);
    }
    if (digits == 0) {
        return -1;
    }
    /* Exactly one whitespace byte ends a number (the last one ends the
     * header and the raster starts right after it). */
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r') {
        return -1;
    }
    return v;
}

negobs_status_t negobs_pgm_read(const char *path, uint8_t *dst, size_t cap,
                                int32_t *w, int32_t *h, char *err,
                                size_t err_len)
{
    FILE *f;
    int magic[2];
    int32_t width;
    int32_t height;
    int32_t maxval;
    size_t need;
    size_t got;
    if (path == NULL || dst == NULL || w == NULL || h == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        int e = errno;
        set_err(err, err_len, path, strerror(e));
        return e == ENOENT ? NEGOBS_ERR_NODEV : NEGOBS_ERR_IO;
    }
    magic[0] = fgetc(f);
    magic[1] = fgetc(f);
    if (magic[0] != 'P' || magic[1] != '5') {
        set_err(err, err_len, path, "not a binary PGM (P5) file");
        (void)fclose(f);
        return NEGOBS_ERR_CORRUPT;
    }
    width = read_number(f);
    height = read_number(f);
    maxval = read_number(f);
    if (width < 1 || height < 1 || maxval < 1) {
        set_err(err, err_len, path, "malformed PGM header");
        (void)fclose(f);
        return NEGOBS_ERR_CORRUPT;
    }
    if (width > NEGOBS_MAX_DIM || height > NEGOBS_MAX_DIM || maxval > 255) {
        set_err(err, err_len, path,
                "PGM size above NEGOBS_MAX_DIM or maxval above 255");
        (void)fclose(f);
        return NEGOBS_ERR_CORRUPT;
    }
    need = (size_t)width * (size_t)height;
    if (need > cap) {
        set_err(err, err_len, path, "image larger than the buffer");
        (void)fclose(f);
        return NEGOBS_ERR_NOSPACE;
    }
    got = fread(dst, 1, need, f);
    if (got != need) {
        int io = ferror(f);
        set_err(err, err_len, path,
                io ? "read error" : "truncated pixel data");
        (void)fclose(f);
        return io ? NEGOBS_ERR_IO : NEGOBS_ERR_CORRUPT;
    }
    (void)fclose(f);
    *w = width;
    *h = height;
    return NEGOBS_OK;
}

negobs_status_t negobs_pgm_write(const char *path,
                                 const negobs_image_u8_t *img)
{
    FILE *f;
    int32_t y;
    int ok;
    if (path == NULL || negobs_image_u8_check(img) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    f = fopen(path, "wb");
    if (f == NULL) {
        return NEGOBS_ERR_IO;
    }
    ok = fprintf(f, "P5\n%ld %ld\n255\n", (long)img->width,
                 (long)img->height) > 0;
    for (y = 0; ok && y < img->height; y++) {
        ok = fwrite(negobs_image_u8_row(img, y), 1, (size_t)img->width, f) ==
             (size_t)img->width;
    }
    if (fclose(f) != 0) {
        ok = 0;
    }
    return ok ? NEGOBS_OK : NEGOBS_ERR_IO;
}
