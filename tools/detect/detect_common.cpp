#include "detect_common.hpp"

#include "colour_bar.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace negobs_detect_tools {

namespace {

// OpenCV's JSON reader (4.6) knows numbers, strings, true/false, arrays
// and objects, but not null, nor the NaN / Infinity that some writers emit.
// Such bare words outside strings are quoted here, so the file parses and
// each reader below decides: a required number that reads "null" is
// missing, "nan" / "inf" are non-finite numbers the callers refuse by name.
std::string quote_bare_words(const std::string &in)
{
    std::string out;
    out.reserve(in.size() + 64);
    bool in_str = false;
    for (size_t i = 0; i < in.size(); ++i) {
        const char c = in[i];
        if (in_str) {
            out += c;
            if (c == '\\' && i + 1 < in.size()) {
                out += in[++i];
            } else if (c == '"') {
                in_str = false;
            }
            continue;
        }
        if (c == '"') {
            in_str = true;
            out += c;
            continue;
        }
        if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
            // a number, exponent included (the 'e' of 1e5 is no word)
            size_t e = i;
            while (e < in.size() && (std::isalnum(static_cast<unsigned char>(in[e])) ||
                                     in[e] == '.' || in[e] == '+' || in[e] == '-')) {
                ++e;
            }
            out.append(in, i, e - i);
            i = e - 1;
            continue;
        }
        const bool sign = (c == '-' || c == '+') && i + 1 < in.size() &&
                          std::isalpha(static_cast<unsigned char>(in[i + 1]));
        if (std::isalpha(static_cast<unsigned char>(c)) || sign) {
            size_t e = i + 1;
            while (e < in.size() && std::isalnum(static_cast<unsigned char>(in[e]))) {
                ++e;
            }
            const std::string w = in.substr(i, e - i);
            out += (w == "true" || w == "false") ? w : "\"" + w + "\"";
            i = e - 1;
            continue;
        }
        out += c;
    }
    return out;
}

// A number: a JSON number, or a quoted bare word that strtod reads in
// full ("nan", "inf", "-Infinity"). "null" and anything else: false.
bool node_num(const cv::FileNode &n, double &out)
{
    if (n.isInt() || n.isReal()) {
        out = static_cast<double>(n);
        return true;
    }
    if (n.isString()) {
        const std::string s = static_cast<std::string>(n);
        char *end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (s != "null" && !s.empty() && *end == '\0') {
            out = v;
            return true;
        }
    }
    return false;
}

bool node_str(const cv::FileNode &n, std::string &out)
{
    if (!n.isString()) {
        return false;
    }
    out = static_cast<std::string>(n);
    return out != "null";
}

// true/false as OpenCV stores them (1/0); anything else is false.
bool node_true(const cv::FileNode &n)
{
    return n.isInt() && static_cast<int>(n) == 1;
}

std::string fmt(const char *f, double v)
{
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

} // namespace

