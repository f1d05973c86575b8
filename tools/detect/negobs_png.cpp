// negobs_png: the full negobs pipeline (stereo -> detect -> alert) on one
// PNG pair or on a sequence folder (negobs_synth output or any folder of
// left_NNNN.png/right_NNNN.png), with overlay pictures and one JSON line
// per frame.
//
// Exit codes: 0 ok, 1 data error (unreadable file, size mismatch, pipeline
// refused the config), 2 bad command line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <getopt.h>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli.hpp"
#include "cli_parse.hpp"
#include "detect_common.hpp"
#include "disp_io.hpp"
#include "rect_table.hpp"
#include "session.hpp"
#include "stereo_common.hpp"

namespace fs = std::filesystem;
using namespace negobs_detect_tools;

namespace {

using negobs_tools::parse_double;
using negobs_tools::parse_int;

void usage(FILE *f)
{
    std::fprintf(
        f, "usage: negobs_png LEFT RIGHT --out DIR [options]\n"
           "       negobs_png --seq DIR --out OUTDIR [options]\n"
           "DIR: negobs_synth output, a folder of left_NNNN.png/right_NNNN.png, or a\n"
           "session recorded by negobs_run --record (session.txt, left.y, right.y;\n"
           "its meta.txt gives the rig geometry and names its calibration table).\n"
           "Runs the whole negobs pipeline and writes OUTDIR/overlay_NNNN.png and\n"
           "one JSON line per frame (stdout, or --json FILE).\n"
           "Camera: read from DIR/gt.json when present (negobs_synth), else:\n"
           "  --f PX            focal length (250 at 320 px width, scaled)\n"
           "  --baseline-mm B   baseline (120)\n"
           "  --cx PX --cy PX   principal point (image centre)\n"
           "  --calib TABLE     rectify every pair with a negobs_calib table (the\n"
           "                    library's remap, as negobs_run --calib); its f, B,\n"
           "                    cx, cy replace the camera values\n"
           "  --height-mm H     camera height hint (1200; 0: no hint). The detector\n"
           "                    measures the mounting on the floor; the hint only\n"
           "                    verifies the start (docs/DETECTION.md)\n"
           "  --pitch-deg P     camera pitch hint, down (20)\n"
           "  --max-disp D      largest disparity searched (library default 63)\n"
           "  --vshift ROWS     left row y matches right row y+ROWS (default:\n"
           "                    the matcher estimates whole rows)\n"
           "  --vshift model    sub-pixel, row-varying alignment stage before the\n"
           "                    matcher (negobs/valign.h; uncalibrated rigs)\n"
           "  --bin K           bin every pair K x K (1..4, default 1) to the\n"
           "                    processing size, as the device does (the port's\n"
           "                    integer area binning); the camera values above\n"
           "                    describe the unbinned images and are scaled\n"
           "Options given on the command line override gt.json.\n"
           "  --fps F           frame rate for timestamps (10, or gt.json's)\n"
           "  --repeat N        single pair: feed it N times (confirmation needs\n"
           "                    3 of 5 frames) (1)\n"
           "  --first N --count N  sequence: frame subset\n"
           "  -j, --json FILE   JSON lines to FILE instead of stdout\n"
           "  --no-overlay      do not write pictures\n"
           "  --disparity       also write OUTDIR/disp_NNNN.png: the disparity the\n"
           "                    detector read (negobs_stereo's png16: value =\n"
           "                    disparity * 16, 0 = no value)\n"
           "  --overlay-scale K scale the pictures by K (0.1..4, default 1; below 1\n"
           "                    also 32 grey levels per channel: small files)\n"
           "  --whole           time only the whole frame (no per-stage clock)\n"
           "  --threads N       threads for the matcher's row bands, 1..64 (default 1);\n"
           "                    the output is the same for every N; with N > 1 the\n"
           "                    stage times add up the threads' CPU time and the\n"
           "                    total is the calling thread's\n"
           "  --profile P       the matcher's memory profile: compact (default,\n"
           "                    the library's) or fast (its growth memo, as\n"
           "                    negobs_run takes where it fits); same output\n"
           "  --coarse on|off   the half-resolution pass for weakly textured\n"
           "                    floors (on, the library's default;\n"
           "                    docs/DETECTION.md)\n"
           "  --pool N          pool N frames along the measured travel (1..4;\n"
           "                    the detector's pool_frames; docs/DETECTION.md)\n"
           "  --summary         one summary line at the end (stdout)\n"
           "  -q, --quiet       no JSON lines on stdout\n"
           "  -h, --help        this text\n"
           "  -V, --version     the negobs version\n"
           "Options take their value as --opt VALUE or --opt=VALUE; -o is --out.\n"
           "Exit: 0 ok, 1 data error, 2 bad command line (also: no arguments).\n");
}

int bad(const std::string &msg)
{
    std::fprintf(stderr, "negobs_png: error: %s\n", msg.c_str());
    std::fprintf(stderr, "try 'negobs_png --help'\n");
    return 2;
}

int fail(const std::string &msg)
{
    std::fprintf(stderr, "negobs_png: error: %s\n", msg.c_str());
    return 1;
}

// gt.json is input data, not trusted: every camera value it gives must be
// a finite number in the range the matching command-line option accepts
// (a NaN used to become 0 and 1e30 an undefined conversion to the
// library's integers). Values overridden on the command line are checked
// there instead. Returns "" or what is wrong.
std::string check_gt_camera(const GtSeq &gt, bool f_set, bool b_set, bool cx_set,
                            bool cy_set, bool h_set, bool pitch_set, bool fps_set)
{
    const struct {
        const char *key;
        double v;
        bool overridden;
        double lo, hi;
    } fields[] = {
        {"f", gt.cam.f, f_set, 1, 8192},
        {"B_mm", gt.cam.baseline_mm, b_set, 1, 1000},
        {"cx", gt.cam.cx, cx_set, 0, 4096},
        {"cy", gt.cam.cy, cy_set, 0, 4096},
        {"H_mm", gt.cam.height_mm, h_set, 200, 3000},
        {"pitch", gt.cam.pitch_deg, pitch_set, -10, 80},
        {"fps", gt.fps, fps_set, 0.001, 1000},
    };
    for (const auto &fl : fields) {
        if (fl.overridden) {
            continue;
        }
        if (!std::isfinite(fl.v) || fl.v < fl.lo || fl.v > fl.hi) {
            char buf[160];
            std::snprintf(buf, sizeof buf,
                          "camera %s = %g is not a finite number "
                          "in %g..%g",
                          fl.key, fl.v, fl.lo, fl.hi);
            return buf;
        }
    }
    if (gt.width < 1 || gt.height < 1 || gt.width > 4096 || gt.height > 4096) {
        return "camera width x height " + std::to_string(gt.width) + "x" +
               std::to_string(gt.height) + " is not in 1..4096";
    }
    return std::string();
}

struct Item {
    std::string left, right, name;
    const GtFrame *gt = nullptr;
    long raw = -1;    // recorded session: frame index in left.y/right.y
    double t_ms = -1; // recorded session: capture time from frames.txt
};

} // namespace

