#include "occlusion.hpp"

#include <cmath>
#include <sys/stat.h>

namespace negobs_tools {

cv::Mat nonocc_from_right_gt(const cv::Mat &gt_left, const cv::Mat &known_left,
                             const cv::Mat &gt_right,
                             const cv::Mat &known_right, double tol_px)
{
    if (gt_left.empty() || gt_left.type() != CV_32F ||
        gt_right.type() != CV_32F || known_left.type() != CV_8U ||
        known_right.type() != CV_8U || gt_right.size() != gt_left.size() ||
        known_left.size() != gt_left.size() ||
        known_right.size() != gt_left.size() || !(tol_px >= 0.0)) {
        return cv::Mat();
    }
    cv::Mat out(gt_left.size(), CV_8U, cv::Scalar(0));
    for (int y = 0; y < gt_left.rows; ++y) {
        const float *dl = gt_left.ptr<float>(y);
        const uint8_t *kl = known_left.ptr<uint8_t>(y);
        const float *dr = gt_right.ptr<float>(y);
        const uint8_t *kr = known_right.ptr<uint8_t>(y);
        uint8_t *o = out.ptr<uint8_t>(y);
        for (int x = 0; x < gt_left.cols; ++x) {
            if (!kl[x] || !std::isfinite(dl[x])) {
                continue;
            }
            const double xr = std::floor(double(x) - double(dl[x]) + 0.5);
            if (xr < 0.0 || xr >= double(gt_left.cols)) {
                continue; // the left border strip: no right pixel at all
            }
            const int c = static_cast<int>(xr);
            if (kr[c] && std::fabs(double(dr[c]) - double(dl[x])) <= tol_px) {
                o[x] = 255;
            }
        }
    }
    return out;
}

namespace {

struct Name {
    std::string dir, stem, ext;
};

Name split_name(const std::string &p)
{
    Name n;
    const size_t slash = p.find_last_of('/');
    n.dir = (slash == std::string::npos) ? std::string()
                                         : p.substr(0, slash + 1);
    const std::string base = (slash == std::string::npos)
                                 ? p
                                 : p.substr(slash + 1);
    const size_t dot = base.find_last_of('.');
    n.stem = (dot == std::string::npos) ? base : base.substr(0, dot);
    n.ext = (dot == std::string::npos) ? std::string() : base.substr(dot);
    return n;
}

// The run of digits that ends the stem ("view1" -> "1"); "" if none.
std::string trailing_digits(const std::string &stem)
{
    size_t i = stem.size();
    while (i > 0 && stem[i - 1] >= '0' && stem[i - 1] <= '9') {
        --i;
    }
    return stem.substr(i);
}

bool is_file(const std::string &p)
{
    struct stat st;
    return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

} // namespace

std::string right_gt_path(const std::string &left_image,
                          const std::string &right_image,
                          const std::string &gt_left)
{
    const std::string nl = trailing_digits(split_name(left_image).stem);
    const std::string nr = trailing_digits(split_name(right_image).stem);
    const Name g = split_name(gt_left);
    if (nl.empty() || nr.empty() || nl == nr || g.stem.size() <= nl.size() ||
        trailing_digits(g.stem) != nl) {
        return std::string();
    }
    const std::string stem = g.stem.substr(0, g.stem.size() - nl.size()) + nr;
    for (const std::string &ext :
         {g.ext, std::string(".png"), std::string(".pgm")}) {
        const std::string p = g.dir + stem + ext;
        if (is_file(p)) {
            return p;
        }
    }
    return std::string();
}

} // namespace negobs_tools