bool read_gt(const std::string &path, GtSeq &gt, std::string &err)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        err = "cannot read " + path;
        return false;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    cv::FileStorage fs;
    try {
        fs.open(quote_bare_words(ss.str()), cv::FileStorage::READ |
                                                cv::FileStorage::MEMORY |
                                                cv::FileStorage::FORMAT_JSON);
    } catch (const cv::Exception &e) {
        err = path + ": not valid JSON (" + e.err + ")";
        return false;
    }
    if (!fs.isOpened() || !fs.root().isMap()) {
        err = path + ": not a JSON object";
        return false;
    }
    const cv::FileNode cam = fs["camera"];
    if (!cam.isMap()) {
        err = path + ": no \"camera\" object (not a negobs_synth gt.json?)";
        return false;
    }
    double v = 0;
    if (!node_num(cam["f"], gt.cam.f) || !node_num(cam["B_mm"], gt.cam.baseline_mm) ||
        !node_num(cam["cx"], gt.cam.cx) || !node_num(cam["cy"], gt.cam.cy) ||
        !node_num(cam["H_mm"], gt.cam.height_mm) ||
        !node_num(cam["pitch"], gt.cam.pitch_deg) || !node_num(cam["width"], v)) {
        err = path + ": camera lacks a number for f/B_mm/cx/cy/H_mm/pitch/width";
        return false;
    }
    // a size outside int would be an undefined conversion
    if (!(v >= 1 && v <= 100000)) {
        err = path + ": camera width is not a number in 1..100000";
        return false;
    }
    gt.width = static_cast<int>(v);
    if (!node_num(cam["height"], v)) {
        err = path + ": camera lacks height";
        return false;
    }
    if (!(v >= 1 && v <= 100000)) {
        err = path + ": camera height is not a number in 1..100000";
        return false;
    }
    gt.height = static_cast<int>(v);
    if (!cam["right_row_shift"].empty() &&
        (!node_num(cam["right_row_shift"], gt.right_row_shift) ||
         !std::isfinite(gt.right_row_shift))) {
        err = path + ": camera right_row_shift is not a finite number";
        return false;
    }
    const cv::FileNode scene = fs["scene"];
    if (scene.isMap()) {
        node_str(scene["hazard"], gt.hazard);
        gt.negative = node_true(scene["negative"]);
    }
    const cv::FileNode render = fs["render"];
    if (render.isMap() && !render["fps"].empty() && !node_num(render["fps"], gt.fps)) {
        err = path + ": render fps is not a number";
        return false;
    }
    const cv::FileNode frames = fs["frames"];
    if (!frames.empty() && !frames.isSeq()) {
        err = path + ": \"frames\" is not a list";
        return false;
    }
    int k = 0;
    for (auto it = frames.begin(); it != frames.end(); ++it, ++k) {
        const cv::FileNode f = *it;
        GtFrame fr;
        const std::string where = path + ": frame " + std::to_string(k);
        if (!f.isMap() || !node_num(f["i"], v) || !node_str(f["left"], fr.left) ||
            !node_str(f["right"], fr.right)) {
            err = where + " lacks i/left/right";
            return false;
        }
        if (!(v >= 0 && v <= 1e8) || v != std::floor(v)) {
            err = where + ": i is not an integer in 0..1e8";
            return false;
        }
        fr.i = static_cast<int>(v);
        node_str(f["hazard"], fr.hazard);
        fr.has_range = node_num(f["edge_range_mm"], fr.edge_range_mm);
        if (fr.has_range && !std::isfinite(fr.edge_range_mm)) {
            err = where + ": edge_range_mm is not finite";
            return false;
        }
        if (node_num(f["drop_mm"], fr.drop_mm) && !std::isfinite(fr.drop_mm)) {
            err = where + ": drop_mm is not finite";
            return false;
        }
        fr.edge_visible = node_true(f["edge_visible"]);
        const cv::FileNode box = f["edge_box"];
        if (box.isSeq() && box.size() == 4) {
            fr.has_box = true;
            for (int b = 0; b < 4; ++b) {
                fr.has_box = fr.has_box && node_num(box[b], fr.box[b]) &&
                             std::isfinite(fr.box[b]);
            }
        }
        gt.frames.push_back(fr);
    }
    return true;
}

double thread_cpu_ms()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

uint32_t thread_cpu_us(void *)
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    // modulo 2^32: the pipeline takes differences (one stage < 71 min)
    return static_cast<uint32_t>(static_cast<uint64_t>(ts.tv_sec) * 1000000u +
                                 static_cast<uint64_t>(ts.tv_nsec) / 1000u);
}

Runner::Runner() = default;

Runner::~Runner()
{
    negobs_pool_destroy(pool_);
    std::free(ws_);
}

