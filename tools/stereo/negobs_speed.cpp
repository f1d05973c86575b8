// negobs_speed: one negobs_stereo_process() and one OpenCV StereoSGBM
// compute() (single thread, same parameters as negobs_eval) on the same
// pair, each bracketed by callgrind client requests, so that
//   valgrind --tool=callgrind --collect-atstart=no negobs_speed L R ...
// counts the instructions of the two matching calls alone (image loading,
// matcher creation and workspace allocation are outside). Instruction
// counts do not depend on the machine's load, unlike times. Without
// valgrind the requests are no-ops and the tool prints CPU times only.
//
// usage: negobs_speed LEFT RIGHT [--crop X,Y,W,H] [-D|--max-disp D]
//                    [--profile compact|fast] [--write-pgm PREFIX]
//                    (exit codes: docs/TOOLS.md)
// --write-pgm also writes the (cropped) grey pair as PREFIXleft.pgm and
// PREFIXright.pgm, the input of bench_frames on targets without OpenCV.
// The callgrind dumps are named "negobs" and "sgbm" in that order
// (tools/negobs bench reads them).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <getopt.h>
#include <memory>
#include <string>
#include <time.h>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#if defined(__has_include)
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#endif
#endif
#ifndef CALLGRIND_TOGGLE_COLLECT
#define CALLGRIND_TOGGLE_COLLECT
#define CALLGRIND_DUMP_STATS_AT(name) (void)(name)
#endif

#include "negobs/stereo.h"
#include "cli.hpp"
#include "stereo_common.hpp"

namespace {

double cpu_ms()
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 +
           static_cast<double>(ts.tv_nsec) / 1e6;
}

// FNV-1a of the map, to compare profiles and builds at a glance.
uint32_t map_hash(const cv::Mat &m)
{
    uint32_t h = 2166136261u;
    for (int y = 0; y < m.rows; ++y) {
        const uint8_t *p = m.ptr<uint8_t>(y);
        for (size_t i = 0; i < static_cast<size_t>(m.cols) * m.elemSize();
             ++i) {
            h = (h ^ p[i]) * 16777619u;
        }
    }
    return h;
}

const char *const kUsage =
    "usage: negobs_speed LEFT RIGHT [--crop X,Y,W,H] [-D|--max-disp D]\n"
    "                    [--profile compact|fast] [--write-pgm PREFIX]\n"
    "One negobs and one OpenCV SGBM matching call, each between callgrind\n"
    "client requests (run it under valgrind --tool=callgrind\n"
    "--collect-atstart=no; tools/negobs bench does). -h/--help, -V/--version.\n"
    "Exit: 0 ok, 1 data error, 2 bad command line (also: no arguments).\n";

// a usage error: the message, the usage, exit 2 (the tools' common table)
int usage(const char *msg)
{
    if (msg != nullptr) {
        std::fprintf(stderr, "negobs_speed: %s\n", msg);
    }
    std::fputs(kUsage, stderr);
    return negobs_cli::kExitUsage;
}

const struct option kLongOpts[] = {
    {"help", no_argument, nullptr, 'h'},
    {"version", no_argument, nullptr, 'V'},
    {"crop", required_argument, nullptr, 'c'},
    {"max-disp", required_argument, nullptr, 'D'},
    {"profile", required_argument, nullptr, 'p'},
    {"write-pgm", required_argument, nullptr, 'w'},
    {nullptr, 0, nullptr, 0},
};

} // namespace

