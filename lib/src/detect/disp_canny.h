/*
 * Canny edges of the disparity map (the paper's step 7), internal to the
 * detect stage, where they only support a hazard found by the residual
 * rule (docs/DETECTION.md section 5): an unsigned edge cannot tell a drop
 * from the contour of an object standing on the ground.
 *
 * Magnitudes are the L1 Sobel magnitude of disp_q4 (1/16 px per unit),
 * saturated at 65535, and 0 where the 3x3 neighbourhood holds an invalid
 * pixel, so holes make no edges. The thresholds follow the paper's
 * normalised form: high = high_permille / 1000 of the largest magnitude
 * in the scanned band, low = low_permille / 1000 of high.
 */
#ifndef NEGOBS_DETECT_DISP_CANNY_H
#define NEGOBS_DETECT_DISP_CANNY_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/image.h"

/* Rows and columns of context kept around the counted rows on each side:
 * hysteresis follows weak edge pixels this far out of the counted band. */
#define DCANNY_MARGIN 6
/* Counted rows: edge row - 2 .. edge row + 1. */
#define DCANNY_ROWS_ABOVE 2
#define DCANNY_ROWS_BELOW 1
/* Window rows = counted rows + both margins. */
#define DCANNY_WIN_ROWS                                                       \
    (DCANNY_ROWS_ABOVE + DCANNY_ROWS_BELOW + 1 + 2 * DCANNY_MARGIN)

typedef struct dcanny_scratch {
    uint16_t *mag;  /* 3 x width: magnitudes of three rows        */
    uint8_t *label; /* DCANNY_WIN_ROWS x width: 0 none, 1 weak, 2 edge */
    int32_t width;  /* image width the buffers were sized for         */
} dcanny_scratch_t;

/* Bytes of the two scratch buffers for images up to `width` columns. */
size_t dcanny_mag_bytes(int32_t width);
size_t dcanny_label_bytes(int32_t width);

/* Largest magnitude over rows [v_top, height - 1), sampled on every second
 * pixel of every second row (it only scales the thresholds). */
int32_t dcanny_band_max(const negobs_image_s16_t *d, int32_t v_top);

/*
 * Canny edge pixels among rows edge_v - DCANNY_ROWS_ABOVE ..
 * edge_v + DCANNY_ROWS_BELOW and columns u0 .. u1 of d: non-maximum
 * suppression along the gradient direction (4 sectors), the two
 * thresholds, and hysteresis inside a window DCANNY_MARGIN rows and
 * columns larger on each side (weak pixels joined to an edge pixel by a
 * chain of weak pixels inside the window become edges; chains leaving the
 * window are cut there). Returns the count, 0 when gmax gives a high
 * threshold below 1. sc must be sized for d->width.
 */
int32_t dcanny_support(const negobs_image_s16_t *d, int32_t gmax,
                       int32_t high_permille, int32_t low_permille, int32_t u0,
                       int32_t u1, int32_t edge_v, const dcanny_scratch_t *sc);

#endif
