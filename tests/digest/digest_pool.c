/*
 * The "pool" line of negobs_digest: the detector's frame pooling
 * (lib/src/detect/detect_pool.c) on six noisy 320x240 disparity maps of a
 * walk toward a 15 cm drop, 120 mm a tick, with a head's bob in the fits:
 * every pooled map (int16, little-endian) and its pooled share. The
 * pipeline walk's texture is not fixed to the floor, so no travel is
 * measured there and nothing is pooled; this line covers the pooling's
 * integer arithmetic on every target. Its own file: the analytic scene
 * (scene_disp.h) and the stereo pair generator digest.c uses
 * (scene_pair.h) share names.
 */
#include "digest_pool.h"

#include <string.h>

#include "detect/detect_internal.h"
#include "scene_disp.h"

#define PW 320
#define PH 240

static int16_t p_disp[PW * PH];
static int16_t p_hist[2][PW * PH];
static int16_t p_out[PW * PH];
static int32_t p_node[NEGOBS_DETECT_POOL_BANDS * 2 * (PW / 8 + 2)];
static detect_priv_t p_priv;

static uint64_t fnv_byte(uint64_t h, uint8_t b)
{
    return (h ^ b) * 1099511628211ull;
}

uint64_t digest_pool(int perturb)
{
    negobs_detect_config_t cfg;
    negobs_image_s16_t img;
    gfit_out_t g;
    uint64_t h = 14695981039346656037ull;
    int32_t f;
    memset(&p_priv, 0, sizeof p_priv);
    negobs_detect_config_default(&cfg, PW, PH);
    cfg.pool_frames = 4;
    p_priv.pool_hist[0] = p_hist[0];
    p_priv.pool_hist[1] = p_hist[1];
    p_priv.pool_out = p_out;
    p_priv.pool_node = p_node;
    img.data = p_disp;
    img.width = PW;
    img.height = PH;
    img.stride = PW;
    for (f = 0; f < 6; f++) {
        synth_scene_t sc;
        const negobs_image_s16_t *m;
        int32_t pooled = 0;
        int32_t i;
        synth_flat(&sc, 1.2, 20.0);
        synth_step(&sc, 3.0 - 0.12 * f, -0.15);
        sc.noise_px = 0.25;
        sc.seed = 100u + (uint32_t)f;
        synth_render(&sc, &cfg.rig, p_disp, PW);
        if (perturb && f == 0) {
            p_disp[200 * PW + 160] = (int16_t)(p_disp[200 * PW + 160] + 16);
        }
        memset(&g, 0, sizeof g);
        g.ok = 1;
        g.pose.height_mm = 1200 + 10 * (f % 2); /* a head's bob */
        g.pose.pitch_mdeg = 20000 - 300 * (f % 3);
        if (negobs_ground_plane_from_pose(&cfg.rig, &g.pose, &g.plane) !=
                NEGOBS_OK ||
            negobs_ground_pose_from_plane(&cfg.rig, &g.plane, &g.pose,
                                          &g.frame) != NEGOBS_OK) {
            return 0;
        }
        g.sigma_q4 = 4;
        m = det_pool_frame(&p_priv, &cfg, &img, &g, 1, (f > 0) ? 120 : 0, 0u,
                           &pooled);
        for (i = 0; i < PW * PH; i++) {
            const uint16_t v = (uint16_t)m->data[i];
            h = fnv_byte(h, (uint8_t)v);
            h = fnv_byte(h, (uint8_t)(v >> 8));
        }
        for (i = 0; i < 4; i++) {
            h = fnv_byte(h, (uint8_t)((uint32_t)pooled >> (8 * i)));
        }
    }
    return h;
}
