/*
 * Test helper for negobs_run --calib: writes a rectification table with
 * the library API (negobs_rectify_table_write), the same format
 * negobs_calib writes, without OpenCV.
 *
 *   app_rect_table OUT WIDTH HEIGHT F_PX BASELINE_MM SHIFT_PX
 *
 * Both maps take the source pixel SHIFT_PX to the right of the rectified
 * one (0: identity; beyond the frame: every pixel gets the border value),
 * principal point at the frame centre, grid shift 2.
 */
#include <stdio.h>
#include <stdlib.h>

#include "negobs/rectify.h"

#define GRID_SHIFT 2
#define MAX_NODES (1024 * 1024)

static int32_t map_q8[2 * MAX_NODES];
static uint8_t table[64 + 2 * MAX_NODES * 8 + 4];

int main(int argc, char **argv)
{
    negobs_rectify_info_t info = {0};
    size_t written = 0;
    long w;
    long h;
    long f;
    long b;
    long shift;
    int32_t gw;
    int32_t gh;
    int32_t i;
    int32_t j;
    FILE *out;
    negobs_status_t st;
    if (argc != 7) {
        fprintf(stderr,
                "usage: %s OUT WIDTH HEIGHT F_PX BASELINE_MM "
                "SHIFT_PX\n",
                argv[0]);
        return 2;
    }
    w = strtol(argv[2], NULL, 10);
    h = strtol(argv[3], NULL, 10);
    f = strtol(argv[4], NULL, 10);
    b = strtol(argv[5], NULL, 10);
    shift = strtol(argv[6], NULL, 10);
    if (w < 1 || h < 1 || w > 4096 || h > 4096 || f < 1 || f > 60000 ||
        b < 1 || b > 4000 || shift < -8000 || shift > 8000) {
        fprintf(stderr, "app_rect_table: argument out of range\n");
        return 2;
    }
    gw = NEGOBS_RECTIFY_GRID_NODES((int32_t)w, GRID_SHIFT);
    gh = NEGOBS_RECTIFY_GRID_NODES((int32_t)h, GRID_SHIFT);
    if ((long)gw * gh > MAX_NODES) {
        fprintf(stderr, "app_rect_table: frame too large\n");
        return 2;
    }
    for (j = 0; j < gh; j++) {
        for (i = 0; i < gw; i++) {
            size_t k = 2u * ((size_t)j * (size_t)gw + (size_t)i);
            map_q8[k] = (int32_t)(((i << GRID_SHIFT) + shift) * 256);
            map_q8[k + 1] = (j << GRID_SHIFT) * 256;
        }
    }
    info.width = (int32_t)w;
    info.height = (int32_t)h;
    info.grid_shift = GRID_SHIFT;
    info.f_q16 = (uint32_t)f * 65536u;
    info.baseline_um = (uint32_t)b * 1000u;
    info.cx_q16 = (int32_t)((w - 1) * 32768);
    info.cy_q16 = (int32_t)((h - 1) * 32768);
    info.doffs_q16 = 0;
    info.rms_mpx = NEGOBS_RECTIFY_RMS_UNKNOWN;
    st = negobs_rectify_table_write(&info, map_q8, map_q8, table, sizeof table,
                                    &written);
    if (st != NEGOBS_OK) {
        fprintf(stderr, "app_rect_table: %s\n", negobs_status_str(st));
        return 1;
    }
    out = fopen(argv[1], "wb");
    if (out == NULL || fwrite(table, 1, written, out) != written ||
        fclose(out) != 0) {
        fprintf(stderr, "app_rect_table: cannot write %s\n", argv[1]);
        return 1;
    }
    return 0;
}
