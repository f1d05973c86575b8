// Shared by negobs_calib and negobs_rectify_check: the stereo image list
// (OpenCV stereo_calib.xml format), chessboard detection and table I/O.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace negobs_calib {

struct ImagePair {
    std::string left;
    std::string right;
};

// Reads an OpenCV FileStorage list ("imagelist" node, or the first
// top-level sequence) of alternating left/right names. Relative names are
// resolved against the list file's folder. Returns false with `err` set.
bool read_image_list(const std::string &path, std::vector<ImagePair> &pairs,
                     std::string &err);

// Parses "9x6" (inner corners per row x per column).
bool parse_size(const std::string &text, cv::Size &size);

// findChessboardCorners + cornerSubPix (11x11 window, 30 iterations /
// 0.01 px). Returns false when the whole board is not found.
bool find_corners(const cv::Mat &grey, cv::Size board,
                  std::vector<cv::Point2f> &corners);

bool file_exists(const std::string &path);
bool read_file(const std::string &path, std::vector<uint8_t> &bytes,
               std::string &err);
bool write_file(const std::string &path, const std::vector<uint8_t> &bytes,
                std::string &err);

} // namespace negobs_calib
