/*
 * A generated walk toward a curb, as stereo pairs for the whole pipeline
 * (the cross-target digest and the fuzz seeds use it; no OpenCV).
 *
 * The geometry is the detect tests' analytic scene (tests/support/scene_disp.h):
 * camera 1.2 m above level ground, pitched 20 deg down, a 15 cm drop whose
 * edge starts WALK_EDGE0_MM ahead and comes WALK_STEP_MM nearer every
 * frame (1 m/s at 10 frames/s). Its exact disparity becomes an image pair
 * in integer arithmetic: the left image is a value-noise texture, the right
 * one samples the same texture WALK_VOFF rows lower and d px to the right,
 * d being the scene's disparity in 1/16 px (linear interpolation). So the
 * pair is what a rectified rig with a small row offset would see, and the
 * matcher, valign and detector all have real work.
 */
#ifndef NEGOBS_TEST_WALK_H
#define NEGOBS_TEST_WALK_H

#include <stdint.h>

#include "negobs/depth.h"

#ifdef __cplusplus
extern "C" {
#endif

#define WALK_FRAMES 24
#define WALK_EDGE0_MM 4000
#define WALK_STEP_MM 100
#define WALK_VOFF 1
#define WALK_MAX_PIXELS (640 * 480)

/**
 * Render frame `frame` (0 .. WALK_FRAMES-1) of the walk for camera cam
 * (width * height <= WALK_MAX_PIXELS) into left and right (stride =
 * width). Returns 0, or -1 for a camera it cannot render.
 */
int walk_render(const negobs_rig_t *cam, int32_t frame, uint8_t *left,
                uint8_t *right);

#ifdef __cplusplus
}
#endif

#endif
