#include "stereo_common.hpp"

#include <cstdio>
#include <cstring>
#include <ctime>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

extern "C" {
#include "negobs/negobs.h"
#include "negobs/stereo.h"
#include "negobs_port/pool.h"
}

namespace negobs_tools {

bool load_grey(const std::string &path, cv::Mat &grey, std::string &err)
{
    cv::Mat img;
    try {
        img = cv::imread(path, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception &e) {
        err = "cannot decode '" + path + "': " + e.what();
        return false;
    }
    if (img.empty()) {
        err = "cannot read '" + path +
              "' (missing, unreadable or not an "
              "image format OpenCV decodes)";
        return false;
    }
    if (img.depth() == CV_16U) {
        img.convertTo(img, CV_8U, 1.0 / 257.0);
    } else if (img.depth() != CV_8U) {
        err = "'" + path + "': unsupported pixel type (need 8 or 16 bit)";
        return false;
    }
    switch (img.channels()) {
    case 1: grey = img; break;
    case 3: cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY); break;
    case 4: cv::cvtColor(img, grey, cv::COLOR_BGRA2GRAY); break;
    default: err = "'" + path + "': unsupported channel count"; return false;
    }
    if (!grey.isContinuous())
        grey = grey.clone();
    return true;
}

std::string check_range(const Range &r, int width)
{
    if (r.min_disp < 0)
        return "--min-disp must be >= 0 (got " + std::to_string(r.min_disp) +
               ")";
    if (r.max_disp <= r.min_disp)
        return "--max-disp (" + std::to_string(r.max_disp) +
               ") must be larger than --min-disp (" +
               std::to_string(r.min_disp) + ")";
    if (r.max_disp > kMaxDispLimit)
        return "--max-disp must be <= " + std::to_string(kMaxDispLimit) +
               " (disparity * 16 is stored in 16 bits)";
    if (width > 0 && r.max_disp >= width)
        return "--max-disp (" + std::to_string(r.max_disp) +
               ") must be smaller than the image width (" +
               std::to_string(width) + ")";
    return std::string();
}

std::string check_engine_limits(const Range &r, int width, int height)
{
#ifdef NEGOBS_STEREO_MAX_RANGE
    if (r.max_disp - r.min_disp + 1 > NEGOBS_STEREO_MAX_RANGE)
        return "the range " + std::to_string(r.min_disp) + ".." +
               std::to_string(r.max_disp) + " spans more than " +
               std::to_string(NEGOBS_STEREO_MAX_RANGE) +
               " disparities (engine limit)";
#else
    (void)r;
#endif
#if defined(NEGOBS_STEREO_MIN_WIDTH) && defined(NEGOBS_STEREO_MIN_HEIGHT)
    if (width < NEGOBS_STEREO_MIN_WIDTH || height < NEGOBS_STEREO_MIN_HEIGHT)
        return std::to_string(width) + "x" + std::to_string(height) +
               " is smaller than the engine's minimum " +
               std::to_string(NEGOBS_STEREO_MIN_WIDTH) + "x" +
               std::to_string(NEGOBS_STEREO_MIN_HEIGHT);
#else
    (void)width;
    (void)height;
#endif
    if (width > NEGOBS_MAX_DIM || height > NEGOBS_MAX_DIM)
        return std::to_string(width) + "x" + std::to_string(height) +
               " is larger than " + std::to_string(NEGOBS_MAX_DIM) + "x" +
               std::to_string(NEGOBS_MAX_DIM);
    return std::string();
}

int opencv_num_disparities(const Range &r)
{
    const int n = r.max_disp - r.min_disp + 1;
    return (n + 15) / 16 * 16;
}

struct NegobsMatcher::Impl {
    negobs_stereo_t ctx;
    std::vector<unsigned char> raw; // over-allocated, aligned inside
    void *ws = nullptr;
    int width = 0;
    int height = 0;
    std::vector<NegobsMatcher::Snapshot> snaps;
    negobs_pool_t *pool = nullptr;
    ~Impl() { negobs_pool_destroy(pool); }
};

NegobsMatcher::NegobsMatcher() = default;
NegobsMatcher::~NegobsMatcher() = default;

static std::string status_text(const char *what, negobs_status_t st)
{
    const char *s = negobs_status_str(st);
    return std::string(what) + " failed: status " + std::to_string(int(st)) +
           (s && *s ? std::string(" (") + s + ")" : std::string());
}

bool NegobsMatcher::init(int width, int height, const Range &r,
                         std::string &err, int gap_fill, int keep_out_of_view)
{
    impl_.reset(new Impl());
    std::memset(&impl_->ctx, 0, sizeof impl_->ctx);
    negobs_stereo_config_t cfg;
    std::memset(&cfg, 0, sizeof cfg);
    negobs_stereo_config_default(&cfg, width, height);
    cfg.min_disp = r.min_disp;
    cfg.max_disp = r.max_disp;
    if (gap_fill >= 0) {
        cfg.gap_fill = gap_fill;
    }
    if (keep_out_of_view >= 0) {
        cfg.keep_out_of_view = keep_out_of_view;
    }
    cfg.band_workers = threads_;
    cfg.subpixel_halfshift = halfshift_ ? 1 : 0;
    size_t bytes = 0;
    negobs_status_t st = negobs_stereo_workspace_size(&cfg, &bytes);
    if (st != NEGOBS_OK) {
        err = status_text("negobs_stereo_workspace_size", st);
        impl_.reset();
        return false;
    }
    impl_->raw.assign(bytes + 16, 0);
    void *p = impl_->raw.data();
    size_t space = impl_->raw.size();
    impl_->ws = std::align(16, bytes, p, space);
    st = negobs_stereo_init(&impl_->ctx, &cfg, impl_->ws, bytes);
    if (st != NEGOBS_OK) {
        err = status_text("negobs_stereo_init", st);
        impl_.reset();
        return false;
    }
    if (threads_ > 1) {
        st = negobs_pool_create(&impl_->pool, threads_);
        negobs_executor_t e = negobs_pool_executor(impl_->pool);
        if (st == NEGOBS_OK) {
            st = negobs_stereo_set_executor(&impl_->ctx, &e);
        }
        if (st != NEGOBS_OK) {
            err = status_text("thread pool", st);
            impl_.reset();
            return false;
        }
    }
    impl_->width = width;
    impl_->height = height;
    bytes_ = bytes;
    return true;
}

// Thread CPU time in ns modulo 2^32 (the engine takes differences).
static uint32_t thread_clock_ns(void *)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<uint32_t>(static_cast<uint64_t>(ts.tv_sec) *
                                     1000000000u +
                                 static_cast<uint64_t>(ts.tv_nsec));
}

