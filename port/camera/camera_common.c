/* Backend-independent camera helpers: defaults and timestamp pairing. */
#include <string.h>

#include "negobs_port/camera.h"

void negobs_camera_config_default(negobs_camera_config_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->width = 640;
    cfg->height = 480;
    cfg->fps = 30;
    cfg->pair_tol_ms = NEGOBS_CAMERA_PAIR_TOL_MS_DEFAULT;
    cfg->exposure = -1;
    cfg->gain = -1;
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
