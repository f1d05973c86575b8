/* Shared helpers of the detect tests: a 320x240 rig and a frame runner. */
#ifndef NEGOBS_TEST_SCENE_UTIL_H
#define NEGOBS_TEST_SCENE_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "negobs/detect.h"
#include "scene_disp.h"

#define RIG_W 320
#define RIG_H 240

typedef struct rig {
    negobs_detect_config_t cfg;
    negobs_detect_t det;
    void *ws;
    void *ws_raw;
    size_t ws_bytes;
    int16_t disp[RIG_W * RIG_H];
    negobs_image_s16_t img;
    negobs_photo_stats_t stats;
    negobs_detect_frame_t frame;
    negobs_detect_result_t res;
    uint32_t now_ms;
} rig_t;

static inline void rig_setup(rig_t *r, const negobs_detect_config_t *cfg)
{
    memset(r, 0, sizeof *r);
    if (cfg != NULL) {
        r->cfg = *cfg;
    } else {
        negobs_detect_config_default(&r->cfg, RIG_W, RIG_H);
    }
    if (negobs_detect_workspace_size(&r->cfg, &r->ws_bytes) != NEGOBS_OK) {
        abort();
    }
    /* 16-byte aligned block inside a malloc'd one (C99 has no
     * aligned_alloc). */
    r->ws_raw = malloc(r->ws_bytes + 16u);
    r->ws = (void *)(((uintptr_t)r->ws_raw + 15u) & ~(uintptr_t)15u);
    if (r->ws_raw == NULL || negobs_detect_init(&r->det, &r->cfg, r->ws,
                                                r->ws_bytes) != NEGOBS_OK) {
        abort();
    }
    r->img.data = r->disp;
    r->img.width = RIG_W;
    r->img.height = RIG_H;
    r->img.stride = RIG_W;
    r->stats.mean = 120;
    r->stats.dark_permille = 10;
    r->stats.saturated_permille = 5;
    r->stats.texture_q4 = 160;
    r->now_ms = 1000;
}

static inline void rig_teardown(rig_t *r)
{
    free(r->ws_raw);
    r->ws_raw = NULL;
    r->ws = NULL;
}

/* Run the detector on r->disp as one frame 100 ms after the previous one
 * (for maps edited after rendering). */
static inline negobs_status_t rig_run(rig_t *r)
{
    r->now_ms += 100;
    r->frame.disp_q4 = &r->img;
    r->frame.left_stats = &r->stats;
    r->frame.right_stats = &r->stats;
    r->frame.t_left_ms = r->now_ms - 40;
    r->frame.t_right_ms = r->now_ms - 40;
    r->frame.now_ms = r->now_ms;
    return negobs_detect_process(&r->det, &r->frame, &r->res);
}

/* Render a scene and run one frame 100 ms after the previous one. */
static inline negobs_status_t rig_frame(rig_t *r, const synth_scene_t *s)
{
    synth_render(s, &r->cfg.rig, r->disp, RIG_W);
    return rig_run(r);
}

/* Nearest raw candidate of the last frame, or NULL. */
static inline const negobs_hazard_t *rig_nearest(const rig_t *r)
{
    const negobs_hazard_t *best = NULL;
    uint32_t i;
    for (i = 0; i < r->res.n_candidates; i++) {
        if (best == NULL || r->res.candidates[i].range_mm < best->range_mm) {
            best = &r->res.candidates[i];
        }
    }
    return best;
}

#endif