bool Runner::init(int width, int height, const CamParams &cam, std::string &err,
                  bool whole)
{
    whole_ = whole;
    negobs_pipeline_config_default(&cfg_, width, height);
    const double cx = cam.cx >= 0 ? cam.cx : (width - 1) / 2.0;
    const double cy = cam.cy >= 0 ? cam.cy : (height - 1) / 2.0;
    cfg_.detect.rig.focal_q4 = static_cast<int32_t>(std::lround(cam.f * 16));
    cfg_.detect.rig.cx_q4 = static_cast<int32_t>(std::lround(cx * 16));
    cfg_.detect.rig.cy_q4 = static_cast<int32_t>(std::lround(cy * 16));
    cfg_.detect.rig.baseline_um = static_cast<int32_t>(
        std::lround(cam.baseline_mm * 1000));
    cfg_.detect.cam_height_mm = static_cast<int32_t>(std::lround(cam.height_mm));
    cfg_.detect.cam_pitch_mdeg = static_cast<int32_t>(std::lround(cam.pitch_deg * 1000));
    if (cam.max_disp > 0) {
        cfg_.stereo.max_disp = cam.max_disp;
        cfg_.detect.max_disp_q4 = (cam.max_disp + 1) * NEGOBS_DISP_ONE;
    }
    if (cam.range_warn_mm > 0) {
        cfg_.detect.range_warn_mm = cam.range_warn_mm;
    }
    if (cam.range_max_mm > 0) {
        cfg_.detect.range_max_mm = cam.range_max_mm;
    }
    if (cam.pool_frames > 0) {
        cfg_.detect.pool_frames = cam.pool_frames;
    }
    if (cam.vshift_set) {
        cfg_.stereo.vertical_search = 0;
        cfg_.stereo.vertical_offset = cam.vshift;
    }
    if (cam.valign) {
        cfg_.valign.enable = 1;
        cfg_.valign.max_disp = cfg_.stereo.max_disp;
    }
    cfg_.stereo.band_workers = threads_;
    cfg_.stereo.memory_profile = profile_;
    cfg_.coarse_pass = coarse_;
    size_t bytes = 0;
    negobs_status_t st = negobs_pipeline_workspace_size(&cfg_, &bytes);
    if (st != NEGOBS_OK) {
        err = std::string("pipeline config rejected: ") + negobs_status_str(st);
        return false;
    }
    std::free(ws_);
    ws_ = std::aligned_alloc(16, (bytes + 15) / 16 * 16);
    if (ws_ == nullptr) {
        err = "out of memory";
        return false;
    }
    st = negobs_pipeline_init(&ctx_, &cfg_, ws_, bytes);
    if (st != NEGOBS_OK) {
        err = std::string("negobs_pipeline_init: ") + negobs_status_str(st);
        return false;
    }
    if (threads_ > 1) {
        if (pool_ == nullptr) {
            st = negobs_pool_create(&pool_, threads_);
        }
        if (st == NEGOBS_OK) {
            negobs_executor_t e = negobs_pool_executor(pool_);
            st = negobs_pipeline_set_executor(&ctx_, &e);
        }
        if (st != NEGOBS_OK) {
            err = std::string("thread pool: ") + negobs_status_str(st);
            return false;
        }
    }
    ready_ = true;
    return true;
}

bool Runner::process(const cv::Mat &left, const cv::Mat &right, uint32_t t_ms,
                     FrameOut &out, std::string &err)
{
    if (!ready_) {
        err = "pipeline not initialised";
        return false;
    }
    negobs_image_u8_t l{}, r{};
    l.data = const_cast<uint8_t *>(left.ptr<uint8_t>(0));
    l.width = left.cols;
    l.height = left.rows;
    l.stride = static_cast<int32_t>(left.step1());
    r.data = const_cast<uint8_t *>(right.ptr<uint8_t>(0));
    r.width = right.cols;
    r.height = right.rows;
    r.stride = static_cast<int32_t>(right.step1());
    negobs_pipeline_frame_t fr{};
    fr.left = &l;
    fr.right = &r;
    fr.t_left_ms = t_ms;
    fr.t_right_ms = t_ms;
    fr.now_ms = t_ms;
    out = FrameOut{};
    negobs_pipeline_result_t *res = &out.res;
    // --whole: no stage clock, only the whole call is timed.
    (void)negobs_pipeline_set_clock(&ctx_, whole_ ? nullptr : thread_cpu_us, nullptr);
    const double t0 = thread_cpu_ms();
    const negobs_status_t st = negobs_pipeline_process(&ctx_, &fr, res);
    out.total_ms = thread_cpu_ms() - t0;
    if (!whole_) {
        // the alignment is part of getting a disparity: counted as stereo
        const uint64_t *tk = res->stage_ticks;
        out.stereo_ms = static_cast<double>(tk[NEGOBS_PIPELINE_STAGE_VALIGN] +
                                            tk[NEGOBS_PIPELINE_STAGE_STEREO]) /
                        1e3;
        out.detect_ms = static_cast<double>(tk[NEGOBS_PIPELINE_STAGE_DETECT]) / 1e3;
    }
    if (st != NEGOBS_OK) {
        err = std::string("pipeline: ") + negobs_status_str(st);
        return false;
    }
    return true;
}

