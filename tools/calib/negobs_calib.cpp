// negobs_calib: stereo calibration -> negobs rectify table.
//
// Input is either a stereo chessboard list in OpenCV's stereo_calib.xml
// format (calibrateCamera per camera, then stereoCalibrate) or an existing
// OpenCV YAML/XML calibration holding M1, D1, M2, D2, R, T. Either way
// stereoRectify + initUndistortRectifyMap give the float maps, which are
// sampled on a node grid, converted to Q.8 and serialised by the library's
// negobs_rectify_table_write() (format in docs/CALIBRATION.md).
//
// Exit codes: 0 success, 1 failure (missing file, too few boards, a
// calibration that cannot be rectified, or any error OpenCV raises, which
// is caught and printed), 2 bad command line. Inputs are validated before
// OpenCV sees them: a frame size within 2..NEGOBS_MAX_DIM, finite
// matrices, positive focal lengths, a rotation R and a non-zero
// translation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <getopt.h>
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

using negobs_calib::ImagePair;

struct Options {
    std::string list;
    std::vector<std::string> yaml;
    std::string out;
    std::string save_yaml;
    cv::Size board{9, 6};
    cv::Size frame{0, 0};
    double square_mm = 25.0;
    bool square_given = false;
    double t_unit_mm = 1.0;
    double alpha = 0.0;
    int grid_shift = -1; // -1: auto
    double max_map_err = 0.02;
    int min_boards = 5;
    bool fix_k3 = false;
};

int usage(const char *argv0, int code)
{
    std::fprintf(
        code ? stderr : stdout,
        "usage: %s (--list STEREO_LIST.xml | --yaml CALIB.yml [--yaml MORE.yml])\n"
        "          --out TABLE.bin [options]\n"
        "\n"
        "  --list FILE       stereo chessboard list, OpenCV stereo_calib.xml format\n"
        "                    (left, right, left, right, ...; relative to the list)\n"
        "  --yaml FILE       existing calibration with M1 D1 M2 D2 R T (repeatable;\n"
        "                    keys are merged, e.g. intrinsics.yml + extrinsics.yml)\n"
        "  -o, --out FILE    rectify table to write (required)\n"
        "  --board WxH       inner corners per row x column (default 9x6)\n"
        "  --square-mm MM    chessboard square size (default 25; sets B's unit)\n"
        "  --size WxH        frame size for --yaml when the file has none\n"
        "  --t-unit-mm MM    millimetres per unit of T in --yaml (default 1)\n"
        "  --alpha A         stereoRectify free scaling, -1 or 0..1 (default 0:\n"
        "                    only valid pixels)\n"
        "  --grid-shift N    node spacing 2^N px, 0..%d, or 'auto' (default): the\n"
        "                    coarsest grid within --max-map-err\n"
        "  --max-map-err PX  auto grid tolerance (default 0.02 px)\n"
        "  --min-boards N    usable pairs required (default 5)\n"
        "  --fix-k3          keep the radial k3 term at 0 (few boards, or boards\n"
        "                    that never reach the image corners)\n"
        "  --save-yaml FILE  also write M1 D1 M2 D2 R T (+ size, rms) for --yaml\n"
        "  -h, --help        this text\n"
        "  -V, --version     the negobs version\n"
        "Options take their value as --opt VALUE or --opt=VALUE; -o is --out.\n"
        "Exit: 0 ok, 1 data error (missing file, too few boards, a calibration\n"
        "that cannot be rectified, an OpenCV error), 2 bad command line (also:\n"
        "no arguments).\n",
        argv0, NEGOBS_RECTIFY_MAX_GRID_SHIFT);
    return code;
}

enum LongOnly {
    O_LIST = 256,
    O_YAML,
    O_SAVE_YAML,
    O_BOARD,
    O_SIZE,
    O_SQUARE,
    O_T_UNIT,
    O_ALPHA,
    O_GRID_SHIFT,
    O_MAX_MAP_ERR,
    O_MIN_BOARDS,
    O_FIX_K3,
};

