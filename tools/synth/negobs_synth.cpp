// negobs_synth: renders rectified stereo pairs and approach sequences with
// exact ground truth for the negative-obstacle detector.  See docs/SYNTH.md.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <getopt.h>
#include <limits>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

extern "C" {
#include "negobs/version.h"
}

#include "cli.hpp"
#include "synth.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Options {
    synth::SceneParams scene;
    synth::Rig rig;
    synth::RenderOptions render;
    synth::SensorOptions sensor;
    double height_mm = 1200.0;
    double pitch_deg = 20.0;
    double roll_deg = 0.0;
    double yaw_deg = 0.0;
    bool cx_set = false, cy_set = false;
    int frames = 1;
    bool single = false;
    double speed = 1.2; // m/s
    double fps = 10.0;
    double bob_mm = 25.0;  // vertical amplitude
    double bob_hz = 1.8;   // step frequency
    double sway_deg = 1.0; // pitch sway amplitude
    double roll_sway_deg = 0.5;
    double yaw_sway_deg = 0.0; // heading sway of the head or trunk
    double side_sway_mm = 0.0; // sideways sway of the body
    uint64_t seed = 1;
    bool texture_seed_set = false;
    uint64_t texture_seed = 1;
    std::string texture_file;
    std::string texture_kind = "asphalt";
    int distractors = 0;
    double exposure_pct = 0.0; // auto-exposure steps of both cameras, +-%
    int exposure_every = 10;   // frames between steps
    int exposure_lag = 0;      // frames the right camera's exposure lags
    double texture_mm = 2.0;
    bool gt_disparity = false;
    bool gt_disparity_right = false;
    int threads = -1;
    bool preview = false;
    bool quiet = false;
    std::string out;
};