namespace {

// The pipeline's disparity map (q4, NEGOBS_DISP_INVALID = no value) as
// negobs_stereo's png16: what the detector read, after the pipeline's own
// matcher settings, the row ROI and any alignment.
bool write_disp_q4(const cv::Mat &disp_q4, const std::string &path, std::string &err)
{
    cv::Mat d;
    cv::Mat valid;
    negobs_tools::negobs_q4_to_float(disp_q4, d, valid);
    return negobs_cli::write_disparity(path, d, valid, negobs_cli::DispFormat::Png16,
                                       err);
}

int run(int argc, char **argv)
{
    std::string seq, out, json_path, calib_path;
    std::vector<std::string> pos;
    double overlay_scale = 1.0;
    double f = -1, B = -1, cx = -1, cy = -1, H = -1, pitch = -1e9, fps = -1;
    int threads = 1; // the times stay one thread's CPU time
    int profile = NEGOBS_STEREO_PROFILE_DEFAULT;
    int coarse = 1;
    int pool = -1; // the detector's pool_frames; < 0: its default
    int max_disp = -1, vshift = 0, repeat = 1, first = 0, count = -1, bin = 1;
    bool valign = false;
    bool vshift_set = false, overlay_on = true, summary = false, quiet = false,
         whole = false, disp_on = false;
    enum {
        O_SEQ = 256,
        O_JSON,
        O_F,
        O_B,
        O_CX,
        O_CY,
        O_H,
        O_PITCH,
        O_MAXD,
        O_VSHIFT,
        O_FPS,
        O_REPEAT,
        O_FIRST,
        O_COUNT,
        O_SCALE,
        O_NO_OVERLAY,
        O_SUMMARY,
        O_WHOLE,
        O_CALIB,
        O_THREADS,
        O_PROFILE,
        O_COARSE,
        O_POOL,
        O_BIN,
        O_DISP
    };
    static const struct option long_opts[] = {
        {"help", no_argument, nullptr, 'h'},
        {"version", no_argument, nullptr, 'V'},
        {"seq", required_argument, nullptr, O_SEQ},
        {"out", required_argument, nullptr, 'o'},
        {"json", required_argument, nullptr, 'j'},
        {"f", required_argument, nullptr, O_F},
        {"baseline-mm", required_argument, nullptr, O_B},
        {"cx", required_argument, nullptr, O_CX},
        {"cy", required_argument, nullptr, O_CY},
        {"height-mm", required_argument, nullptr, O_H},
        {"pitch-deg", required_argument, nullptr, O_PITCH},
        {"max-disp", required_argument, nullptr, O_MAXD},
        {"vshift", required_argument, nullptr, O_VSHIFT},
        {"fps", required_argument, nullptr, O_FPS},
        {"repeat", required_argument, nullptr, O_REPEAT},
        {"first", required_argument, nullptr, O_FIRST},
        {"count", required_argument, nullptr, O_COUNT},
        {"overlay-scale", required_argument, nullptr, O_SCALE},
        {"no-overlay", no_argument, nullptr, O_NO_OVERLAY},
        {"summary", no_argument, nullptr, O_SUMMARY},
        {"quiet", no_argument, nullptr, 'q'},
        {"whole", no_argument, nullptr, O_WHOLE},
        {"calib", required_argument, nullptr, O_CALIB},
        {"threads", required_argument, nullptr, O_THREADS},
        {"profile", required_argument, nullptr, O_PROFILE},
        {"coarse", required_argument, nullptr, O_COARSE},
        {"pool", required_argument, nullptr, O_POOL},
        {"bin", required_argument, nullptr, O_BIN},
        {"disparity", no_argument, nullptr, O_DISP},
        {nullptr, 0, nullptr, 0},
    };
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    opterr = 0;
    int c;
    int li = -1;
    while ((c = getopt_long(argc, argv, ":hVo:j:q", long_opts, &li)) != -1) {
        const char *v = optarg;
        const std::string a = c == ':' || c == '?' ? std::string(argv[optind - 1])
                                                   : std::string();
        bool ok = true;
        switch (c) {
        case 'h': usage(stdout); return 0;
        case 'V': negobs_cli::print_version("negobs_png"); return 0;
        case O_SEQ: seq = v; break;
        case 'o': out = v; break;
        case 'j': json_path = v; break;
        case O_CALIB: calib_path = v; break;
        case O_F: ok = negobs_cli::parse_double(v, 1, 8192, f); break;
        case O_B: ok = negobs_cli::parse_double(v, 1, 1000, B); break;
        case O_CX: ok = negobs_cli::parse_double(v, 0, 4096, cx); break;
        case O_CY: ok = negobs_cli::parse_double(v, 0, 4096, cy); break;
        case O_H:
            ok = negobs_cli::parse_double(v, 0, 3000, H) && (H == 0 || H >= 200);
            break;
        case O_PITCH: ok = negobs_cli::parse_double(v, -10, 80, pitch); break;
        case O_MAXD: ok = negobs_cli::parse_int(v, 8, 255, max_disp); break;
        case O_VSHIFT:
            if (std::string(v) == "model") {
                valign = true;
            } else {
                ok = negobs_cli::parse_int(v, -16, 16, vshift);
                vshift_set = true;
            }
            break;
        case O_FPS: ok = negobs_cli::parse_double(v, 1e-3, 1000, fps); break;
        case O_REPEAT: ok = negobs_cli::parse_int(v, 1, 1000, repeat); break;
        case O_FIRST: ok = negobs_cli::parse_int(v, 0, 10000000, first); break;
        case O_COUNT: ok = negobs_cli::parse_int(v, 1, 10000000, count); break;
        case O_SCALE: ok = negobs_cli::parse_double(v, 0.1, 4, overlay_scale); break;
        case O_NO_OVERLAY: overlay_on = false; break;
        case O_DISP: disp_on = true; break;
        case O_SUMMARY: summary = true; break;
        case 'q': quiet = true; break;
        case O_WHOLE: whole = true; break;
        case O_BIN: ok = negobs_cli::parse_int(v, 1, 4, bin); break;
        case O_THREADS:
            ok = negobs_cli::parse_int(v, 1, NEGOBS_POOL_MAX_THREADS, threads);
            break;
        case O_PROFILE: ok = negobs_cli::parse_memory_profile(v, profile); break;
        case O_COARSE:
            ok = (v != nullptr && (std::string(v) == "on" || std::string(v) == "off"));
            coarse = (ok && std::string(v) == "on") ? 1 : 0;
            break;
        case O_POOL: ok = negobs_cli::parse_int(v, 1, 4, pool); break;
        case ':': return bad("option " + a + " needs a value");
        default: return bad("unknown option " + a);
        }
        if (!ok) {
            return bad("bad value '" + std::string(v) + "' for --" +
                       (li >= 0 ? long_opts[li].name : "?"));
        }
        li = -1;
    }
    for (int i = optind; i < argc; ++i) {
        pos.emplace_back(argv[i]);
    }
    if (seq.empty() == (pos.size() != 2)) {
        return bad(seq.empty() ? "give LEFT RIGHT or --seq DIR"
                               : "--seq DIR takes no LEFT RIGHT arguments");
    }
    if (out.empty() && (overlay_on || disp_on)) {
        return bad(disp_on ? "--disparity needs --out DIR"
                           : "--out DIR is required (or --no-overlay)");
    }

    GtSeq gt;
    bool have_gt = false;
    std::vector<Item> items;
    Session session;
    negobs_rect_tools::RectTable rect;
    if (!calib_path.empty()) {
        const std::string err = rect.load(calib_path);
        if (!err.empty()) {
            return fail(err);
        }
    }
    if (!seq.empty()) {
        if (!fs::is_directory(seq)) {
            return fail("sequence folder " + seq + " does not exist");
        }
        const std::string gp = (fs::path(seq) / "gt.json").string();
        std::string err;
        if (is_session(seq)) {
            err = read_session(seq, session);
            if (!err.empty()) {
                return fail(err);
            }
            for (long k = 0; k < session.frames; ++k) {
                Item it;
                char name[32];
                std::snprintf(name, sizeof name, "pair_%06ld", k);
                it.name = name;
                it.raw = k;
                it.t_ms = session.t_ms[static_cast<size_t>(k)];
                items.push_back(it);
            }
            session_geometry(session, seq, !calib_path.empty(), rect.crc32(), f, B, cx,
                             cy);
        } else if (fs::exists(gp)) {
            if (!read_gt(gp, gt, err)) {
                return fail(err);
            }
            err = check_gt_camera(gt, f > 0, B > 0, cx >= 0, cy >= 0, H > 0, pitch > -1e8,
                                  fps > 0);
            if (!err.empty()) {
                return fail(gp + ": " + err);
            }
            have_gt = true;
            for (const GtFrame &g : gt.frames) {
                Item it;
                it.left = (fs::path(seq) / g.left).string();
                it.right = (fs::path(seq) / g.right).string();
                it.name = g.left;
                it.gt = &g;
                items.push_back(it);
            }
        } else {
            std::vector<std::string> lefts;
            for (const auto &e : fs::directory_iterator(seq)) {
                const std::string n = e.path().filename().string();
                if (n.rfind("left_", 0) == 0 && e.path().extension() == ".png") {
                    lefts.push_back(n);
                }
            }
            std::sort(lefts.begin(), lefts.end());
            for (const std::string &n : lefts) {
                Item it;
                it.left = (fs::path(seq) / n).string();
                it.right = (fs::path(seq) / ("right_" + n.substr(5))).string();
                it.name = n;
                items.push_back(it);
            }
        }
        if (items.empty()) {
            return fail("no frames (left_NNNN.png, gt.json or session.txt) in " + seq);
        }
        if (first >= static_cast<int>(items.size())) {
            return bad("--first beyond the last frame");
        }
        items.erase(items.begin(), items.begin() + first);
        if (count > 0 && count < static_cast<int>(items.size())) {
            items.resize(static_cast<size_t>(count));
        }
    } else {
        for (int r = 0; r < repeat; ++r) {
            Item it;
            it.left = pos[0];
            it.right = pos[1];
            it.name = fs::path(pos[0]).filename().string();
            items.push_back(it);
        }
    }

    CamParams cam = have_gt ? gt.cam : CamParams{};
    if (f > 0)
        cam.f = f;
    if (B > 0)
        cam.baseline_mm = B;
    if (cx >= 0)
        cam.cx = cx;
    if (cy >= 0)
        cam.cy = cy;
    if (!calib_path.empty()) {
        // the table's measured geometry, unless given on the command line
        const bool f_cli = f > 0, b_cli = B > 0;
        if (!f_cli) {
            cam.f = f = rect.f_px();
        }
        if (!b_cli) {
            cam.baseline_mm = B = rect.baseline_mm();
        }
        if (cx < 0 && rect.info().cx_q16 >= 0) {
            cam.cx = rect.cx();
        }
        if (cy < 0 && rect.info().cy_q16 >= 0) {
            cam.cy = rect.cy();
        }
    }
    if (H >= 0)
        cam.height_mm = H;
    if (pitch > -1e8)
        cam.pitch_deg = pitch;
    cam.max_disp = max_disp;
    cam.pool_frames = pool;
    cam.vshift_set = vshift_set;
    cam.vshift = vshift;
    cam.valign = valign;
    if (fps <= 0) {
        fps = have_gt ? gt.fps : 10.0;
    }

    if (overlay_on || disp_on) {
        std::error_code ec;
        fs::create_directories(out, ec);
        if (ec) {
            return fail("cannot create " + out + ": " + ec.message());
        }
    }
    FILE *jf = nullptr;
    if (!json_path.empty()) {
        jf = std::fopen(json_path.c_str(), "w");
        if (jf == nullptr) {
            return fail("cannot write " + json_path);
        }
    } else if (!quiet) {
        jf = stdout;
    }

    Runner runner;
    runner.set_threads(threads);
    runner.set_memory_profile(profile);
    runner.set_coarse(coarse);
    int w = 0, h = 0;
    int n = 0, nhaz = 0, nnoinfo = 0, first_conf = -1;
    int n_beyond = 0, beyond_mm = 0; // floor beyond the disparity range
    int first_conf_range = -1;
    double first_conf_gt = -1;
    double sum_st = 0, sum_dt = 0, sum_tot = 0;
    int max_disp_used = 63;
    for (size_t k = 0; k < items.size(); ++k) {
        const Item &it = items[k];
        cv::Mat L, R;
        std::string err;
        if (it.raw >= 0) {
            if (!read_session_frame(seq, "left", it.raw, session, L, err) ||
                !read_session_frame(seq, "right", it.raw, session, R, err)) {
                return fail(err);
            }
        } else if (!load_grey(it.left, L, err) || !load_grey(it.right, R, err)) {
            return fail(err);
        }
        if (!calib_path.empty()) {
            err = rect.apply(L, R);
            if (!err.empty()) {
                return fail(err);
            }
        }
        const int eye_w = L.cols, eye_h = L.rows;
        if (L.size() == R.size() && !bin_pair(bin, L, R, err)) {
            return fail(err);
        }
        if (L.size() != R.size()) {
            return fail("size mismatch: " + it.left + " is " + std::to_string(L.cols) +
                        "x" + std::to_string(L.rows) + ", " + it.right + " is " +
                        std::to_string(R.cols) + "x" + std::to_string(R.rows));
        }
        if (k == 0) {
            w = L.cols;
            h = L.rows;
            if (have_gt && (gt.width != eye_w || gt.height != eye_h)) {
                return fail("gt.json says " + std::to_string(gt.width) + "x" +
                            std::to_string(gt.height) + ", images are " +
                            std::to_string(eye_w) + "x" + std::to_string(eye_h));
            }
            if (!have_gt && f <= 0) {
                cam.f = 250.0 * eye_w / 320.0;
            }
            bin_camera(bin, eye_w, eye_h, cam);
            if (!runner.init(w, h, cam, err, whole)) {
                return fail(err);
            }
            max_disp_used = runner.config().stereo.max_disp;
        } else if (L.cols != w || L.rows != h) {
            return fail("size mismatch: " + it.left + " differs from frame 0");
        }
        const uint32_t t_ms = 1000u + static_cast<uint32_t>(std::lround(
                                          it.t_ms >= 0 ? it.t_ms : 1000.0 * k / fps));
        FrameOut o;
        if (!runner.process(L, R, t_ms, o, err)) {
            return fail(err);
        }
        const int frame_no = it.gt ? it.gt->i : static_cast<int>(k);
        if (jf != nullptr) {
            std::fprintf(jf, "%s\n",
                         json_line(frame_no, it.name, o, it.gt, w, h).c_str());
            std::fflush(jf);
        }
        if (disp_on) {
            char fn[64];
            std::snprintf(fn, sizeof fn, "disp_%04d.png", frame_no);
            const std::string p = (fs::path(out) / fn).string();
            std::string werr;
            if (!write_disp_q4(runner.disparity(), p, werr)) {
                return fail(werr);
            }
        }
        if (overlay_on) {
            cv::Mat ov = overlay(L, runner.disparity(), max_disp_used, frame_no, o,
                                 it.gt);
            if (overlay_scale != 1.0) {
                cv::resize(ov, ov, cv::Size(), overlay_scale, overlay_scale,
                           overlay_scale < 1 ? cv::INTER_AREA : cv::INTER_NEAREST);
                if (overlay_scale < 1) {
                    cv::bitwise_and(ov, cv::Scalar(0xF8, 0xF8, 0xF8), ov);
                }
            }
            char fn[64];
            std::snprintf(fn, sizeof fn, "overlay_%04d.png", frame_no);
            const std::string p = (fs::path(out) / fn).string();
            if (!cv::imwrite(p, ov)) {
                return fail("cannot write " + p);
            }
        }
        const negobs_detect_result_t &d = o.res.detect;
        ++n;
        if (d.state == NEGOBS_DETECT_HAZARD) {
            ++nhaz;
        }
        if (d.state == NEGOBS_DETECT_NO_INFO) {
            ++nnoinfo;
        }
        if (d.range_near_mm > 0) {
            ++n_beyond;
            beyond_mm = std::max(beyond_mm, d.range_near_mm);
        }
        for (uint32_t j = 0; j < d.n_hazards && first_conf < 0; ++j) {
            if (d.hazards[j].flags & NEGOBS_HAZARD_F_CONFIRMED) {
                first_conf = frame_no;
                first_conf_range = d.hazards[j].range_mm;
                if (it.gt && it.gt->has_range) {
                    first_conf_gt = it.gt->edge_range_mm;
                }
            }
        }
        sum_st += std::max(0.0, o.stereo_ms);
        sum_dt += std::max(0.0, o.detect_ms);
        sum_tot += o.total_ms;
    }
    if (jf != nullptr && jf != stdout) {
        std::fclose(jf);
    }
    if (summary) {
        std::printf("summary: %d frames (%dx%d), hazard state in %d, no-info in %d; ", n,
                    w, h, nhaz, nnoinfo);
        if (first_conf >= 0) {
            std::printf("first confirmed hazard at frame %d, range %.2f m", first_conf,
                        first_conf_range / 1000.0);
            if (first_conf_gt >= 0) {
                std::printf(" (true %.2f m)", first_conf_gt / 1000.0);
            }
        } else {
            std::printf("no confirmed hazard");
        }
        if (have_gt) {
            std::printf("; scene %s%s", gt.hazard.c_str(),
                        gt.negative ? " (negative obstacle)" : " (must not alarm)");
        }
        if (whole) {
            std::printf("; mean CPU %.1f ms/frame\n", sum_tot / std::max(1, n));
        } else {
            std::printf("; mean CPU stereo %.1f ms, detect %.2f ms (%.1f %%)\n",
                        sum_st / std::max(1, n), sum_dt / std::max(1, n),
                        sum_st > 0 ? 100.0 * sum_dt / sum_st : 0.0);
        }
    }
    if (n_beyond > 0) {
        // not an error: that floor is out of view, like floor below the image
        std::fprintf(stderr,
                     "negobs_png: note: on %d of %d frames the floor nearer than "
                     "up to %d mm lay beyond the disparity range (--max-disp %d) "
                     "and was not measured; a larger --max-disp measures it\n",
                     n_beyond, n, beyond_mm, max_disp_used);
    }
    return 0;
}

} // namespace

int main(int argc, char **argv)
{
    return negobs_cli::main_guard("negobs_png", argc, argv, run);
}