cv::Mat Runner::aligned_right() const
{
    const negobs_image_u8_t *r = negobs_pipeline_aligned_right(&ctx_);
    if (!ready_ || r == nullptr || r->data == nullptr) {
        return cv::Mat();
    }
    return cv::Mat(r->height, r->width, CV_8UC1, r->data, static_cast<size_t>(r->stride));
}

cv::Mat Runner::disparity() const
{
    const negobs_image_s16_t *d = negobs_pipeline_disparity(&ctx_);
    if (d == nullptr) {
        return cv::Mat();
    }
    return cv::Mat(d->height, d->width, CV_16SC1, d->data,
                   static_cast<size_t>(d->stride) * sizeof(int16_t));
}

const char *state_name(int s)
{
    switch (s) {
    case NEGOBS_DETECT_CLEAR: return "CLEAR";
    case NEGOBS_DETECT_HAZARD: return "HAZARD";
    case NEGOBS_DETECT_NO_INFO: return "NO_INFO";
    default: return "?";
    }
}

const char *level_name(int l)
{
    switch (l) {
    case NEGOBS_LEVEL_NONE: return "NONE";
    case NEGOBS_LEVEL_CAUTION: return "CAUTION";
    case NEGOBS_LEVEL_IMMINENT: return "IMMINENT";
    default: return "?";
    }
}

const char *pattern_name(int p)
{
    static const char *const names[] = {
        "NONE",        "READY",       "LOW_BATTERY",  "NO_INFO_ENTRY", "NO_INFO",
        "CAUTION_FAR", "CAUTION_MID", "CAUTION_NEAR", "IMMINENT",      "SHORT_SIGHT"};
    static_assert(sizeof names / sizeof names[0] == NEGOBS_PATTERN_COUNT,
                  "one name per pattern");
    return (p >= 0 && p < NEGOBS_PATTERN_COUNT) ? names[p] : "?";
}

const char *type_name(int t)
{
    switch (t) {
    case NEGOBS_HAZARD_UNKNOWN: return "UNKNOWN";
    case NEGOBS_HAZARD_DROP: return "DROP";
    case NEGOBS_HAZARD_STAIRS: return "STAIRS";
    case NEGOBS_HAZARD_HOLE: return "HOLE";
    default: return "?";
    }
}

const char *mount_source_name(int s)
{
    switch (s) {
    case NEGOBS_MOUNT_CONFIG: return "config";
    case NEGOBS_MOUNT_ESTIMATED: return "estimated";
    case NEGOBS_MOUNT_HELD: return "held";
    default: return "?";
    }
}

const char *ground_ref_name(int by)
{
    switch (by) {
    case NEGOBS_GROUND_REF_NONE: return "none";
    case NEGOBS_GROUND_REF_HINT: return "hint";
    case NEGOBS_GROUND_REF_FEET: return "feet";
    case NEGOBS_GROUND_REF_WALK: return "walk";
    case NEGOBS_GROUND_REF_TIME: return "time";
    default: return "?";
    }
}