const struct option kLongOpts[] = {
    {"help", no_argument, nullptr, 'h'},
    {"version", no_argument, nullptr, 'V'},
    {"list", required_argument, nullptr, O_LIST},
    {"yaml", required_argument, nullptr, O_YAML},
    {"out", required_argument, nullptr, 'o'},
    {"save-yaml", required_argument, nullptr, O_SAVE_YAML},
    {"board", required_argument, nullptr, O_BOARD},
    {"size", required_argument, nullptr, O_SIZE},
    {"square-mm", required_argument, nullptr, O_SQUARE},
    {"t-unit-mm", required_argument, nullptr, O_T_UNIT},
    {"alpha", required_argument, nullptr, O_ALPHA},
    {"grid-shift", required_argument, nullptr, O_GRID_SHIFT},
    {"max-map-err", required_argument, nullptr, O_MAX_MAP_ERR},
    {"min-boards", required_argument, nullptr, O_MIN_BOARDS},
    {"fix-k3", no_argument, nullptr, O_FIX_K3},
    {nullptr, 0, nullptr, 0},
};

// 0 = parsed, otherwise the exit code to return (+100: exit 0 after
// --help / --version).
int parse_args(int argc, char **argv, Options &o)
{
    if (argc < 2) {
        return usage(argv[0], 2);
    }
    opterr = 0;
    int c;
    int li = -1;
    while ((c = getopt_long(argc, argv, "+:hVo:", kLongOpts, &li)) != -1) {
        const char *v = optarg;
        bool ok = true;
        switch (c) {
        case 'h': return usage(argv[0], 0) + 100;
        case 'V': negobs_cli::print_version("negobs_calib"); return 100;
        case O_FIX_K3: o.fix_k3 = true; break;
        case O_LIST: o.list = v; break;
        case O_YAML: o.yaml.push_back(v); break;
        case 'o': o.out = v; break;
        case O_SAVE_YAML: o.save_yaml = v; break;
        case O_BOARD: ok = negobs_calib::parse_size(v, o.board); break;
        case O_SIZE:
            // bounded here, before anything multiplies the two sides
            ok = negobs_calib::parse_size(v, o.frame) &&
                 o.frame.width <= NEGOBS_MAX_DIM &&
                 o.frame.height <= NEGOBS_MAX_DIM;
            if (!ok) {
                std::fprintf(stderr,
                             "negobs_calib: --size %s: frame size "
                             "must be WxH with 2 <= W, H <= %d\n",
                             v, NEGOBS_MAX_DIM);
                return 2;
            }
            break;
        case O_SQUARE:
            ok = negobs_cli::parse_double(v, 1e-3, 1e6, o.square_mm);
            o.square_given = true;
            break;
        case O_T_UNIT:
            ok = negobs_cli::parse_double(v, 1e-6, 1e6, o.t_unit_mm);
            break;
        case O_ALPHA:
            ok = negobs_cli::parse_double(v, -1.0, 1.0, o.alpha);
            break;
        case O_GRID_SHIFT:
            if (std::string(v) == "auto") {
                o.grid_shift = -1;
            } else {
                ok = negobs_cli::parse_int(v, 0, NEGOBS_RECTIFY_MAX_GRID_SHIFT,
                                           o.grid_shift);
            }
            break;
        case O_MAX_MAP_ERR:
            ok = negobs_cli::parse_double(v, 1e-6, 1e3, o.max_map_err);
            break;
        case O_MIN_BOARDS:
            ok = negobs_cli::parse_int(v, 1, 100000, o.min_boards);
            break;
        case ':':
            std::fprintf(stderr, "negobs_calib: %s needs a value\n",
                         argv[optind - 1]);
            return usage(argv[0], 2);
        default:
            std::fprintf(stderr, "negobs_calib: unknown option %s\n",
                         argv[optind - 1]);
            return usage(argv[0], 2);
        }
        if (!ok) {
            // the option's name (argv[optind - 1] is the value when given
            // as a separate word)
            std::fprintf(stderr, "negobs_calib: bad value for --%s: %s\n",
                         li >= 0 ? kLongOpts[li].name : "?", v);
            return 2;
        }
        li = -1;
    }
    if (optind < argc) {
        std::fprintf(stderr, "negobs_calib: unexpected argument %s\n",
                     argv[optind]);
        return usage(argv[0], 2);
    }
    if (o.list.empty() == o.yaml.empty()) {
        std::fprintf(stderr, "negobs_calib: give exactly one of --list or "
                             "--yaml\n");
        return usage(argv[0], 2);
    }
    if (o.out.empty()) {
        std::fprintf(stderr, "negobs_calib: --out is required\n");
        return usage(argv[0], 2);
    }
    return 0;
}

