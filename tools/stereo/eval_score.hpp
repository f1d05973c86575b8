// Disparity scoring shared by negobs_eval's two modes: the built-in sets
// (negobs, StereoBM, StereoSGBM on every pair with ground truth) and
// --score, which scores one map from any matcher in any of the formats of
// tools/common/disp_io.hpp, like Middlebury's evaldisp.
#ifndef NEGOBS_TOOLS_EVAL_SCORE_HPP
#define NEGOBS_TOOLS_EVAL_SCORE_HPP

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace negobs_tools {

// Scores over the evaluated pixels (eval_mask != 0), all in %:
//   density  share that has a value
//   bad1     of those with a value, |error| > 1 px
//   bad1all  wrong by > 1 px or no value
//   bad2     of those with a value, |error| > 2 px
//   rms      RMS error (px) over those with a value
struct DispScore {
    long evaluated = 0, with_value = 0;
    double density = 0, bad1 = 0, bad1all = 0, bad2 = 0, rms = 0;
};

// disp, gt: CV_32F px; valid, eval_mask: CV_8U, != 0 = yes.
DispScore score_disparity(const cv::Mat &disp, const cv::Mat &valid,
                          const cv::Mat &gt, const cv::Mat &eval_mask);

// One row of a machine-readable result: a set and a matcher.
struct ScoreRow {
    std::string set, matcher;
    int width = 0, height = 0;
    DispScore s;
    double cpu_ms = -1; // < 0: not timed
};

// CSV (header line + one line per row) or a JSON array of objects; path
// "-" is stdout. false when the file cannot be written.
bool write_score_csv(const std::string &path,
                     const std::vector<ScoreRow> &rows);
bool write_score_json(const std::string &path,
                      const std::vector<ScoreRow> &rows);
bool write_score_markdown(const std::string &path,
                          const std::vector<ScoreRow> &rows,
                          const std::string &command_line);

// negobs_eval --score: the options after the mode was chosen.
struct ScoreOptions {
    std::string map, gt, mask;
    std::string map_format = "auto"; // auto|png16|kitti|pfm
    double map_scale = 0;            // <= 0: the format's own
    double gt_scale = 0;             // <= 0: by the GT file (see --help)
    std::string csv, json, markdown;
    std::string name; // the set column; default the map's file name
    std::string command_line;
};

// Reads, scores, prints one line and writes the requested files. Returns
// 0, 1 (data error: unreadable file, size mismatch, no GT pixel) or 2
// (bad --format).
int score_map_main(const ScoreOptions &o);

} // namespace negobs_tools

#endif