std::string reasons_string(uint32_t reasons, const char *sep)
{
    static const char *const names[] = {
        "TOO_DARK",   "SATURATED", "LOW_TEXTURE", "FEW_GROUND", "GROUND_REJECTED",
        "STALE",      "UNSYNCED",  "NOISY",       "BAD_INPUT",  "GROUND_UNVERIFIED",
        "NEAR_UNSEEN"};
    std::string s;
    for (unsigned b = 0; b < sizeof names / sizeof names[0]; ++b) {
        if (reasons & (1u << b)) {
            if (!s.empty()) {
                s += sep;
            }
            s += names[b];
        }
    }
    return s;
}

std::string flags_string(uint32_t flags, const char *sep)
{
    static const char *const names[] = {"CONFIRMED",   "HELD",     "H_LOWER",     "CANNY",
                                        "GROUND_DROP", "TEXTURED", "UNIT_SHALLOW"};
    std::string s;
    for (unsigned b = 0; b < sizeof names / sizeof names[0]; ++b) {
        if (flags & (1u << b)) {
            if (!s.empty()) {
                s += sep;
            }
            s += names[b];
        }
    }
    return s;
}

namespace {

std::string quoted_list(const std::string &joined)
{
    // joined uses "," as separator
    std::string out = "[";
    std::stringstream ss(joined);
    std::string item;
    bool first = true;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) {
            continue;
        }
        out += first ? "\"" : ",\"";
        out += item + "\"";
        first = false;
    }
    return out + "]";
}

std::string hazard_json(const negobs_hazard_t &h)
{
    std::ostringstream o;
    o << "{\"type\":\"" << type_name(h.type) << "\",\"level\":\"" << level_name(h.level)
      << "\",\"track\":" << h.track_id << ",\"range_mm\":" << h.range_mm
      << ",\"lateral_mm\":" << h.lateral_mm
      << ",\"bearing_deg\":" << fmt("%.1f", h.bearing_mdeg / 1000.0)
      << ",\"drop_mm\":" << h.drop_mm << ",\"box\":[" << h.u0 << "," << h.v0 << ","
      << h.u1 << "," << h.v1 << "],\"confidence\":" << fmt("%.3f", h.conf_q15 / 32767.0)
      << ",\"strips\":" << h.strips
      << ",\"flags\":" << quoted_list(flags_string(h.flags, ",")) << "}";
    return o.str();
}

} // namespace

