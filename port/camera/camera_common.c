/* Backend-independent camera helpers: defaults, timestamp pairing and
 * frozen-stream detection. */
#include <string.h>

#include "negobs_port/camera.h"

void negobs_capture_config_default(negobs_capture_config_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->width = 640;
    cfg->height = 480;
    cfg->fps = 30;
    cfg->pair_tol_ms = NEGOBS_CAPTURE_PAIR_TOL_MS_DEFAULT;
    cfg->exposure = -1;
    cfg->gain = -1;
    cfg->frozen_frames = NEGOBS_CAPTURE_FROZEN_FRAMES_DEFAULT;
}

/*
 * Two free-running sensors deliver frames at about the same rate with an
 * unknown phase. With one pending frame per side, the rule is: if they are
 * close enough, they are a pair; otherwise the older one can never find a
 * closer partner (the other side only gets newer), so drop it and wait for
 * that side's next frame.
 */
negobs_pair_action_t negobs_pair_decide(uint64_t left_ns, uint64_t right_ns,
                                        uint64_t tol_ns)
{
    uint64_t d = left_ns > right_ns ? left_ns - right_ns : right_ns - left_ns;
    if (d <= tol_ns) {
        return NEGOBS_PAIR_MATCH;
    }
    return left_ns < right_ns ? NEGOBS_PAIR_DROP_LEFT : NEGOBS_PAIR_DROP_RIGHT;
}

/*
 * A sensor whose driver or ISP hangs may go on handing out the last buffer:
 * frames keep arriving, so neither a timeout nor the watchdog notices, and
 * the detector would keep judging an old view of the street. Sampling is
 * enough: noise flips many of the few thousand sampled pixels every frame,
 * and a 32-bit FNV-1a collision between two real frames, `limit` times in
 * a row, does not happen.
 */
uint32_t negobs_frame_signature(const negobs_image_u8_t *img)
{
    uint32_t h = 2166136261u;
    int32_t x;
    int32_t y;
    if (img == NULL || img->data == NULL || img->width <= 0 ||
        img->height <= 0) {
        return 0;
    }
    for (y = 0; y < img->height; y += 2) {
        const uint8_t *row = img->data + (size_t)y * (size_t)img->stride;
        for (x = 0; x < img->width; x += 3) {
            h = (h ^ row[x]) * 16777619u;
        }
    }
    return h;
}

bool negobs_frozen_update(negobs_frozen_t *f, uint32_t sig, int32_t limit)
{
    if (f->have_last && sig == f->last_sig) {
        if (f->repeats < UINT32_MAX) {
            f->repeats++;
        }
    } else {
        f->repeats = 0;
    }
    f->last_sig = sig;
    f->have_last = true;
    if (limit <= 0) {
        return false;
    }
    if (limit < 2) {
        limit = 2;
    }
    return f->repeats + 1u >= (uint32_t)limit;
}
