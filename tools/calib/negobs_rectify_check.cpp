// negobs_rectify_check: applies a rectify table with the library's integer
// remap (negobs_rectify_process) to every pair of a stereo chessboard list,
// detects the corners in both rectified images and reports how well
// matching corners share a row: the RMS of y_left - y_right. On a good
// calibration it is well under a pixel; the raw images are measured too
// for comparison.
//
// Exit codes: 0 pass, 1 failure or RMS >= --max-rms, 2 bad command line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <getopt.h>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib_common.hpp"
#include "cli.hpp"

extern "C" {
#include "negobs/rectify.h"
}

namespace {

int usage(const char *argv0, int code)
{
    std::fprintf(
        code ? stderr : stdout,
        "usage: %s --table TABLE.bin --list STEREO_LIST.xml [--board WxH]\n"
        "          [--max-rms PX] [--save DIR] [--yaml CALIB.yml [--alpha A]]\n"
        "  --max-rms PX  fail when the row RMS is >= PX (default 0.5)\n"
        "  --save DIR    write the rectified pairs as DIR/rect_NN_{l,r}.png\n"
        "  --yaml FILE   calibration written by negobs_calib --save-yaml: also\n"
        "                rectify with OpenCV's float maps and cv::remap and report\n"
        "                that figure and the pixel difference to the library\n"
        "  --alpha A     stereoRectify alpha used for the table (default 0)\n"
        "  -h, --help    this text;  -V, --version  the negobs version\n"
        "Options take their value as --opt VALUE or --opt=VALUE.\n"
        "Exit: 0 rows aligned, 1 data error or row RMS >= --max-rms,\n"
        "2 bad command line (also: no arguments).\n",
        argv0);
    return code;
}

negobs_image_u8_t view(cv::Mat &m)
{
    negobs_image_u8_t img;
    img.data = m.ptr<uint8_t>(0);
    img.width = m.cols;
    img.height = m.rows;
    img.stride = static_cast<int32_t>(m.step1());
    return img;
}

// Sum of squared row differences of matching corners. findChessboardCorners
// may number a board from either end; the order whose first-to-last
// direction agrees with the left image's is used.
void row_diffs(const std::vector<cv::Point2f> &l, std::vector<cv::Point2f> r,
               double &sum_sq, double &sum, size_t &n)
{
    const cv::Point2f dl = l.back() - l.front();
    const cv::Point2f dr = r.back() - r.front();
    if (dl.dot(dr) < 0) {
        std::reverse(r.begin(), r.end());
    }
    for (size_t i = 0; i < l.size(); ++i) {
        const double d = static_cast<double>(l[i].y) - r[i].y;
        sum_sq += d * d;
        sum += d;
        ++n;
    }
}

// OpenCV's own float rectification of the same calibration, as a
// reference for the integer remap. Same calls as negobs_calib.
bool opencv_maps(const std::string &path, double alpha, cv::Size size,
                 cv::Mat maps[2][2])
{
    cv::FileStorage fs;
    try {
        if (!fs.open(path, cv::FileStorage::READ)) {
            return false;
        }
    } catch (const cv::Exception &) {
        return false;
    }
    cv::Mat M1, D1, M2, D2, R, T;
    fs["M1"] >> M1;
    fs["D1"] >> D1;
    fs["M2"] >> M2;
    fs["D2"] >> D2;
    fs["R"] >> R;
    fs["T"] >> T;
    if (M1.empty() || D1.empty() || M2.empty() || D2.empty() || R.empty() ||
        T.empty()) {
        return false;
    }
    cv::Mat R1, R2, P1, P2, Q;
    cv::stereoRectify(M1, D1, M2, D2, size, R, T, R1, R2, P1, P2, Q,
                      cv::CALIB_ZERO_DISPARITY, alpha, size);
    cv::initUndistortRectifyMap(M1, D1, R1, P1, size, CV_32FC1, maps[0][0],
                                maps[0][1]);
    cv::initUndistortRectifyMap(M2, D2, R2, P2, size, CV_32FC1, maps[1][0],
                                maps[1][1]);
    return true;
}

struct FreeDeleter {
    void operator()(void *p) const { std::free(p); }
};

const struct option kLongOpts[] = {
    {"help", no_argument, nullptr, 'h'},
    {"version", no_argument, nullptr, 'V'},
    {"table", required_argument, nullptr, 't'},
    {"list", required_argument, nullptr, 'l'},
    {"save", required_argument, nullptr, 's'},
    {"yaml", required_argument, nullptr, 'y'},
    {"alpha", required_argument, nullptr, 'a'},
    {"board", required_argument, nullptr, 'b'},
    {"max-rms", required_argument, nullptr, 'r'},
    {nullptr, 0, nullptr, 0},
};

int run(int argc, char **argv)
{
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    std::string table_path, list_path, save_dir, yaml_path;
    cv::Size board(9, 6);
    double max_rms = 0.5;
    double alpha = 0.0;
    if (argc < 2) {
        return usage(argv[0], 2);
    }
    opterr = 0;
    int c;
    // long options only (+ -h, -V): the names say what each file is
    while ((c = getopt_long(argc, argv, "+:hV", kLongOpts, nullptr)) != -1) {
        const std::string v = optarg ? optarg : "";
        switch (c) {
        case 'h': return usage(argv[0], 0);
        case 'V': negobs_cli::print_version("negobs_rectify_check"); return 0;
        case 't': table_path = v; break;
        case 'l': list_path = v; break;
        case 's': save_dir = v; break;
        case 'y': yaml_path = v; break;
        case 'a':
            if (!negobs_cli::parse_double(optarg, -1, 1, alpha)) {
                std::fprintf(stderr, "negobs_rectify_check: bad --alpha %s\n",
                             optarg);
                return 2;
            }
            break;
        case 'b':
            if (!negobs_calib::parse_size(v, board)) {
                std::fprintf(stderr, "negobs_rectify_check: bad --board %s\n",
                             optarg);
                return 2;
            }
            break;
        case 'r':
            if (!negobs_cli::parse_double(optarg, 1e-9, 1e6, max_rms)) {
                std::fprintf(stderr,
                             "negobs_rectify_check: bad --max-rms %s\n",
                             optarg);
                return 2;
            }
            break;
        case ':':
            std::fprintf(stderr, "negobs_rectify_check: %s needs a value\n",
                         argv[optind - 1]);
            return usage(argv[0], 2);
        default:
            std::fprintf(stderr, "negobs_rectify_check: unknown option %s\n",
                         argv[optind - 1]);
            return usage(argv[0], 2);
        }
    }
    if (optind < argc) {
        std::fprintf(stderr, "negobs_rectify_check: unexpected argument %s\n",
                     argv[optind]);
        return usage(argv[0], 2);
    }
    if (table_path.empty() || list_path.empty()) {
        return usage(argv[0], 2);
    }

    std::vector<uint8_t> table;
    std::string err;
    if (!negobs_calib::read_file(table_path, table, err)) {
        std::fprintf(stderr, "negobs_rectify_check: %s\n", err.c_str());
        return 1;
    }
    negobs_rectify_info_t info;
    negobs_status_t st = negobs_rectify_table_check(table.data(), table.size(),
                                                    0, 0, &info);
    if (st != NEGOBS_OK) {
        std::fprintf(stderr, "negobs_rectify_check: %s: %s\n",
                     table_path.c_str(), negobs_status_str(st));
        return 1;
    }
    negobs_rectify_config_t cfg;
    negobs_rectify_config_default(&cfg, info.width, info.height);
    cfg.table = table.data();
    cfg.table_bytes = table.size();
    size_t ws_bytes = 0;
    st = negobs_rectify_workspace_size(&cfg, &ws_bytes);
    std::unique_ptr<void, FreeDeleter> ws(
        std::aligned_alloc(16, (ws_bytes + 15) / 16 * 16));
    negobs_rectify_t ctx;
    if (st == NEGOBS_OK) {
        st = negobs_rectify_init(&ctx, &cfg, ws.get(), ws_bytes);
    }
    if (st != NEGOBS_OK) {
        std::fprintf(stderr, "negobs_rectify_check: init: %s\n",
                     negobs_status_str(st));
        return 1;
    }
    std::printf("table: %dx%d, grid step %d, f = %.3f px, B = %.3f mm, "
                "cx = %.3f, cy = %.3f\n",
                info.width, info.height, 1 << info.grid_shift,
                info.f_q16 / 65536.0, info.baseline_um / 1000.0,
                info.cx_q16 / 65536.0, info.cy_q16 / 65536.0);

    std::vector<negobs_calib::ImagePair> pairs;
    if (!negobs_calib::read_image_list(list_path, pairs, err)) {
        std::fprintf(stderr, "negobs_rectify_check: %s\n", err.c_str());
        return 1;
    }
    cv::Mat cvmaps[2][2];
    const bool ref = !yaml_path.empty();
    if (ref && !opencv_maps(yaml_path, alpha,
                            cv::Size(info.width, info.height), cvmaps)) {
        std::fprintf(stderr,
                     "negobs_rectify_check: cannot read M1 D1 M2 D2 "
                     "R T from %s\n",
                     yaml_path.c_str());
        return 1;
    }
    double sq_rect = 0, sum_rect = 0, sq_raw = 0, sum_raw = 0, sq_cv = 0;
    double sum_cv = 0;
    size_t n_rect = 0, n_raw = 0, n_cv = 0;
    double diff_sum = 0;
    double diff_max = 0;
    size_t diff_n = 0;
    int used = 0;
    int index = 0;
    for (const auto &p : pairs) {
        ++index;
        cv::Mat l = cv::imread(p.left, cv::IMREAD_GRAYSCALE);
        cv::Mat r = cv::imread(p.right, cv::IMREAD_GRAYSCALE);
        if (l.empty() || r.empty()) {
            std::fprintf(stderr, "negobs_rectify_check: cannot read %s\n",
                         (l.empty() ? p.left : p.right).c_str());
            return 1;
        }
        if (l.cols != info.width || l.rows != info.height ||
            r.size() != l.size()) {
            std::fprintf(stderr,
                         "negobs_rectify_check: %s is %dx%d, the "
                         "table is for %dx%d\n",
                         p.left.c_str(), l.cols, l.rows, info.width,
                         info.height);
            return 1;
        }
        cv::Mat lr(l.size(), CV_8UC1), rr(r.size(), CV_8UC1);
        negobs_image_u8_t il = view(l), ir = view(r);
        negobs_image_u8_t ol = view(lr), orr = view(rr);
        negobs_rectify_stats_t stats;
        st = negobs_rectify_process(&ctx, &il, &ir, &ol, &orr, &stats);
        if (st != NEGOBS_OK) {
            std::fprintf(stderr, "negobs_rectify_check: process: %s\n",
                         negobs_status_str(st));
            return 1;
        }
        if (!save_dir.empty()) {
            char name[64];
            std::snprintf(name, sizeof name, "/rect_%02d_l.png", index);
            cv::imwrite(save_dir + name, lr);
            std::snprintf(name, sizeof name, "/rect_%02d_r.png", index);
            cv::imwrite(save_dir + name, rr);
        }
        if (ref) {
            cv::Mat cvl, cvr;
            cv::remap(l, cvl, cvmaps[0][0], cvmaps[0][1], cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(0));
            cv::remap(r, cvr, cvmaps[1][0], cvmaps[1][1], cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(0));
            for (const auto &pr :
                 {std::make_pair(&lr, &cvl), std::make_pair(&rr, &cvr)}) {
                cv::Mat d;
                cv::absdiff(*pr.first, *pr.second, d);
                double mx = 0;
                cv::minMaxLoc(d, nullptr, &mx);
                diff_max = std::max(diff_max, mx);
                diff_sum += cv::sum(d)[0];
                diff_n += d.total();
            }
            std::vector<cv::Point2f> kl, kr;
            if (negobs_calib::find_corners(cvl, board, kl) &&
                negobs_calib::find_corners(cvr, board, kr)) {
                row_diffs(kl, kr, sq_cv, sum_cv, n_cv);
            }
        }
        std::vector<cv::Point2f> cl, cr, rl, rrw;
        if (negobs_calib::find_corners(l, board, rl) &&
            negobs_calib::find_corners(r, board, rrw)) {
            row_diffs(rl, rrw, sq_raw, sum_raw, n_raw);
        }
        if (!negobs_calib::find_corners(lr, board, cl) ||
            !negobs_calib::find_corners(rr, board, cr)) {
            std::printf("  pair %2d: board not found after rectification\n",
                        index);
            continue;
        }
        double s2 = 0, s1 = 0;
        size_t n = 0;
        row_diffs(cl, cr, s2, s1, n);
        std::printf("  pair %2d: row RMS %.3f px (mean %+.3f) over %zu "
                    "corners\n",
                    index, std::sqrt(s2 / n), s1 / n, n);
        sq_rect += s2;
        sum_rect += s1;
        n_rect += n;
        ++used;
    }
    if (used == 0) {
        std::fprintf(stderr, "negobs_rectify_check: no pair with the board "
                             "in both rectified images\n");
        return 1;
    }
    const double rms = std::sqrt(sq_rect / n_rect);
    if (n_raw > 0) {
        std::printf("raw images:       row RMS %.3f px over %zu corners\n",
                    std::sqrt(sq_raw / n_raw), n_raw);
    }
    if (n_cv > 0) {
        std::printf("rectified (OpenCV float maps + cv::remap): row RMS "
                    "%.3f px (mean %+.3f) over %zu corners\n",
                    std::sqrt(sq_cv / n_cv), sum_cv / n_cv, n_cv);
        std::printf("lib vs cv::remap pixels: mean |diff| %.3f, max %.0f "
                    "grey levels\n",
                    diff_sum / diff_n, diff_max);
    }
    std::printf("rectified (lib):  row RMS %.3f px (mean %+.3f) over %zu "
                "corners in %d of %zu pairs; limit %.3f\n",
                rms, sum_rect / n_rect, n_rect, used, pairs.size(), max_rms);
    if (!(rms < max_rms)) {
        std::fprintf(stderr,
                     "negobs_rectify_check: FAIL: row RMS %.3f px "
                     ">= %.3f\n",
                     rms, max_rms);
        return 1;
    }
    std::printf("PASS\n");
    return 0;
}

} // namespace

int main(int argc, char **argv)
{
    return negobs_cli::main_guard("negobs_rectify_check", argc, argv, run);
}
