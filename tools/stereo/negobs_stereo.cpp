// negobs_stereo: run the negobs disparity engine on one rectified pair.
//
//   negobs_stereo LEFT RIGHT OUT.png [--max-disp N] [--min-disp N]
//                 [--format png16|kitti|pfm] [--color PICTURE.png]
//
// This command-line interface is stable: scripts rely on it. The exit
// codes follow the host tools' common table (docs/TOOLS.md).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <getopt.h>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli.hpp"
#include "colour_bar.hpp"
#include "disp_io.hpp"
#include "rect_table.hpp"
#include "negobs_port/pool.h"
#include "stereo_common.hpp"

extern "C" {
#include "negobs/stereo.h"
#include "negobs/valign.h"
}

namespace {

// 0 / 1 / 2 as every negobs tool (tools/common/cli.hpp); 3..5 its own.
enum Exit {
    EXIT_OK = negobs_cli::kExitOk,
    EXIT_INPUT = negobs_cli::kExitData,  // an input image cannot be read
    EXIT_USAGE = negobs_cli::kExitUsage, // bad command line or range
    EXIT_SIZE = 3,    // left/right sizes differ or are out of bounds
    EXIT_LIBRARY = 4, // the negobs library reported an error
    EXIT_OUTPUT = 5,  // an output file cannot be written
};

const char *const kHelp =
    "usage: negobs_stereo LEFT RIGHT OUT [-D|--max-disp N] [-d|--min-disp N]\n"
    "                     [-f|--format png16|kitti|pfm] [-c|--color PICTURE]\n"
    "                     [--confidence CONF.png] [--align] [--halfshift]\n"
    "                     [-s|--stats] [--threads N]\n"
    "\n"
    "Computes the disparity of the rectified pair LEFT (reference) / RIGHT\n"
    "with the negobs fixed-point engine and writes OUT.\n"
    "\n"
    "Inputs: any image OpenCV reads (PNG, PPM/PGM, BMP, JPEG, TIFF, ...);\n"
    "colour is converted to grey, 16-bit to 8-bit. Both must have the same\n"
    "size (at most 4096 x 4096, at least the engine's minimum).\n"
    "\n"
    "Output OUT, by --format (default png16). A point at column x in LEFT\n"
    "is at column x - disparity in RIGHT.\n"
    "  png16  16-bit grey PNG, OpenCV's fixed point: value = disparity * 16\n"
    "         (1/16 px steps), 0 = no value. A disparity of exactly 0 px\n"
    "         (or below) cannot be represented and is written as 0 = no\n"
    "         value; use --min-disp >= 1 if that matters.\n"
    "  kitti  16-bit grey PNG, KITTI's devkit: value = disparity * 256,\n"
    "         0 = no value; --max-disp at most 255\n"
    "  pfm    OUT.pfm, Middlebury 2014 / SceneFlow float map: one channel,\n"
    "         little endian (scale -1), rows bottom to top, inf = no value\n"
    "\n"
    "Options:\n"
    "  -D, --max-disp N  largest disparity searched, pixels (default 64);\n"
    "                 at most the engine's bound for the frame (width - 6\n"
    "                 and 2000 with its 5x5 window; an error names it),\n"
    "                 and the range max-disp - min-disp + 1 at most the\n"
    "                 engine's limit (NEGOBS_STEREO_MAX_RANGE, 256)\n"
    "  -d, --min-disp N  smallest disparity searched, pixels (default 0);\n"
    "                 0 <= N < max-disp\n"
    "  -f, --format F png16 (default), kitti or pfm, see above\n"
    "  -c, --color FILE  also write a colour picture (TURBO map over\n"
    "                 [min-disp, max-disp], black = no value) with its\n"
    "                 colour bar and scale on the right\n"
    "  --confidence FILE  also write the engine's confidence map as an 8-bit\n"
    "                 grey PNG: 0 = no value, 2 = filled from neighbours,\n"
    "                 4 = textureless, 8..255 = matched (~255 x NCC);\n"
    "                 negobs/stereo.h, NEGOBS_STEREO_CONF_*\n"
    "  --align        estimate the vertical misalignment (sub-pixel offset,\n"
    "                 row and column slopes; negobs/valign.h) and resample\n"
    "                 RIGHT to LEFT's rows before matching: for pairs that\n"
    "                 are not rectified (e.g. the SurDis wearable)\n"
    "  --calib TABLE  rectify LEFT/RIGHT first with a negobs_calib table (the\n"
    "                 library's remap, as negobs_run --calib); the images must\n"
    "                 have the table's size (exit 3 otherwise, 2 for an\n"
    "                 unreadable or corrupt table)\n"
    "  --halfshift    average each sub-pixel offset with the one on the\n"
    "                 right image shifted by half a pixel, which cancels\n"
    "                 the parabola's pull towards whole pixels (the\n"
    "                 library's subpixel_halfshift; off by default, the\n"
    "                 pipeline's half-size pass turns it on)\n"
    "  --dense        keep the values whose match falls left of the right\n"
    "                 image (the library's default); without it they get\n"
    "                 no value: the right camera never saw those points\n"
    "  -s, --stats    print the engine statistics and timing (total and per\n"
    "                 stage, thread CPU time) to stderr; with --threads N > 1\n"
    "                 the stages add up every thread's time, the total is\n"
    "                 the calling thread's\n"
    "  --threads N    threads for the engine's row bands, 1..64 (default 1);\n"
    "                 the output is the same for every N\n"
    "  --stages FILE  also write one picture of the map after every stage\n"
    "                 (GCS, DP, LR check, speckles, gap fill, adaptive\n"
    "                 mean) beside LEFT, colours as --color, each tile\n"
    "                 labelled with its density (.png/.jpg/.ppm/.bmp)\n"
    "  -h, --help     this text\n"
    "  -V, --version  the negobs version\n"
    "Options take their value as --opt VALUE or --opt=VALUE.\n"
    "\n"
    "Exit codes (0-2 as every negobs tool):\n"
    "  0  success\n"
    "  1  an input image cannot be read or decoded\n"
    "  2  bad command line or disparity range (also: no arguments)\n"
    "  3  left and right sizes differ, or the size is not supported\n"
    "  4  the negobs library reported an error\n"
    "  5  an output file cannot be written\n";

// The largest --max-disp the engine accepts for a width x height frame
// and this --min-disp, asked from the library itself (its bound follows
// from the matching window and the 16-bit Q4 output, and is private to it;
// acceptance only grows as max_disp falls). A value above it is a usage
// error, named before any work; the library's own refusal would come late
// and read as a library failure. Returns min_disp when it accepts none.
int engine_max_disp(int width, int height, int min_disp)
{
    auto accepted = [&](int max_disp) {
        negobs_stereo_config_t cfg;
        negobs_stereo_config_default(&cfg, width, height);
        cfg.min_disp = min_disp;
        cfg.max_disp = max_disp;
        size_t bytes = 0;
        return negobs_stereo_workspace_size(&cfg, &bytes) == NEGOBS_OK;
    };
    int lo = min_disp; // the largest value known to be accepted (or none)
    int hi = std::min({width - 1, negobs_tools::kMaxDispLimit,
                       min_disp + NEGOBS_STEREO_MAX_RANGE - 1});
    if (hi <= lo || !accepted(lo + 1)) {
        return min_disp;
    }
    lo = lo + 1;
    while (lo < hi) {
        const int mid = lo + (hi - lo + 1) / 2;
        if (accepted(mid)) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    return lo;
}

std::string check_engine_range(const negobs_tools::Range &r, int width,
                               int height, const char *frame)
{
    const int top = engine_max_disp(width, height, r.min_disp);
    if (r.max_disp <= top) {
        return std::string();
    }
    return "--max-disp " + std::to_string(r.max_disp) +
           " is beyond the engine's range for " + frame + " with --min-disp " +
           std::to_string(r.min_disp) + ": --max-disp must be " +
           std::to_string(r.min_disp + 1) + ".." + std::to_string(top);
}

bool write_png(const std::string &path, const cv::Mat &img)
{
    try {
        return cv::imwrite(path, img);
    } catch (const cv::Exception &e) {
        std::fprintf(stderr, "negobs_stereo: cannot write '%s': %s\n",
                     path.c_str(), e.what());
        return false;
    }
}

// The library's alignment stage on one pair: estimate, then resample.
bool align_right(const cv::Mat &left, const cv::Mat &right,
                 const negobs_tools::Range &range, cv::Mat &aligned,
                 std::string &text, std::string &err)
{
    negobs_valign_config_t cfg;
    negobs_valign_config_default(&cfg, left.cols, left.rows);
    cfg.min_disp = range.min_disp;
    cfg.max_disp = range.max_disp < left.cols ? range.max_disp : left.cols - 1;
    if (cfg.max_disp - cfg.min_disp > 255) {
        cfg.max_disp = cfg.min_disp + 255;
    }
    size_t bytes = 0;
    negobs_status_t st = negobs_valign_workspace_size(&cfg, &bytes);
    if (st != NEGOBS_OK) {
        err = std::string("alignment stage refused the size: ") +
              negobs_status_str(st);
        return false;
    }
    std::vector<unsigned char> raw(bytes + 16);
    void *p = raw.data();
    size_t space = raw.size();
    void *ws = std::align(16, bytes, p, space);
    negobs_valign_t ctx;
    st = negobs_valign_init(&ctx, &cfg, ws, bytes);
    aligned.create(right.size(), CV_8UC1);
    negobs_image_u8_t l{const_cast<uint8_t *>(left.ptr<uint8_t>(0)), left.cols,
                        left.rows, static_cast<int32_t>(left.step1())};
    negobs_image_u8_t r{const_cast<uint8_t *>(right.ptr<uint8_t>(0)),
                        right.cols, right.rows,
                        static_cast<int32_t>(right.step1())};
    negobs_image_u8_t o{aligned.ptr<uint8_t>(0), aligned.cols, aligned.rows,
                        static_cast<int32_t>(aligned.step1())};
    negobs_valign_stats_t vs;
    if (st == NEGOBS_OK) {
        st = negobs_valign_process(&ctx, &l, &r, &o, &vs);
    }
    if (st != NEGOBS_OK) {
        err = std::string("alignment stage: ") + negobs_status_str(st);
        return false;
    }
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "alignment %s: right row = left row + %.3f %+.5f (y - %d) "
                  "%+.5f (x - %d) px; %d tiles, residual %.3f px",
                  vs.accepted ? "estimated"
                              : "not estimated (too little "
                                "texture), rows unchanged",
                  vs.model.offset_q16 / 65536.0,
                  vs.model.slope_y_q16 / 65536.0, left.rows / 2,
                  vs.model.slope_x_q16 / 65536.0, left.cols / 2, vs.tiles_used,
                  vs.resid_q4 / 16.0);
    text = buf;
    return true;
}

// LEFT and the map after every stage in one picture, two rows of tiles,
// each under a caption with the stage and the share of pixels with a value.
cv::Mat stage_montage(
    const cv::Mat &left,
    const std::vector<negobs_tools::NegobsMatcher::Snapshot> &snaps,
    const negobs_tools::Range &range)
{
    const int cap = 22;
    const int w = left.cols;
    const int h = left.rows;
    const int tiles = static_cast<int>(snaps.size()) + 1;
    const int cols = (tiles + 1) / 2;
    cv::Mat out((h + cap) * 2, w * cols, CV_8UC3, cv::Scalar(255, 255, 255));
    for (int t = 0; t < tiles; ++t) {
        cv::Mat tile;
        std::string label;
        if (t == 0) {
            cv::cvtColor(left, tile, cv::COLOR_GRAY2BGR);
            label = "left image";
        } else {
            const auto &sn = snaps[static_cast<size_t>(t - 1)];
            cv::Mat d, v;
            negobs_tools::negobs_q4_to_float(sn.disp_q4, d, v);
            tile = negobs_tools::colourise(d, v, range.min_disp,
                                           range.max_disp);
            char buf[96];
            std::snprintf(buf, sizeof buf, "%d. after %s: %.1f %%", t,
                          sn.name.c_str(),
                          100.0 * cv::countNonZero(v) / double(w * h));
            label = buf;
        }
        const int x0 = (t % cols) * w;
        const int y0 = (t / cols) * (h + cap);
        tile.copyTo(out(cv::Rect(x0, y0 + cap, w, h)));
        cv::putText(out, label, cv::Point(x0 + 4, y0 + cap - 6),
                    cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1,
                    cv::LINE_AA);
    }
    return out;
}

const struct option kLongOpts[] = {
    {"help", no_argument, nullptr, 'h'},
    {"version", no_argument, nullptr, 'V'},
    {"max-disp", required_argument, nullptr, 'D'},
    {"min-disp", required_argument, nullptr, 'd'},
    {"format", required_argument, nullptr, 'f'},
    {"color", required_argument, nullptr, 'c'},
    {"colour", required_argument, nullptr, 'c'},
    {"confidence", required_argument, nullptr, 'C'},
    {"stages", required_argument, nullptr, 'S'},
    {"stats", no_argument, nullptr, 's'},
    {"align", no_argument, nullptr, 'a'},
    {"dense", no_argument, nullptr, 'e'},
    {"halfshift", no_argument, nullptr, 'H'},
    {"calib", required_argument, nullptr, 'K'},
    {"threads", required_argument, nullptr, 'T'},
    {nullptr, 0, nullptr, 0},
};

int run(int argc, char **argv)
{
    std::vector<std::string> pos;
    negobs_tools::Range range;
    std::string colour_path;
    std::string conf_path;
    std::string stages_path;
    std::string calib_path;
    negobs_cli::DispFormat format = negobs_cli::DispFormat::Png16;
    bool stats = false;
    bool align = false;
    bool dense = false;
    bool halfshift = false;
    int threads = 1; // the times of --stats stay one thread's CPU time
    if (argc < 2) {
        std::fputs(kHelp, stderr);
        return EXIT_USAGE;
    }
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":hVD:d:f:c:s", kLongOpts, nullptr)) !=
           -1) {
        switch (c) {
        case 'h': std::fputs(kHelp, stdout); return EXIT_OK;
        case 'V': negobs_cli::print_version("negobs_stereo"); return EXIT_OK;
        case 'D':
        case 'd':
            (c == 'D' ? range.max_disp : range.min_disp) = negobs_cli::int_arg(
                c == 'D' ? "--max-disp" : "--min-disp", optarg, -100000,
                100000);
            break;
        case 'f':
            if (!negobs_cli::parse_disp_format(optarg, format)) {
                throw negobs_cli::UsageError(std::string("--format '") +
                                             optarg +
                                             "' is not png16, kitti or pfm");
            }
            break;
        case 'c': colour_path = optarg; break;
        case 'C': conf_path = optarg; break;
        case 'S': stages_path = optarg; break;
        case 's': stats = true; break;
        case 'a': align = true; break;
        case 'e': dense = true; break;
        case 'H': halfshift = true; break;
        case 'K': calib_path = optarg; break;
        case 'T':
            threads = negobs_cli::int_arg("--threads", optarg, 1,
                                          NEGOBS_POOL_MAX_THREADS);
            break;
        case ':':
            throw negobs_cli::UsageError(std::string(argv[optind - 1]) +
                                         " needs a value");
        default:
            throw negobs_cli::UsageError("unknown option '" +
                                         std::string(argv[optind - 1]) + "'");
        }
    }
    for (int i = optind; i < argc; ++i) {
        pos.emplace_back(argv[i]);
    }
    if (pos.size() != 3) {
        std::fprintf(stderr,
                     "negobs_stereo: need LEFT RIGHT OUT (got %zu "
                     "file names); see --help\n",
                     pos.size());
        return EXIT_USAGE;
    }
    const std::string &out = pos[2];
    auto has_ext = [](const std::string &p, const std::string &e) {
        if (p.size() <= e.size())
            return false;
        std::string t = p.substr(p.size() - e.size());
        for (char &ch : t)
            ch = static_cast<char>(
                std::tolower(static_cast<unsigned char>(ch)));
        return t == e;
    };
    auto picture_ext = [&](const std::string &p) {
        return p.empty() || has_ext(p, ".png") || has_ext(p, ".jpg") ||
               has_ext(p, ".ppm") || has_ext(p, ".bmp");
    };
    const bool pfm = format == negobs_cli::DispFormat::Pfm;
    if (!has_ext(out, pfm ? ".pfm" : ".png") ||
        (!conf_path.empty() && !has_ext(conf_path, ".png")) ||
        !picture_ext(colour_path) || !picture_ext(stages_path)) {
        std::fprintf(stderr, "negobs_stereo: OUT must end in .png (.pfm "
                             "with --format pfm), --confidence in .png "
                             "(lossless); --color and --stages in "
                             ".png/.jpg/.ppm/.bmp\n");
        return EXIT_USAGE;
    }
    // KITTI's x256 scale stores at most 255.996 px: a wider search could
    // produce a value the file cannot hold, so it is refused before any
    // work rather than clipped.
    if (format == negobs_cli::DispFormat::Kitti && range.max_disp > 255) {
        std::fprintf(stderr,
                     "negobs_stereo: --format kitti stores disparities up "
                     "to 255.996 px: --max-disp must be <= 255\n");
        return EXIT_USAGE;
    }
    std::string err = negobs_tools::check_range(range, 0);
    if (err.empty()) {
        // the bound no frame size lifts (the widest frame the engine takes)
        err = check_engine_range(range, NEGOBS_MAX_DIM, NEGOBS_MAX_DIM,
                                 "any frame");
    }
    if (!err.empty()) {
        std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
        return EXIT_USAGE;
    }

    cv::Mat left, right;
    if (!negobs_tools::load_grey(pos[0], left, err) ||
        !negobs_tools::load_grey(pos[1], right, err)) {
        std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
        return EXIT_INPUT;
    }
    if (left.size() != right.size()) {
        std::fprintf(stderr,
                     "negobs_stereo: size mismatch: left %dx%d, right %dx%d\n",
                     left.cols, left.rows, right.cols, right.rows);
        return EXIT_SIZE;
    }
    if (!calib_path.empty()) {
        negobs_rect_tools::RectTable rect;
        err = rect.load(calib_path);
        if (!err.empty()) {
            std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
            return EXIT_INPUT;
        }
        err = rect.apply(left, right);
        if (!err.empty()) {
            std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
            return EXIT_SIZE;
        }
    }
    // Size first (with a trivial range), then the range against the size.
    err = negobs_tools::check_engine_limits(negobs_tools::Range{0, 1},
                                            left.cols, left.rows);
    if (!err.empty()) {
        std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
        return EXIT_SIZE;
    }
    err = negobs_tools::check_range(range, left.cols);
    if (err.empty())
        err = negobs_tools::check_engine_limits(range, left.cols, left.rows);
    if (err.empty()) {
        const std::string frame = "a " + std::to_string(left.cols) + "x" +
                                  std::to_string(left.rows) + " frame";
        err = check_engine_range(range, left.cols, left.rows, frame.c_str());
    }
    if (!err.empty()) {
        std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
        return EXIT_USAGE;
    }

    negobs_tools::NegobsMatcher m;
    m.set_threads(threads);
    m.set_subpixel_halfshift(halfshift);
    if (!m.init(left.cols, left.rows, range, err, -1, dense ? 1 : 0)) {
        std::fprintf(stderr, "negobs_stereo: %s (size %dx%d, range %d..%d)\n",
                     err.c_str(), left.cols, left.rows, range.min_disp,
                     range.max_disp);
        return EXIT_LIBRARY;
    }
    m.profile_stages(stats);
    m.keep_stages(!stages_path.empty());
    cv::Mat disp_q4, conf;
    const int64 t0 = cv::getTickCount();
    std::string align_text;
    if (align) {
        cv::Mat aligned;
        if (!align_right(left, right, range, aligned, align_text, err)) {
            std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
            return EXIT_LIBRARY;
        }
        right = aligned;
    }
    if (!m.process(left, right, disp_q4, conf, err)) {
        std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
        return EXIT_LIBRARY;
    }
    const double ms = 1000.0 * double(cv::getTickCount() - t0) /
                      cv::getTickFrequency();
    if (stats) {
        std::fprintf(stderr,
                     "negobs_stereo: %dx%d range %d..%d: %.1f ms, "
                     "workspace %zu bytes, %s\n",
                     left.cols, left.rows, range.min_disp, range.max_disp, ms,
                     m.workspace_bytes(), m.last_stats().c_str());
        if (align) {
            std::fprintf(stderr, "negobs_stereo: %s\n", align_text.c_str());
        }
        // the confidence scale of negobs/stereo.h, counted
        long n_none = 0, n_filled = 0, n_flat = 0, n_matched = 0, n_other = 0;
        for (int y = 0; y < conf.rows; ++y) {
            const uint8_t *c = conf.ptr<uint8_t>(y);
            for (int x = 0; x < conf.cols; ++x) {
                if (c[x] == NEGOBS_STEREO_CONF_NONE)
                    ++n_none;
                else if (c[x] == NEGOBS_STEREO_CONF_FILLED)
                    ++n_filled;
                else if (c[x] == NEGOBS_STEREO_CONF_FLAT)
                    ++n_flat;
                else if (c[x] >= NEGOBS_STEREO_CONF_MATCHED_MIN)
                    ++n_matched;
                else
                    ++n_other;
            }
        }
        std::fprintf(stderr,
                     "negobs_stereo: confidence: %ld matched, %ld filled, "
                     "%ld textureless, %ld no value, %ld other\n",
                     n_matched, n_filled, n_flat, n_none, n_other);
    }

    if (format == negobs_cli::DispFormat::Png16) {
        // the Q4 values are already disparity x 16: written as they are
        if (!write_png(out, negobs_tools::negobs_q4_to_png16(disp_q4))) {
            std::fprintf(stderr, "negobs_stereo: cannot write '%s'\n",
                         out.c_str());
            return EXIT_OUTPUT;
        }
    } else {
        cv::Mat d, v;
        negobs_tools::negobs_q4_to_float(disp_q4, d, v);
        if (!negobs_cli::write_disparity(out, d, v, format, err)) {
            std::fprintf(stderr, "negobs_stereo: %s\n", err.c_str());
            return EXIT_OUTPUT;
        }
    }
    if (!conf_path.empty() && !write_png(conf_path, conf)) {
        std::fprintf(stderr, "negobs_stereo: cannot write '%s'\n",
                     conf_path.c_str());
        return EXIT_OUTPUT;
    }
    if (!colour_path.empty()) {
        cv::Mat d, v;
        negobs_tools::negobs_q4_to_float(disp_q4, d, v);
        // the scale beside the picture: which colour is which disparity
        if (!write_png(colour_path,
                       negobs_cli::with_colour_bar(
                           negobs_tools::colourise(d, v, range.min_disp,
                                                   range.max_disp),
                           cv::COLORMAP_TURBO, range.min_disp, range.max_disp,
                           "px"))) {
            std::fprintf(stderr, "negobs_stereo: cannot write '%s'\n",
                         colour_path.c_str());
            return EXIT_OUTPUT;
        }
    }
    if (!stages_path.empty() &&
        !write_png(stages_path, stage_montage(left, m.stages(), range))) {
        std::fprintf(stderr, "negobs_stereo: cannot write '%s'\n",
                     stages_path.c_str());
        return EXIT_OUTPUT;
    }
    return EXIT_OK;
}

} // namespace

int main(int argc, char **argv)
{
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    // an exception that escapes is an internal failure, as a library error
    return negobs_cli::main_guard("negobs_stereo", argc, argv, run,
                                  EXIT_LIBRARY);
}
