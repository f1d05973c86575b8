// Shared plumbing of the stereo host tools (negobs_stereo, negobs_eval):
// image loading, the negobs engine wrapper, OpenCV's fixed-point disparity
// convention and colour maps.
#ifndef NEGOBS_TOOLS_STEREO_COMMON_HPP
#define NEGOBS_TOOLS_STEREO_COMMON_HPP

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace negobs_tools {

// Read any file OpenCV decodes (PNG, PPM/PGM, BMP, JPEG, ...) as 8-bit
// grey. Colour images are converted with cv::COLOR_BGR2GRAY, 16-bit ones
// are scaled down to 8 bits. Returns false and sets err when unreadable.
bool load_grey(const std::string &path, cv::Mat &grey, std::string &err);

// Disparity search range in pixels, both ends included.
struct Range {
    int min_disp = 0;
    int max_disp = 64;
};

// Largest disparity the tools accept: disp_q4 is int16 (disparity * 16).
constexpr int kMaxDispLimit = 2047;

// Checks a range against an image width; returns an empty string when
// usable, else a sentence saying what is wrong.
std::string check_range(const Range &r, int width);

// Checks the engine's own limits (largest range, smallest frame) where the
// stereo header publishes them; empty string when fine.
std::string check_engine_limits(const Range &r, int width, int height);

// Number of disparities OpenCV searches for a range: the range length
// rounded up to a multiple of 16 (OpenCV requires it).
int opencv_num_disparities(const Range &r);

// Owns a negobs stereo context and its 16-byte aligned workspace.
class NegobsMatcher {
public:
    NegobsMatcher();
    ~NegobsMatcher();
    NegobsMatcher(const NegobsMatcher &) = delete;
    NegobsMatcher &operator=(const NegobsMatcher &) = delete;

    // Configures for width x height and the range. On failure returns
    // false and sets err (library status text included). keep_out_of_view
    // >= 0 overrides the engine's (1: a dense map, values whose match
    // falls left of the right image kept). gap_fill >= 0
    // overrides the engine's row gap fill (0 = off; -1: its default).
    bool init(int width, int height, const Range &r, std::string &err,
              int gap_fill = -1, int keep_out_of_view = -1);

    // Threads for the engine's row bands from the next init() on (a
    // negobs_port pool; 1 = the calling thread only, the default). The
    // disparities do not depend on it.
    void set_threads(int threads) { threads_ = threads < 1 ? 1 : threads; }
    // negobs_stereo_config_t.subpixel_halfshift for the next init()
    void set_subpixel_halfshift(bool on) { halfshift_ = on; }

    // Runs the engine. disp_q4 becomes CV_16SC1 (disparity * 16 or
    // NEGOBS_DISP_INVALID), confidence CV_8UC1. Both inputs 8-bit grey of
    // the configured size. Returns false and sets err on a library error.
    bool process(const cv::Mat &left, const cv::Mat &right, cv::Mat &disp_q4,
                 cv::Mat &confidence, std::string &err);

    // Times every engine stage (negobs_stereo_set_clock, thread CPU time)
    // from the next process() on; last_stats() then lists them.
    void profile_stages(bool on);

    // Keeps a copy of the map after every stage the engine reports
    // (negobs_stereo_set_observer) from the next process() on; stages()
    // then returns them in order, as disparity * 16 (CV_16S, also after
    // GCS, whose whole pixels are scaled here) with the stage's name.
    void keep_stages(bool on);
    struct Snapshot {
        std::string name;
        cv::Mat disp_q4;
    };
    const std::vector<Snapshot> &stages() const;

    std::size_t workspace_bytes() const { return bytes_; }
    // Statistics of the last process() call, formatted on one line.
    const std::string &last_stats() const { return stats_text_; }

    struct Impl; // opaque; public only so the engine's callbacks can name it

private:
    std::unique_ptr<Impl> impl_;
    std::size_t bytes_ = 0;
    std::string stats_text_;
    bool profile_ = false;
    int threads_ = 1;
    bool halfshift_ = false;
};

// negobs disp_q4 (CV_16S, INT16_MIN = none) -> OpenCV's 16-bit PNG
// convention (CV_16U, disparity * 16, 0 = no value). Disparities <= 0 px
// have no representation there and become 0 (= no value).
cv::Mat negobs_q4_to_png16(const cv::Mat &disp_q4);

// Disparity in pixels as CV_32F plus a validity mask (CV_8U, 255 = value):
//  - from negobs disp_q4 (INT16_MIN = none);
void negobs_q4_to_float(const cv::Mat &disp_q4, cv::Mat &disp, cv::Mat &valid);
//  - from OpenCV StereoBM/SGBM output (CV_16S disparity * 16; values below
//    min_disp * 16 mark "no value").
void opencv_q4_to_float(const cv::Mat &disp16, int min_disp, cv::Mat &disp,
                        cv::Mat &valid);

// Colour picture of a disparity map: COLORMAP_TURBO over [lo, hi] px,
// pixels without value black.
cv::Mat colourise(const cv::Mat &disp, const cv::Mat &valid, double lo,
                  double hi);

} // namespace negobs_tools

#endif