struct Calibration {
    cv::Mat M1, D1, M2, D2, R, T; // T in millimetres
    cv::Size size;
    double rms = -1.0; // stereo RMS reprojection error (px), < 0 unknown
    double rms_left = -1.0;
    double rms_right = -1.0;
    int boards = 0;
};

bool calibrate_from_list(const Options &o, Calibration &c)
{
    std::vector<ImagePair> pairs;
    std::string err;
    if (!negobs_calib::read_image_list(o.list, pairs, err)) {
        std::fprintf(stderr, "negobs_calib: %s\n", err.c_str());
        return false;
    }
    std::vector<std::vector<cv::Point2f>> pts_l, pts_r;
    for (const auto &p : pairs) {
        for (const auto *name : {&p.left, &p.right}) {
            if (!negobs_calib::file_exists(*name)) {
                std::fprintf(stderr, "negobs_calib: missing image %s\n",
                             name->c_str());
                return false;
            }
        }
        cv::Mat l = cv::imread(p.left, cv::IMREAD_GRAYSCALE);
        cv::Mat r = cv::imread(p.right, cv::IMREAD_GRAYSCALE);
        if (l.empty() || r.empty()) {
            std::fprintf(stderr, "negobs_calib: cannot decode %s\n",
                         (l.empty() ? p.left : p.right).c_str());
            return false;
        }
        if (c.size.area() == 0) {
            c.size = l.size();
        }
        if (l.size() != c.size || r.size() != c.size) {
            std::fprintf(stderr,
                         "negobs_calib: %s / %s: size differs from "
                         "%dx%d\n",
                         p.left.c_str(), p.right.c_str(), c.size.width,
                         c.size.height);
            return false;
        }
        std::vector<cv::Point2f> cl, cr;
        const bool fl = negobs_calib::find_corners(l, o.board, cl);
        const bool fr = fl && negobs_calib::find_corners(r, o.board, cr);
        if (fl && fr) {
            pts_l.push_back(cl);
            pts_r.push_back(cr);
        } else {
            std::printf("  skipped pair %s: board not found in %s image\n",
                        p.left.c_str(), fl ? "right" : "left");
        }
    }
    c.boards = static_cast<int>(pts_l.size());
    std::printf("boards: %d of %zu pairs usable (%dx%d inner corners, "
                "square %.3f mm%s)\n",
                c.boards, pairs.size(), o.board.width, o.board.height,
                o.square_mm,
                o.square_given ? "" : ", default: set --square-mm");
    if (c.boards < o.min_boards) {
        std::fprintf(stderr,
                     "negobs_calib: too few boards: %d usable "
                     "pairs, need at least %d (--min-boards)\n",
                     c.boards, o.min_boards);
        return false;
    }

    std::vector<cv::Point3f> board_mm;
    for (int i = 0; i < o.board.height; ++i) {
        for (int j = 0; j < o.board.width; ++j) {
            board_mm.emplace_back(static_cast<float>(j * o.square_mm),
                                  static_cast<float>(i * o.square_mm), 0.f);
        }
    }
    std::vector<std::vector<cv::Point3f>> obj(pts_l.size(), board_mm);

    // Each camera alone first (well-conditioned), then the pair with the
    // intrinsics as a starting guess so R, T and the intrinsics are refined
    // jointly. TUNABLE: the full 5-parameter model (k1 k2 p1 p2 k3); on the
    // opencv-doc set it aligns rows better than k3 fixed (0.160 vs 0.208 px
    // row RMS) at the same reprojection error. --fix-k3 restores the
    // simpler model for boards that do not reach the image corners.
    const int mono_flags = o.fix_k3 ? cv::CALIB_FIX_K3 : 0;
    std::vector<cv::Mat> rv, tv;
    c.M1 = cv::Mat::eye(3, 3, CV_64F);
    c.M2 = cv::Mat::eye(3, 3, CV_64F);
    c.rms_left = cv::calibrateCamera(obj, pts_l, c.size, c.M1, c.D1, rv, tv,
                                     mono_flags);
    c.rms_right = cv::calibrateCamera(obj, pts_r, c.size, c.M2, c.D2, rv, tv,
                                      mono_flags);
    cv::Mat E, F;
    c.rms = cv::stereoCalibrate(
        obj, pts_l, pts_r, c.M1, c.D1, c.M2, c.D2, c.size, c.R, c.T, E, F,
        cv::CALIB_USE_INTRINSIC_GUESS | mono_flags,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100,
                         1e-6));
    return true;
}