int main(int argc, char **argv)
{
    std::vector<std::string> pos;
    int cx = 0, cy = 0, cw = 0, ch = 0, max_disp = 63;
    int profile = -1;
    std::string pgm_prefix;
    if (argc < 2) {
        return usage(nullptr);
    }
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":hVD:", kLongOpts, nullptr)) != -1) {
        const std::string v = optarg ? optarg : "";
        if (c == 'h') {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (c == 'V') {
            negobs_cli::print_version("negobs_speed");
            return 0;
        } else if (c == 'c') {
            if (std::sscanf(optarg, "%d,%d,%d,%d", &cx, &cy, &cw, &ch) != 4 ||
                cw <= 0 || ch <= 0 || cx < 0 || cy < 0) {
                return usage("--crop takes X,Y,W,H");
            }
        } else if (c == 'D') {
            if (!negobs_cli::parse_int(optarg, 1, negobs_tools::kMaxDispLimit,
                                       max_disp)) {
                return usage("--max-disp takes an integer 1..2047");
            }
        } else if (c == 'w') {
            pgm_prefix = v;
        } else if (c == 'p') {
            if (!negobs_cli::parse_memory_profile(v.c_str(), profile)) {
                return usage("--profile takes compact or fast");
            }
        } else if (c == ':') {
            return usage(
                (std::string(argv[optind - 1]) + " needs a value").c_str());
        } else {
            return usage(
                ("unknown option " + std::string(argv[optind - 1])).c_str());
        }
    }
    for (int i = optind; i < argc; ++i) {
        pos.emplace_back(argv[i]);
    }
    if (pos.size() != 2) {
        return usage("need LEFT and RIGHT");
    }
    cv::Mat l, r;
    std::string err;
    if (!negobs_tools::load_grey(pos[0], l, err) ||
        !negobs_tools::load_grey(pos[1], r, err)) {
        std::fprintf(stderr, "negobs_speed: %s\n", err.c_str());
        return negobs_cli::kExitData;
    }
    if (l.size() != r.size()) {
        std::fprintf(stderr, "negobs_speed: images differ in size\n");
        return negobs_cli::kExitData;
    }
    if (cw > 0) {
        if (cx + cw > l.cols || cy + ch > l.rows) {
            return usage("--crop leaves the image");
        }
        l = l(cv::Rect(cx, cy, cw, ch)).clone();
        r = r(cv::Rect(cx, cy, cw, ch)).clone();
    }
    if (!pgm_prefix.empty() && (!cv::imwrite(pgm_prefix + "left.pgm", l) ||
                                !cv::imwrite(pgm_prefix + "right.pgm", r))) {
        std::fprintf(stderr, "negobs_speed: cannot write %s*.pgm\n",
                     pgm_prefix.c_str());
        return negobs_cli::kExitData;
    }
    cv::setNumThreads(0); // SGBM single-threaded, like negobs

    negobs_stereo_config_t cfg;
    std::memset(&cfg, 0, sizeof cfg);
    negobs_stereo_config_default(&cfg, l.cols, l.rows);
    cfg.max_disp = max_disp;
    if (profile >= 0) {
        cfg.memory_profile = profile;
    }
    size_t bytes = 0;
    negobs_stereo_t ctx;
    std::memset(&ctx, 0, sizeof ctx);
    if (negobs_stereo_workspace_size(&cfg, &bytes) != NEGOBS_OK) {
        std::fprintf(stderr, "negobs_speed: bad negobs config\n");
        return negobs_cli::kExitData;
    }
    std::vector<uint64_t> ws((bytes + 7) / 8 + 2);
    void *p = ws.data();
    size_t space = ws.size() * 8;
    p = std::align(16, bytes, p, space);
    if (p == nullptr ||
        negobs_stereo_init(&ctx, &cfg, p, bytes) != NEGOBS_OK) {
        std::fprintf(stderr, "negobs_speed: negobs init failed\n");
        return negobs_cli::kExitData;
    }
    cv::Mat disp(l.rows, l.cols, CV_16SC1);
    negobs_image_u8_t li = {l.data, l.cols, l.rows,
                            static_cast<int32_t>(l.step)};
    negobs_image_u8_t ri = {r.data, r.cols, r.rows,
                            static_cast<int32_t>(r.step)};
    negobs_image_s16_t di = {reinterpret_cast<int16_t *>(disp.data), disp.cols,
                             disp.rows, static_cast<int32_t>(disp.step / 2)};

    negobs_tools::Range range;
    range.min_disp = 0;
    range.max_disp = max_disp;
    const int bs = 5;
    cv::Ptr<cv::StereoSGBM> sgbm = cv::StereoSGBM::create(
        0, negobs_tools::opencv_num_disparities(range), bs, 8 * bs * bs,
        32 * bs * bs, 1, 63, 10, 100, 32, cv::StereoSGBM::MODE_SGBM);
    cv::Mat sd;

    double t0 = cpu_ms();
    CALLGRIND_TOGGLE_COLLECT;
    negobs_stereo_stats_t stats;
    negobs_status_t st = negobs_stereo_process(&ctx, &li, &ri, &di, nullptr,
                                               &stats);
    CALLGRIND_TOGGLE_COLLECT;
    CALLGRIND_DUMP_STATS_AT("negobs");
    double t1 = cpu_ms();
    CALLGRIND_TOGGLE_COLLECT;
    sgbm->compute(l, r, sd);
    CALLGRIND_TOGGLE_COLLECT;
    CALLGRIND_DUMP_STATS_AT("sgbm");
    double t2 = cpu_ms();
    if (st != NEGOBS_OK) {
        std::fprintf(stderr, "negobs_speed: negobs_stereo_process failed\n");
        return 3;
    }
    std::printf("%dx%d D=%d negobs %.1f ms (workspace %zu bytes), SGBM %.1f ms"
                " (CPU time, one run each)\n",
                l.cols, l.rows, max_disp + 1, t1 - t0, bytes, t2 - t1);
    long valid = 0;
    for (int y = 0; y < disp.rows; ++y) {
        const int16_t *row = disp.ptr<int16_t>(y);
        for (int x = 0; x < disp.cols; ++x) {
            valid += row[x] != NEGOBS_DISP_INVALID;
        }
    }
    std::printf("negobs: %u seeds, %u grown, %u cells scored, %ld valid px, "
                "map checksum %08lx\n",
                stats.seeds, stats.grown, stats.visited_cells, valid,
                static_cast<unsigned long>(map_hash(disp)));
    return 0;
}
