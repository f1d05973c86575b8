// Shared plumbing of the detection host tools (negobs_png,
// negobs_detect_eval): camera parameters, negobs_synth's gt.json, the
// pipeline run with per-stage timing, JSON lines and overlay pictures.
#ifndef NEGOBS_TOOLS_DETECT_COMMON_HPP
#define NEGOBS_TOOLS_DETECT_COMMON_HPP

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "stereo_common.hpp"

extern "C" {
#include "negobs/negobs.h"
#include "negobs_port/frame_convert.h"
#include "negobs_port/pool.h"
}

namespace negobs_detect_tools {

// Rig description. NaN principal point = image centre ((w-1)/2, (h-1)/2).
struct CamParams {
    double f = 250.0; // px
    double baseline_mm = 120.0;
    double cx = -1.0; // < 0: centre
    double cy = -1.0;
    double height_mm = 1200.0;
    double pitch_deg = 20.0;
    int max_disp = -1;       // < 0: library default
    bool vshift_set = false; // false: the matcher estimates it
    int vshift = 0;          // rows: left y matches right y + vshift
    bool valign = false;     // true: sub-pixel alignment stage (valign.h)
    int range_warn_mm = -1;  // alert zones; < 0: library default
    int range_max_mm = -1;
    int pool_frames = -1; // detector's pool_frames; < 0: library default
};

// One frame of negobs_synth's gt.json (docs/SYNTH.md).
struct GtFrame {
    int i = 0;
    std::string left, right;
    std::string hazard;
    bool has_range = false;
    double edge_range_mm = 0.0;
    double drop_mm = 0.0;
    bool edge_visible = false;
    bool has_box = false;
    double box[4] = {0, 0, 0, 0};
};

struct GtSeq {
    CamParams cam;
    int width = 0, height = 0;
    double right_row_shift = 0.0;
    std::string hazard;
    bool negative = false;
    double fps = 10.0;
    std::vector<GtFrame> frames;
};

// Reads negobs_synth's gt.json with OpenCV's JSON reader (any layout:
// re-indented or compacted files read the same) and validates the values
// it keeps: camera numbers present (finite checks are the caller's, which
// knows the ranges), width/height in 1..100000, frame i an integer, left/
// right strings, ranges and boxes finite. Returns false with err naming
// the file and the field.
bool read_gt(const std::string &path, GtSeq &gt, std::string &err);

// Reads an 8-bit grey image (colour converted). false + err if unreadable.
// The stereo tools' loader, the one the image fuzzer drives
// (tests/fuzz/fuzz_image.cpp).
using negobs_tools::load_grey;

// Thread CPU time in ms (robust against other load on the machine).
double thread_cpu_ms();
// The same clock in microseconds modulo 2^32, as the pipeline's stage clock.
uint32_t thread_cpu_us(void *user);

// One frame's outcome.
struct FrameOut {
    negobs_pipeline_result_t res{};
    double stereo_ms = -1.0; // < 0: not measured separately (--whole)
    double detect_ms = -1.0;
    double total_ms = 0.0;
};

// Owns a pipeline context and its aligned workspace.
class Runner {
public:
    Runner();
    ~Runner();
    Runner(const Runner &) = delete;
    Runner &operator=(const Runner &) = delete;

    // Configures the pipeline for width x height and cam. tweak (optional)
    // may edit the config before init. false + err on failure.
    bool init(int width, int height, const CamParams &cam, std::string &err,
              bool whole = false);

    // Threads for the matcher's row bands from the next init() on (a
    // negobs_port pool; 1, the default: the calling thread). The output
    // does not depend on it.
    void set_threads(int threads) { threads_ = threads < 1 ? 1 : threads; }
    // The matcher's memory profile (NEGOBS_STEREO_PROFILE_*) from the next
    // init() on; the output does not depend on it.
    void set_memory_profile(int profile) { profile_ = profile; }
    // The pipeline's half-resolution pass (coarse_pass, 1 by default)
    // from the next init() on.
    void set_coarse(int on) { coarse_ = on ? 1 : 0; }

    // Runs one pair captured at t_ms through negobs_pipeline_process. Stage
    // timings come from the pipeline's clock hook (thread CPU time); with
    // whole = true no clock is set and only the whole call is timed.
    bool process(const cv::Mat &left, const cv::Mat &right, uint32_t t_ms, FrameOut &out,
                 std::string &err);

    // Last disparity (CV_16S, disp*16, INT16_MIN invalid), a view.
    cv::Mat disparity() const;
    // Right image as the matcher saw it: the alignment stage's output when
    // it is on (a view), else empty.
    cv::Mat aligned_right() const;
    // Last stereo confidence map (the pipeline's own buffer).
    const negobs_image_u8_t *confidence() const
    {
        return negobs_pipeline_confidence(&ctx_);
    }
    const negobs_pipeline_config_t &config() const { return cfg_; }

private:
    negobs_pipeline_config_t cfg_{};
    negobs_pipeline_t ctx_{};
    void *ws_ = nullptr;
    bool whole_ = false;
    bool ready_ = false;
    int threads_ = 1;
    int profile_ = NEGOBS_STEREO_PROFILE_DEFAULT;
    int coarse_ = 1;
    negobs_pool_t *pool_ = nullptr;
};

// Names.
const char *state_name(int state);
const char *level_name(int level);
// "config", "estimated" or "held" (negobs_mount_source_t).
const char *mount_source_name(int source);
// negobs_ground_ref_by_t as the JSON's ground_ref.by: none hint feet walk time
const char *ground_ref_name(int by);
const char *pattern_name(int pattern);
const char *type_name(int type);
std::string reasons_string(uint32_t reasons, const char *sep);
std::string flags_string(uint32_t flags, const char *sep);

// JSON line of one frame (no newline). gt may be null; name = file.
std::string json_line(int frame, const std::string &name, const FrameOut &o,
                      const GtFrame *gt, int width, int height);

// Colour disparity (jet, invalid black) scaled to max_disp px.
cv::Mat colour_disparity(const cv::Mat &disp_q4, int max_disp);

// Left image with hazards and candidates, colour disparity beside it and a
// status bar below. gt (optional) draws the ground-truth edge box.
cv::Mat overlay(const cv::Mat &left, const cv::Mat &disp_q4, int max_disp, int frame,
                const FrameOut &o, const GtFrame *gt,
                const std::vector<cv::Rect> &labels = {});

// Integer k x k area binning of a pair to the processing size, as the
// device does (docs/CAMERAS.md, "Choosing the processing size"): the port's
// own plan, bin and intrinsics (port/camera/frame_convert.c), so a binned
// PNG is what the wearable would process. The eye is centre-cropped to a
// multiple of k; f, cx and cy (in cam, for the eye's full size; cx, cy < 0:
// the centre, kept) become f / k and (c - crop - (k - 1) / 2) / k, rounded
// to 1/16 px by the port. k = 1: nothing changes. false + err on a size
// the port refuses.
bool bin_pair(int k, cv::Mat &left, cv::Mat &right, std::string &err);
void bin_camera(int k, int eye_w, int eye_h, CamParams &cam);

} // namespace negobs_detect_tools

#endif
