// Non-occluded pixels of a left view from the ground truth of both views,
// for the sets that ship a right-view GT but no occlusion mask (Middlebury
// 2001 Poster, the 2006 half-size sets), and where to find that right GT.
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace negobs_tools {

// A left pixel with GT disparity d is visible in the right view when the
// right GT at column round(x - d) is known and within `tol_px` of d: the
// left-right consistency test Middlebury's own nonocc masks come from.
// gt_left, gt_right: CV_32F disparities in px; known_left, known_right:
// CV_8U, non-zero where the GT is known; all the same size. Returns CV_8U,
// 255 where non-occluded, 0 elsewhere (also where the left GT is unknown).
// An empty Mat when the inputs do not fit together.
cv::Mat nonocc_from_right_gt(const cv::Mat &gt_left, const cv::Mat &known_left,
                             const cv::Mat &gt_right,
                             const cv::Mat &known_right, double tol_px = 1.0);

// The right-view GT beside a left-view GT, by Middlebury's naming: the GT
// file is named after its view's number (disp1.png for view1.png, disp2.pgm
// for im2.ppm), so the right view's number (view5.png, im6.ppm) names the
// right GT (disp5.png, disp6.pgm). Tries the GT's own extension, then .png
// and .pgm. Returns the path of an existing file, or "" when the names do
// not follow that pattern or no such file exists.
std::string right_gt_path(const std::string &left_image,
                          const std::string &right_image,
                          const std::string &gt_left);

} // namespace negobs_tools