void NegobsMatcher::profile_stages(bool on)
{
    profile_ = on;
    if (impl_)
        (void)negobs_stereo_set_clock(&impl_->ctx,
                                      on ? thread_clock_ns : nullptr, nullptr);
}

// negobs_stereo_observer_fn: user is the matcher's Impl.
static void observe_stage(void *user, negobs_stereo_stage_t stage,
                          const negobs_image_s16_t *disp)
{
    static const char *const names[NEGOBS_STEREO_STAGE_COUNT] = {
        "vertical", "range",    "windows",  "Canny",    "GCS (seeds + growth)",
        "DP",       "LR check", "speckles", "gap fill", "adaptive mean",
        "output"};
    auto *impl = static_cast<NegobsMatcher::Impl *>(user);
    // the view may be a crop of the frame's lower rows: place it
    cv::Mat m(impl->height, impl->width, CV_16SC1,
              cv::Scalar(NEGOBS_DISP_INVALID));
    const int top = impl->height - disp->height;
    for (int y = 0; y < disp->height; ++y) {
        const int16_t *src = negobs_image_s16_row(disp, y);
        int16_t *dst = m.ptr<int16_t>(top + y);
        for (int x = 0; x < disp->width; ++x) {
            const int16_t v = src[x];
            dst[x] = (stage == NEGOBS_STEREO_STAGE_GCS &&
                      v != NEGOBS_DISP_INVALID)
                         ? static_cast<int16_t>(v * NEGOBS_DISP_ONE)
                         : v;
        }
    }
    impl->snaps.push_back(NegobsMatcher::Snapshot{names[stage], m});
}

void NegobsMatcher::keep_stages(bool on)
{
    if (impl_)
        (void)negobs_stereo_set_observer(
            &impl_->ctx, on ? observe_stage : nullptr, impl_.get());
}

const std::vector<NegobsMatcher::Snapshot> &NegobsMatcher::stages() const
{
    static const std::vector<Snapshot> none;
    return impl_ ? impl_->snaps : none;
}