bool read_mat(const cv::FileStorage &fs, const char *key, cv::Mat &m)
{
    cv::FileNode n = fs[key];
    if (n.empty()) {
        return false;
    }
    n >> m;
    if (m.empty()) {
        return false;
    }
    m.convertTo(m, CV_64F);
    return true;
}

bool calibration_from_yaml(const Options &o, Calibration &c)
{
    int w = 0;
    int h = 0;
    for (const auto &path : o.yaml) {
        if (!negobs_calib::file_exists(path)) {
            std::fprintf(stderr,
                         "negobs_calib: calibration file not found: "
                         "%s\n",
                         path.c_str());
            return false;
        }
        cv::FileStorage fs;
        try {
            if (!fs.open(path, cv::FileStorage::READ)) {
                std::fprintf(stderr, "negobs_calib: cannot parse %s\n",
                             path.c_str());
                return false;
            }
        } catch (const cv::Exception &e) {
            std::fprintf(stderr, "negobs_calib: cannot parse %s: %s\n",
                         path.c_str(), e.what());
            return false;
        }
        read_mat(fs, "M1", c.M1);
        read_mat(fs, "D1", c.D1);
        read_mat(fs, "M2", c.M2);
        read_mat(fs, "D2", c.D2);
        read_mat(fs, "R", c.R);
        read_mat(fs, "T", c.T);
        if (!fs["image_width"].empty()) {
            fs["image_width"] >> w;
            fs["image_height"] >> h;
        }
        if (!fs["rms"].empty()) {
            fs["rms"] >> c.rms;
        }
    }
    const struct {
        const char *name;
        const cv::Mat *m;
        int rows, cols;
    } need[] = {{"M1", &c.M1, 3, 3}, {"M2", &c.M2, 3, 3}, {"R", &c.R, 3, 3}};
    for (const auto &n : need) {
        if (n.m->rows != n.rows || n.m->cols != n.cols) {
            std::fprintf(stderr,
                         "negobs_calib: %s missing or not 3x3 in "
                         "the calibration file(s)\n",
                         n.name);
            return false;
        }
    }
    if (c.D1.empty() || c.D2.empty()) {
        std::fprintf(stderr, "negobs_calib: D1/D2 missing in the "
                             "calibration file(s)\n");
        return false;
    }
    if (c.T.total() != 3) {
        std::fprintf(stderr, "negobs_calib: T missing or not 3 values\n");
        return false;
    }
    c.T = c.T.reshape(1, 3) * o.t_unit_mm;
    if (o.frame.width > 0) {
        c.size = o.frame;
    } else if (w != 0 || h != 0) {
        if (w < 2 || h < 2 || w > NEGOBS_MAX_DIM || h > NEGOBS_MAX_DIM) {
            std::fprintf(stderr,
                         "negobs_calib: image_width/image_height "
                         "%dx%d in the calibration file: must be "
                         "2..%d\n",
                         w, h, NEGOBS_MAX_DIM);
            return false;
        }
        c.size = cv::Size(w, h);
    } else {
        std::fprintf(stderr, "negobs_calib: frame size unknown: the file "
                             "has no image_width/image_height, pass --size "
                             "WxH\n");
        return false;
    }
    return true;
}

bool save_yaml(const std::string &path, const Calibration &c)
{
    cv::FileStorage fs;
    try {
        if (!fs.open(path, cv::FileStorage::WRITE)) {
            return false;
        }
    } catch (const cv::Exception &) {
        return false;
    }
    fs << "image_width" << c.size.width << "image_height" << c.size.height;
    fs << "M1" << c.M1 << "D1" << c.D1 << "M2" << c.M2 << "D2" << c.D2;
    fs << "R" << c.R << "T" << c.T << "rms" << c.rms;
    return true;
}

