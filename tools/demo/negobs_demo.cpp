// negobs_demo: the default job of `tools/negobs demo`, no hardware needed.
//
// Runs what the library computes today on Debian's opencv-doc stereo pair
// (aloeL/aloeR) and says plainly which pipeline stages are not wired yet.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

extern "C" {
#include "negobs/negobs.h"
}

namespace {

struct Options {
    std::string out = "build/demo";
    std::string data;
    std::string opencv_doc = "/usr/share/doc/opencv-doc/examples/data";
};

int usage(const char *argv0, int code)
{
    std::fprintf(code ? stderr : stdout,
                 "usage: %s [--out DIR] [--data DIR] [--opencv-doc DIR]\n",
                 argv0);
    return code;
}

// Fraction of pixels whose 5x5 window has enough contrast to be matched:
// the same box sums feed the matcher's NCC and the "too little texture"
// no-information cue.
struct Texture {
    double textured_fraction = 0.0;
    cv::Mat stddev_map; // 8-bit, window standard deviation (grey levels)
};

bool texture_of(const cv::Mat &grey, Texture &t)
{
    const int w = grey.cols;
    const int h = grey.rows;
    std::vector<uint16_t> sum(static_cast<size_t>(w) * static_cast<size_t>(h));
    std::vector<uint32_t> sumsq(sum.size());
    std::vector<uint32_t> col(2 * static_cast<size_t>(w));
    negobs_image_u8_t img;
    img.data = const_cast<uint8_t *>(grey.ptr<uint8_t>(0));
    img.width = w;
    img.height = h;
    img.stride = static_cast<int32_t>(grey.step1());
    negobs_status_t st = negobs_boxsum_u8(&img, 2, sum.data(), w, sumsq.data(),
                                          w, col.data());
    if (st != NEGOBS_OK) {
        std::fprintf(stderr, "negobs_boxsum_u8: %s\n", negobs_status_str(st));
        return false;
    }
    t.stddev_map = cv::Mat::zeros(h, w, CV_8UC1);
    size_t textured = 0;
    size_t total = 0;
    for (int y = 2; y < h - 2; y++) {
        for (int x = 2; x < w - 2; x++) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(w) +
                             static_cast<size_t>(x);
            // 25^2 * variance = 25 * Q - S^2, exact in 32 bits.
            const uint32_t s = sum[i];
            const uint32_t v25 = 25u * sumsq[i] - s * s;
            const uint32_t sd = negobs_isqrt_u32(v25) / 25u;
            t.stddev_map.at<uint8_t>(y, x) =
                static_cast<uint8_t>(sd > 63u ? 255u : sd * 4u);
            total++;
            if (sd >= 4u) {
                textured++;
            }
        }
    }
    t.textured_fraction =
        total ? static_cast<double>(textured) / static_cast<double>(total) : 0.0;
    return true;
}

} // namespace

int main(int argc, char **argv)
{
    Options o;
    for (int i = 1; i < argc; i++) {
        const std::string a = argv[i];
        if ((a == "--out" || a == "--data" || a == "--opencv-doc") &&
            i + 1 < argc) {
            const std::string v = argv[++i];
            if (a == "--out") o.out = v;
            else if (a == "--data") o.data = v;
            else o.opencv_doc = v;
        } else if (a == "-h" || a == "--help") {
            return usage(argv[0], 0);
        } else {
            std::fprintf(stderr, "negobs_demo: unknown argument '%s'\n",
                         a.c_str());
            return usage(argv[0], 2);
        }
    }
    const std::string left_path = o.opencv_doc + "/aloeL.jpg";
    const std::string right_path = o.opencv_doc + "/aloeR.jpg";
    cv::Mat left = cv::imread(left_path, cv::IMREAD_GRAYSCALE);
    cv::Mat right = cv::imread(right_path, cv::IMREAD_GRAYSCALE);
    if (left.empty() || right.empty()) {
        std::fprintf(stderr,
                     "negobs_demo: cannot read %s / %s (install opencv-doc)\n",
                     left_path.c_str(), right_path.c_str());
        return 1;
    }
    std::printf("negobs %s demo on %s (%dx%d)\n", negobs_version(),
                left_path.c_str(), left.cols, left.rows);
    Texture tl;
    Texture tr;
    if (!texture_of(left, tl) || !texture_of(right, tr)) {
        return 1;
    }
    std::printf("  5x5 window texture (std dev >= 4 grey levels): left %.1f %%,"
                " right %.1f %% of pixels\n",
                100.0 * tl.textured_fraction, 100.0 * tr.textured_fraction);
    const std::string out_png = o.out + "/texture_left.png";
    if (!cv::imwrite(out_png, tl.stddev_map)) {
        std::fprintf(stderr, "negobs_demo: cannot write %s\n", out_png.c_str());
        return 1;
    }
    std::printf("  wrote %s\n", out_png.c_str());
    std::printf("  not wired yet: disparity, detection and alerting "
                "(no obstacle result is shown)\n");
    return 0;
}
