/*
 * Forward travel along the floor between two frames (detect_travel.c):
 * what verifies a start that the mounting hint cannot (docs/DETECTION.md
 * 6.2, "Verified by walking").
 */
#ifndef NEGOBS_DETECT_TRAVEL_H
#define NEGOBS_DETECT_TRAVEL_H

#include <stdint.h>

#include "negobs/depth.h"
#include "negobs/executor.h"
#include "negobs/ground.h"
#include "negobs/image.h"

/* Floor patches kept from one frame to the next: an 8 x 8 grid. */
#define TRAVEL_SAMPLES 64
/* Side of a patch (px): odd, the matcher's own window size. */
#define TRAVEL_PATCH 5
#ifndef TRAVEL_STRIDE
#define TRAVEL_STRIDE 2
#endif

typedef struct travel_track {
    int32_t n; /* patches held from the previous frame (0: none) */
    uint32_t t_ms;
    int32_t fwd_mm[TRAVEL_SAMPLES]; /* floor point along the heading   */
    int32_t lat_mm[TRAVEL_SAMPLES]; /* and across it                   */
    uint8_t px[TRAVEL_SAMPLES][TRAVEL_PATCH * TRAVEL_PATCH];
} travel_track_t;

/* The floor's axes in camera coordinates, Q30: n (down to the floor),
 * f (along the floor in the heading), r (along the floor, to the right).
 * With n = (cos p sin r, cos p cos r, sin p):
 * f = (-sin p sin r, -sin p cos r, cos p), r = (cos r, -sin r, 0). */
typedef struct floor_axes {
    int64_t n[3];
    int64_t f[3];
    int64_t r[3];
    int64_t h_mm;
} floor_axes_t;

/* The axes of a fitted floor; 0 when it has none (no pitch or height). */
int travel_axes_of(const negobs_ground_frame_t *fr, floor_axes_t *a);

/* Pixel, 1/16 px, of the floor point fwd_mm ahead of the camera's foot
 * and lat_mm to the right; 0 when it lies behind or within 200 mm of the
 * camera. A camera-frame point (mm, Q30) is at most 2^14 * 2^30 * 3 <
 * 2^46, and the focal length in 1/16 px (< 2^17) times it stays below
 * 2^63. */
int travel_pixel_q4(const negobs_rig_t *rig, const floor_axes_t *a,
                    int32_t fwd_mm, int32_t lat_mm, int32_t *u_q4,
                    int32_t *v_q4);

/* A travel follower holds TRAVEL_TRACKS tracks (t[0], t[1]): the last
 * frame's patches, and those of the frame up to which the travel was last
 * measured, while a later frame's was not (travel_step). */
#define TRAVEL_TRACKS 2

/* Forget the patches (the next frame measures nothing). */
static inline void travel_reset(travel_track_t *t)
{
    t[0].n = 0;
    t[1].n = 0;
}

/*
 * The forward travel (mm) of the camera along the floor, read on this
 * frame's left image through this frame's floor (rig, frame), from the
 * frame up to which it was last measured: the last frame's patches (t[0])
 * or, when the last frame's travel was not measured, those of that
 * earlier frame (t[1], held for at most the longest gap measured). Then this
 * frame's patches replace t[0]. *pair_mm: the travel since the last
 * frame alone, as the pooling needs it (0: not measured). Returns 0 when
 * the travel is not measured clearly (no patches, too long a gap, a flat
 * or moving scene, standing still): nothing is ever counted that the
 * images do not show. Integer only.
 */
int32_t travel_step(travel_track_t *t, const negobs_rig_t *rig,
                    const negobs_ground_plane_t *plane,
                    const negobs_ground_frame_t *frame,
                    const negobs_image_u8_t *left, uint32_t now_ms,
                    const negobs_executor_t *exec, int32_t *pair_mm);

#endif