void usage(FILE *fp, const char *argv0)
{
    std::fprintf(fp,
                 "usage: %s --out DIR [options]\n"
                 "Renders rectified 8-bit grey stereo pairs (left_NNNN.png, right_NNNN.png)\n"
                 "and ground truth (gt.json) by exact per-pixel ray casting.\n"
                 "\n"
                 "Scene:\n"
                 "  --scene S            curb|stairs|hole|upstep|wall|flat|ramp (default curb)\n"
                 "  --edge-mm D          horizontal distance from the start position to the\n"
                 "                       hazard's near edge (default 4000)\n"
                 "  --drop-mm H          curb/hole depth, up-step height (default 150)\n"
                 "  --steps N            stairs: number of steps (default 3)\n"
                 "  --rise-mm R          stairs: riser height (default 170)\n"
                 "  --run-mm R           stairs: tread depth (default 300)\n"
                 "  --hole-width-mm W    hole: lateral size (default 1000)\n"
                 "  --hole-length-mm L   hole: size along the walking direction (default 800)\n"
                 "  --hole-offset-mm X   hole: lateral centre, + = right (default 0)\n"
                 "  --wall-height-mm H   wall height (default 2500)\n"
                 "  --grade-pct G        ramp: fall of the ground beyond the edge, %% of the\n"
                 "                       horizontal distance; negative = uphill (default\n"
                 "                       8.33, a 1:12 curb cut)\n"
                 "  --ramp-mm L          ramp: horizontal length of the slope, then level\n"
                 "                       ground again; 0 = it never ends (default 1800)\n"
                 "                       The walker follows the ground: on the ramp the\n"
                 "                       camera stays --height-mm above the surface under it\n"
                 "  --lower-shade K      brightness of surfaces below the near ground (0.9)\n"
                 "  --distractors N      N random intensity-only distractors on the near\n"
                 "                       ground: painted stripes, hard shadows, dark patches,\n"
                 "                       manhole covers (default 0; never to be alarmed)\n"
                 "  --texture-kind K     asphalt|paving|concrete|worn procedural texture\n"
                 "                       (default asphalt; concrete and worn are weak,\n"
                 "                       low-contrast textures)\n"
                 "  --texture FILE       tile a grey photo on all surfaces instead\n"
                 "  --texture-mm S       photo: millimetres per photo pixel (default 2)\n"
                 "  --texture-seed N     seed of the procedural texture (default: --seed)\n"
                 "Camera (left = reference; right shifted by the baseline to the right):\n"
                 "  --width W --height H image size (default 320 240)\n"
                 "  --f F                focal length in px (default 250)\n"
                 "  --cx X --cy Y        principal point (default (W-1)/2, (H-1)/2)\n"
                 "  --baseline-mm B      stereo baseline (default 120)\n"
                 "  --height-mm H        camera height above the near ground (default 1200)\n"
                 "  --pitch-deg P        downward pitch (default 20)\n"
                 "  --roll-deg R         roll, + = right side down (default 0)\n"
                 "  --yaw-deg Y          heading relative to the edge normal (default 0)\n"
                 "Sequence:\n"
                 "  --single             one pair, no motion (same as --frames 1 without\n"
                 "                       bobbing or sway)\n"
                 "  --frames N           number of frames (default 1)\n"
                 "  --speed V            walking speed m/s (default 1.2)\n"
                 "  --fps F              frame rate (default 10)\n"
                 "  --bob-mm A           vertical bobbing amplitude (default 25)\n"
                 "  --bob-hz F           bobbing (step) frequency (default 1.8)\n"
                 "  --sway-deg A         pitch sway amplitude (default 1.0)\n"
                 "  --roll-sway-deg A    roll sway amplitude, half step frequency (0.5)\n"
                 "  --yaw-sway-deg A     heading sway amplitude, half step frequency (0):\n"
                 "                       the camera turns, the walk keeps its heading\n"
                 "  --side-sway-mm A     sideways sway amplitude, half step frequency (0)\n"
                 "  --seed N             seed for motion phases, texture and noise (default 1)\n"
                 "Sensor:\n"
                 "  --noise S            Gaussian noise sigma in grey levels (default 0)\n"
                 "  --gain-right G       right exposure/gain factor (default 1)\n"
                 "  --offset-right O     right offset in grey levels (default 0)\n"
                 "  --brightness K       gain of both cameras (default 1)\n"
                 "  --exposure-pct P     auto-exposure changes within a sequence: every\n"
                 "                       --exposure-every frames the exposure of both\n"
                 "                       cameras moves to a new random level within +-P %%\n"
                 "                       of the start, over 3 frames (default 0: none)\n"
                 "  --exposure-every N   frames between exposure changes (default 10)\n"
                 "  --exposure-lag-right N  the right camera's exposure follows N frames\n"
                 "                       late (independent auto-exposure; default 0)\n"
                 "  --blur S             lens blur, Gaussian PSF sigma in px (default 0)\n"
                 "  --vshift-right R     vertical misalignment: right image content moved\n"
                 "                       down by R rows, sub-pixel allowed (default 0)\n"
                 "  --ss N               NxN supersampling per pixel, 1..4 (default 2)\n"
                 "Output:\n"
                 "  --out DIR            output folder (created)\n"
                 "  --gt-disparity       also write disp_NNNN.png (16-bit, disparity*16,\n"
                 "                       0 = no surface) of the left image\n"
                 "  --gt-disparity-right also write dispr_NNNN.png, the right image's GT\n"
                 "                       disparity (same encoding; its match is at x + d)\n"
                 "  --threads N          worker threads (default: OpenCV's choice, all cores)\n"
                 "  --preview            also write preview_NNNN.png: left image with the GT\n"
                 "                       edge line, next to the GT disparity (brighter = nearer)\n"
                 "  -q, --quiet          no progress/timing line\n"
                 "  -h, --help           this text\n"
                 "  -V, --version        the negobs version\n"
                 "Options take their value as --opt VALUE or --opt=VALUE; -o is --out.\n"
                 "Exit: 0 ok, 1 data error (texture unreadable, output not writable),\n"
                 "2 bad command line (also: no arguments).\n"
                 "Example:\n"
                 "  %s --scene curb --drop-mm 150 --edge-mm 4000 --frames 60 --speed 1.2 \\\n"
                 "     --fps 10 --noise 2 --seed 7 --out /tmp/curb\n",
                 argv0, argv0);
}

bool parse_double(const char *s, double &out)
{
    if (!s || !*s)
        return false;
    char *end = nullptr;
    errno = 0;
    const double v = std::strtod(s, &end);
    if (errno != 0 || *end != '\0' || !std::isfinite(v))
        return false;
    out = v;
    return true;
}

bool parse_u64(const char *s, uint64_t &out)
{
    if (!s || !*s || *s == '-')
        return false;
    char *end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(s, &end, 10);
    if (errno != 0 || *end != '\0')
        return false;
    out = v;
    return true;
}

bool parse_int(const char *s, int &out)
{
    double d;
    if (!parse_double(s, d) || d != std::floor(d) || std::fabs(d) > 1e9)
        return false;
    out = static_cast<int>(d);
    return true;
}

int fail(const char *argv0, const std::string &msg)
{
    std::fprintf(stderr, "%s: error: %s\n(try --help)\n", argv0, msg.c_str());
    return 2;
}

