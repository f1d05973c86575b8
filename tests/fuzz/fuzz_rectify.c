/*
 * Fuzz target: the calibration-table loader and the integer remap.
 * Half the inputs are raw table bytes (with the CRC optionally patched so
 * the checks behind it are reached); the other half build a well-formed
 * table from fuzzed header values and node coordinates, then corrupt one
 * byte, and run the remap when the loader accepts it.
 */
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "negobs/rectify.h"

#define MAXW 48
#define MAXH 32
#define MAXNODES ((MAXW + 2) * (MAXH + 2))

static uint8_t table[64 + 2 * MAXNODES * 8 + 4 + 64];
static int32_t lmap[2 * MAXNODES];
static int32_t rmap[2 * MAXNODES];
static uint8_t src[MAXW * MAXH];
static uint8_t dst_l[MAXW * MAXH];
static uint8_t dst_r[MAXW * MAXH];
static uint8_t ws_store[1024] __attribute__((aligned(16)));

static void patch_crc(uint8_t *t, size_t len)
{
    uint32_t crc;
    if (len < 4) {
        return;
    }
    crc = negobs_rectify_crc32(0, t, len - 4);
    t[len - 4] = (uint8_t)crc;
    t[len - 3] = (uint8_t)(crc >> 8);
    t[len - 2] = (uint8_t)(crc >> 16);
    t[len - 1] = (uint8_t)(crc >> 24);
}

static void run_remap(const uint8_t *t, size_t len, int32_t w, int32_t h)
{
    negobs_rectify_config_t cfg;
    negobs_rectify_t ctx;
    negobs_rectify_stats_t st;
    negobs_image_u8_t a = {src, w, h, w};
    negobs_image_u8_t bl = {dst_l, w, h, w};
    negobs_image_u8_t br = {dst_r, w, h, w};
    size_t bytes = 0;

    negobs_rectify_config_default(&cfg, w, h);
    cfg.table = t;
    cfg.table_bytes = len;
    if (negobs_rectify_workspace_size(&cfg, &bytes) != NEGOBS_OK) {
        return;
    }
    if (bytes > sizeof ws_store) {
        abort(); /* a 48-pixel frame needs far less */
    }
    if (negobs_rectify_init(&ctx, &cfg, ws_store, bytes) != NEGOBS_OK) {
        return;
    }
    if (negobs_rectify_process(&ctx, &a, &a, &bl, &br, &st) != NEGOBS_OK) {
        abort(); /* an accepted table must always remap */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input_t in = {data, size, 0};
    uint8_t mode = fuzz_u8(&in);
    int32_t w = fuzz_range(&in, 1, MAXW);
    int32_t h = fuzz_range(&in, 1, MAXH);
    size_t len;
    negobs_rectify_info_t info;

    fuzz_fill(&in, src, sizeof src);
    if (mode & 1u) {
        len = size - in.pos < sizeof table ? size - in.pos : sizeof table;
        memcpy(table, data + in.pos, len);
        if (mode & 2u) {
            patch_crc(table, len);
        }
        if (negobs_rectify_table_check(table, len, w, h, &info) == NEGOBS_OK) {
            run_remap(table, len, w, h);
        }
        return 0;
    }
    memset(&info, 0, sizeof info);
    info.width = w;
    info.height = h;
    info.grid_shift = fuzz_range(&in, 0, 5);
    info.f_q16 = (uint32_t)fuzz_u16(&in) << 8;
    info.baseline_um = fuzz_u16(&in);
    {
        int32_t gw = ((w - 1) >> (info.grid_shift > 4 ? 4 : info.grid_shift)) +
                     2;
        int32_t gh = ((h - 1) >> (info.grid_shift > 4 ? 4 : info.grid_shift)) +
                     2;
        int32_t i;
        for (i = 0; i < 2 * gw * gh && i < 2 * MAXNODES; i++) {
            lmap[i] = fuzz_range(&in, -20000, 20000);
            rmap[i] = fuzz_range(&in, -20000, 20000);
        }
    }
    if (negobs_rectify_table_write(&info, lmap, rmap, table, sizeof table,
                                   &len) != NEGOBS_OK) {
        return 0;
    }
    if (mode & 2u) {
        size_t pos = fuzz_u16(&in) % len;
        table[pos] ^= (uint8_t)(fuzz_u8(&in) | 1u);
        if (mode & 4u) {
            patch_crc(table, len);
        }
    } else if (negobs_rectify_table_check(table, len, w, h, NULL) !=
               NEGOBS_OK) {
        abort(); /* the writer's own output must load */
    }
    run_remap(table, len, w, h);
    return 0;
}