int32_t to_q(double v, double one, double lo, double hi, int *clamped)
{
    double q = std::floor(v * one + 0.5);
    if (q < lo) {
        q = lo;
        ++*clamped;
    } else if (q > hi) {
        q = hi;
        ++*clamped;
    }
    return static_cast<int32_t>(q);
}

// The map a table with this grid would produce at every frame pixel,
// compared with the exact float map over the pixels whose source lies in
// the frame. Returns the largest error in pixels.
double grid_error(const cv::Mat &mx, const cv::Mat &my, cv::Size size,
                  int shift)
{
    const int step = 1 << shift;
    double worst = 0.0;
    for (int y = 0; y < size.height; ++y) {
        const int gy = (y >> shift) << shift;
        const double fy = static_cast<double>(y - gy) / step;
        for (int x = 0; x < size.width; ++x) {
            const float sx = mx.at<float>(y, x);
            const float sy = my.at<float>(y, x);
            if (sx < 0 || sy < 0 || sx > size.width - 1 ||
                sy > size.height - 1) {
                continue;
            }
            const int gx = (x >> shift) << shift;
            const double fx = static_cast<double>(x - gx) / step;
            auto interp = [&](const cv::Mat &m) {
                return (1 - fx) * (1 - fy) * m.at<float>(gy, gx) +
                       fx * (1 - fy) * m.at<float>(gy, gx + step) +
                       (1 - fx) * fy * m.at<float>(gy + step, gx) +
                       fx * fy * m.at<float>(gy + step, gx + step);
            };
            const double ex = std::fabs(interp(mx) - sx);
            const double ey = std::fabs(interp(my) - sy);
            worst = std::max(worst, std::max(ex, ey));
        }
    }
    return worst;
}

bool all_finite(const cv::Mat &m)
{
    return !m.empty() && cv::checkRange(m, true, nullptr, -1e12, 1e12);
}

// What stereoRectify and initUndistortRectifyMap need, checked first so a
// bad file is named as such instead of failing inside OpenCV: finite
// values, focal lengths > 0, a distortion model OpenCV knows, a rotation R
// and two camera centres that are apart (a zero T has no epipolar geometry
// to rectify).
bool calibration_usable(const Calibration &c)
{
    const struct {
        const char *name;
        const cv::Mat *m;
    } mats[] = {{"M1", &c.M1}, {"D1", &c.D1}, {"M2", &c.M2},
                {"D2", &c.D2}, {"R", &c.R},   {"T", &c.T}};
    for (const auto &m : mats) {
        if (!all_finite(*m.m)) {
            std::fprintf(stderr,
                         "negobs_calib: %s holds a value that is "
                         "not finite (or beyond 1e12)\n",
                         m.name);
            return false;
        }
    }
    for (const cv::Mat *m : {&c.M1, &c.M2}) {
        if (!(m->at<double>(0, 0) > 0.0) || !(m->at<double>(1, 1) > 0.0)) {
            std::fprintf(stderr,
                         "negobs_calib: %s: focal lengths must be "
                         "> 0\n",
                         m == &c.M1 ? "M1" : "M2");
            return false;
        }
    }
    for (const cv::Mat *d : {&c.D1, &c.D2}) {
        const size_t n = d->total();
        if (n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
            std::fprintf(stderr,
                         "negobs_calib: %s has %zu coefficients; "
                         "OpenCV takes 4, 5, 8, 12 or 14\n",
                         d == &c.D1 ? "D1" : "D2", n);
            return false;
        }
    }
    // R must be a rotation: anything else gives a table that "rectifies"
    // into nonsense without any error (a zero R did). 1e-3 is loose enough
    // for a rotation written with 6 decimals, far below any real error.
    const cv::Mat rtr = c.R.t() * c.R - cv::Mat::eye(3, 3, CV_64F);
    if (cv::norm(rtr, cv::NORM_INF) > 1e-3 ||
        std::fabs(cv::determinant(c.R) - 1.0) > 1e-3) {
        std::fprintf(stderr, "negobs_calib: R is not a rotation matrix "
                             "(R^T R != I or det(R) != 1)\n");
        return false;
    }
    // 1 micrometre: far below any real rig, far above rounding noise
    if (cv::norm(c.T) < 1e-3) {
        std::fprintf(stderr, "negobs_calib: the translation T between the "
                             "cameras is zero: no stereo baseline, nothing "
                             "to rectify\n");
        return false;
    }
    return true;
}