// Options that take a value; their getopt_long codes are 256 + index.
const char *const kValued[] = {"scene",
                               "edge-mm",
                               "drop-mm",
                               "steps",
                               "rise-mm",
                               "run-mm",
                               "hole-width-mm",
                               "hole-length-mm",
                               "hole-offset-mm",
                               "wall-height-mm",
                               "grade-pct",
                               "ramp-mm",
                               "lower-shade",
                               "texture-kind",
                               "distractors",
                               "texture",
                               "texture-mm",
                               "texture-seed",
                               "width",
                               "height",
                               "f",
                               "cx",
                               "cy",
                               "baseline-mm",
                               "height-mm",
                               "pitch-deg",
                               "roll-deg",
                               "yaw-deg",
                               "frames",
                               "speed",
                               "fps",
                               "bob-mm",
                               "bob-hz",
                               "sway-deg",
                               "roll-sway-deg",
                               "yaw-sway-deg",
                               "side-sway-mm",
                               "seed",
                               "noise",
                               "gain-right",
                               "offset-right",
                               "blur",
                               "brightness",
                               "exposure-pct",
                               "exposure-every",
                               "exposure-lag-right",
                               "vshift-right",
                               "ss",
                               "threads",
                               "out"};
// Flags: codes 512 + index.
const char *const kFlags[] = {"single", "gt-disparity", "gt-disparity-right", "preview"};

// Input or output trouble after a good command line: exit 1.
int fail_data(const char *argv0, const std::string &msg)
{
    std::fprintf(stderr, "%s: error: %s\n", argv0, msg.c_str());
    return negobs_cli::kExitData;
}