std::string json_line(int frame, const std::string &name, const FrameOut &o,
                      const GtFrame *gt, int width, int height)
{
    const negobs_detect_result_t &d = o.res.detect;
    std::ostringstream s;
    s << "{\"frame\":" << frame << ",\"file\":\"" << name << "\",\"stereo_status\":\""
      << negobs_status_str(static_cast<negobs_status_t>(o.res.stereo_status))
      << "\",\"state\":\"" << state_name(d.state)
      << "\",\"reasons\":" << quoted_list(reasons_string(d.reasons, ","))
      << ",\"level\":\"" << level_name(d.level)
      << "\",\"nearest_range_mm\":" << d.nearest_range_mm
      << ",\"clear_to_mm\":" << d.clear_to_mm << ",\"short_sight\":" << d.short_sight
      << ",\"noise_vouch_mm\":" << d.noise_vouch_mm
      << ",\"blocked_at_mm\":" << d.blocked_at_mm
      << ",\"range_near_mm\":" << d.range_near_mm
      << ",\"pooled_permille\":" << d.pooled_permille << ",\"pattern\":\""
      << pattern_name(o.res.motor.pattern) << "\",\"motor_on\":" << o.res.motor.on
      << ",\"duty_permille\":" << o.res.motor.duty_permille << ",\"hazards\":[";
    for (uint32_t k = 0; k < d.n_hazards && k < NEGOBS_DETECT_MAX_HAZARDS; ++k) {
        s << (k ? "," : "") << hazard_json(d.hazards[k]);
    }
    s << "],\"candidates\":[";
    for (uint32_t k = 0; k < d.n_candidates && k < NEGOBS_DETECT_MAX_HAZARDS; ++k) {
        s << (k ? "," : "") << hazard_json(d.candidates[k]);
    }
    const double npix = static_cast<double>(width) * height;
    s << "],\"stereo\":{\"valid\":" << o.res.stereo.valid << ",\"valid_pct\":"
      << fmt("%.1f", npix > 0 ? 100.0 * o.res.stereo.valid / npix : 0.0)
      << ",\"seeds\":" << o.res.stereo.seeds << ",\"range\":[" << o.res.stereo.range_min
      << "," << o.res.stereo.range_max
      << "],\"vertical_offset\":" << o.res.stereo.vertical_offset
      << ",\"first_row\":" << o.res.stereo.first_row
      << ",\"weak_permille\":" << o.res.weak_permille
      << ",\"coarse\":" << o.res.coarse_ran
      << ",\"coarse_replaced\":" << o.res.coarse_replaced
      << "},\"ground\":{\"valid\":" << d.ground_valid
      << ",\"valid_permille\":" << d.ground_valid_permille
      << ",\"inliers\":" << d.ground_inliers
      << ",\"sigma_px\":" << fmt("%.3f", d.sigma_q4 / 16.0)
      << ",\"height_mm\":" << d.pose.height_mm
      << ",\"pitch_deg\":" << fmt("%.2f", d.pose.pitch_mdeg / 1000.0)
      << "},\"mount\":{\"height_mm\":" << d.mount.height_mm
      << ",\"pitch_mdeg\":" << d.mount.pitch_mdeg
      << ",\"roll_mdeg\":" << d.mount.roll_mdeg << ",\"source\":\""
      << mount_source_name(d.mount.source) << "\"},\"ground_ref\":{\"by\":\""
      << ground_ref_name(d.ground_ref_by) << "\",\"height_mm\":" << d.ground_ref_height_mm
      << ",\"pitch_mdeg\":" << d.ground_ref_pitch_mdeg << "},\"ms\":{";
    if (o.stereo_ms >= 0) {
        s << "\"stereo\":" << fmt("%.2f", o.stereo_ms)
          << ",\"detect\":" << fmt("%.2f", o.detect_ms) << ",";
    }
    s << "\"total\":" << fmt("%.2f", o.total_ms) << "}";
    if (gt != nullptr) {
        s << ",\"gt\":{\"hazard\":\"" << gt->hazard << "\",\"edge_range_mm\":";
        if (gt->has_range) {
            s << fmt("%.0f", gt->edge_range_mm);
        } else {
            s << "null";
        }
        s << ",\"drop_mm\":" << fmt("%.0f", gt->drop_mm)
          << ",\"edge_visible\":" << (gt->edge_visible ? "true" : "false") << "}";
    }
    s << "}";
    return s.str();
}

cv::Mat colour_disparity(const cv::Mat &disp_q4, int max_disp)
{
    cv::Mat grey(disp_q4.size(), CV_8UC1);
    cv::Mat mask(disp_q4.size(), CV_8UC1);
    const double scale = 255.0 / (16.0 * std::max(1, max_disp));
    for (int y = 0; y < disp_q4.rows; ++y) {
        const int16_t *d = disp_q4.ptr<int16_t>(y);
        uint8_t *g = grey.ptr<uint8_t>(y);
        uint8_t *m = mask.ptr<uint8_t>(y);
        for (int x = 0; x < disp_q4.cols; ++x) {
            if (d[x] == NEGOBS_DISP_INVALID || d[x] < 0) {
                g[x] = 0;
                m[x] = 0;
            } else {
                g[x] = cv::saturate_cast<uint8_t>(d[x] * scale);
                m[x] = 255;
            }
        }
    }
    cv::Mat col;
    cv::applyColorMap(grey, col, cv::COLORMAP_JET);
    cv::Mat out(disp_q4.size(), CV_8UC3, cv::Scalar(0, 0, 0));
    col.copyTo(out, mask);
    return out;
}

