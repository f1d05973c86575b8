/*
 * Integer bilinear remap through a rectify table.
 *
 * For output row y the two node rows around it are blended once into a row
 * of interpolated nodes (the only workspace buffer, 2 * grid_w int32).
 * Along the row the map is then linear inside each grid cell, so the
 * per-pixel source coordinate is advanced by a constant step: one add per
 * coordinate and pixel, exact because nothing is rounded until the final
 * shift back to Q.8. Sampling is a correctly rounded bilinear blend of the
 * four raw pixels around that Q.8 coordinate.
 */
#include "negobs/rectify.h"

#include <string.h>

#include "arena.h"
#include "table_le.h"

#define RECTIFY_READY 0x52454354u /* "RECT" */

void negobs_rectify_config_default(negobs_rectify_config_t *cfg, int32_t width,
                                   int32_t height)
{
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->width = width;
    cfg->height = height;
    cfg->table = NULL;
    cfg->table_bytes = 0;
    cfg->border_u8 = 0;
}

static int size_ok(int32_t width, int32_t height)
{
    return width >= 1 && height >= 1 && width <= NEGOBS_MAX_DIM &&
           height <= NEGOBS_MAX_DIM;
}

/*
 * The one carve used by both workspace_size (measuring arena) and init.
 * The row buffer is sized for the finest grid (shift 0), so the size does
 * not depend on the table and a static buffer fits any table of this size.
 */
static negobs_status_t carve(negobs_arena_t *a, int32_t width, int32_t **row_q)
{
    size_t nodes = (size_t)NEGOBS_RECTIFY_GRID_NODES(width, 0);
    *row_q = (int32_t *)negobs_arena_take(a, 2u * nodes * sizeof(int32_t));
    return negobs_arena_status(a);
}

negobs_status_t negobs_rectify_workspace_size(
    const negobs_rectify_config_t *cfg, size_t *bytes_out)
{
    negobs_arena_t a;
    int32_t *row_q;
    negobs_status_t st;
    if (cfg == NULL || bytes_out == NULL ||
        !size_ok(cfg->width, cfg->height)) {
        return NEGOBS_ERR_INVAL;
    }
    negobs_arena_init(&a, NULL, 0);
    st = carve(&a, cfg->width, &row_q);
    if (st != NEGOBS_OK) {
        return st;
    }
    *bytes_out = negobs_arena_used(&a);
    return NEGOBS_OK;
}