// Returns 0 on success, -1 for --help / --version, otherwise an exit code.
int parse(int argc, char **argv, Options &o)
{
    const char *a0 = "negobs_synth";
    bool edge_set = false;
    if (argc < 2) {
        usage(stderr, a0);
        return 2;
    }
    std::vector<struct option> opts;
    for (size_t k = 0; k < sizeof kValued / sizeof kValued[0]; ++k)
        opts.push_back({kValued[k], required_argument, nullptr, 256 + static_cast<int>(k)});
    for (size_t k = 0; k < sizeof kFlags / sizeof kFlags[0]; ++k)
        opts.push_back({kFlags[k], no_argument, nullptr, 512 + static_cast<int>(k)});
    opts.push_back({"help", no_argument, nullptr, 'h'});
    opts.push_back({"version", no_argument, nullptr, 'V'});
    opts.push_back({"quiet", no_argument, nullptr, 'q'});
    opts.push_back({nullptr, 0, nullptr, 0});
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, "+:hVqo:", opts.data(), nullptr)) != -1) {
        if (c == 'h') {
            usage(stdout, a0);
            return -1;
        }
        if (c == 'V') {
            negobs_cli::print_version("negobs_synth");
            return -1;
        }
        if (c == ':')
            return fail(a0, std::string("option ") + argv[optind - 1] + " needs a value");
        if (c == '?')
            return fail(a0, std::string("unknown option '") + argv[optind - 1] + "'");
        if (c == 'q') {
            o.quiet = true;
            continue;
        }
        if (c >= 512) {
            const std::string flag = kFlags[c - 512];
            if (flag == "single")
                o.single = true;
            else if (flag == "gt-disparity")
                o.gt_disparity = true;
            else if (flag == "gt-disparity-right")
                o.gt_disparity_right = true;
            else
                o.preview = true;
            continue;
        }
        const std::string arg = c == 'o' ? std::string("--out")
                                         : "--" + std::string(kValued[c - 256]);
        const std::string val = optarg;
        const char *v = val.c_str();
        double d = 0.0;
        int n = 0;
        auto num = [&](double &dst, double lo, double hi) {
            if (!parse_double(v, d))
                return fail(a0, "option " + arg + ": '" + val + "' is not a number");
            if (d < lo || d > hi) {
                char buf[160];
                std::snprintf(buf, sizeof buf, "option %s: %g is outside [%g, %g]", arg.c_str(), d,
                              lo, hi);
                return fail(a0, buf);
            }
            dst = d;
            return 0;
        };
        auto integer = [&](int &dst, int lo, int hi) {
            if (!parse_int(v, n))
                return fail(a0, "option " + arg + ": '" + val + "' is not an integer");
            if (n < lo || n > hi) {
                char buf[160];
                std::snprintf(buf, sizeof buf, "option %s: %d is outside [%d, %d]", arg.c_str(), n,
                              lo, hi);
                return fail(a0, buf);
            }
            dst = n;
            return 0;
        };
        int rc = 0;
        double mm = 0.0;
        if (arg == "--scene") {
            if (!synth::hazard_from_name(val, o.scene.hazard))
                return fail(a0,
                            "unknown scene '" + val + "' (curb|stairs|hole|upstep|wall|flat|ramp)");
        } else if (arg == "--edge-mm") {
            rc = num(mm, -1e6, 1e6);
            o.scene.edge_z = mm * 1e-3;
            edge_set = true;
        } else if (arg == "--drop-mm") {
            rc = num(mm, 1.0, 1e5);
            o.scene.drop = mm * 1e-3;
        } else if (arg == "--steps") {
            rc = integer(o.scene.steps, 1, 100);
        } else if (arg == "--rise-mm") {
            rc = num(mm, 1.0, 1e4);
            o.scene.rise = mm * 1e-3;
        } else if (arg == "--run-mm") {
            rc = num(mm, 10.0, 1e5);
            o.scene.run = mm * 1e-3;
        } else if (arg == "--hole-width-mm") {
            rc = num(mm, 10.0, 1e6);
            o.scene.hole_width = mm * 1e-3;
        } else if (arg == "--hole-length-mm") {
            rc = num(mm, 10.0, 1e6);
            o.scene.hole_length = mm * 1e-3;
        } else if (arg == "--hole-offset-mm") {
            rc = num(mm, -1e6, 1e6);
            o.scene.hole_offset = mm * 1e-3;
        } else if (arg == "--wall-height-mm") {
            rc = num(mm, 1.0, 1e6);
            o.scene.wall_height = mm * 1e-3;
        } else if (arg == "--grade-pct") {
            double g = 0.0;
            rc = num(g, -50.0, 50.0);
            o.scene.ramp_grade = g * 1e-2;
        } else if (arg == "--ramp-mm") {
            rc = num(mm, 0.0, 1e6);
            o.scene.ramp_length = mm > 0.0 ? mm * 1e-3 : std::numeric_limits<double>::infinity();
        } else if (arg == "--lower-shade") {
            rc = num(o.scene.lower_shade, 0.0, 2.0);
        } else if (arg == "--texture-kind") {
            o.texture_kind = val;
            if (val != "asphalt" && val != "paving" && val != "concrete" && val != "worn")
                return fail(a0,
                            "unknown texture kind '" + val + "' (asphalt|paving|concrete|worn)");
        } else if (arg == "--distractors") {
            rc = integer(o.distractors, 0, 1000);
        } else if (arg == "--texture") {
            o.texture_file = val;
        } else if (arg == "--texture-mm") {
            rc = num(o.texture_mm, 0.01, 1000.0);
        } else if (arg == "--texture-seed") {
            if (!parse_u64(v, o.texture_seed))
                return fail(a0,
                            "option --texture-seed: '" + val + "' is not a non-negative integer");
            o.texture_seed_set = true;
        } else if (arg == "--width") {
            rc = integer(o.rig.width, 16, 8192);
        } else if (arg == "--height") {
            rc = integer(o.rig.height, 16, 8192);
        } else if (arg == "--f") {
            rc = num(o.rig.f, 10.0, 1e5);
        } else if (arg == "--cx") {
            rc = num(o.rig.cx, -1e5, 1e5);
            o.cx_set = true;
        } else if (arg == "--cy") {
            rc = num(o.rig.cy, -1e5, 1e5);
            o.cy_set = true;
        } else if (arg == "--baseline-mm") {
            rc = num(mm, 1.0, 1e4);
            o.rig.baseline = mm * 1e-3;
        } else if (arg == "--height-mm") {
            rc = num(o.height_mm, 50.0, 1e5);
        } else if (arg == "--pitch-deg") {
            rc = num(o.pitch_deg, -80.0, 89.0);
        } else if (arg == "--roll-deg") {
            rc = num(o.roll_deg, -90.0, 90.0);
        } else if (arg == "--yaw-deg") {
            rc = num(o.yaw_deg, -80.0, 80.0);
        } else if (arg == "--frames") {
            rc = integer(o.frames, 1, 100000);
        } else if (arg == "--speed") {
            rc = num(o.speed, 0.0, 20.0);
        } else if (arg == "--fps") {
            rc = num(o.fps, 0.1, 1000.0);
        } else if (arg == "--bob-mm") {
            rc = num(o.bob_mm, 0.0, 500.0);
        } else if (arg == "--bob-hz") {
            rc = num(o.bob_hz, 0.0, 20.0);
        } else if (arg == "--sway-deg") {
            rc = num(o.sway_deg, 0.0, 30.0);
        } else if (arg == "--roll-sway-deg") {
            rc = num(o.roll_sway_deg, 0.0, 30.0);
        } else if (arg == "--yaw-sway-deg") {
            rc = num(o.yaw_sway_deg, 0.0, 30.0);
        } else if (arg == "--side-sway-mm") {
            rc = num(o.side_sway_mm, 0.0, 500.0);
        } else if (arg == "--seed") {
            if (!parse_u64(v, o.seed))
                return fail(a0, "option --seed: '" + val + "' is not a non-negative integer");
        } else if (arg == "--noise") {
            rc = num(o.sensor.noise_sigma, 0.0, 100.0);
        } else if (arg == "--gain-right") {
            rc = num(o.sensor.gain_right, 0.05, 20.0);
        } else if (arg == "--offset-right") {
            rc = num(o.sensor.offset_right, -255.0, 255.0);
        } else if (arg == "--blur") {
            rc = num(o.sensor.blur, 0.0, 20.0);
        } else if (arg == "--brightness") {
            rc = num(o.sensor.brightness, 0.01, 20.0);
        } else if (arg == "--exposure-pct") {
            rc = num(o.exposure_pct, 0.0, 90.0);
        } else if (arg == "--exposure-every") {
            rc = integer(o.exposure_every, 1, 100000);
        } else if (arg == "--exposure-lag-right") {
            rc = integer(o.exposure_lag, 0, 100);
        } else if (arg == "--vshift-right") {
            rc = num(o.rig.right_row_shift, -100.0, 100.0);
        } else if (arg == "--ss") {
            rc = integer(o.render.supersample, 1, 4);
        } else if (arg == "--threads") {
            rc = integer(o.threads, 1, 256);
        } else if (arg == "--out") {
            o.out = val;
        } else {
            return fail(a0, "unknown option '" + arg + "'");
        }
        if (rc)
            return rc;
    }
    if (optind < argc)
        return fail(a0, std::string("unexpected argument '") + argv[optind] + "'");
    (void)edge_set;
    if (o.out.empty())
        return fail(a0, "--out DIR is required");
    if (!o.cx_set)
        o.rig.cx = (o.rig.width - 1) * 0.5;
    if (!o.cy_set)
        o.rig.cy = (o.rig.height - 1) * 0.5;
    if (!o.texture_seed_set)
        o.texture_seed = o.seed;
    if (o.single) {
        if (o.frames != 1)
            return fail(a0, "--single and --frames N > 1 contradict each other");
        o.bob_mm = 0.0;
        o.sway_deg = 0.0;
        o.roll_sway_deg = 0.0;
        o.yaw_sway_deg = 0.0;
        o.side_sway_mm = 0.0;
    }
    if (o.height_mm * 1e-3 <= 0.0)
        return fail(a0, "--height-mm must be positive");
    if (o.scene.hazard == synth::Hazard::Stairs && o.scene.steps < 1)
        return fail(a0, "--steps must be >= 1");
    return 0;
}

