/*
 * Analytic synthetic disparity maps for the detect tests and the curb walk
 * (walk.c) (test code may use double; the library may not).
 *
 * Camera at height H (m) above level ground, pitch p down, roll r. With the
 * unit ground normal n = (cos p sin r, cos p cos r, sin p) in camera
 * coordinates (x right, y down, z forward), a camera ray P = t*(x', y', 1),
 * x' = (u-cx)/f, y' = (v-cy)/f, is t*(n.P') below the camera, t*(fw.P')
 * ahead and t*(l.P') to the right, with fw = (z - sin p * n)/cos p and
 * l = (n_y, -n_x, 0)/cos p. The terrain is a piecewise-constant height
 * profile along the forward distance (drops, steps, stairs, walls), which
 * a ray crosses segment by segment: it hits a riser where its height at
 * the segment start is below the segment height, else the horizontal
 * surface if that lies inside the segment. Depth is t, disparity f*B/t.
 * A profile may be limited laterally (holes); outside it the ground is
 * flat. Noise is the sum of four uniforms (close to Gaussian, sigma given).
 * Optional row-correlated noise adds one offset per block of
 * noise_row_len_px columns x noise_row_rows rows (blocks staggered from row
 * to row of blocks), like a matcher whose errors are shared by its window
 * and by its DP along the row: averaging the columns of a strip does not
 * reduce it. It has its own generator, so maps without it are unchanged.
 */
#ifndef NEGOBS_TEST_SCENE_DISP_H
#define NEGOBS_TEST_SCENE_DISP_H

#include <math.h>
#include <string.h>

#include "negobs/depth.h"
#include "negobs/fixed.h"
#include "test_rng.h"

#define SYNTH_MAX_SEG 16

typedef struct synth_scene {
    double h_m;                /* camera height                              */
    double pitch_deg;          /* down positive                              */
    double roll_deg;           /* > 0: ground nearer on the right            */
    int nseg;                  /* profile segments (0: flat ground)          */
    double z_m[SYNTH_MAX_SEG]; /* segment start (forward distance)   */
    double y_m[SYNTH_MAX_SEG]; /* segment height (lower < 0)         */
    double lat_half_m;         /* profile lateral half-width (0: unlimited)  */
    double yaw_deg;      /* profile axis turned right of straight ahead */
    double noise_px;     /* disparity noise sigma (px)                 */
    double noise_far_px; /* if > 0: sigma grows linearly from noise_px
                            at 1 m depth to this at 5 m              */
    double dropout;      /* share of pixels made invalid at random     */
    int inv_u0, inv_v0, inv_u1, inv_v1; /* invalid box (u1 > u0)     */
    double noise_row_px;  /* sigma of the row-correlated offset (px)  */
    int noise_row_len_px; /* its block length along a row (px)        */
    int noise_row_rows;   /* its block height (rows)                  */
    int noise_row_v0;     /* only rows >= this get it (0: all)        */
    uint32_t seed;
} synth_scene_t;

static inline void synth_flat(synth_scene_t *s, double h, double pitch)
{
    memset(s, 0, sizeof *s);
    s->h_m = h;
    s->pitch_deg = pitch;
    s->seed = 1;
}

/* Add a step at forward distance z to height y (relative to the ground at
 * the feet, lower < 0). */
static inline void synth_step(synth_scene_t *s, double z, double y)
{
    if (s->nseg == 0) {
        s->z_m[0] = 0.0;
        s->y_m[0] = 0.0;
        s->nseg = 1;
    }
    s->z_m[s->nseg] = z;
    s->y_m[s->nseg] = y;
    s->nseg++;
}

static inline double synth_uniform(uint32_t *st)
{
    return (double)test_lcg_next(st) / 16777216.0;
}

static inline double synth_gauss(uint32_t *st)
{
    double a = synth_uniform(st) + synth_uniform(st) + synth_uniform(st) +
               synth_uniform(st);
    return (a - 2.0) * 1.7320508075688772;
}

/* Row-correlated offset (px) of pixel (u, v): one Gaussian per block,
 * from a hash of the block and the seed. */
static inline double synth_row_offset(const synth_scene_t *s, int32_t u,
                                      int32_t v)
{
    int len = (s->noise_row_len_px > 0) ? s->noise_row_len_px : 1;
    int rows = (s->noise_row_rows > 0) ? s->noise_row_rows : 1;
    uint32_t bv = (uint32_t)(v / rows);
    uint32_t bu = (uint32_t)((u + (int32_t)((bv * 37u) % (uint32_t)len)) /
                             len);
    uint32_t st = (s->seed + 7u) * 2246822519u ^ (bv * 3266489917u) ^
                  (bu * 668265263u);
    st ^= st >> 15;
    st *= 2654435761u;
    return s->noise_row_px * synth_gauss(&st);
}