bool NegobsMatcher::process(const cv::Mat &left, const cv::Mat &right,
                            cv::Mat &disp_q4, cv::Mat &confidence,
                            std::string &err)
{
    if (!impl_) {
        err = "negobs matcher not initialised";
        return false;
    }
    if (left.type() != CV_8UC1 || right.type() != CV_8UC1 ||
        left.cols != impl_->width || left.rows != impl_->height ||
        right.size() != left.size()) {
        err = "negobs matcher: inputs must be 8-bit grey of the configured "
              "size";
        return false;
    }
    disp_q4.create(left.size(), CV_16SC1);
    confidence.create(left.size(), CV_8UC1);
    negobs_image_u8_t l, rr, c;
    l.data = const_cast<uint8_t *>(left.ptr<uint8_t>(0));
    l.width = left.cols;
    l.height = left.rows;
    l.stride = static_cast<int32_t>(left.step1());
    rr.data = const_cast<uint8_t *>(right.ptr<uint8_t>(0));
    rr.width = right.cols;
    rr.height = right.rows;
    rr.stride = static_cast<int32_t>(right.step1());
    c.data = confidence.ptr<uint8_t>(0);
    c.width = confidence.cols;
    c.height = confidence.rows;
    c.stride = static_cast<int32_t>(confidence.step1());
    negobs_image_s16_t d;
    d.data = disp_q4.ptr<int16_t>(0);
    d.width = disp_q4.cols;
    d.height = disp_q4.rows;
    d.stride = static_cast<int32_t>(disp_q4.step1());
    impl_->snaps.clear();
    negobs_stereo_stats_t stats;
    std::memset(&stats, 0, sizeof stats);
    negobs_status_t st = negobs_stereo_process(&impl_->ctx, &l, &rr, &d, &c,
                                               &stats);
    if (st != NEGOBS_OK) {
        err = status_text("negobs_stereo_process", st);
        return false;
    }
    stats_text_ = "seeds " + std::to_string(stats.seeds) + ", queue peak " +
                  std::to_string(stats.queue_peak) + ", queue overflows " +
                  std::to_string(stats.queue_overflows) + ", visited cells " +
                  std::to_string(stats.visited_cells) + ", band " +
                  std::to_string(stats.band);
#ifdef NEGOBS_STEREO_MAX_RANGE // header generation with the extended stats
    stats_text_ += ", edges " + std::to_string(stats.edges) + ", grown " +
                   std::to_string(stats.grown) + ", valid " +
                   std::to_string(stats.valid) + ", range used " +
                   std::to_string(stats.range_min) + ".." +
                   std::to_string(stats.range_max) + ", vertical offset " +
                   std::to_string(stats.vertical_offset);
#endif
    if (profile_) {
        static const char *const names[NEGOBS_STEREO_STAGE_COUNT] = {
            "vertical", "range",   "windows",  "canny", "gcs",   "dp",
            "lr",       "speckle", "gap_fill", "mean",  "output"};
        char buf[64];
        stats_text_ += "; stage ms:";
        for (int k = 0; k < NEGOBS_STEREO_STAGE_COUNT; ++k) {
            std::snprintf(buf, sizeof buf, " %s %.2f", names[k],
                          static_cast<double>(stats.stage_ticks[k]) / 1e6);
            stats_text_ += buf;
        }
    }
    return true;
}

cv::Mat negobs_q4_to_png16(const cv::Mat &disp_q4)
{
    CV_Assert(disp_q4.type() == CV_16SC1);
    cv::Mat out(disp_q4.size(), CV_16UC1);
    for (int y = 0; y < disp_q4.rows; ++y) {
        const int16_t *s = disp_q4.ptr<int16_t>(y);
        uint16_t *o = out.ptr<uint16_t>(y);
        for (int x = 0; x < disp_q4.cols; ++x)
            o[x] = s[x] > 0 ? static_cast<uint16_t>(s[x]) : uint16_t(0);
    }
    return out;
}

void negobs_q4_to_float(const cv::Mat &disp_q4, cv::Mat &disp, cv::Mat &valid)
{
    CV_Assert(disp_q4.type() == CV_16SC1);
    disp.create(disp_q4.size(), CV_32FC1);
    valid.create(disp_q4.size(), CV_8UC1);
    for (int y = 0; y < disp_q4.rows; ++y) {
        const int16_t *s = disp_q4.ptr<int16_t>(y);
        float *d = disp.ptr<float>(y);
        uint8_t *v = valid.ptr<uint8_t>(y);
        for (int x = 0; x < disp_q4.cols; ++x) {
            const bool ok = s[x] != INT16_MIN;
            d[x] = ok ? static_cast<float>(s[x]) / 16.0f : 0.0f;
            v[x] = ok ? 255 : 0;
        }
    }
}

void opencv_q4_to_float(const cv::Mat &disp16, int min_disp, cv::Mat &disp,
                        cv::Mat &valid)
{
    CV_Assert(disp16.type() == CV_16SC1);
    disp.create(disp16.size(), CV_32FC1);
    valid.create(disp16.size(), CV_8UC1);
    const int lo = min_disp * 16;
    for (int y = 0; y < disp16.rows; ++y) {
        const int16_t *s = disp16.ptr<int16_t>(y);
        float *d = disp.ptr<float>(y);
        uint8_t *v = valid.ptr<uint8_t>(y);
        for (int x = 0; x < disp16.cols; ++x) {
            const bool ok = s[x] >= lo;
            d[x] = ok ? static_cast<float>(s[x]) / 16.0f : 0.0f;
            v[x] = ok ? 255 : 0;
        }
    }
}

cv::Mat colourise(const cv::Mat &disp, const cv::Mat &valid, double lo,
                  double hi)
{
    CV_Assert(disp.type() == CV_32FC1 && valid.type() == CV_8UC1);
    const double span = hi > lo ? hi - lo : 1.0;
    cv::Mat grey;
    disp.convertTo(grey, CV_8U, 255.0 / span, -lo * 255.0 / span);
    cv::Mat colour;
    cv::applyColorMap(grey, colour, cv::COLORMAP_TURBO);
    colour.setTo(cv::Scalar::all(0), valid == 0);
    return colour;
}

} // namespace negobs_tools