cv::Mat overlay(const cv::Mat &left, const cv::Mat &disp_q4, int max_disp, int frame,
                const FrameOut &o, const GtFrame *gt, const std::vector<cv::Rect> &labels)
{
    // Small frames are drawn at 2x so labels stay legible.
    const int k = left.cols < 480 ? 2 : 1;
    cv::Mat l3;
    cv::cvtColor(left, l3, cv::COLOR_GRAY2BGR);
    // Scale to the range the matcher actually searched, else everything
    // near the ground is one colour.
    const int dmax = o.res.stereo.range_max >= 8
                         ? std::min(max_disp, o.res.stereo.range_max)
                         : max_disp;
    cv::Mat dc = colour_disparity(disp_q4, dmax);
    if (k != 1) {
        cv::resize(l3, l3, cv::Size(), k, k, cv::INTER_NEAREST);
        cv::resize(dc, dc, cv::Size(), k, k, cv::INTER_NEAREST);
    }
    const double fs = 0.45;
    const int font = cv::FONT_HERSHEY_SIMPLEX;
    for (const cv::Rect &r : labels) {
        cv::rectangle(l3, cv::Rect(r.x * k, r.y * k, r.width * k, r.height * k),
                      cv::Scalar(255, 255, 0), 1);
    }
    if (gt != nullptr && gt->has_box) {
        cv::line(l3,
                 cv::Point(static_cast<int>(gt->box[0] * k),
                           static_cast<int>((gt->box[1] + 0.5) * k)),
                 cv::Point(static_cast<int>(gt->box[2] * k),
                           static_cast<int>((gt->box[3] + 0.5) * k)),
                 cv::Scalar(0, 200, 0), 1);
    }
    const negobs_detect_result_t &d = o.res.detect;
    for (uint32_t i = 0; i < d.n_candidates && i < NEGOBS_DETECT_MAX_HAZARDS; ++i) {
        const negobs_hazard_t &h = d.candidates[i];
        cv::rectangle(l3, cv::Point(h.u0 * k, h.v0 * k),
                      cv::Point(h.u1 * k + k - 1, h.v1 * k + k - 1),
                      cv::Scalar(0, 220, 255), 1);
    }
    for (uint32_t i = 0; i < d.n_hazards && i < NEGOBS_DETECT_MAX_HAZARDS; ++i) {
        const negobs_hazard_t &h = d.hazards[i];
        const cv::Scalar c = h.level == NEGOBS_LEVEL_IMMINENT ? cv::Scalar(0, 0, 255)
                                                              : cv::Scalar(0, 128, 255);
        cv::rectangle(l3, cv::Point(h.u0 * k, h.v0 * k),
                      cv::Point(h.u1 * k + k - 1, h.v1 * k + k - 1), c, 2);
        char txt[96];
        std::snprintf(txt, sizeof txt, "%s %.2fm %dcm%s", type_name(h.type),
                      h.range_mm / 1000.0, (h.drop_mm + 5) / 10,
                      (h.flags & NEGOBS_HAZARD_F_HELD) ? " held" : "");
        int base = 0;
        cv::Size ts = cv::getTextSize(txt, font, fs, 1, &base);
        int ty = h.v0 * k - 4;
        if (ty - ts.height < 0) {
            ty = h.v1 * k + ts.height + 4;
        }
        const int tx = std::max(0, std::min(h.u0 * k, l3.cols - ts.width));
        cv::rectangle(l3, cv::Point(tx, ty - ts.height - 2),
                      cv::Point(tx + ts.width, ty + 2), cv::Scalar(0, 0, 0), cv::FILLED);
        cv::putText(l3, txt, cv::Point(tx, ty), font, fs, c, 1, cv::LINE_AA);
    }
    // the disparity panel's scale (JET over 0..dmax px, black = no value)
    cv::Mat top;
    cv::hconcat(l3, negobs_cli::with_colour_bar(dc, cv::COLORMAP_JET, 0, dmax, "px"),
                top);
    const int bar_h = 40;
    cv::Mat bar(bar_h, top.cols, CV_8UC3, cv::Scalar(40, 40, 40));
    cv::Scalar sc = d.state == NEGOBS_DETECT_HAZARD    ? cv::Scalar(0, 128, 255)
                    : d.state == NEGOBS_DETECT_NO_INFO ? cv::Scalar(200, 200, 200)
                                                       : cv::Scalar(0, 220, 0);
    char l1[256], l2[256];
    std::string rs = reasons_string(d.reasons, "|");
    std::snprintf(l1, sizeof l1, "#%d %s  level %s  pattern %s  motor %s%s%s", frame,
                  state_name(d.state), level_name(d.level),
                  pattern_name(o.res.motor.pattern), o.res.motor.on ? "ON" : "off",
                  rs.empty() ? "" : "  reasons ", rs.c_str());
    std::string gts;
    if (gt != nullptr && gt->has_range) {
        gts = "  GT " + gt->hazard + " " + fmt("%.2fm", gt->edge_range_mm / 1000) +
              " drop " + fmt("%.0fmm", gt->drop_mm);
    }
    std::snprintf(l2, sizeof l2,
                  "valid %.0f%%  seeds %u  sigma %.2fpx  mount %.2fm %.1fdeg %s  "
                  "stereo %.1fms detect %.1fms%s",
                  100.0 * o.res.stereo.valid / std::max(1, left.cols * left.rows),
                  o.res.stereo.seeds, d.sigma_q4 / 16.0, d.mount.height_mm / 1000.0,
                  d.mount.pitch_mdeg / 1000.0, mount_source_name(d.mount.source),
                  o.stereo_ms, o.detect_ms, gts.c_str());
    cv::putText(bar, l1, cv::Point(6, 16), font, fs, sc, 1, cv::LINE_AA);
    cv::putText(bar, l2, cv::Point(6, 34), font, fs, cv::Scalar(220, 220, 220), 1,
                cv::LINE_AA);
    cv::Mat out;
    cv::vconcat(top, bar, out);
    return out;
}