negobs_status_t negobs_rectify_init(negobs_rectify_t *ctx,
                                    const negobs_rectify_config_t *cfg,
                                    void *workspace, size_t workspace_bytes)
{
    negobs_arena_t a;
    negobs_status_t st;
    size_t per_map;

    if (ctx == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    memset(ctx, 0, sizeof *ctx);
    if (cfg == NULL || workspace == NULL ||
        !size_ok(cfg->width, cfg->height)) {
        return NEGOBS_ERR_INVAL;
    }
    st = negobs_rectify_table_check(cfg->table, cfg->table_bytes, cfg->width,
                                    cfg->height, &ctx->info);
    if (st != NEGOBS_OK) {
        return st;
    }
    negobs_arena_init(&a, workspace, workspace_bytes);
    st = carve(&a, cfg->width, &ctx->row_q);
    if (st != NEGOBS_OK) {
        return st;
    }
    per_map = (size_t)ctx->info.grid_w * (size_t)ctx->info.grid_h *
              RT_NODE_BYTES;
    ctx->cfg = cfg;
    ctx->map[0] = cfg->table +
                  negobs_rd_u32le(cfg->table + RT_OFF_HEADER_BYTES);
    ctx->map[1] = ctx->map[0] + per_map;
    ctx->ready = RECTIFY_READY;
    return NEGOBS_OK;
}

/*
 * Round a Q.(8 + n) coordinate to Q.8, half up, n in 0..8, without a
 * branch and without shifting a negative value (implementation-defined in
 * C99): |v| <= 2^29, so v + 2^30 is positive; 2^30 is a multiple of 2^n,
 * so removing (2^30 >> n) afterwards is exact. bias_round = 2^30 plus half
 * an output unit (0 when n = 0).
 */
#define RECTIFY_BIAS ((int32_t)1 << 30)

static inline int32_t to_q8(int32_t v, int n, int32_t bias_round)
{
    return (int32_t)((uint32_t)(v + bias_round) >> n) - (RECTIFY_BIAS >> n);
}

/*
 * Blend node rows gy and gy + 1 with weights (step - fy, fy): row_q gets
 * grid_w (x, y) pairs in Q.(8 + s). |node| <= 2^21 and the weights sum to
 * 2^s <= 16, so |row_q| <= 2^25.
 */
static void blend_node_rows(const negobs_rectify_t *ctx, const uint8_t *map,
                            int32_t y)
{
    const int32_t s = ctx->info.grid_shift;
    const int32_t gw = ctx->info.grid_w;
    const int32_t fy = y & ((1 << s) - 1);
    const int32_t wy0 = (1 << s) - fy;
    const uint8_t *n0 = map + (size_t)(y >> s) * (size_t)gw * RT_NODE_BYTES;
    const uint8_t *n1 = n0 + (size_t)gw * RT_NODE_BYTES;
    int32_t *q = ctx->row_q;
    int32_t i;
    for (i = 0; i < 2 * gw; i++) {
        q[i] = negobs_rd_s32le(n0 + (size_t)i * 4u) * wy0 +
               negobs_rd_s32le(n1 + (size_t)i * 4u) * fy;
    }
}

/*
 * Correctly rounded bilinear sample at a Q.8 coordinate known to lie in
 * [0, w-1] x [0, h-1]. A zero weight never reads past the last row or
 * column: the neighbour offset is 0 then.
 * Scaling: top/bot <= 255 * 256 (Q.8), v <= 255 * 2^16 (Q.16, 24 bits).
 */
static inline uint8_t sample_q8(const negobs_image_u8_t *raw, int32_t cx,
                                int32_t cy)
{
    const int32_t xi = cx >> NEGOBS_RECTIFY_FRAC_BITS;
    const int32_t yi = cy >> NEGOBS_RECTIFY_FRAC_BITS;
    const int32_t wx = cx & (NEGOBS_RECTIFY_ONE_Q8 - 1);
    const int32_t wy = cy & (NEGOBS_RECTIFY_ONE_Q8 - 1);
    const uint8_t *r0 = negobs_image_u8_row(raw, yi) + xi;
    const uint8_t *r1 = (wy != 0) ? r0 + raw->stride : r0;
    const int32_t dx = (wx != 0) ? 1 : 0;
    const int32_t top = (int32_t)r0[0] * (NEGOBS_RECTIFY_ONE_Q8 - wx) +
                        (int32_t)r0[dx] * wx;
    const int32_t bot = (int32_t)r1[0] * (NEGOBS_RECTIFY_ONE_Q8 - wx) +
                        (int32_t)r1[dx] * wx;
    const int32_t v = top * (NEGOBS_RECTIFY_ONE_Q8 - wy) + bot * wy;
    return (uint8_t)((v + (1 << 15)) >> 16);
}

/*
 * One output row. Inside grid cell gx the map is linear in x, so the
 * Q.(8 + 2s) coordinate starts at row_q[gx] * 2^s and grows by
 * row_q[gx + 1] - row_q[gx] per pixel; |values| <= 2^29.
 * Returns the number of border pixels.
 */
static uint32_t remap_row(const negobs_rectify_t *ctx,
                          const negobs_image_u8_t *raw, uint8_t *out)
{
    const int32_t s = ctx->info.grid_shift;
    const int32_t step = 1 << s;
    const int32_t w = ctx->info.width;
    const int32_t xmax = (raw->width - 1) * NEGOBS_RECTIFY_ONE_Q8;
    const int32_t ymax = (raw->height - 1) * NEGOBS_RECTIFY_ONE_Q8;
    const uint8_t border = ctx->cfg->border_u8;
    const int32_t *q = ctx->row_q;
    const int sh = (int)(2 * s);
    const int32_t bias_round = RECTIFY_BIAS +
                               ((sh > 0) ? ((int32_t)1 << (sh - 1)) : 0);
    uint32_t nborder = 0;
    int32_t x0;

    for (x0 = 0; x0 < w; x0 += step) {
        const int32_t *n = q + (size_t)(x0 >> s) * 2u;
        int32_t ax = n[0] * step;
        int32_t ay = n[1] * step;
        const int32_t dx = n[2] - n[0];
        const int32_t dy = n[3] - n[1];
        const int32_t x1 = (x0 + step < w) ? x0 + step : w;
        int32_t x;
        for (x = x0; x < x1; x++) {
            const int32_t cx = to_q8(ax, sh, bias_round);
            const int32_t cy = to_q8(ay, sh, bias_round);
            if (cx < 0 || cy < 0 || cx > xmax || cy > ymax) {
                out[x] = border;
                nborder++;
            } else {
                out[x] = sample_q8(raw, cx, cy);
            }
            ax += dx;
            ay += dy;
        }
    }
    return nborder;
}

/* Byte ranges of two images intersect (compared as addresses). */
static int overlaps(const negobs_image_u8_t *a, const negobs_image_u8_t *b)
{
    uintptr_t a0 = (uintptr_t)a->data;
    uintptr_t a1 = a0 +
                   (uintptr_t)((size_t)(a->height - 1) * (size_t)a->stride +
                               (size_t)a->width);
    uintptr_t b0 = (uintptr_t)b->data;
    uintptr_t b1 = b0 +
                   (uintptr_t)((size_t)(b->height - 1) * (size_t)b->stride +
                               (size_t)b->width);
    return a0 < b1 && b0 < a1;
}

static negobs_status_t check_pair(const negobs_rectify_t *ctx,
                                  const negobs_image_u8_t *raw,
                                  const negobs_image_u8_t *rect)
{
    if (negobs_image_u8_check(raw) != NEGOBS_OK ||
        negobs_image_u8_check(rect) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    if (raw->width != ctx->info.width || raw->height != ctx->info.height ||
        rect->width != ctx->info.width || rect->height != ctx->info.height) {
        return NEGOBS_ERR_INVAL;
    }
    if (overlaps(raw, rect)) {
        return NEGOBS_ERR_INVAL;
    }
    return NEGOBS_OK;
}

negobs_status_t negobs_rectify_rows(negobs_rectify_t *ctx,
                                    negobs_rectify_camera_t camera,
                                    const negobs_image_u8_t *raw,
                                    negobs_image_u8_t *rect, int32_t y0,
                                    int32_t y1, negobs_rectify_stats_t *stats)
{
    const uint8_t *map;
    negobs_status_t st;
    uint32_t nborder = 0;
    int32_t y;

    if (ctx == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (ctx->ready != RECTIFY_READY) {
        return NEGOBS_ERR_STATE;
    }
    if (camera != NEGOBS_RECTIFY_CAMERA_LEFT &&
        camera != NEGOBS_RECTIFY_CAMERA_RIGHT) {
        return NEGOBS_ERR_INVAL;
    }
    st = check_pair(ctx, raw, rect);
    if (st != NEGOBS_OK) {
        return st;
    }
    if (y0 < 0 || y1 < y0 || y1 > ctx->info.height) {
        return NEGOBS_ERR_INVAL;
    }
    map = ctx->map[(camera == NEGOBS_RECTIFY_CAMERA_LEFT) ? 0 : 1];
    for (y = y0; y < y1; y++) {
        blend_node_rows(ctx, map, y);
        nborder += remap_row(ctx, raw, negobs_image_u8_row(rect, y));
    }
    if (stats != NULL) {
        stats->border_pixels = nborder;
    }
    return NEGOBS_OK;
}

negobs_status_t negobs_rectify_process(negobs_rectify_t *ctx,
                                       const negobs_image_u8_t *left,
                                       const negobs_image_u8_t *right,
                                       negobs_image_u8_t *left_rect,
                                       negobs_image_u8_t *right_rect,
                                       negobs_rectify_stats_t *stats)
{
    negobs_rectify_stats_t sl = {0};
    negobs_rectify_stats_t sr = {0};
    negobs_status_t st;
    int32_t h;

    if (ctx == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    if (ctx->ready != RECTIFY_READY) {
        return NEGOBS_ERR_STATE;
    }
    h = ctx->info.height;
    /* Check both pairs first so a bad right image leaves nothing written. */
    st = check_pair(ctx, left, left_rect);
    if (st == NEGOBS_OK) {
        st = check_pair(ctx, right, right_rect);
    }
    if (st != NEGOBS_OK) {
        return st;
    }
    st = negobs_rectify_rows(ctx, NEGOBS_RECTIFY_CAMERA_LEFT, left, left_rect,
                             0, h, &sl);
    if (st == NEGOBS_OK) {
        st = negobs_rectify_rows(ctx, NEGOBS_RECTIFY_CAMERA_RIGHT, right,
                                 right_rect, 0, h, &sr);
    }
    if (st == NEGOBS_OK && stats != NULL) {
        stats->border_pixels = sl.border_pixels + sr.border_pixels;
    }
    return st;
}
