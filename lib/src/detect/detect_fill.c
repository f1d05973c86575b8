/* Rectification fill: the part of each image that lies outside the
 * camera's field of view (docs/DETECTION.md 10.2, "Out of view"). */
#include "detect_internal.h"

/*
 * A rectified image is resampled from the sensor; where the map leaves the
 * sensor, the remap writes a constant (usually 0) or replicates the sensor's
 * edge pixel along the row. Either way a row of fill is a run of exactly
 * identical grey levels reaching the image border.
 *
 * FILL_MIN_RUN: under sensor noise of at least 1 LSB (shot and read noise
 * of an 8-bit sensor, even on a uniform wall) eight neighbouring pixels are
 * exactly equal with a chance below 1 in 100 per row; only clipped regions
 * (black 0, saturated 255) give such runs in a real scene.
 * FILL_MIN_ROWS_DIV: a side is treated as fill only when a quarter of the
 * rows carry such a run there; the map leaves the sensor along a smooth
 * curve that spans a large part of a border, while a clipped object touches
 * it over a few rows.
 * FILL_MAX_DIV: a run of a quarter of the width or more is not fill: a
 * rectification that loses that much is broken, and such a run is more
 * likely a clipped scene; that row stays in view (unseen, not out of view).
 * FILL_GAP_ROWS: edge replication with interpolation is not exactly
 * constant on every row (a row's run breaks where the interpolated edge
 * changes by 1 LSB), so a row takes the longest run within +-4 rows.
 * The width: a side's fill is at most the lower quartile of its rows' runs.
 * A clipped dark or bright object beside the fill (a shadow, a black floor,
 * which a camera clips to 0 like a constant fill) lengthens the runs of the
 * rows it covers; unless it covers three quarters of the fill's rows it
 * does not widen the fill beyond that quartile. A fill that curves (wider
 * at the corners) is cut at the quartile: left in view, unseen, the safe
 * side.
 */
#define FILL_MIN_RUN 8
#define FILL_MIN_ROWS_DIV 4
#define FILL_MAX_DIV 4
#define FILL_GAP_ROWS 4

/* Length of the run of pixels equal to row[u0] starting at u0 and going in
 * steps of du (+1 or -1), at most max_n. */
static int32_t same_run(const uint8_t *row, int32_t u0, int32_t du,
                        int32_t max_n)
{
    int32_t n = 1;
    while (n < max_n && row[u0 + n * du] == row[u0]) {
        n++;
    }
    return n;
}

/* Fill run of one border of row v: 0 unless FILL_MIN_RUN <= run < max_n. */
static int32_t row_run(const negobs_image_u8_t *img, int32_t v, int32_t side,
                       int32_t max_n)
{
    const uint8_t *row = negobs_image_u8_row(img, v);
    int32_t r = (side == 0) ? same_run(row, 0, 1, max_n)
                            : same_run(row, img->width - 1, -1, max_n);
    return (r >= FILL_MIN_RUN && r < max_n) ? r : 0;
}

/* Rows of out[0..n) with a run of at least t. */
static int32_t rows_at_least(const int16_t *out, int32_t n, int32_t t)
{
    int32_t c = 0;
    int32_t v;
    for (v = 0; v < n; v++) {
        c += out[v] >= t;
    }
    return c;
}

/* Per row, the fill width of one side into out[] (img->height entries):
 * the longest run within +-FILL_GAP_ROWS rows, at most the lower quartile
 * of the rows' runs; all 0 when fewer than a quarter of the rows have a
 * run. */
static void side_runs(const negobs_image_u8_t *img, int32_t side, int16_t *out)
{
    int16_t ring[FILL_GAP_ROWS];
    int32_t max_n = img->width / FILL_MAX_DIV;
    int32_t n = 0;
    int32_t lo = FILL_MIN_RUN;
    int32_t hi = max_n;
    int32_t v;
    for (v = 0; v < img->height; v++) {
        out[v] = (int16_t)((max_n > FILL_MIN_RUN)
                               ? row_run(img, v, side, max_n)
                               : 0);
        n += out[v] > 0;
    }
    if (n * FILL_MIN_ROWS_DIV < img->height) {
        memset(out, 0, (size_t)img->height * sizeof *out);
        return;
    }
    /* lower quartile: the largest t that 3/4 of the runs reach */
    while (hi - lo > 1) {
        int32_t t = (lo + hi) / 2;
        if (rows_at_least(out, img->height, t) * 4 >= n * 3) {
            lo = t;
        } else {
            hi = t;
        }
    }
    /* Sliding maximum, in place: the raw runs of the FILL_GAP_ROWS rows
     * above v, already overwritten, are kept in a ring. */
    for (v = 0; v < img->height; v++) {
        int32_t top = geom_min_s32(v + FILL_GAP_ROWS, img->height - 1);
        int32_t m = out[v];
        int32_t w;
        for (w = geom_max_s32(v - FILL_GAP_ROWS, 0); w < v; w++) {
            m = geom_max_s32(m, ring[w % FILL_GAP_ROWS]);
        }
        for (w = v + 1; w <= top; w++) {
            m = geom_max_s32(m, out[w]);
        }
        ring[v % FILL_GAP_ROWS] = out[v];
        out[v] = (int16_t)geom_min_s32(m, lo);
    }
}

negobs_status_t negobs_detect_fill_extent(const negobs_image_u8_t *img,
                                          int16_t *view_u0, int16_t *view_u1)
{
    int32_t v;
    if (view_u0 == NULL || view_u1 == NULL ||
        negobs_image_u8_check(img) != NEGOBS_OK || img->width > INT16_MAX) {
        return NEGOBS_ERR_INVAL;
    }
    side_runs(img, 0, view_u0);
    side_runs(img, 1, view_u1);
    for (v = 0; v < img->height; v++) {
        view_u1[v] = (int16_t)(img->width - view_u1[v]);
    }
    return NEGOBS_OK;
}