namespace {

bool bin_plan(int k, int eye_w, int eye_h, negobs_bin_plan_t &plan)
{
    return k >= 1 &&
           negobs_bin_plan(eye_w, eye_h, eye_w / k, eye_h / k, &plan) == NEGOBS_OK &&
           plan.k == k;
}

} // namespace

bool bin_pair(int k, cv::Mat &left, cv::Mat &right, std::string &err)
{
    if (k == 1) {
        return true;
    }
    negobs_bin_plan_t plan;
    if (left.size() != right.size() || left.type() != CV_8UC1 ||
        right.type() != CV_8UC1 || !bin_plan(k, left.cols, left.rows, plan)) {
        err = "cannot bin a " + std::to_string(left.cols) + "x" +
              std::to_string(left.rows) + " pair by " + std::to_string(k);
        return false;
    }
    for (cv::Mat *m : {&left, &right}) {
        cv::Mat src = m->isContinuous() ? *m : m->clone();
        cv::Mat dst(plan.out_h, plan.out_w, CV_8UC1);
        negobs_bin_u8(src.data, src.step, 1, &plan, dst.data, dst.step);
        *m = dst;
    }
    return true;
}

void bin_camera(int k, int eye_w, int eye_h, CamParams &cam)
{
    negobs_bin_plan_t plan;
    if (k == 1 || !bin_plan(k, eye_w, eye_h, plan)) {
        return;
    }
    int32_t f_q4 = static_cast<int32_t>(std::lround(cam.f * 16.0));
    int32_t cx_q4 = cam.cx < 0 ? -1 : static_cast<int32_t>(std::lround(cam.cx * 16.0));
    int32_t cy_q4 = cam.cy < 0 ? -1 : static_cast<int32_t>(std::lround(cam.cy * 16.0));
    negobs_bin_intrinsics_q4(&plan, &f_q4, &cx_q4, &cy_q4);
    cam.f = f_q4 / 16.0;
    cam.cx = cam.cx < 0 ? -1.0 : cx_q4 / 16.0;
    cam.cy = cam.cy < 0 ? -1.0 : cy_q4 / 16.0;
}

} // namespace negobs_detect_tools