std::string fmt(const char *f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char *f, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, f);
    std::vsnprintf(buf, sizeof buf, f, ap);
    va_end(ap);
    return buf;
}

bool write_png(const std::string &path, const cv::Mat &m)
{
    const std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, 3};
    try {
        return cv::imwrite(path, m, params);
    } catch (const cv::Exception &) {
        return false;
    }
}

// 16-bit disparity PNG: round(d*16), at least 1 where a surface is hit,
// 0 = no surface.
cv::Mat disp16(const cv::Mat &disp)
{
    cv::Mat d16(disp.rows, disp.cols, CV_16U);
    for (int y = 0; y < disp.rows; ++y) {
        const float *s = disp.ptr<float>(y);
        uint16_t *q = d16.ptr<uint16_t>(y);
        for (int x = 0; x < disp.cols; ++x) {
            if (s[x] <= 0.0f) {
                q[x] = 0;
            } else {
                const long v = std::lround(static_cast<double>(s[x]) * 16.0);
                q[x] = static_cast<uint16_t>(std::clamp(v, 1L, 65535L));
            }
        }
    }
    return d16;
}

// Exposure factor of every frame (both cameras before the right one's
// lag). Auto-exposure reacts to a change of scene brightness in steps and
// settles over a few frames, so each change is a ramp over 3 frames to a
// new level within +-exposure_pct of the start; levels come from their own
// random stream so the motion and noise of a seed do not change.
std::vector<double> exposure_schedule(const Options &o)
{
    std::vector<double> e(static_cast<size_t>(o.frames), 1.0);
    if (o.exposure_pct <= 0.0)
        return e;
    synth::Rng rng(o.seed * 0xA24BAED4963EE407ull + 23);
    double from = 1.0, to = 1.0;
    int start = 0;
    constexpr int kSettleFrames = 3;
    for (int i = 0; i < o.frames; ++i) {
        if (i > 0 && i % o.exposure_every == 0) {
            from = e[static_cast<size_t>(i - 1)];
            to = 1.0 + o.exposure_pct * 1e-2 * (2.0 * rng.uniform() - 1.0);
            start = i;
        }
        const double a = std::min(1.0, (i - start + 1) / static_cast<double>(kSettleFrames));
        e[static_cast<size_t>(i)] = i < o.exposure_every ? 1.0 : from + a * (to - from);
    }
    return e;
}

