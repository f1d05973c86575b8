// Round trips of the disparity file formats (disp_io.hpp).
//   test_disp_io unit                 the writers and readers on a map
//                                     made here (no other input)
//   test_disp_io aloe STEREO AL AR DIR negobs_stereo on opencv-doc's aloe
//                                     pair in every --format, read back
//                                     with OpenCV and the own reader and
//                                     compared with the png16 map
// Exit 0 pass, 1 fail, 77 skipped (aloe pair absent).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>
#include <sys/stat.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "disp_io.hpp"

using negobs_cli::DispFormat;

namespace {

int failures = 0;

void check(bool ok, const std::string &what)
{
    std::printf("%s - %s\n", ok ? "ok" : "FAIL", what.c_str());
    if (!ok) {
        ++failures;
    }
}

// A map whose rows all differ, so a flipped or shifted raster shows.
void make_map(cv::Mat &d, cv::Mat &v)
{
    d.create(37, 53, CV_32F);
    v.create(d.size(), CV_8U);
    for (int y = 0; y < d.rows; ++y) {
        for (int x = 0; x < d.cols; ++x) {
            d.at<float>(y, x) = static_cast<float>(y * 3 + x % 7) +
                                0.0625f * (x % 16);
            v.at<uint8_t>(y, x) = (x * 7 + y * 3) % 11 == 0 ? 0 : 255;
        }
    }
}

bool same(const cv::Mat &d0, const cv::Mat &v0, const cv::Mat &d1,
          const cv::Mat &v1, double tol)
{
    if (d0.size() != d1.size() || v0.size() != v1.size()) {
        return false;
    }
    for (int y = 0; y < d0.rows; ++y) {
        for (int x = 0; x < d0.cols; ++x) {
            const bool a = v0.at<uint8_t>(y, x) != 0,
                       b = v1.at<uint8_t>(y, x) != 0;
            if (a != b) {
                return false;
            }
            if (a &&
                std::fabs(d0.at<float>(y, x) - d1.at<float>(y, x)) > tol) {
                return false;
            }
        }
    }
    return true;
}

int unit(const std::string &dir)
{
    cv::Mat d, v;
    make_map(d, v);
    std::string err;
    const struct {
        DispFormat f;
        const char *name;
        double tol; // the format's step
    } cases[] = {{DispFormat::Png16, "m16.png", 1.0 / 32},
                 {DispFormat::Kitti, "mk.png", 1.0 / 512},
                 {DispFormat::Pfm, "m.pfm", 0.0}};
    for (const auto &c : cases) {
        const std::string p = dir + "/" + c.name;
        cv::Mat d1, v1;
        const bool w = negobs_cli::write_disparity(p, d, v, c.f, err);
        const bool r = w && negobs_cli::read_disparity(p, c.f, 0, d1, v1, err);
        check(w && r && same(d, v, d1, v1, c.tol),
              std::string(negobs_cli::disp_format_name(c.f)) +
                  " write/read round trip " + err);
    }
    // the PNG formats hold what their scale says: a KITTI value of 1 px is 256
    cv::Mat raw = cv::imread(dir + "/mk.png", cv::IMREAD_UNCHANGED);
    check(raw.type() == CV_16UC1 &&
              raw.at<uint16_t>(1, 1) == std::lround(d.at<float>(1, 1) * 256),
          "kitti stores disparity x 256 in a 16-bit PNG");
    raw = cv::imread(dir + "/m16.png", cv::IMREAD_UNCHANGED);
    check(raw.type() == CV_16UC1 &&
              raw.at<uint16_t>(1, 1) == std::lround(d.at<float>(1, 1) * 16),
          "png16 stores disparity x 16 in a 16-bit PNG");
    // OpenCV's own PFM reader agrees with ours: orientation and byte order
    cv::Mat cvp = cv::imread(dir + "/m.pfm", cv::IMREAD_UNCHANGED);
    bool agree = cvp.type() == CV_32FC1 && cvp.size() == d.size();
    for (int y = 0; agree && y < d.rows; ++y) {
        for (int x = 0; x < d.cols; ++x) {
            const float c = cvp.at<float>(y, x);
            agree = agree && (v.at<uint8_t>(y, x) ? c == d.at<float>(y, x)
                                                  : std::isinf(c));
        }
    }
    check(
        agree,
        "OpenCV reads our PFM with the same rows and values (inf = no value)");
    // a big-endian file (scale +1), written by hand, top row first in the map
    {
        std::ofstream o(dir + "/be.pfm", std::ios::binary);
        o << "Pf\n2 2\n1.0\n";
        const unsigned char rows[16] = {
            0x40, 0x40, 0, 0, 0x40, 0x80, 0, 0,  // 3, 4 (bottom)
            0x3f, 0x80, 0, 0, 0x40, 0,    0, 0}; // 1, 2 (top)
        o.write(reinterpret_cast<const char *>(rows), 16);
    }
    cv::Mat be;
    check(negobs_cli::read_pfm(dir + "/be.pfm", be, err) &&
              be.at<float>(0, 0) == 1.f && be.at<float>(0, 1) == 2.f &&
              be.at<float>(1, 0) == 3.f && be.at<float>(1, 1) == 4.f,
          "big-endian PFM (scale > 0) read with the last stored row on top");
    // damaged files are refused with a message, not read past their end
    {
        std::ofstream o(dir + "/short.pfm", std::ios::binary);
        o << "Pf\n4 4\n-1\n" << std::string(20, '\0');
    }
    err.clear();
    const bool short_refused = !negobs_cli::read_pfm(dir + "/short.pfm", be,
                                                     err);
    check(short_refused && err.find("shorter") != std::string::npos,
          "a short PFM raster is an error: " + err);
    {
        std::ofstream o(dir + "/bad.pfm", std::ios::binary);
        o << "P6\n4 4\n255\n";
    }
    check(!negobs_cli::read_pfm(dir + "/bad.pfm", be, err),
          "a non-PFM header is refused");
    // a value KITTI cannot hold is an error, not a silent clip
    cv::Mat big(2, 2, CV_32F, cv::Scalar(300.f)),
        bv(2, 2, CV_8U, cv::Scalar(255));
    err.clear();
    const bool big_refused = !negobs_cli::write_disparity(
        dir + "/big.png", big, bv, DispFormat::Kitti, err);
    check(big_refused && err.find("does not fit") != std::string::npos,
          "kitti refuses 300 px: " + err);
    // a tiny positive disparity must not turn into the "no value" marker
    cv::Mat tiny(1, 1, CV_32F, cv::Scalar(0.01f)),
        tv(1, 1, CV_8U, cv::Scalar(255)), d1, v1;
    check(negobs_cli::write_disparity(dir + "/tiny.png", tiny, tv,
                                      DispFormat::Png16, err) &&
              negobs_cli::read_disparity(dir + "/tiny.png", DispFormat::Png16,
                                         0, d1, v1, err) &&
              v1.at<uint8_t>(0, 0) != 0,
          "0.01 px stays a value in png16");
    return failures ? 1 : 0;
}

int run_stereo(const std::string &exe, const std::string &l,
               const std::string &r, const std::string &out, const char *fmt)
{
    const std::string cmd = "'" + exe + "' '" + l + "' '" + r + "' '" + out +
                            "' --max-disp 211 --format=" + fmt;
    return std::system(cmd.c_str());
}

int aloe(const std::string &exe, const std::string &l, const std::string &r,
         const std::string &dir)
{
    struct stat st;
    if (::stat(l.c_str(), &st) != 0 || ::stat(r.c_str(), &st) != 0) {
        std::printf("skipped: aloe pair absent (apt install opencv-doc)\n");
        return 77;
    }
    const std::string p16 = dir + "/aloe16.png", pk = dir + "/aloek.png",
                      pf = dir + "/aloe.pfm";
    check(run_stereo(exe, l, r, p16, "png16") == 0,
          "negobs_stereo --format=png16");
    check(run_stereo(exe, l, r, pk, "kitti") == 0,
          "negobs_stereo --format=kitti");
    check(run_stereo(exe, l, r, pf, "pfm") == 0, "negobs_stereo --format=pfm");
    if (failures) {
        return 1;
    }
    const cv::Mat ref = cv::imread(p16, cv::IMREAD_UNCHANGED);
    const cv::Mat k = cv::imread(pk, cv::IMREAD_UNCHANGED);
    const cv::Mat fo = cv::imread(pf, cv::IMREAD_UNCHANGED);
    cv::Mat fown;
    std::string err;
    const bool own = negobs_cli::read_pfm(pf, fown, err);
    check(ref.type() == CV_16UC1 && k.type() == CV_16UC1 &&
              fo.type() == CV_32FC1 && own && ref.size() == k.size() &&
              ref.size() == fo.size() && ref.size() == fown.size(),
          "all three maps read back (OpenCV and own PFM reader), same size");
    if (failures) {
        return 1;
    }
    long n_val = 0, bad_k = 0, bad_f = 0, bad_own = 0;
    for (int y = 0; y < ref.rows; ++y) {
        for (int x = 0; x < ref.cols; ++x) {
            const uint16_t q = ref.at<uint16_t>(y, x);
            const double d = q / 16.0;
            n_val += q != 0;
            // the Q4 engine output is exact in all three: x256 = q x 16
            bad_k += k.at<uint16_t>(y, x) != static_cast<uint16_t>(q * 16u);
            const float f = fo.at<float>(y, x), g = fown.at<float>(y, x);
            bad_f += q ? f != d : !std::isinf(f);
            bad_own += q ? g != d : !std::isinf(g);
        }
    }
    std::printf("# aloe: %ld of %d px with a value\n", n_val,
                ref.rows * ref.cols);
    check(n_val > ref.rows * ref.cols / 2, "the map is mostly dense");
    check(bad_k == 0, "kitti = png16 x 16 on every pixel (" +
                          std::to_string(bad_k) + " differ)");
    check(bad_f == 0, "pfm (OpenCV reader) = png16 / 16, inf = no value (" +
                          std::to_string(bad_f) + " differ)");
    check(bad_own == 0, "pfm (own reader) = png16 / 16 (" +
                            std::to_string(bad_own) + " differ)");
    return failures ? 1 : 0;
}

} // namespace

int main(int argc, char **argv)
{
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "unit" && argc == 3) {
        ::mkdir(argv[2], 0755);
        return unit(argv[2]);
    }
    if (mode == "aloe" && argc == 6) {
        ::mkdir(argv[5], 0755);
        return aloe(argv[2], argv[3], argv[4], argv[5]);
    }
    std::fprintf(
        stderr, "usage: test_disp_io unit DIR | aloe STEREO LEFT RIGHT DIR\n");
    return 2;
}
