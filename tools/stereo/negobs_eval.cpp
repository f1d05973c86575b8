// negobs_eval: accuracy and speed of negobs against OpenCV StereoBM and
// StereoSGBM on every ground-truth pair of $NEGOBS_DATA/manifest.tsv and on
// Debian opencv-doc's aloe pair, in one single-threaded run.
//
// See --help for the options, the metrics and the exit codes; the matcher
// parameters are documented next to make_bm() / make_sgbm() and in
// docs/EVALUATION.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <getopt.h>
#include <limits>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <time.h>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli.hpp"
#include "colour_bar.hpp"
#include "eval_score.hpp"
#include "occlusion.hpp"
#include "stereo_common.hpp"

#ifndef NEGOBS_BUILD_TYPE
#define NEGOBS_BUILD_TYPE "unknown"
#endif

namespace {

using negobs_tools::Range;

// 0 / 1 / 2 / 77 as every negobs tool (tools/common/cli.hpp); 3, 4 its own.
enum Exit {
    EXIT_OK = negobs_cli::kExitOk,
    EXIT_DATA = negobs_cli::kExitData, // manifest or a file unreadable,
                                       // set unknown
    EXIT_USAGE = negobs_cli::kExitUsage,
    EXIT_CHECK = 3,                    // --check thresholds not met
    EXIT_LIBRARY = 4,                  // negobs or OpenCV failed on a pair
    EXIT_SKIP = negobs_cli::kExitSkip, // --check: data absent
};

const char *const kAloeSet = "aloe-opencv-doc";

const char *const kHelp =
    "usage: negobs_eval --all | --set NAME... | --list [options]\n"
    "       negobs_eval --score MAP --gt GT [--gt-scale S] [--mask M]\n"
    "                   [--format F] [--csv FILE] [--json FILE]\n"
    "\n"
    "Without arguments it prints this text and exits 2: the full\n"
    "evaluation takes a long time, so it runs only when asked (--all, or\n"
    "any option that selects or writes something).\n"
    "\n"
    "Runs negobs, OpenCV StereoBM and OpenCV StereoSGBM on every pair with\n"
    "ground truth (GT) listed in DATA/manifest.tsv and on Debian opencv-doc's\n"
    "aloe pair (set name 'aloe-opencv-doc'), single-threaded, in one process,\n"
    "and prints per set and matcher:\n"
    "  density  % of evaluated pixels that got a disparity\n"
    "  bad1     % of evaluated pixels WITH a value whose |error| > 1 px\n"
    "  bad1all  % of evaluated pixels that are wrong by > 1 px OR have no value\n"
    "  bad2     % of evaluated pixels with a value whose |error| > 2 px\n"
    "  rms      RMS error (px) over evaluated pixels with a value\n"
    "  time     best-of-N CPU time of this thread (all matchers run on it)\n"
    "           for the matching call alone (no I/O, no grey conversion, no\n"
    "           matcher creation); the console also shows best-of-N wall\n"
    "           time\n"
    "  negobs/BM, negobs/SGBM  time ratios (< 1: negobs is faster)\n"
    "Evaluated pixels: inside the set's non-occlusion mask where it has one,\n"
    "else every pixel with known GT. All three matchers search the same range\n"
    "0..max_disp (manifest column; OpenCV's numDisparities rounded up to 16).\n"
    "A second table scores the same maps on non-occluded pixels only, the\n"
    "protocol of the paper's Table 5 (printed beside it): the set's mask, else\n"
    "a mask derived from the right-view GT found beside the GT by Middlebury's\n"
    "naming (disp1 for view1 -> disp5 for view5; disp2 -> disp6): a left pixel\n"
    "with GT d counts when the right GT at x - d agrees within 1 px.\n"
    "\n"
    "Options:\n"
    "  --data DIR        data folder (default $NEGOBS_DATA, else\n"
    "                    <repo>/../shared/data for a binary in its build\n"
    "                    tree, none when installed); absent -> its sets are\n"
    "                    skipped\n"
    "  --opencv-doc DIR  folder with aloeL.jpg, aloeR.jpg, aloeGT.png\n"
    "                    (default /usr/share/doc/opencv-doc/examples/data)\n"
    "  --all             every available set (the default selection)\n"
    "  -s, --set NAME    evaluate this set only (repeatable; exact name)\n"
    "  --list            list the available sets and exit\n"
    "  --matchers LIST   comma list of negobs,bm,sgbm (default all three;\n"
    "                    negobs only with --check)\n"
    "  --threads N       negobs' row bands on N threads (default 1; the maps\n"
    "                    are the same, its CPU ms then counts the calling\n"
    "                    thread only)\n"
    "  --repeat N        timing runs per matcher, best kept (default 3;\n"
    "                    1 with --check)\n"
    "  -m, --markdown FILE  write the table as Markdown\n"
    "  -c, --csv FILE    write one line per set and matcher as CSV (set,\n"
    "                    matcher, width, height, evaluated_px, density_pct,\n"
    "                    bad1_pct, bad1all_pct, bad2_pct, rms_px, cpu_ms)\n"
    "  -j, --json FILE   the same rows as a JSON array of objects\n"
    "                    (FILE '-' for both: stdout)\n"
    "  --progress        progress with an ETA on stderr, one line per set\n"
    "                    (default: redrawn in place when stderr is a\n"
    "                    terminal, off otherwise); --no-progress: never\n"
    "  --plots DIR       write DIR/eval_bad1all.png and DIR/eval_time.png\n"
    "  --pictures DIR    write DIR/eval_<set>.png: negobs | BM | SGBM | GT colour\n"
    "                    maps (TURBO over 0..max_disp, black = no value)\n"
    "  --pictures-format png|jpg   (default png)\n"
    "  --pictures-width N          shrink wider pictures to N px (1600)\n"
    "  --drop-out-of-view  negobs drops the values whose match falls left\n"
    "                    of the right image (keep_out_of_view = 0; the\n"
    "                    default keeps them, as the library does)\n"
    "  --check MAXBAD1 MINDENSITY\n"
    "                    regression guard: fail unless, on every selected\n"
    "                    set, negobs bad1 <= MAXBAD1 and density >=\n"
    "                    MINDENSITY (both in %)\n"
    "  -h, --help        this text\n"
    "  -V, --version     the negobs version\n"
    "\n"
    "Scoring one map (any matcher), like Middlebury's evaldisp:\n"
    "  --score MAP       the disparity map: png16 (x16, 0 = no value), kitti\n"
    "                    (x256), pfm (non-finite = no value); by -f, else\n"
    "                    .pfm -> pfm, other images -> png16\n"
    "  -f, --format F    auto (default), png16, kitti or pfm\n"
    "  --map-scale S     divide the map's values by S instead (e.g. 1 for\n"
    "                    an 8-bit map that holds pixels)\n"
    "  --gt GT           ground truth: PFM (inf = unknown), or an image whose\n"
    "                    value / S is the disparity, 0 = unknown\n"
    "  --gt-scale S      default: 1 for PFM and 8-bit images (full-size\n"
    "                    Middlebury), 256 for 16-bit PNG (KITTI); 2 or 4\n"
    "                    for half / quarter size Middlebury\n"
    "  --mask M          evaluate only where M is 255 (Middlebury's\n"
    "                    non-occlusion masks: 128 occluded, 0 unknown)\n"
    "  --name NAME       the set column of the output (default: MAP's name)\n"
    "  The metrics are the ones above; a line goes to stdout unless a\n"
    "  table is written there ('-'); -m/-c/-j write Markdown/CSV/JSON.\n"
    "Options take their value as --opt VALUE or --opt=VALUE.\n"
    "\n"
    "Exit codes (0-2 and 77 as every negobs tool):\n"
    "  0   success (and --check passed)\n"
    "  1   data error: manifest, a listed image, a map or GT unreadable,\n"
    "      size mismatch, unknown --set, no GT pixel to score\n"
    "  2   bad command line (also: no arguments)\n"
    "  3   --check failed\n"
    "  4   a matcher (negobs library or OpenCV) failed\n"
    "  77  --check could not run: data absent\n"
    "      (Meson counts it as skipped)\n";

bool is_dir(const std::string &p)
{
    struct stat st;
    return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool is_file(const std::string &p)
{
    struct stat st;
    return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

// mkdir -p; true when the folder exists afterwards.
bool make_dirs(const std::string &p)
{
    for (size_t i = 1; i <= p.size(); ++i) {
        if (i == p.size() || p[i] == '/') {
            const std::string part = p.substr(0, i);
            if (!is_dir(part) && ::mkdir(part.c_str(), 0755) != 0 &&
                !is_dir(part))
                return false;
        }
    }
    return is_dir(p);
}

bool parse_double(const char *s, double &out)
{
    if (!s || !*s)
        return false;
    char *end = nullptr;
    out = std::strtod(s, &end);
    return *end == '\0' && std::isfinite(out);
}

struct SetSpec {
    std::string name;
    std::string left, right, gt, mask; // absolute paths; mask may be empty
    std::string gt_right;              // right-view GT beside gt ("" if none)
    double gt_scale = 1.0;
    int max_disp = 0; // 0: derive from the GT
    std::string origin;
};

std::vector<std::string> split(const std::string &s, char sep)
{
    std::vector<std::string> out;
    std::string cur;
    std::istringstream in(s);
    while (std::getline(in, cur, sep))
        out.push_back(cur);
    if (!s.empty() && s.back() == sep)
        out.push_back(std::string());
    return out;
}

// Reads the GT rows of DATA/manifest.tsv. Returns false (err set) when the
// file exists but is malformed.
bool read_manifest(const std::string &dir, std::vector<SetSpec> &sets,
                   int &no_gt, std::string &err)
{
    const std::string path = dir + "/manifest.tsv";
    std::ifstream in(path);
    if (!in) {
        err = "cannot read " + path;
        return false;
    }
    std::string line;
    int lineno = 0;
    no_gt = 0;
    while (std::getline(in, line)) {
        ++lineno;
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (line.empty() || line[0] == '#')
            continue;
        const std::vector<std::string> f = split(line, '\t');
        if (lineno == 1 && !f.empty() && f[0] == "set")
            continue; // header
        if (f.size() < 7) {
            err = path + ":" + std::to_string(lineno) +
                  ": expected at least 7 tab-separated columns";
            return false;
        }
        if (f[3] == "-" || f[3].empty()) {
            ++no_gt;
            continue;
        }
        SetSpec s;
        s.name = f[0];
        s.left = dir + "/" + f[1];
        s.right = dir + "/" + f[2];
        s.gt = dir + "/" + f[3];
        s.mask = (f[5] == "-" || f[5].empty()) ? std::string()
                                               : dir + "/" + f[5];
        double scale = 0.0, md = 0.0;
        if (!parse_double(f[4].c_str(), scale) || scale <= 0.0 ||
            !parse_double(f[6].c_str(), md) || md < 1.0) {
            err = path + ":" + std::to_string(lineno) +
                  ": bad gt_scale or max_disp";
            return false;
        }
        s.gt_scale = scale;
        s.max_disp = static_cast<int>(std::ceil(md));
        s.origin = "manifest";
        s.gt_right = negobs_tools::right_gt_path(s.left, s.right, s.gt);
        sets.push_back(s);
    }
    return true;
}

// ---------------------------------------------------------------- matchers

// StereoBM: the parameters of OpenCV's samples/cpp/stereo_match.cpp
// (block 9, prefilter cap 31, texture threshold 10, uniqueness 15,
// speckle window 100 / range 32, disp12MaxDiff 1).
cv::Ptr<cv::StereoBM> make_bm(const Range &r)
{
    cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(
        negobs_tools::opencv_num_disparities(r), 9);
    bm->setMinDisparity(r.min_disp);
    bm->setPreFilterCap(31);
    bm->setTextureThreshold(10);
    bm->setUniquenessRatio(15);
    bm->setSpeckleWindowSize(100);
    bm->setSpeckleRange(32);
    bm->setDisp12MaxDiff(1);
    return bm;
}

// StereoSGBM: block 5, P1 = 8*5*5, P2 = 32*5*5 (grey, one channel), mode
// MODE_SGBM (5 paths), uniqueness 10, prefilter cap 63, speckle window 100 /
// range 32, disp12MaxDiff 1: OpenCV's stereo_match.cpp sample with a 5x5
// block.
cv::Ptr<cv::StereoSGBM> make_sgbm(const Range &r)
{
    const int bs = 5;
    return cv::StereoSGBM::create(
        r.min_disp, negobs_tools::opencv_num_disparities(r), bs, 8 * bs * bs,
        32 * bs * bs, 1, 63, 10, 100, 32, cv::StereoSGBM::MODE_SGBM);
}

enum MatcherId { M_NEGOBS = 0, M_BM = 1, M_SGBM = 2, M_COUNT = 3 };
const char *const kMatcherName[M_COUNT] = {"negobs", "BM", "SGBM"};

struct Metrics {
    bool ran = false;
    std::string note; // why it did not run
    double density = 0, bad1 = 0, bad1all = 0, bad2 = 0, rms = 0;
    double ms = 0;       // thread CPU time, best of N
    double wall_ms = 0;  // wall time, best of N
    cv::Mat disp, valid; // float px + mask, for pictures
};

struct SetResult {
    SetSpec spec;
    int width = 0, height = 0;
    Range range;
    long evaluated = 0;
    bool skipped = false;
    std::string skip_reason;
    Metrics m[M_COUNT];
    Metrics nofill; // negobs with gap_fill = 0 (scores only, not timed)
    // negobs' map after each stage (negobs_stereo_set_observer; one
    // untimed run): scored on every known pixel and, where a mask exists,
    // on non-occluded ones; the maps are dropped once scored
    struct StageScore {
        std::string name;
        Metrics all, nonocc;
    };
    std::vector<StageScore> stages;
    // The same maps scored on non-occluded pixels only (the protocol of
    // the paper's Table 5): the set's mask, else one derived from its
    // right-view GT; nonocc_from is "" when neither exists.
    Metrics nonocc[M_COUNT];
    std::string nonocc_from;
    long nonocc_px = 0;
    double mask_agree = -1.0; // derived vs the set's own mask, % of known
    cv::Mat gt, gt_valid;
};

void score(const cv::Mat &disp, const cv::Mat &valid, const cv::Mat &gt,
           const cv::Mat &eval_mask, Metrics &m)
{
    const negobs_tools::DispScore d = negobs_tools::score_disparity(
        disp, valid, gt, eval_mask);
    m.density = d.density;
    m.bad1 = d.bad1;
    m.bad2 = d.bad2;
    m.bad1all = d.bad1all;
    m.rms = d.rms;
}

// CPU time of the calling thread in ms. Every matcher runs on this thread
// (cv::setNumThreads(0)), so on an idle machine it equals the wall time; on
// a shared one it is far less disturbed by other processes.
double thread_cpu_ms()
{
    timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0)
        return std::chrono::duration<double, std::milli>(
                   std::chrono::steady_clock::now().time_since_epoch())
            .count();
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

// Best of `repeat` runs: thread CPU time (returned) and wall time (wall_ms).
template <typename F>
double best_of(int repeat, F &&f, bool &ok, double &wall_ms)
{
    double best = std::numeric_limits<double>::infinity();
    wall_ms = std::numeric_limits<double>::infinity();
    ok = true;
    for (int i = 0; i < repeat && ok; ++i) {
        const auto w0 = std::chrono::steady_clock::now();
        const double c0 = thread_cpu_ms();
        ok = f();
        const double c1 = thread_cpu_ms();
        const auto w1 = std::chrono::steady_clock::now();
        best = std::min(best, c1 - c0);
        wall_ms = std::min(
            wall_ms,
            std::chrono::duration<double, std::milli>(w1 - w0).count());
    }
    return best;
}

struct Options {
    std::string data;
    std::string opencv_doc = "/usr/share/doc/opencv-doc/examples/data";
    std::vector<std::string> sets;
    bool list = false;
    bool use[M_COUNT] = {true, true, true};
    bool matchers_given = false;
    int repeat = 3;
    bool repeat_given = false;
    int threads = 1; // negobs' row bands on a port/ pool (--threads)
    std::string markdown, plots, pictures, csv, json;
    int progress = -1; // --progress 1, --no-progress 0, -1: on a terminal
    std::string pictures_ext = "png";
    int pictures_width = 1600;
    bool check = false;
    bool drop_oov = false; // --drop-out-of-view: keep_out_of_view = 0
    double check_bad1 = 0, check_density = 0;
    std::string command_line;
};

bool load_gt(const SetSpec &s, const std::string &path, cv::Mat &gt,
             cv::Mat &known, std::string &err)
{
    cv::Mat raw = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (raw.empty()) {
        err = "cannot read GT '" + path + "'";
        return false;
    }
    if (raw.channels() == 3)
        cv::cvtColor(raw, raw, cv::COLOR_BGR2GRAY);
    else if (raw.channels() == 4)
        cv::cvtColor(raw, raw, cv::COLOR_BGRA2GRAY);
    if (raw.channels() != 1 ||
        (raw.depth() != CV_8U && raw.depth() != CV_16U)) {
        err = "GT '" + path + "': unsupported pixel type";
        return false;
    }
    raw.convertTo(gt, CV_32F, 1.0 / s.gt_scale);
    known = raw > 0;
    return true;
}

// Runs and scores negobs on one pair (res.m[M_NEGOBS]); returns an exit
// code.
int run_negobs(const Options &opt, const SetSpec &spec, const cv::Mat &left,
               const cv::Mat &right, const cv::Mat &eval_mask, SetResult &res)
{
    Metrics &mn = res.m[M_NEGOBS];
    const std::string limit = negobs_tools::check_engine_limits(
        res.range, left.cols, left.rows);
    if (!limit.empty()) {
        std::printf("  [%s] negobs skipped: %s\n", spec.name.c_str(),
                    limit.c_str());
        mn.note = "skipped: " + limit;
        return EXIT_OK;
    }
    std::string err;
    negobs_tools::NegobsMatcher nm;
    nm.set_threads(opt.threads);
    if (!nm.init(left.cols, left.rows, res.range, err, -1,
                 opt.drop_oov ? 0 : -1)) {
        std::fprintf(stderr, "negobs_eval: %s: %s\n", spec.name.c_str(),
                     err.c_str());
        return EXIT_LIBRARY;
    }
    cv::Mat q4, conf;
    bool ok = true;
    mn.ms = best_of(
        opt.repeat, [&] { return nm.process(left, right, q4, conf, err); }, ok,
        mn.wall_ms);
    if (!ok) {
        std::fprintf(stderr, "negobs_eval: %s: %s\n", spec.name.c_str(),
                     err.c_str());
        return EXIT_LIBRARY;
    }
    negobs_tools::negobs_q4_to_float(q4, mn.disp, mn.valid);
    score(mn.disp, mn.valid, res.gt, eval_mask, mn);
    mn.ran = true;
    std::printf("  [%s] negobs: %s\n", spec.name.c_str(),
                nm.last_stats().c_str());
    {
        // The same engine without the row gap fill: what the matcher
        // itself vouches for, to show what the fill adds (density) and
        // costs (bad1). One untimed run.
        negobs_tools::NegobsMatcher raw;
        cv::Mat q4r, confr;
        if (raw.init(left.cols, left.rows, res.range, err, 0,
                     opt.drop_oov ? 0 : -1) &&
            raw.process(left, right, q4r, confr, err)) {
            cv::Mat dr, vr;
            negobs_tools::negobs_q4_to_float(q4r, dr, vr);
            score(dr, vr, res.gt, eval_mask, res.nofill);
            res.nofill.ran = true;
        }
    }
    {
        // The map after every stage, to show what each one adds and costs.
        negobs_tools::NegobsMatcher staged;
        cv::Mat q4s, confs;
        if (staged.init(left.cols, left.rows, res.range, err, -1,
                        opt.drop_oov ? 0 : -1)) {
            staged.keep_stages(true);
            if (staged.process(left, right, q4s, confs, err)) {
                for (const auto &sn : staged.stages()) {
                    SetResult::StageScore sc;
                    sc.name = sn.name;
                    negobs_tools::negobs_q4_to_float(sn.disp_q4, sc.all.disp,
                                                     sc.all.valid);
                    score(sc.all.disp, sc.all.valid, res.gt, eval_mask,
                          sc.all);
                    sc.all.ran = true;
                    res.stages.push_back(sc);
                }
            }
        }
    }
    return EXIT_OK;
}

// Evaluates one set; returns an exit code (EXIT_OK unless fatal).
int evaluate(const Options &opt, const SetSpec &spec, SetResult &res)
{
    res.spec = spec;
    std::string err;
    cv::Mat left, right;
    if (!negobs_tools::load_grey(spec.left, left, err) ||
        !negobs_tools::load_grey(spec.right, right, err)) {
        std::fprintf(stderr, "negobs_eval: %s: %s\n", spec.name.c_str(),
                     err.c_str());
        return EXIT_DATA;
    }
    cv::Mat known;
    if (!load_gt(spec, spec.gt, res.gt, known, err)) {
        std::fprintf(stderr, "negobs_eval: %s: %s\n", spec.name.c_str(),
                     err.c_str());
        return EXIT_DATA;
    }
    if (left.size() != right.size() || left.size() != res.gt.size()) {
        std::fprintf(stderr,
                     "negobs_eval: %s: size mismatch: left %dx%d, right "
                     "%dx%d, GT %dx%d\n",
                     spec.name.c_str(), left.cols, left.rows, right.cols,
                     right.rows, res.gt.cols, res.gt.rows);
        return EXIT_DATA;
    }
    cv::Mat eval_mask = known.clone();
    if (!spec.mask.empty()) {
        cv::Mat mask = cv::imread(spec.mask, cv::IMREAD_GRAYSCALE);
        if (mask.empty() || mask.size() != left.size()) {
            std::fprintf(stderr,
                         "negobs_eval: %s: cannot read mask '%s' or "
                         "its size differs\n",
                         spec.name.c_str(), spec.mask.c_str());
            return EXIT_DATA;
        }
        eval_mask &= (mask == 255);
    }
    // Non-occluded pixels for the paper's protocol. A derived mask is
    // checked against the set's own where both exist (Cones: 98.5 % of
    // the known pixels agree).
    cv::Mat nonocc;
    if (!spec.gt_right.empty()) {
        cv::Mat gt_r, known_r;
        if (!load_gt(spec, spec.gt_right, gt_r, known_r, err) ||
            gt_r.size() != res.gt.size()) {
            std::fprintf(stderr, "negobs_eval: %s: right-view GT: %s\n",
                         spec.name.c_str(),
                         err.empty() ? "size differs" : err.c_str());
            return EXIT_DATA;
        }
        nonocc = negobs_tools::nonocc_from_right_gt(res.gt, known, gt_r,
                                                    known_r);
        if (!spec.mask.empty()) {
            const long n = cv::countNonZero(known);
            const long differ = cv::countNonZero(
                ((nonocc != 0) != (eval_mask != 0)) & known);
            res.mask_agree = n ? 100.0 * double(n - differ) / double(n) : 0;
            std::printf("  [%s] non-occlusion mask derived from %s agrees "
                        "with the set's mask on %.1f %% of the known pixels\n",
                        spec.name.c_str(), spec.gt_right.c_str(),
                        res.mask_agree);
        } else {
            res.nonocc_from = "derived from the right-view GT (" +
                              spec.gt_right.substr(
                                  spec.gt_right.find_last_of('/') + 1) +
                              ")";
        }
    }
    if (!spec.mask.empty()) {
        nonocc = eval_mask;
        res.nonocc_from = "the set's mask";
    }
    res.gt_valid = known;
    res.width = left.cols;
    res.height = left.rows;
    res.evaluated = cv::countNonZero(eval_mask);
    int md = spec.max_disp;
    if (md <= 0) {
        double mx = 0;
        cv::minMaxLoc(res.gt, nullptr, &mx);
        md = static_cast<int>(std::ceil(mx));
    }
    res.range.min_disp = 0;
    res.range.max_disp = md;
    err = negobs_tools::check_range(res.range, left.cols);
    if (!err.empty()) {
        std::fprintf(stderr, "negobs_eval: %s: %s\n", spec.name.c_str(),
                     err.c_str());
        return EXIT_DATA;
    }

    // negobs
    Metrics &mn = res.m[M_NEGOBS];
    if (opt.use[M_NEGOBS]) {
        const int rc = run_negobs(opt, spec, left, right, eval_mask, res);
        if (rc != EXIT_OK)
            return rc;
    } else {
        mn.note = "not selected";
    }

    // OpenCV
    for (int id : {int(M_BM), int(M_SGBM)}) {
        Metrics &m = res.m[id];
        if (!opt.use[id]) {
            m.note = "not selected";
            continue;
        }
        cv::Ptr<cv::StereoMatcher> sm;
        if (id == M_BM)
            sm = make_bm(res.range);
        else
            sm = make_sgbm(res.range);
        cv::Mat d16;
        bool ok = true;
        try {
            m.ms = best_of(
                opt.repeat,
                [&] {
                    sm->compute(left, right, d16);
                    return true;
                },
                ok, m.wall_ms);
        } catch (const cv::Exception &e) {
            std::fprintf(stderr, "negobs_eval: %s: %s failed: %s\n",
                         spec.name.c_str(), kMatcherName[id], e.what());
            return EXIT_LIBRARY;
        }
        negobs_tools::opencv_q4_to_float(d16, res.range.min_disp, m.disp,
                                         m.valid);
        score(m.disp, m.valid, res.gt, eval_mask, m);
        m.ran = true;
    }
    for (SetResult::StageScore &sc : res.stages) {
        if (!res.nonocc_from.empty()) {
            score(sc.all.disp, sc.all.valid, res.gt, nonocc, sc.nonocc);
            sc.nonocc.ran = true;
        }
        sc.all.disp.release();
        sc.all.valid.release();
    }
    if (!res.nonocc_from.empty()) {
        res.nonocc_px = cv::countNonZero(nonocc);
        for (int id = 0; id < M_COUNT; ++id) {
            if (res.m[id].ran) {
                score(res.m[id].disp, res.m[id].valid, res.gt, nonocc,
                      res.nonocc[id]);
                res.nonocc[id].ran = true;
            }
        }
    }
    return EXIT_OK;
}

// bad1 (%) of the paper's Table 5 (Fazli et al. 2011) for its four sets;
// < 0 for the others.
double paper_bad1(const std::string &set)
{
    if (set == "middlebury2003_cones")
        return 5.0;
    if (set == "middlebury2001_poster")
        return 4.47;
    if (set == "middlebury2006_Aloe_half")
        return 5.3;
    if (set == "middlebury2006_Flowerpots_half")
        return 5.53;
    return -1.0;
}

// ------------------------------------------------------------------ output

std::string fmt(const char *f, double v)
{
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

std::string ratio(const SetResult &r, int other)
{
    if (!r.m[M_NEGOBS].ran || !r.m[other].ran || r.m[other].ms <= 0)
        return "-";
    return fmt("%.2f", r.m[M_NEGOBS].ms / r.m[other].ms);
}

void print_table(const std::vector<SetResult> &res)
{
    std::printf("\n%-32s %-7s %8s %7s %8s %7s %7s %9s %9s %9s %9s\n", "set",
                "matcher", "density", "bad1", "bad1all", "bad2", "rms",
                "cpu ms", "wall ms", "neg/BM", "neg/SGBM");
    for (const SetResult &r : res) {
        for (int id = 0; id < M_COUNT; ++id) {
            const Metrics &m = r.m[id];
            if (!m.ran) {
                std::printf("%-32s %-7s %s\n", r.spec.name.c_str(),
                            kMatcherName[id], m.note.c_str());
                continue;
            }
            std::printf("%-32s %-7s %7.1f%% %6.1f%% %7.1f%% %6.1f%% %7.2f "
                        "%9.1f %9.1f %9s %9s\n",
                        r.spec.name.c_str(), kMatcherName[id], m.density,
                        m.bad1, m.bad1all, m.bad2, m.rms, m.ms, m.wall_ms,
                        id == M_NEGOBS ? ratio(r, M_BM).c_str() : "",
                        id == M_NEGOBS ? ratio(r, M_SGBM).c_str() : "");
        }
    }
}

// density / bad1 of each matcher on non-occluded pixels, against the
// paper's bad1. Console and Markdown share the rows.
std::vector<std::vector<std::string>> nonocc_rows(
    const std::vector<SetResult> &res)
{
    std::vector<std::vector<std::string>> rows;
    for (const SetResult &r : res) {
        if (r.nonocc_from.empty())
            continue;
        std::vector<std::string> row = {r.spec.name, r.nonocc_from,
                                        std::to_string(r.nonocc_px)};
        for (int id = 0; id < M_COUNT; ++id) {
            const Metrics &m = r.nonocc[id];
            row.push_back(m.ran ? fmt("%.1f", m.density) : "-");
            row.push_back(m.ran ? fmt("%.1f", m.bad1) : "-");
        }
        const double pb = paper_bad1(r.spec.name);
        row.push_back(pb >= 0 ? fmt("%.2f", pb) : "-");
        rows.push_back(row);
    }
    return rows;
}

const char *const kNonoccHead[] = {"set",
                                   "non-occluded pixels from",
                                   "px",
                                   "negobs density %",
                                   "negobs bad1 %",
                                   "BM density %",
                                   "BM bad1 %",
                                   "SGBM density %",
                                   "SGBM bad1 %",
                                   "paper bad1 %"};

void print_nonocc(const std::vector<SetResult> &res)
{
    const auto rows = nonocc_rows(res);
    if (rows.empty())
        return;
    std::printf(
        "\nNon-occluded pixels only (the paper's Table 5 protocol):\n");
    // columns of nonocc_rows: set, from, px, then density and bad1 of
    // negobs, BM, SGBM, then the paper's bad1
    std::printf("%-32s %8s %8s %8s %8s %8s %8s %8s %6s\n", "set", "px",
                "neg dens", "neg bad1", "BM dens", "BM bad1", "SGBM dns",
                "SGBM b1", "paper");
    for (const auto &r : rows)
        std::printf("%-32s %8s %7s%% %7s%% %7s%% %7s%% %7s%% %7s%% %6s\n",
                    r[0].c_str(), r[2].c_str(), r[3].c_str(), r[4].c_str(),
                    r[5].c_str(), r[6].c_str(), r[7].c_str(), r[8].c_str(),
                    r[9].c_str());
}

// negobs after each stage: density and bad1 on every known pixel and on
// non-occluded ones. Console and Markdown share the rows.
std::vector<std::vector<std::string>> stage_rows(
    const std::vector<SetResult> &res)
{
    std::vector<std::vector<std::string>> rows;
    for (const SetResult &r : res)
        for (const SetResult::StageScore &sc : r.stages) {
            rows.push_back(
                {r.spec.name, sc.name, fmt("%.1f", sc.all.density),
                 fmt("%.1f", sc.all.bad1), fmt("%.1f", sc.all.bad1all),
                 sc.nonocc.ran ? fmt("%.1f", sc.nonocc.density) : "-",
                 sc.nonocc.ran ? fmt("%.1f", sc.nonocc.bad1) : "-"});
        }
    return rows;
}

const char *const kStageHead[] = {"set",
                                  "after stage",
                                  "density %",
                                  "bad1 %",
                                  "bad1all %",
                                  "density % non-occluded",
                                  "bad1 % non-occluded"};

void print_stages(const std::vector<SetResult> &res)
{
    const auto rows = stage_rows(res);
    if (rows.empty())
        return;
    std::printf("\nnegobs after each stage (one untimed run; whole pixels "
                "after GCS):\n");
    std::printf("%-32s %-22s %8s %8s %8s %9s %9s\n", "set", "after stage",
                "density", "bad1", "bad1all", "nocc dens", "nocc bad1");
    for (const auto &r : rows)
        std::printf("%-32s %-22s %7s%% %7s%% %7s%% %8s%% %8s%%\n",
                    r[0].c_str(), r[1].c_str(), r[2].c_str(), r[3].c_str(),
                    r[4].c_str(), r[5].c_str(), r[6].c_str());
}

// Mean over the sets where the matcher ran.
struct Mean {
    int n = 0;
    double density = 0, bad1 = 0, bad1all = 0, bad2 = 0, rms = 0, ms = 0;
};

Mean mean_of(const std::vector<SetResult> &res, int id)
{
    Mean a;
    for (const SetResult &r : res) {
        const Metrics &m = r.m[id];
        if (!m.ran)
            continue;
        ++a.n;
        a.density += m.density;
        a.bad1 += m.bad1;
        a.bad1all += m.bad1all;
        a.bad2 += m.bad2;
        a.rms += m.rms;
        a.ms += m.ms;
    }
    if (a.n) {
        a.density /= a.n;
        a.bad1 /= a.n;
        a.bad1all /= a.n;
        a.bad2 /= a.n;
        a.rms /= a.n;
    }
    return a;
}

bool write_markdown(const std::string &path, const Options &opt,
                    const std::vector<SetResult> &res)
{
    std::ofstream o(path);
    if (!o)
        return false;
    o << "<!-- generated by negobs_eval; do not edit by hand -->\n\n";
    o << "Command: `" << opt.command_line << "`\n\n";
    o << "OpenCV " << CV_VERSION << ", cv::setNumThreads(0) (sequential), "
      << "time = CPU time of the calling thread, best of " << opt.repeat
      << " runs, negobs build type `" << NEGOBS_BUILD_TYPE << "`"
      << (opt.threads > 1
              ? ", negobs on " + std::to_string(opt.threads) +
                    " threads (its CPU ms is the calling thread's share "
                    "only; the maps are those of one thread)"
              : std::string())
      << ".\n\n";
    o << "| set | size | range (px) | eval px | matcher | density % | bad1 % "
         "| bad1all % | bad2 % | RMS px | CPU ms | negobs/BM | negobs/SGBM "
         "|\n";
    o << "|---|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const SetResult &r : res) {
        for (int id = 0; id < M_COUNT; ++id) {
            const Metrics &m = r.m[id];
            o << "| " << (id == 0 ? r.spec.name : std::string()) << " | "
              << (id == 0 ? std::to_string(r.width) + "x" +
                                std::to_string(r.height)
                          : std::string())
              << " | "
              << (id == 0 ? std::to_string(r.range.min_disp) + "-" +
                                std::to_string(r.range.max_disp)
                          : std::string())
              << " | "
              << (id == 0 ? std::to_string(r.evaluated) : std::string())
              << " | " << kMatcherName[id] << " | ";
            if (!m.ran) {
                o << "*" << m.note << "* | | | | | | | |\n";
                continue;
            }
            o << fmt("%.1f", m.density) << " | " << fmt("%.1f", m.bad1)
              << " | " << fmt("%.1f", m.bad1all) << " | "
              << fmt("%.1f", m.bad2) << " | " << fmt("%.2f", m.rms) << " | "
              << fmt("%.1f", m.ms) << " | "
              << (id == M_NEGOBS ? ratio(r, M_BM) : std::string()) << " | "
              << (id == M_NEGOBS ? ratio(r, M_SGBM) : std::string()) << " |\n";
        }
    }
    o << "\nnegobs without its row gap fill (`gap_fill = 0`, same run, not "
         "timed): what the matcher itself vouches for, against the table "
         "above:\n\n";
    o << "| set | density % | bad1 % | bad1all % | density % with fill | "
         "bad1 % with fill |\n";
    o << "|---|---:|---:|---:|---:|---:|\n";
    for (const SetResult &r : res) {
        if (!r.nofill.ran || !r.m[M_NEGOBS].ran)
            continue;
        o << "| " << r.spec.name << " | " << fmt("%.1f", r.nofill.density)
          << " | " << fmt("%.1f", r.nofill.bad1) << " | "
          << fmt("%.1f", r.nofill.bad1all) << " | "
          << fmt("%.1f", r.m[M_NEGOBS].density) << " | "
          << fmt("%.1f", r.m[M_NEGOBS].bad1) << " |\n";
    }
    const auto nrows = nonocc_rows(res);
    if (!nrows.empty()) {
        o << "\nThe same maps scored on non-occluded pixels only, the "
             "protocol of the paper's Table 5: the set's own mask where it "
             "has one (the table above then already is this), else a mask "
             "derived from its right-view GT (a left pixel with GT d is "
             "non-occluded when the right GT at x - d agrees within 1 px; "
             "the left border strip is excluded):\n\n|";
        for (const char *h : kNonoccHead)
            o << " " << h << " |";
        o << "\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const auto &r : nrows) {
            o << "|";
            for (const std::string &c : r)
                o << " " << c << " |";
            o << "\n";
        }
    }
    const auto srows = stage_rows(res);
    if (!srows.empty()) {
        o << "\nnegobs after each stage (`negobs_stereo_set_observer`, one "
             "untimed run with the defaults; after GCS the map holds the "
             "grown and selected whole-pixel matches, so its bad1 counts "
             "their quantisation too):\n\n|";
        for (const char *h : kStageHead)
            o << " " << h << " |";
        o << "\n|---|---|---:|---:|---:|---:|---:|\n";
        for (const auto &r : srows) {
            o << "|";
            for (const std::string &c : r)
                o << " " << c << " |";
            o << "\n";
        }
    }
    o << "\nMean over sets (time: sum):\n\n";
    o << "| matcher | sets | density % | bad1 % | bad1all % | bad2 % | RMS px "
         "| total CPU ms |\n";
    o << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (int id = 0; id < M_COUNT; ++id) {
        const Mean a = mean_of(res, id);
        o << "| " << kMatcherName[id] << " | " << a.n << " | ";
        if (!a.n) {
            o << "*" << (res.empty() ? "no set" : res[0].m[id].note)
              << "* | | | | | |\n";
            continue;
        }
        o << fmt("%.1f", a.density) << " | " << fmt("%.1f", a.bad1) << " | "
          << fmt("%.1f", a.bad1all) << " | " << fmt("%.1f", a.bad2) << " | "
          << fmt("%.2f", a.rms) << " | " << fmt("%.1f", a.ms) << " |\n";
    }
    double tn = 0, tb = 0, ts = 0;
    for (const SetResult &r : res)
        if (r.m[M_NEGOBS].ran && r.m[M_BM].ran && r.m[M_SGBM].ran) {
            tn += r.m[M_NEGOBS].ms;
            tb += r.m[M_BM].ms;
            ts += r.m[M_SGBM].ms;
        }
    if (tn > 0 && tb > 0 && ts > 0)
        o << "\nTotal CPU time ratio over the sets where all three ran: "
          << "negobs/BM " << fmt("%.2f", tn / tb) << ", negobs/SGBM "
          << fmt("%.2f", tn / ts) << ".\n";
    return bool(o);
}

std::string short_name(const std::string &n)
{
    std::string s = n;
    const size_t u = s.find('_');
    if (s.rfind("middlebury", 0) == 0 && u != std::string::npos)
        s = s.substr(u + 1);
    const std::string half = "_half";
    if (s.size() > half.size() &&
        s.compare(s.size() - half.size(), half.size(), half) == 0)
        s.resize(s.size() - half.size());
    return s;
}

const cv::Scalar kBarColour[M_COUNT] = {cv::Scalar(40, 140, 230), // orange
                                        cv::Scalar(200, 120, 40), // blue
                                        cv::Scalar(90, 170, 60)}; // green

// Grouped bar plot: one group per set, one bar per matcher. log_scale: y is
// log10 (values must be > 0).
cv::Mat bar_plot(const std::vector<SetResult> &res, const std::string &title,
                 const std::string &unit,
                 const std::function<double(const Metrics &)> &value,
                 bool log_scale)
{
    const int group_w = 108, left_m = 70, right_m = 20, top_m = 64,
              bottom_m = 44, plot_h = 300;
    const int n = static_cast<int>(res.size());
    const int w = left_m + right_m + std::max(1, n) * group_w;
    const int h = top_m + plot_h + bottom_m;
    cv::Mat img(h, std::max(w, 520), CV_8UC3, cv::Scalar::all(255));
    const int font = cv::FONT_HERSHEY_SIMPLEX;
    const cv::Scalar black(0, 0, 0), grid(220, 220, 220);

    double vmax = 0, vmin = std::numeric_limits<double>::infinity();
    for (const SetResult &r : res)
        for (int id = 0; id < M_COUNT; ++id)
            if (r.m[id].ran) {
                vmax = std::max(vmax, value(r.m[id]));
                if (value(r.m[id]) > 0)
                    vmin = std::min(vmin, value(r.m[id]));
            }
    double lo = 0, hi = 1, step = 1;
    if (log_scale) {
        lo = std::floor(std::log10(std::isfinite(vmin) ? vmin : 1.0));
        hi = std::ceil(std::log10(std::max(vmax, 1e-3) * 1.0001));
        if (hi <= lo)
            hi = lo + 1;
    } else {
        step = vmax > 50 ? 20 : vmax > 20 ? 10 : vmax > 10 ? 5 : 2;
        hi = std::max(step, std::ceil(vmax * 1.08 / step) * step);
    }
    auto ypix = [&](double v) {
        double t = log_scale ? (std::log10(std::max(v, 1e-9)) - lo) / (hi - lo)
                             : (v - lo) / (hi - lo);
        t = std::min(1.0, std::max(0.0, t));
        return top_m + plot_h - static_cast<int>(std::lround(t * plot_h));
    };

    // grid + y labels
    std::vector<double> ticks;
    if (log_scale) {
        for (double e = lo; e <= hi + 1e-9; e += 1)
            ticks.push_back(std::pow(10.0, e));
    } else {
        for (double t = 0; t <= hi + 1e-9; t += step)
            ticks.push_back(t);
    }
    for (double t : ticks) {
        const int y = ypix(t);
        cv::line(img, cv::Point(left_m, y), cv::Point(img.cols - right_m, y),
                 grid, 1);
        const std::string s = t >= 1 || t == 0 ? fmt("%.0f", t) : fmt("%g", t);
        cv::putText(img, s, cv::Point(8, y + 5), font, 0.45, black, 1,
                    cv::LINE_AA);
    }
    cv::line(img, cv::Point(left_m, top_m), cv::Point(left_m, top_m + plot_h),
             black, 1);
    cv::line(img, cv::Point(left_m, top_m + plot_h),
             cv::Point(img.cols - right_m, top_m + plot_h), black, 1);
    cv::putText(img, title + " (" + unit + ")", cv::Point(left_m, 22), font,
                0.6, black, 1, cv::LINE_AA);

    // legend
    int lx = left_m;
    for (int id = 0; id < M_COUNT; ++id) {
        bool any = false;
        for (const SetResult &r : res)
            any = any || r.m[id].ran;
        cv::rectangle(img, cv::Rect(lx, 34, 14, 14), kBarColour[id],
                      cv::FILLED);
        std::string label = kMatcherName[id];
        if (!any)
            label += " (" +
                     (res.empty() ? std::string("n/a") : res[0].m[id].note) +
                     ")";
        cv::putText(img, label, cv::Point(lx + 18, 46), font, 0.45, black, 1,
                    cv::LINE_AA);
        int base = 0;
        lx += 30 + cv::getTextSize(label, font, 0.45, 1, &base).width;
    }

    // bars
    const int bar_w = 26;
    for (int i = 0; i < n; ++i) {
        const SetResult &r = res[static_cast<size_t>(i)];
        const int gx = left_m + i * group_w + (group_w - 3 * bar_w) / 2;
        for (int id = 0; id < M_COUNT; ++id) {
            if (!r.m[id].ran)
                continue;
            const double v = value(r.m[id]);
            const int x0 = gx + id * bar_w;
            const int y0 = ypix(v);
            cv::rectangle(img, cv::Point(x0, y0),
                          cv::Point(x0 + bar_w - 3, top_m + plot_h),
                          kBarColour[id], cv::FILLED);
            const std::string s = v >= 100 ? fmt("%.0f", v) : fmt("%.1f", v);
            cv::putText(img, s, cv::Point(x0 - 2, y0 - 4), font, 0.32, black,
                        1, cv::LINE_AA);
        }
        std::string label = short_name(r.spec.name);
        int base = 0;
        double scale = 0.45;
        while (scale > 0.3 &&
               cv::getTextSize(label, font, scale, 1, &base).width >
                   group_w - 4)
            scale -= 0.03;
        const int tw = cv::getTextSize(label, font, scale, 1, &base).width;
        cv::putText(img, label,
                    cv::Point(left_m + i * group_w + (group_w - tw) / 2,
                              top_m + plot_h + 22),
                    font, scale, black, 1, cv::LINE_AA);
    }
    return img;
}

cv::Mat labelled(const cv::Mat &img, const std::string &label)
{
    cv::Mat out = img.clone();
    int base = 0;
    const int tw =
        cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.6, 1, &base).width;
    cv::rectangle(out, cv::Rect(0, 0, std::min(out.cols, tw + 10), 26),
                  cv::Scalar::all(255), cv::FILLED);
    cv::putText(out, label, cv::Point(5, 19), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar::all(0), 1, cv::LINE_AA);
    return out;
}

bool write_picture(const Options &opt, const SetResult &r)
{
    const double hi = r.range.max_disp, lo = r.range.min_disp;
    std::vector<cv::Mat> panels;
    for (int id = 0; id < M_COUNT; ++id) {
        cv::Mat p;
        if (r.m[id].ran) {
            p = negobs_tools::colourise(r.m[id].disp, r.m[id].valid, lo, hi);
        } else {
            p = cv::Mat(r.height, r.width, CV_8UC3, cv::Scalar::all(128));
        }
        panels.push_back(labelled(p, kMatcherName[id]));
    }
    panels.push_back(
        labelled(negobs_tools::colourise(r.gt, r.gt_valid, lo, hi), "GT"));
    // one scale for the four panels, which share the colour range
    panels.push_back(
        negobs_cli::colour_bar(r.height, cv::COLORMAP_TURBO, lo, hi, "px"));
    cv::Mat row;
    cv::hconcat(panels, row);
    const int max_w = opt.pictures_width;
    if (row.cols > max_w)
        cv::resize(row, row, cv::Size(max_w, row.rows * max_w / row.cols), 0,
                   0, cv::INTER_AREA);
    try {
        return cv::imwrite(
            opt.pictures + "/eval_" + r.spec.name + "." + opt.pictures_ext,
            row,
            {cv::IMWRITE_JPEG_QUALITY, 85, cv::IMWRITE_PNG_COMPRESSION, 9});
    } catch (const cv::Exception &) {
        return false;
    }
}

bool write_png(const std::string &path, const cv::Mat &img)
{
    try {
        return cv::imwrite(path, img, {cv::IMWRITE_PNG_COMPRESSION, 9});
    } catch (const cv::Exception &) {
        return false;
    }
}

bool parse_matchers(const std::string &s, Options &opt)
{
    for (int id = 0; id < M_COUNT; ++id)
        opt.use[id] = false;
    for (const std::string &t : split(s, ',')) {
        if (t == "negobs")
            opt.use[M_NEGOBS] = true;
        else if (t == "bm" || t == "BM")
            opt.use[M_BM] = true;
        else if (t == "sgbm" || t == "SGBM")
            opt.use[M_SGBM] = true;
        else
            return false;
    }
    return true;
}

enum LongOnly {
    O_DATA = 256,
    O_OPENCV_DOC,
    O_LIST,
    O_MATCHERS,
    O_REPEAT,
    O_PLOTS,
    O_PICTURES,
    O_PICTURES_FORMAT,
    O_PICTURES_WIDTH,
    O_DROP_OOV,
    O_CHECK,
    O_ALL,
    O_SCORE,
    O_GT,
    O_GT_SCALE,
    O_MAP_SCALE,
    O_MASK,
    O_NAME,
    O_PROGRESS,
    O_NO_PROGRESS,
    O_THREADS,
};

const struct option kLongOpts[] = {
    {"help", no_argument, nullptr, 'h'},
    {"version", no_argument, nullptr, 'V'},
    {"data", required_argument, nullptr, O_DATA},
    {"opencv-doc", required_argument, nullptr, O_OPENCV_DOC},
    {"set", required_argument, nullptr, 's'},
    {"list", no_argument, nullptr, O_LIST},
    {"all", no_argument, nullptr, O_ALL},
    {"matchers", required_argument, nullptr, O_MATCHERS},
    {"repeat", required_argument, nullptr, O_REPEAT},
    {"markdown", required_argument, nullptr, 'm'},
    {"csv", required_argument, nullptr, 'c'},
    {"json", required_argument, nullptr, 'j'},
    {"plots", required_argument, nullptr, O_PLOTS},
    {"pictures", required_argument, nullptr, O_PICTURES},
    {"pictures-format", required_argument, nullptr, O_PICTURES_FORMAT},
    {"pictures-width", required_argument, nullptr, O_PICTURES_WIDTH},
    {"drop-out-of-view", no_argument, nullptr, O_DROP_OOV},
    {"check", required_argument, nullptr, O_CHECK},
    {"score", required_argument, nullptr, O_SCORE},
    {"gt", required_argument, nullptr, O_GT},
    {"gt-scale", required_argument, nullptr, O_GT_SCALE},
    {"format", required_argument, nullptr, 'f'},
    {"map-scale", required_argument, nullptr, O_MAP_SCALE},
    {"mask", required_argument, nullptr, O_MASK},
    {"name", required_argument, nullptr, O_NAME},
    {"progress", no_argument, nullptr, O_PROGRESS},
    {"no-progress", no_argument, nullptr, O_NO_PROGRESS},
    {"threads", required_argument, nullptr, O_THREADS},
    {nullptr, 0, nullptr, 0},
};

// One row per set and matcher that ran, for --csv / --json.
std::vector<negobs_tools::ScoreRow> score_rows(
    const Options &opt, const std::vector<SetResult> &res)
{
    std::vector<negobs_tools::ScoreRow> rows;
    for (const SetResult &r : res) {
        for (int id = 0; id < M_COUNT; ++id) {
            const Metrics &m = r.m[id];
            if (!opt.use[id] || !m.ran)
                continue;
            negobs_tools::ScoreRow row;
            row.set = r.spec.name;
            row.matcher = kMatcherName[id];
            row.width = r.width;
            row.height = r.height;
            row.s.evaluated = r.evaluated;
            row.s.density = m.density;
            row.s.bad1 = m.bad1;
            row.s.bad1all = m.bad1all;
            row.s.bad2 = m.bad2;
            row.s.rms = m.rms;
            row.cpu_ms = m.ms;
            rows.push_back(row);
        }
    }
    return rows;
}

int run(int argc, char **argv)
{
    Options opt;
    negobs_tools::ScoreOptions sco;
    bool score_mode = false;
    {
        std::string cl = "negobs_eval";
        for (int i = 1; i < argc; ++i)
            cl += std::string(" ") + argv[i];
        opt.command_line = cl;
        sco.command_line = cl;
    }
    // the full evaluation takes minutes to hours: never by accident
    if (argc < 2) {
        std::fputs(kHelp, stderr);
        std::fputs("\nnegobs_eval: no arguments: give --all for the full "
                   "evaluation\n",
                   stderr);
        return EXIT_USAGE;
    }
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, "+:hVs:m:c:j:f:", kLongOpts,
                            nullptr)) != -1) {
        const std::string v = optarg ? optarg : "";
        switch (c) {
        case 'h': std::fputs(kHelp, stdout); return EXIT_OK;
        case 'V': negobs_cli::print_version("negobs_eval"); return EXIT_OK;
        case O_LIST: opt.list = true; break;
        case O_ALL: break; // the default selection, spelled out
        case O_DATA: opt.data = v; break;
        case O_OPENCV_DOC: opt.opencv_doc = v; break;
        case 's': opt.sets.push_back(v); break;
        case 'm':
            opt.markdown = v;
            sco.markdown = v;
            break;
        case 'c':
            opt.csv = v;
            sco.csv = v;
            break;
        case 'j':
            opt.json = v;
            sco.json = v;
            break;
        case O_PLOTS: opt.plots = v; break;
        case O_PICTURES: opt.pictures = v; break;
        case O_PICTURES_FORMAT:
            if (v != "png" && v != "jpg")
                throw negobs_cli::UsageError(
                    "--pictures-format takes png or jpg");
            opt.pictures_ext = v;
            break;
        case O_PICTURES_WIDTH:
            opt.pictures_width = negobs_cli::int_arg("--pictures-width",
                                                     optarg, 64, 20000);
            break;
        case O_MATCHERS:
            if (!parse_matchers(v, opt))
                throw negobs_cli::UsageError(
                    "--matchers takes a comma list of negobs,bm,sgbm");
            opt.matchers_given = true;
            break;
        case O_REPEAT:
            opt.repeat = negobs_cli::int_arg("--repeat", optarg, 1, 1000);
            opt.repeat_given = true;
            break;
        case O_DROP_OOV: opt.drop_oov = true; break;
        case O_THREADS:
            opt.threads = negobs_cli::int_arg("--threads", optarg, 1, 64);
            break;
        case O_CHECK:
            // two values: MAXBAD1 MINDENSITY (the second is the next word)
            if (optind >= argc)
                throw negobs_cli::UsageError(
                    "--check takes two numbers (MAXBAD1 MINDENSITY, in %)");
            opt.check_bad1 = negobs_cli::double_arg("--check MAXBAD1", optarg,
                                                    0, 100);
            opt.check_density = negobs_cli::double_arg("--check MINDENSITY",
                                                       argv[optind++], 0, 100);
            opt.check = true;
            break;
        case O_SCORE:
            score_mode = true;
            sco.map = v;
            break;
        case O_GT: sco.gt = v; break;
        case O_GT_SCALE:
            sco.gt_scale = negobs_cli::double_arg("--gt-scale", optarg, 1e-6,
                                                  1e6);
            break;
        case O_MAP_SCALE:
            sco.map_scale = negobs_cli::double_arg("--map-scale", optarg, 1e-6,
                                                   1e6);
            break;
        case 'f': sco.map_format = v; break;
        case O_MASK: sco.mask = v; break;
        case O_NAME: sco.name = v; break;
        case O_PROGRESS: opt.progress = 1; break;
        case O_NO_PROGRESS: opt.progress = 0; break;
        case ':':
            throw negobs_cli::UsageError(std::string(argv[optind - 1]) +
                                         " needs a value");
        default:
            throw negobs_cli::UsageError("unknown argument '" +
                                         std::string(argv[optind - 1]) + "'");
        }
    }
    if (optind < argc)
        throw negobs_cli::UsageError("unexpected argument '" +
                                     std::string(argv[optind]) + "'");
    if (score_mode || !sco.gt.empty()) {
        if (sco.map.empty() || sco.gt.empty())
            throw negobs_cli::UsageError("--score MAP needs --gt GT");
        return negobs_tools::score_map_main(sco);
    }
    if (!sco.mask.empty() || sco.gt_scale > 0 || sco.map_scale > 0 ||
        sco.map_format != "auto" || !sco.name.empty())
        throw negobs_cli::UsageError("--gt-scale, --map-scale, --format, "
                                     "--mask and --name go with --score");
    if (opt.check) {
        if (!opt.matchers_given) {
            opt.use[M_NEGOBS] = true;
            opt.use[M_BM] = opt.use[M_SGBM] = false;
        }
        if (!opt.repeat_given)
            opt.repeat = 1;
    }

    cv::setNumThreads(0); // sequential: same footing as the C library

    // Collect the sets.
    if (opt.data.empty())
        opt.data = negobs_cli::default_data_dir();
    std::vector<SetSpec> all;
    if (is_dir(opt.data)) {
        std::string err;
        int no_gt = 0;
        if (!read_manifest(opt.data, all, no_gt, err)) {
            std::fprintf(stderr, "negobs_eval: %s\n", err.c_str());
            return EXIT_DATA;
        }
        std::printf("negobs_eval: %s: %zu pairs with GT (%d pairs without GT "
                    "not evaluated)\n",
                    opt.data.c_str(), all.size(), no_gt);
    } else {
        std::printf("negobs_eval: data folder '%s' absent: skipping the "
                    "manifest sets (set NEGOBS_DATA or --data)\n",
                    opt.data.empty() ? "(none: an installed binary)"
                                     : opt.data.c_str());
    }
    {
        SetSpec aloe;
        aloe.name = kAloeSet;
        aloe.left = opt.opencv_doc + "/aloeL.jpg";
        aloe.right = opt.opencv_doc + "/aloeR.jpg";
        aloe.gt = opt.opencv_doc + "/aloeGT.png";
        aloe.gt_scale = 1.0; // full-size Middlebury Aloe: value = disparity
        aloe.max_disp = 0;   // from the GT (211 px)
        aloe.origin = "opencv-doc";
        if (is_file(aloe.left) && is_file(aloe.right) && is_file(aloe.gt))
            all.push_back(aloe);
        else
            std::printf("negobs_eval: opencv-doc aloe pair absent from '%s': "
                        "skipping it (apt install opencv-doc)\n",
                        opt.opencv_doc.c_str());
    }
    if (opt.list) {
        for (const SetSpec &s : all)
            std::printf("%s\t%s\n", s.name.c_str(), s.left.c_str());
        return EXIT_OK;
    }
    std::vector<SetSpec> chosen;
    if (opt.sets.empty()) {
        chosen = all;
    } else {
        for (const std::string &n : opt.sets) {
            auto it = std::find_if(
                all.begin(), all.end(),
                [&](const SetSpec &s) { return s.name == n; });
            if (it == all.end()) {
                const bool skip = opt.check;
                std::fprintf(skip ? stdout : stderr,
                             "negobs_eval: set '%s' %s (see --list)\n",
                             n.c_str(),
                             skip ? "not available here: skipped"
                                  : "unknown or its files are absent");
                return skip ? EXIT_SKIP : EXIT_DATA;
            }
            chosen.push_back(*it);
        }
    }
    if (chosen.empty()) {
        std::printf("negobs_eval: no set to evaluate\n");
        return opt.check ? EXIT_SKIP : EXIT_OK;
    }

    std::vector<SetResult> results;
    negobs_cli::Progress progress(
        "negobs_eval", "sets", static_cast<long>(chosen.size()), opt.progress);
    for (const SetSpec &s : chosen) {
        progress.step(static_cast<long>(results.size()), s.name);
        std::printf("negobs_eval: %s ...\n", s.name.c_str());
        std::fflush(stdout);
        SetResult r;
        const int rc = evaluate(opt, s, r);
        if (rc != EXIT_OK)
            return rc;
        results.push_back(r);
    }
    progress.step(static_cast<long>(results.size()));
    progress.finish();
    print_table(results);
    print_nonocc(results);
    print_stages(results);

    int rc = EXIT_OK;
    for (const std::string *d : {&opt.plots, &opt.pictures})
        if (!d->empty() && !make_dirs(*d)) {
            std::fprintf(stderr, "negobs_eval: cannot create folder '%s'\n",
                         d->c_str());
            rc = EXIT_DATA;
        }
    if (!opt.markdown.empty() && !write_markdown(opt.markdown, opt, results)) {
        std::fprintf(stderr, "negobs_eval: cannot write '%s'\n",
                     opt.markdown.c_str());
        rc = EXIT_DATA;
    }
    const std::vector<negobs_tools::ScoreRow> rows = score_rows(opt, results);
    if (!opt.csv.empty() && !negobs_tools::write_score_csv(opt.csv, rows)) {
        std::fprintf(stderr, "negobs_eval: cannot write '%s'\n",
                     opt.csv.c_str());
        rc = EXIT_DATA;
    }
    if (!opt.json.empty() && !negobs_tools::write_score_json(opt.json, rows)) {
        std::fprintf(stderr, "negobs_eval: cannot write '%s'\n",
                     opt.json.c_str());
        rc = EXIT_DATA;
    }
    if (!opt.plots.empty()) {
        const cv::Mat p1 = bar_plot(
            results, "bad1all: wrong by > 1 px or no value",
            "% of evaluated px", [](const Metrics &m) { return m.bad1all; },
            false);
        const cv::Mat p2 = bar_plot(
            results,
            "CPU time per pair, 1 thread, best of " +
                std::to_string(opt.repeat),
            "ms, log scale", [](const Metrics &m) { return m.ms; }, true);
        if (!write_png(opt.plots + "/eval_bad1all.png", p1) ||
            !write_png(opt.plots + "/eval_time.png", p2)) {
            std::fprintf(stderr, "negobs_eval: cannot write plots into '%s'\n",
                         opt.plots.c_str());
            rc = EXIT_DATA;
        }
    }
    if (!opt.pictures.empty()) {
        for (const SetResult &r : results)
            if (!write_picture(opt, r)) {
                std::fprintf(stderr,
                             "negobs_eval: cannot write pictures into "
                             "'%s'\n",
                             opt.pictures.c_str());
                rc = EXIT_DATA;
                break;
            }
    }

    if (opt.check) {
        bool pass = true;
        for (const SetResult &r : results) {
            const Metrics &m = r.m[M_NEGOBS];
            const bool ok = m.ran && m.bad1 <= opt.check_bad1 &&
                            m.density >= opt.check_density;
            std::printf("check %s: negobs bad1 %.2f%% (max %.2f), density "
                        "%.2f%% (min %.2f): %s\n",
                        r.spec.name.c_str(), m.bad1, opt.check_bad1, m.density,
                        opt.check_density, ok ? "PASS" : "FAIL");
            pass = pass && ok;
        }
        if (!pass)
            return EXIT_CHECK;
    }
    return rc;
}

} // namespace

int main(int argc, char **argv)
{
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    // an exception that escapes is a matcher failure (OpenCV or negobs)
    return negobs_cli::main_guard("negobs_eval", argc, argv, run,
                                  EXIT_LIBRARY);
}
