// Separability of a drop-off from the disparity noise, measured on the
// whole walking corridor: an upper bound for any detector that works from
// one disparity map, independent of the library's own rule.
//
// For every row the corridor profile p(v) is the median, over the corridor
// columns, of the residual d - ground model. A drop edge at row v shows as
// a jump J(v) = median(p over the N rows nearer) - median(p over the N rows
// farther), positive (the farther surface is lower). Slow errors of the
// ground model cancel in J; row-correlated matching noise does not. The
// frame's own spread of J (1.4826 * MAD over all rows of the scan) is the
// noise it must beat.
#ifndef NEGOBS_TOOLS_PROFILE_JUMP_HPP
#define NEGOBS_TOOLS_PROFILE_JUMP_HPP

#include <opencv2/core.hpp>

#include "negobs/ground.h"

struct JumpStats {
    bool ok = false;    // enough rows with data
    double sigma = 0;   // spread of J over the frame (px)
    double label_j = 0; // largest J within +-window rows of the label
    int label_v = -1;
    double label_z = 0;   // (label_j - median J) / sigma
    double label_rel = 0; // label_j / ground disparity at label_v
    double other_j = 0;   // largest J elsewhere in the scan
    int other_v = -1;
    double other_z = 0;
};

// disp: CV_16S, disparity * 16, values < 0 invalid. plane: the ground
// model of the frame. Corridor columns [u0, u1), scan rows [v0, rows).
// label_v: the row of the labelled edge (its nearest row); rows within
// `window` of it count as "label", the rest as "elsewhere". N: rows on
// each side of the jump.
JumpStats profile_jump(const cv::Mat &disp, const negobs_ground_plane_t &plane, int u0,
                       int u1, int v0, int label_v, int window = 20, int n = 10);

#endif