int run(int argc, char **argv);

} // namespace

// Every OpenCV call can throw; none may end the tool with an abort (exit
// 134): the boundary turns whatever escapes into a message and exit 1.
int main(int argc, char **argv)
{
    return negobs_cli::main_guard("negobs_calib", argc, argv, run);
}

namespace {

int run(int argc, char **argv)
{
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    Options o;
    const int pa = parse_args(argc, argv, o);
    if (pa != 0) {
        return pa >= 100 ? 0 : pa;
    }

    Calibration c;
    if (!o.list.empty() ? !calibrate_from_list(o, c)
                        : !calibration_from_yaml(o, c)) {
        return 1;
    }
    if (!calibration_usable(c)) {
        return 1;
    }
    if (c.size.width > NEGOBS_MAX_DIM || c.size.height > NEGOBS_MAX_DIM) {
        std::fprintf(stderr,
                     "negobs_calib: frame %dx%d exceeds "
                     "NEGOBS_MAX_DIM %d\n",
                     c.size.width, c.size.height, NEGOBS_MAX_DIM);
        return 1;
    }

    cv::Mat R1, R2, P1, P2, Q;
    cv::stereoRectify(c.M1, c.D1, c.M2, c.D2, c.size, c.R, c.T, R1, R2, P1, P2,
                      Q, cv::CALIB_ZERO_DISPARITY, o.alpha, c.size);
    const double f = P1.at<double>(0, 0);
    const double cx = P1.at<double>(0, 2);
    const double cy = P1.at<double>(1, 2);
    const double tx = P2.at<double>(0, 3) / P2.at<double>(0, 0);
    if (std::fabs(P2.at<double>(1, 3)) > std::fabs(P2.at<double>(0, 3))) {
        std::fprintf(stderr, "negobs_calib: the cameras are stacked "
                             "vertically; only side-by-side rigs are "
                             "supported\n");
        return 1;
    }
    if (tx > 0) {
        std::fprintf(stderr, "negobs_calib: the 'right' camera sits left of "
                             "the 'left' one (T.x > 0): swap the images in "
                             "the list\n");
        return 1;
    }
    const double baseline_mm = -tx;
    const double doffs = P2.at<double>(0, 2) - cx;

    // Float maps on a canvas that covers every node of the coarsest grid
    // (the last node column/row lies at or past the frame edge).
    cv::Mat maps[2][2];
    const int max_shift = NEGOBS_RECTIFY_MAX_GRID_SHIFT;
    const cv::Size canvas(
        (NEGOBS_RECTIFY_GRID_NODES(c.size.width, 0) - 1) + (1 << max_shift),
        (NEGOBS_RECTIFY_GRID_NODES(c.size.height, 0) - 1) + (1 << max_shift));
    const cv::Mat *M[2] = {&c.M1, &c.M2};
    const cv::Mat *D[2] = {&c.D1, &c.D2};
    const cv::Mat *Rr[2] = {&R1, &R2};
    const cv::Mat *P[2] = {&P1, &P2};
    for (int cam = 0; cam < 2; ++cam) {
        cv::initUndistortRectifyMap(*M[cam], *D[cam], *Rr[cam], *P[cam],
                                    canvas, CV_32FC1, maps[cam][0],
                                    maps[cam][1]);
    }

    int shift = o.grid_shift;
    double err[NEGOBS_RECTIFY_MAX_GRID_SHIFT + 1] = {};
    for (int s = 0; s <= max_shift; ++s) {
        err[s] = std::max(grid_error(maps[0][0], maps[0][1], c.size, s),
                          grid_error(maps[1][0], maps[1][1], c.size, s));
        if (o.grid_shift < 0 && err[s] <= o.max_map_err) {
            shift = s;
        }
    }
    if (shift < 0) {
        shift = 0;
    }

    negobs_rectify_info_t info = {};
    info.width = c.size.width;
    info.height = c.size.height;
    info.grid_shift = shift;
    int clamped = 0;
    info.f_q16 = static_cast<uint32_t>(
        to_q(f, 65536.0, 1, INT32_MAX, &clamped));
    info.baseline_um = static_cast<uint32_t>(
        to_q(baseline_mm, 1000.0, 0, INT32_MAX, &clamped));
    info.cx_q16 = to_q(cx, 65536.0, INT32_MIN, INT32_MAX, &clamped);
    info.cy_q16 = to_q(cy, 65536.0, INT32_MIN, INT32_MAX, &clamped);
    info.doffs_q16 = to_q(doffs, 65536.0, INT32_MIN, INT32_MAX, &clamped);
    info.rms_mpx = (c.rms >= 0) ? static_cast<uint32_t>(to_q(
                                      c.rms, 1000.0, 0, INT32_MAX, &clamped))
                                : NEGOBS_RECTIFY_RMS_UNKNOWN;
    if (clamped != 0) {
        std::fprintf(stderr, "negobs_calib: f, B, cx, cy or RMS out of the "
                             "table's range\n");
        return 1;
    }

    const int gw = NEGOBS_RECTIFY_GRID_NODES(c.size.width, shift);
    const int gh = NEGOBS_RECTIFY_GRID_NODES(c.size.height, shift);
    std::vector<int32_t> nodes[2];
    const double lim = NEGOBS_RECTIFY_COORD_LIMIT_Q8;
    int node_clamped = 0;
    for (int cam = 0; cam < 2; ++cam) {
        nodes[cam].resize(static_cast<size_t>(2 * gw * gh));
        for (int gy = 0; gy < gh; ++gy) {
            for (int gx = 0; gx < gw; ++gx) {
                const size_t k = 2 * static_cast<size_t>(gy * gw + gx);
                const int px = gx << shift;
                const int py = gy << shift;
                // A clamped node is far outside the frame; the pixels it
                // influences sample the border either way.
                nodes[cam][k] = to_q(maps[cam][0].at<float>(py, px), 256.0,
                                     -lim, lim, &node_clamped);
                nodes[cam][k + 1] = to_q(maps[cam][1].at<float>(py, px), 256.0,
                                         -lim, lim, &node_clamped);
            }
        }
    }

    size_t bytes = 0;
    negobs_status_t st = negobs_rectify_table_size(info.width, info.height,
                                                   shift, &bytes);
    std::vector<uint8_t> table(bytes);
    if (st == NEGOBS_OK) {
        st = negobs_rectify_table_write(&info, nodes[0].data(),
                                        nodes[1].data(), table.data(),
                                        table.size(), &bytes);
    }
    if (st == NEGOBS_OK) {
        st = negobs_rectify_table_check(table.data(), table.size(), info.width,
                                        info.height, nullptr);
    }
    if (st != NEGOBS_OK) {
        std::fprintf(stderr, "negobs_calib: table encoding failed: %s\n",
                     negobs_status_str(st));
        return 1;
    }
    std::string err_text;
    if (!negobs_calib::write_file(o.out, table, err_text)) {
        std::fprintf(stderr, "negobs_calib: %s\n", err_text.c_str());
        return 1;
    }
    if (!o.save_yaml.empty() && !save_yaml(o.save_yaml, c)) {
        std::fprintf(stderr, "negobs_calib: cannot write %s\n",
                     o.save_yaml.c_str());
        return 1;
    }

    if (c.rms >= 0) {
        if (c.rms_left >= 0) {
            std::printf("RMS reprojection error: %.4f px stereo (left %.4f, "
                        "right %.4f mono)\n",
                        c.rms, c.rms_left, c.rms_right);
        } else {
            std::printf("RMS reprojection error: %.4f px (from file)\n",
                        c.rms);
        }
    } else {
        std::printf("RMS reprojection error: unknown (not in the file)\n");
    }
    std::printf("rectified: f = %.3f px, B = %.3f mm, cx = %.3f px, "
                "cy = %.3f px, doffs = %.3f px\n",
                f, baseline_mm, cx, cy, doffs);
    std::printf("grid: step %d px (shift %d), max map interpolation error "
                "%.4f px [by shift:",
                1 << shift, shift, err[shift]);
    for (int s = 0; s <= max_shift; ++s) {
        std::printf(" %.4f", err[s]);
    }
    std::printf("]\n");
    if (node_clamped != 0) {
        std::printf("note: %d node coordinates beyond +-8192 px clamped "
                    "(far outside the frame)\n",
                    node_clamped);
    }
    std::printf("table: %dx%d, %zu bytes -> %s\n", info.width, info.height,
                bytes, o.out.c_str());
    return 0;
}

} // namespace