int run(int argc, char **argv)
{
    Options o;
    const int prc = parse(argc, argv, o);
    if (prc == -1)
        return 0;
    if (prc != 0)
        return prc;

    const char *a0 = "negobs_synth";
    if (o.threads > 0)
        cv::setNumThreads(o.threads);
    std::error_code ec;
    std::filesystem::create_directories(o.out, ec);
    if (ec || !std::filesystem::is_directory(o.out))
        return fail_data(a0, "cannot create output folder '" + o.out + "'");

    synth::Texture tex;
    std::string err;
    const bool tex_ok = o.texture_file.empty()
                            ? tex.make_procedural(o.texture_seed, o.texture_kind, err)
                            : tex.load_photo(o.texture_file, o.texture_mm, err);
    if (!tex_ok)
        return fail_data(a0, err);

    // Distractors from 1 m ahead to 2 m past the edge (8 m on flat
    // ground), on the Y = 0 surfaces only.
    o.scene.distractors = synth::random_distractors(
        o.distractors, 1.0,
        o.scene.hazard == synth::Hazard::Flat ? 8.0 : std::max(2.0, o.scene.edge_z + 2.0), o.seed);
    const synth::Scene scene(o.scene);
    const bool sequence = !o.single;
    // Motion phases from the seed, so every sequence bobs differently.
    synth::Rng mrng(o.seed * 0x9E3779B97F4A7C15ull + 17);
    const double ph_bob = 2.0 * kPi * mrng.uniform();
    const double ph_pitch = 2.0 * kPi * mrng.uniform();
    const double ph_roll = 2.0 * kPi * mrng.uniform();
    const double ph_yaw = 2.0 * kPi * mrng.uniform(); // drawn last: older phases keep
    const double ph_side = 2.0 * kPi * mrng.uniform();
    const double yaw = o.yaw_deg * kPi / 180.0;
    const std::vector<double> exposure = exposure_schedule(o);

    const std::string gt_path = o.out + "/gt.json";
    FILE *gt = std::fopen(gt_path.c_str(), "w");
    if (!gt)
        return fail_data(a0, "cannot write '" + gt_path + "'");
    const synth::SceneParams &sp = o.scene;
    std::string dlist;
    for (const synth::Distractor &d : sp.distractors) {
        if (!dlist.empty())
            dlist += ", ";
        if (d.kind == synth::Distractor::Manhole)
            dlist += fmt("{\"type\": \"manhole\", \"x_mm\": %.0f, \"z_mm\": %.0f, "
                         "\"radius_mm\": %.0f, \"value\": %.3g}",
                         d.x0 * 1e3, d.z0 * 1e3, d.x1 * 1e3, d.value);
        else
            dlist += fmt("{\"type\": \"%s\", \"x_mm\": [%.0f, %.0f], \"z_mm\": [%.0f, %.0f], "
                         "\"value\": %.3g}",
                         synth::distractor_name(d.kind), d.x0 * 1e3, d.x1 * 1e3, d.z0 * 1e3,
                         d.z1 * 1e3, d.value);
    }
    std::fprintf(gt, "{\n\"generator\": \"negobs_synth %s\",\n", negobs_version());
    std::fprintf(gt,
                 "\"camera\": {\"f\": %.6g, \"B_mm\": %.6g, \"cx\": %.6g, \"cy\": %.6g, "
                 "\"H_mm\": %.6g, \"pitch\": %.6g, \"roll\": %.6g, \"yaw\": %.6g, "
                 "\"width\": %d, \"height\": %d, \"right_row_shift\": %.6g},\n",
                 o.rig.f, o.rig.baseline * 1e3, o.rig.cx, o.rig.cy, o.height_mm, o.pitch_deg,
                 o.roll_deg, o.yaw_deg, o.rig.width, o.rig.height, o.rig.right_row_shift);
    std::fprintf(
        gt,
        "\"scene\": {\"hazard\": \"%s\", \"negative\": %s, \"edge_mm\": %.6g, "
        "\"drop_mm\": %.6g, \"steps\": %d, \"rise_mm\": %.6g, \"run_mm\": %.6g, "
        "\"hole_width_mm\": %.6g, \"hole_length_mm\": %.6g, "
        "\"hole_offset_mm\": %.6g, \"wall_height_mm\": %.6g, "
        "\"ramp_grade_pct\": %.6g, \"ramp_mm\": %s, "
        "\"texture\": \"%s\", \"texture_seed\": %llu, \"distractors\": [%s]},\n",
        synth::hazard_name(sp.hazard),
        (sp.hazard == synth::Hazard::Curb || sp.hazard == synth::Hazard::Stairs ||
         sp.hazard == synth::Hazard::Hole)
            ? "true"
            : "false",
        sp.edge_z * 1e3, sp.drop * 1e3, sp.steps, sp.rise * 1e3, sp.run * 1e3, sp.hole_width * 1e3,
        sp.hole_length * 1e3, sp.hole_offset * 1e3, sp.wall_height * 1e3, sp.ramp_grade * 1e2,
        std::isfinite(sp.ramp_length) ? fmt("%.6g", sp.ramp_length * 1e3).c_str() : "null",
        negobs_cli::json_escape(o.texture_file.empty() ? o.texture_kind : o.texture_file).c_str(),
        static_cast<unsigned long long>(o.texture_seed), dlist.c_str());
    std::fprintf(
        gt,
        "\"render\": {\"supersample\": %d, \"noise\": %.6g, \"gain_right\": %.6g, "
        "\"offset_right\": %.6g, \"brightness\": %.6g, \"blur\": %.6g, \"seed\": %llu, "
        "\"speed_mps\": %.6g, \"fps\": %.6g, \"bob_mm\": %.6g, \"bob_hz\": %.6g, "
        "\"sway_deg\": %.6g, \"roll_sway_deg\": %.6g, \"yaw_sway_deg\": %.6g, \"side_sway_mm\": %.6g, "
        "\"gt_disparity\": %s, "
        "\"gt_disparity_right\": %s, \"exposure_pct\": %.6g, \"exposure_every\": %d, "
        "\"exposure_lag_right\": %d},\n",
        o.render.supersample, o.sensor.noise_sigma, o.sensor.gain_right, o.sensor.offset_right,
        o.sensor.brightness, o.sensor.blur, static_cast<unsigned long long>(o.seed),
        sequence ? o.speed : 0.0, o.fps, o.bob_mm, o.bob_hz, o.sway_deg, o.roll_sway_deg,
        o.yaw_sway_deg, o.side_sway_mm, o.gt_disparity ? "true" : "false",
        o.gt_disparity_right ? "true" : "false", o.exposure_pct, o.exposure_every, o.exposure_lag);
    std::fprintf(gt, "\"frames\": [\n");

    double render_ms = 0.0;
    const auto t_start = std::chrono::steady_clock::now();
    for (int i = 0; i < o.frames; ++i) {
        const double t = sequence ? i / o.fps : 0.0;
        const double dist = sequence ? o.speed * t : 0.0;
        const double w = 2.0 * kPi * o.bob_hz * t;
        synth::Pose pose;
        const double side = o.side_sway_mm * 1e-3 * std::sin(0.5 * w + ph_side);
        pose.x = dist * std::sin(yaw) + side * std::cos(yaw);
        pose.z = dist * std::cos(yaw) - side * std::sin(yaw);
        // On a ramp the walker follows the surface under the camera.
        const double ground_y = scene.ground_y(pose.z);
        pose.y = o.height_mm * 1e-3 + o.bob_mm * 1e-3 * std::sin(w + ph_bob) + ground_y;
        pose.pitch = o.pitch_deg + o.sway_deg * std::sin(w + ph_pitch);
        pose.roll = o.roll_deg + o.roll_sway_deg * std::sin(0.5 * w + ph_roll);
        pose.yaw = o.yaw_deg + o.yaw_sway_deg * std::sin(0.5 * w + ph_yaw);

        const auto t0 = std::chrono::steady_clock::now();
        cv::Mat lf, rf, disp;
        synth::render_view(scene, tex, o.rig, pose, 0, o.render, lf,
                           (o.gt_disparity || o.preview) ? &disp : nullptr);
        cv::Mat dispr;
        synth::render_view(scene, tex, o.rig, pose, 1, o.render, rf,
                           o.gt_disparity_right ? &dispr : nullptr);
        synth::apply_blur(lf, o.sensor.blur);
        synth::apply_blur(rf, o.sensor.blur);
        const uint64_t fseed = o.seed * 0xD1B54A32D192ED03ull + static_cast<uint64_t>(i) * 7919u +
                               1;
        cv::Mat l8, r8;
        synth::SensorOptions sl = o.sensor, sr = o.sensor;
        const double exp_l = exposure[static_cast<size_t>(i)];
        const double exp_r = exposure[static_cast<size_t>(std::max(0, i - o.exposure_lag))];
        sl.brightness *= exp_l;
        sr.brightness *= exp_r;
        synth::apply_sensor(lf, 0, sl, fseed, l8);
        synth::apply_sensor(rf, 1, sr, fseed, r8);
        const synth::EdgeGT eg = synth::edge_ground_truth(scene, o.rig, pose);
        render_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                               t0)
                         .count();

        const std::string ln = fmt("left_%04d.png", i), rn = fmt("right_%04d.png", i);
        const std::string dn = fmt("disp_%04d.png", i);
        if (!write_png(o.out + "/" + ln, l8) || !write_png(o.out + "/" + rn, r8)) {
            std::fclose(gt);
            return fail_data(a0, "cannot write images into '" + o.out + "'");
        }
        if ((o.gt_disparity && !write_png(o.out + "/" + dn, disp16(disp))) ||
            (o.gt_disparity_right &&
             !write_png(o.out + "/" + fmt("dispr_%04d.png", i), disp16(dispr)))) {
            std::fclose(gt);
            return fail_data(a0, "cannot write disparity into '" + o.out + "'");
        }

        if (o.preview) {
            // Left image with the GT edge line | GT disparity (0..max -> 0..255).
            cv::Mat l = l8.clone(), d8;
            if (eg.visible)
                cv::line(l, cv::Point2d(eg.u_min, eg.v_at_u_min),
                         cv::Point2d(eg.u_max, eg.v_at_u_max), cv::Scalar(255), 1, cv::LINE_8);
            double dmax = 0.0;
            cv::minMaxLoc(disp, nullptr, &dmax);
            disp.convertTo(d8, CV_8U, dmax > 0.0 ? 255.0 / dmax : 0.0);
            cv::Mat both;
            cv::hconcat(l, d8, both);
            if (!write_png(o.out + "/" + fmt("preview_%04d.png", i), both)) {
                std::fclose(gt);
                return fail_data(a0, "cannot write preview into '" + o.out + "'");
            }
        }

        // Horizontal distance from the camera to the edge line, measured
        // perpendicular to it (negative once the edge is passed).
        const bool has_edge = sp.hazard != synth::Hazard::Flat;
        std::string edge = "null", rows = "null", box = "null", rowc = "null", line = "null";
        if (has_edge)
            edge = fmt("%.1f", (sp.edge_z - pose.z) * 1e3);
        if (eg.visible) {
            rows = fmt("[%.2f, %.2f]", eg.v_min, eg.v_max);
            box = fmt("[%.0f, %.2f, %.0f, %.2f]", eg.u_min, eg.v_min, eg.u_max, eg.v_max);
            line = fmt("[%.0f, %.2f, %.0f, %.2f]", eg.u_min, eg.v_at_u_min, eg.u_max,
                       eg.v_at_u_max);
        }
        if (eg.has_row_at_cx)
            rowc = fmt("%.2f", eg.row_at_cx);
        // Further edges: every step edge of the stairs, the far rim of a hole.
        std::string extra;
        if (sp.hazard == synth::Hazard::Stairs) {
            extra = ", \"step_ranges_mm\": [";
            for (int k = 0; k < sp.steps; ++k)
                extra += fmt("%s%.1f", k ? ", " : "", (sp.edge_z + k * sp.run - pose.z) * 1e3);
            extra += "]";
        } else if (sp.hazard == synth::Hazard::Hole) {
            extra = fmt(", \"far_edge_range_mm\": %.1f",
                        (sp.edge_z + sp.hole_length - pose.z) * 1e3);
        }
        double drop = 0.0;
        switch (sp.hazard) {
        case synth::Hazard::Curb:
        case synth::Hazard::Hole: drop = sp.drop; break;
        case synth::Hazard::Stairs: drop = sp.rise; break;
        case synth::Hazard::Upstep: drop = -sp.drop; break;
        default: drop = 0.0; break;
        }
        std::fprintf(
            gt,
            "{\"i\": %d, \"t_s\": %.4f, \"left\": \"%s\", \"right\": \"%s\", "
            "\"disparity\": %s, \"hazard\": \"%s\", \"edge_range_mm\": %s, "
            "\"drop_mm\": %.1f, \"total_drop_mm\": %.1f, \"edge_visible\": %s, "
            "\"edge_cols\": %d, \"edge_rows\": %s, \"edge_box\": %s, \"edge_line\": %s, "
            "\"edge_row_at_cx\": %s, \"H_mm\": %.2f, \"pitch\": %.4f, "
            "\"roll\": %.4f, \"yaw\": %.4f, \"cam_x_mm\": %.1f, \"cam_z_mm\": %.1f, "
            "\"ground_y_mm\": %.1f, \"exposure\": [%.4f, %.4f]%s}%s\n",
            i, t, ln.c_str(), rn.c_str(), o.gt_disparity ? ("\"" + dn + "\"").c_str() : "null",
            synth::hazard_name(sp.hazard), edge.c_str(), drop * 1e3,
            (sp.hazard == synth::Hazard::Stairs ? sp.rise * sp.steps : drop) * 1e3,
            eg.visible ? "true" : "false", eg.cols_visible, rows.c_str(), box.c_str(), line.c_str(),
            rowc.c_str(), (pose.y - ground_y) * 1e3, pose.pitch, pose.roll, pose.yaw, pose.x * 1e3,
            pose.z * 1e3, ground_y * 1e3, exp_l, exp_r, extra.c_str(), i + 1 < o.frames ? "," : "");
    }
    std::fprintf(gt, "]\n}\n");
    if (std::fclose(gt) != 0)
        return fail_data(a0, "cannot write '" + gt_path + "'");
    if (!o.quiet) {
        const double total = std::chrono::duration<double, std::milli>(
                                 std::chrono::steady_clock::now() - t_start)
                                 .count();
        std::fprintf(stderr,
                     "negobs_synth: %d frame(s) %dx%d ss=%d into %s: render %.1f ms/frame, "
                     "total %.1f ms/frame\n",
                     o.frames, o.rig.width, o.rig.height, o.render.supersample, o.out.c_str(),
                     render_ms / o.frames, total / o.frames);
    }
    return 0;
}

} // namespace

int main(int argc, char **argv)
{
    return negobs_cli::main_guard("negobs_synth", argc, argv, run);
}
