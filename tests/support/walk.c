/* The curb walk of walk.h: analytic disparity, then an integer texture warp. */
#include "walk.h"

#include "scene_disp.h"

static int16_t walk_disp[WALK_MAX_PIXELS];

/* Texture value of one cell (x, y): a hash, so every target agrees. */
static uint32_t walk_cell(int32_t x, int32_t y)
{
    uint32_t h = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return 40u + (h & 0xffu) * 170u / 255u;
}

/* Texture at column x_q4 (1/16 px) of row y: cells 2 px wide, linearly
 * interpolated, so a sub-pixel shift is a real change of grey level. */
static uint8_t walk_tex(int32_t x_q4, int32_t y)
{
    int32_t cell = x_q4 / 32; /* x_q4 >= 0: u * 16 plus a disparity */
    int32_t frac = x_q4 % 32;
    uint32_t a = walk_cell(cell, y);
    uint32_t b = walk_cell(cell + 1, y);
    return (uint8_t)((a * (uint32_t)(32 - frac) + b * (uint32_t)frac + 16u) /
                     32u);
}

int walk_render(const negobs_rig_t *cam, int32_t frame, uint8_t *left,
                uint8_t *right)
{
    synth_scene_t s;
    int32_t w = cam->width;
    int32_t h = cam->height;
    int32_t u;
    int32_t v;

    if (w < 8 || h < 8 || (int64_t)w * h > WALK_MAX_PIXELS || frame < 0 ||
        frame >= WALK_FRAMES) {
        return -1;
    }
    synth_flat(&s, 1.2, 20.0);
    synth_step(&s, (WALK_EDGE0_MM - WALK_STEP_MM * frame) / 1000.0, -0.15);
    synth_render(&s, cam, walk_disp, w);
    for (v = 0; v < h; v++) {
        for (u = 0; u < w; u++) {
            left[v * w + u] = walk_tex(u * 16, v);
        }
    }
    /* right row v + WALK_VOFF shows left row v; the rows it lacks at the
     * top are plain texture (no match, as at a real image border) */
    for (v = 0; v < h; v++) {
        int32_t src = v - WALK_VOFF;
        for (u = 0; u < w; u++) {
            int32_t d = 0;
            if (src >= 0) {
                d = walk_disp[src * w + u];
                d = (d == NEGOBS_DISP_INVALID || d < 0) ? 0 : d;
            }
            right[v * w + u] = walk_tex(u * 16 + d, src >= 0 ? src : v + h);
        }
    }
    return 0;
}