/* Depth t (m) of the first surface hit by the ray, <= 0 for none. */
static inline double synth_hit(const synth_scene_t *s, const double *dn,
                               double fwd, double lat, int use_profile,
                               double *lat_hit)
{
    int i;
    int n = use_profile ? s->nseg : 0;
    if (n == 0) {
        if (dn[0] <= 0.0) {
            return -1.0;
        }
        *lat_hit = lat * (s->h_m / dn[0]);
        return s->h_m / dn[0];
    }
    for (i = 0; i < n; i++) {
        double zs = s->z_m[i];
        double ze = (i + 1 < n) ? s->z_m[i + 1] : 1e9;
        double y = s->y_m[i];
        if (i > 0 && fwd > 0.0) {
            double t = zs / fwd;
            double hray = s->h_m - dn[0] * t;
            if (hray <= y) {
                *lat_hit = lat * t;
                return t;
            }
        }
        if (dn[0] > 0.0 && s->h_m - y > 0.0) {
            double t = (s->h_m - y) / dn[0];
            double f = t * fwd;
            if (f >= zs && f < ze) {
                *lat_hit = lat * t;
                return t;
            }
        }
    }
    return -1.0;
}

static inline void synth_render(const synth_scene_t *s,
                                const negobs_rig_t *cam, int16_t *disp,
                                int32_t stride)
{
    const double d2r = 3.14159265358979323846 / 180.0;
    double p = s->pitch_deg * d2r;
    double r = s->roll_deg * d2r;
    double n[3];
    double fw[3];
    double l[3];
    double f = cam->focal_q4 / 16.0;
    double cx = cam->cx_q4 / 16.0;
    double cy = cam->cy_q4 / 16.0;
    double b = cam->baseline_um / 1e6;
    double cyaw = cos(s->yaw_deg * d2r);
    double syaw = sin(s->yaw_deg * d2r);
    uint32_t st = s->seed * 2654435761u + 12345u;
    int32_t u;
    int32_t v;

    n[0] = cos(p) * sin(r);
    n[1] = cos(p) * cos(r);
    n[2] = sin(p);
    fw[0] = -sin(p) * n[0] / cos(p);
    fw[1] = -sin(p) * n[1] / cos(p);
    fw[2] = (1.0 - sin(p) * n[2]) / cos(p);
    l[0] = n[1] / cos(p);
    l[1] = -n[0] / cos(p);
    l[2] = 0.0;
    for (v = 0; v < cam->height; v++) {
        for (u = 0; u < cam->width; u++) {
            double x = (u - cx) / f;
            double y = (v - cy) / f;
            double dn[1];
            double fwd0 = fw[0] * x + fw[1] * y + fw[2];
            double lat0 = l[0] * x + l[1] * y;
            /* Coordinates along and across the (possibly turned) profile. */
            double fwd = fwd0 * cyaw + lat0 * syaw;
            double lat = lat0 * cyaw - fwd0 * syaw;
            double lh = 0.0;
            double t;
            double d;
            int16_t *out = disp + (size_t)v * (size_t)stride + u;
            dn[0] = n[0] * x + n[1] * y + n[2];
            t = synth_hit(s, dn, fwd, lat, 1, &lh);
            if (s->lat_half_m > 0.0 && t > 0.0 && fabs(lh) > s->lat_half_m) {
                t = synth_hit(s, dn, fwd, lat, 0, &lh);
            }
            if (t <= 0.0 || t > 60.0) {
                *out = NEGOBS_DISP_INVALID;
                continue;
            }
            d = f * b / t;
            if (s->noise_far_px > 0.0) {
                double w = (t - 1.0) / 4.0;
                w = (w < 0.0) ? 0.0 : ((w > 1.0) ? 1.0 : w);
                d += (s->noise_px + (s->noise_far_px - s->noise_px) * w) *
                     synth_gauss(&st);
            } else if (s->noise_px > 0.0) {
                d += s->noise_px * synth_gauss(&st);
            }
            if (s->noise_row_px > 0.0 && v >= s->noise_row_v0) {
                d += synth_row_offset(s, u, v);
            }
            if (d < 0.0) {
                d = 0.0;
            }
            *out = (int16_t)floor(d * 16.0 + 0.5);
            if (s->dropout > 0.0 && synth_uniform(&st) < s->dropout) {
                *out = NEGOBS_DISP_INVALID;
            }
            if (s->inv_u1 > s->inv_u0 && u >= s->inv_u0 && u < s->inv_u1 &&
                v >= s->inv_v0 && v < s->inv_v1) {
                *out = NEGOBS_DISP_INVALID;
            }
        }
    }
}

#endif
