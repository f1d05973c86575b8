// Checks of negobs_synth (Meson suite 'tools'):
//   flat_gt      GT disparity of flat ground equals the analytic v-disparity
//                line (B/H)(f sin(theta) + cos(theta)(v - cy)); the CLI's
//                16-bit disparity PNG and edge row agree with it.
//   ramp_gt      every GT disparity of a ramp scene (down and up) puts its
//                point on the analytic surface: level, sloped, level again;
//                the walker's camera follows the surface (gt.json).
//   warp         warping the right image onto the left with the GT
//                disparity reproduces the left image (visible pixels).
//   determinism  same seed -> identical bytes; another seed -> different.
//   bad_options  malformed command lines exit non-zero with a message.
//   roll_gt      under roll the GT disparity of flat ground is the rolled
//                plane's analytic formula and the edge GT separates the
//                two levels of a curb in every column.
//   sensor       gain/offset mismatch reaches the right camera only;
//                exposure changes follow gt.json's per-frame factors (and
//                the right camera's lag); weak textures are weak.
// usage: test_synth MODE PATH_TO_negobs_synth
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "synth.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;
int failures = 0;

void check(bool ok, const std::string &what)
{
    if (!ok) {
        std::fprintf(stderr, "FAIL: %s\n", what.c_str());
        ++failures;
    }
}

std::string g_exe;

fs::path scratch(const std::string &name)
{
    fs::path p = fs::temp_directory_path() /
                 ("negobs_synth_test_" + std::to_string(getpid()) + "_" + name);
    fs::remove_all(p);
    return p;
}

int run(const std::string &args, std::string *err_out = nullptr)
{
    const fs::path err = scratch("stderr.txt");
    const std::string cmd = "'" + g_exe + "' " + args + " >/dev/null 2>'" + err.string() + "'";
    const int st = std::system(cmd.c_str());
    if (err_out) {
        std::ifstream f(err);
        std::stringstream ss;
        ss << f.rdbuf();
        *err_out = ss.str();
    }
    fs::remove(err);
    if (st == -1 || !WIFEXITED(st))
        return -1;
    return WEXITSTATUS(st);
}

std::string slurp(const fs::path &p)
{
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

bool json_number(const std::string &doc, const std::string &key, double &v)
{
    const size_t k = doc.find("\"" + key + "\": ");
    if (k == std::string::npos)
        return false;
    const char *p = doc.c_str() + k + key.size() + 4;
    char *end = nullptr;
    v = std::strtod(p, &end);
    return end != p;
}

// ------------------------------------------------------------------ flat_gt

int test_flat_gt()
{
    synth::SceneParams sp;
    sp.hazard = synth::Hazard::Flat;
    const synth::Scene scene(sp);
    synth::Texture tex;
    std::string err;
    check(tex.make_procedural(3, "asphalt", err), "texture: " + err);
    for (double pitch : {15.0, 20.0, 25.0}) {
        synth::Rig rig;
        synth::Pose pose;
        pose.pitch = pitch;
        pose.y = 1.2;
        cv::Mat img, disp;
        synth::render_view(scene, tex, rig, pose, 0, synth::RenderOptions{}, img, &disp);
        const double th = pitch * kPi / 180.0;
        const double horizon = rig.cy - rig.f * std::tan(th);
        int checked = 0;
        double worst = 0.0;
        for (int v : {30, 60, 90, 120, 150, 180, 210, 239}) {
            if (v < horizon + 1.0)
                continue;
            const double expect = rig.baseline / pose.y *
                                  (rig.f * std::sin(th) + std::cos(th) * (v - rig.cy));
            for (int u : {0, 57, 160, 251, 319}) {
                const double got = disp.at<float>(v, u);
                worst = std::max(worst, std::fabs(got - expect));
                ++checked;
            }
        }
        check(checked >= 20, "flat_gt: enough rows below the horizon");
        check(worst < 1e-3, "flat_gt: GT disparity off by " + std::to_string(worst) +
                                " px at pitch " + std::to_string(pitch));
        // Above the horizon there is no surface.
        const int vs = static_cast<int>(std::floor(horizon)) - 2;
        if (vs >= 0)
            check(disp.at<float>(vs, 160) == 0.0f, "flat_gt: sky has disparity 0");
    }

    // Same through the CLI: 16-bit PNG (disparity*16) and the edge row.
    const fs::path out = scratch("flat_gt");
    const int rc = run("--single --scene curb --edge-mm 4000 --pitch-deg 20 --height-mm 1200 "
                       "--gt-disparity --quiet --out '" +
                       out.string() + "'");
    check(rc == 0, "flat_gt: CLI single curb run");
    if (rc == 0) {
        const cv::Mat d16 = cv::imread((out / "disp_0000.png").string(), cv::IMREAD_UNCHANGED);
        check(!d16.empty() && d16.type() == CV_16U, "flat_gt: disparity PNG is 16-bit");
        if (!d16.empty()) {
            const double th = 20.0 * kPi / 180.0;
            double worst = 0.0;
            for (int v : {150, 180, 210, 239}) { // near ground, before the edge
                const double expect = 0.12 / 1.2 *
                                      (250.0 * std::sin(th) + std::cos(th) * (v - 119.5));
                worst = std::max(worst, std::fabs(d16.at<uint16_t>(v, 100) / 16.0 - expect));
            }
            check(worst <= 1.0 / 32.0 + 1e-9, "flat_gt: PNG disparity quantised to 1/16");
        }
        const std::string gt = slurp(out / "gt.json");
        double row = 0.0;
        check(json_number(gt, "edge_row_at_cx", row), "flat_gt: gt.json has edge_row_at_cx");
        const double expect = 119.5 - 250.0 * std::tan((20.0 * kPi / 180.0) - std::atan(1.2 / 4.0));
        check(std::fabs(row - expect) < 0.01,
              "flat_gt: edge row " + std::to_string(row) + " vs " + std::to_string(expect));
        double range = 0.0;
        check(json_number(gt, "edge_range_mm", range) && std::fabs(range - 4000.0) < 0.05,
              "flat_gt: edge range 4000 mm");
    }
    fs::remove_all(out);

    // Sequence: per-frame range = start - speed*t, and the edge row follows
    // the per-frame (bobbing, swaying) pose.
    const fs::path seq = scratch("flat_seq");
    const int rs = run("--scene curb --edge-mm 6000 --frames 12 --speed 1.5 --fps 5 --bob-mm 40 "
                       "--sway-deg 2 --roll-sway-deg 0 --seed 4 --quiet --out '" +
                       seq.string() + "'");
    check(rs == 0, "flat_gt: CLI sequence run");
    std::ifstream f(seq / "gt.json");
    std::string line;
    int frames = 0, rows_checked = 0;
    double h_min = 1e9, h_max = -1e9;
    while (std::getline(f, line)) {
        if (line.rfind("{\"i\": ", 0) != 0)
            continue;
        double i = 0, range = 0, h = 0, pitch = 0, row = 0;
        check(json_number(line, "i", i) && json_number(line, "edge_range_mm", range) &&
                  json_number(line, "H_mm", h) && json_number(line, "pitch", pitch),
              "flat_gt: frame line has i, edge_range_mm, H_mm, pitch");
        check(std::fabs(range - (6000.0 - 1500.0 * i / 5.0)) < 0.06,
              "flat_gt: frame range follows speed and fps");
        h_min = std::min(h_min, h);
        h_max = std::max(h_max, h);
        if (json_number(line, "edge_row_at_cx", row)) {
            const double expect = 119.5 -
                                  250.0 * std::tan(pitch * kPi / 180.0 - std::atan(h / range));
            // pitch and H are printed with 4 and 2 decimals.
            check(std::fabs(row - expect) < 0.02, "flat_gt: sequence edge row " +
                                                      std::to_string(row) + " vs " +
                                                      std::to_string(expect));
            ++rows_checked;
        }
        ++frames;
    }
    check(frames == 12, "flat_gt: 12 frame lines");
    check(rows_checked >= 6, "flat_gt: edge visible in the approach");
    check(h_max - h_min > 20.0 && h_max < 1240.01 && h_min > 1159.99,
          "flat_gt: bobbing within +-40 mm");
    fs::remove_all(seq);

    // Heading and sideways sway: the camera turns and the body sways to and
    // fro within the amplitudes while the walk keeps its heading (the range
    // still follows speed and fps).
    const fs::path ys = scratch("yaw_sway");
    check(run("--scene curb --edge-mm 6000 --frames 12 --speed 1.5 --fps 5 --yaw-sway-deg 3 "
              "--side-sway-mm 30 "
              "--seed 4 --quiet --out '" +
              ys.string() + "'") == 0,
          "flat_gt: yaw sway run");
    std::ifstream fy(ys / "gt.json");
    double yaw_min = 1e9, yaw_max = -1e9, x_min = 1e9, x_max = -1e9;
    int yaw_frames = 0;
    while (std::getline(fy, line)) {
        double i = 0, range = 0, yaw = 0, x = 0;
        if (line.rfind("{\"i\": ", 0) != 0 || !json_number(line, "i", i) ||
            !json_number(line, "edge_range_mm", range) || !json_number(line, "yaw", yaw) ||
            !json_number(line, "cam_x_mm", x))
            continue;
        check(std::fabs(range - (6000.0 - 1500.0 * i / 5.0)) < 0.06,
              "flat_gt: yaw sway keeps the walk's heading");
        yaw_min = std::min(yaw_min, yaw);
        yaw_max = std::max(yaw_max, yaw);
        x_min = std::min(x_min, x);
        x_max = std::max(x_max, x);
        ++yaw_frames;
    }
    check(yaw_frames == 12 && yaw_max - yaw_min > 2.0 && yaw_max <= 3.0001 && yaw_min >= -3.0001,
          "flat_gt: heading sways within +-3 deg");
    check(x_max - x_min > 20.0 && x_max <= 30.01 && x_min >= -30.01,
          "flat_gt: the body sways sideways within +-30 mm");
    fs::remove_all(ys);

    // Under roll and yaw the edge is a slanted straight line; its row at
    // the principal column lies on edge_line.
    const fs::path sl = scratch("slant");
    check(run("--single --roll-deg 5 --yaw-deg 20 --quiet --out '" + sl.string() + "'") == 0,
          "flat_gt: slanted run");
    const std::string sg = slurp(sl / "gt.json");
    const size_t k = sg.find("\"edge_line\": [");
    double u0 = 0, v0 = 0, u1 = 0, v1 = 0, rowc = 0;
    check(k != std::string::npos &&
              std::sscanf(sg.c_str() + k, "\"edge_line\": [%lf, %lf, %lf, %lf]", &u0, &v0, &u1,
                          &v1) == 4 &&
              json_number(sg, "edge_row_at_cx", rowc),
          "flat_gt: slanted edge_line and edge_row_at_cx present");
    const double on_line = v0 + (v1 - v0) * (159.5 - u0) / (u1 - u0);
    check(std::fabs(v1 - v0) > 30.0, "flat_gt: roll 5 + yaw 20 slants the edge");
    check(std::fabs(rowc - on_line) < 0.02, "flat_gt: edge row at cx " + std::to_string(rowc) +
                                                " on edge_line " + std::to_string(on_line));
    fs::remove_all(sl);
    return failures;
}

// ------------------------------------------------------------------ warp

// Catmull-Rom bicubic interpolation (keeps most of the texture's high
// frequencies, unlike bilinear at half-pixel offsets).
float bicubic(const cv::Mat &m, double x, double y)
{
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double ax = x - x0, ay = y - y0;
    auto weights = [](double t, double w[4]) {
        const double t2 = t * t, t3 = t2 * t;
        w[0] = 0.5 * (-t3 + 2 * t2 - t);
        w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
        w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
        w[3] = 0.5 * (t3 - t2);
    };
    double wx[4], wy[4];
    weights(ax, wx);
    weights(ay, wy);
    double acc = 0.0;
    for (int j = 0; j < 4; ++j) {
        const int yy = std::clamp(y0 - 1 + j, 0, m.rows - 1);
        double r = 0.0;
        for (int i = 0; i < 4; ++i) {
            const int xx = std::clamp(x0 - 1 + i, 0, m.cols - 1);
            r += wx[i] * m.at<float>(yy, xx);
        }
        acc += wy[j] * r;
    }
    return static_cast<float>(acc);
}

struct WarpCase {
    synth::Hazard hazard;
    double edge, drop;
    double pitch, roll, yaw, vshift;
    int ss;
    bool expect_occlusion;
    double blur; // lens PSF; sub-pixel row shifts need a band-limited image
    int distractors;
};

int test_warp()
{
    synth::Texture tex;
    std::string err;
    check(tex.make_procedural(11, "asphalt", err), "texture: " + err);
    const WarpCase cases[] = {
        {synth::Hazard::Curb, 3.0, 0.2, 20.0, 0.0, 0.0, 0.0, 2, false, 0.0, 0},
        {synth::Hazard::Stairs, 3.0, 0.2, 22.0, 3.0, 0.0, 0.5, 2, false, 0.7, 0},
        // A deep pit close by, to the left: its right-hand rim hides more of
        // the floor from the right camera (occlusion detected and skipped).
        {synth::Hazard::Hole, 2.5, 0.5, 18.0, -2.0, -10.0, -1.0, 3, true, 0.0, 0},
        {synth::Hazard::Upstep, 3.0, 0.2, 20.0, 0.0, 0.0, 0.25, 2, false, 0.7, 0},
        {synth::Hazard::Wall, 3.0, 0.2, 15.0, 1.0, -5.0, 0.0, 1, false, 0.0, 0},
        // A ramp (default 1:12 over 1.8 m): texture continuous over the
        // sloped surface, seen from both cameras.
        {synth::Hazard::Ramp, 2.5, 0.2, 16.0, 2.0, 5.0, 0.0, 2, false, 0.0, 0},
        {synth::Hazard::Flat, 3.0, 0.2, 25.0, 0.0, 0.0, 0.0, 2, false, 0.0, 0},
        // Painted stripes, shadows, patches, manholes: intensity only.
        {synth::Hazard::Flat, 3.0, 0.2, 22.0, 0.0, 0.0, 0.0, 2, false, 0.0, 12},
    };
    for (const WarpCase &wc : cases) {
        synth::SceneParams sp;
        sp.hazard = wc.hazard;
        sp.edge_z = wc.edge;
        sp.drop = wc.drop;
        sp.hole_offset = -1.2;
        sp.hole_length = 2.0;
        sp.distractors = synth::random_distractors(wc.distractors, 1.0, 6.0, 21);
        const synth::Scene scene(sp);
        synth::Rig rig;
        rig.right_row_shift = wc.vshift;
        synth::Pose pose;
        pose.pitch = wc.pitch;
        pose.roll = wc.roll;
        pose.yaw = wc.yaw;
        synth::RenderOptions ro;
        ro.supersample = wc.ss;
        cv::Mat L, R, D;
        synth::render_view(scene, tex, rig, pose, 0, ro, L, &D);
        synth::render_view(scene, tex, rig, pose, 1, ro, R, nullptr);
        synth::apply_blur(L, wc.blur);
        synth::apply_blur(R, wc.blur);
        double point_sum = 0.0;
        long point_n = 0;
        const synth::CameraFrame cl = synth::camera_frame(rig, pose, 0);
        const synth::CameraFrame cr = synth::camera_frame(rig, pose, 1);
        double sum = 0.0;
        long n = 0, occluded = 0, disp_err = 0;
        std::vector<double> row_err(static_cast<size_t>(rig.height)),
            row_n(static_cast<size_t>(rig.height));
        for (int y = 2; y < rig.height - 2; ++y) {
            for (int x = 2; x < rig.width - 2; ++x) {
                const float d = D.at<float>(y, x);
                if (d <= 0.0f)
                    continue;
                // Skip depth edges (mixed pixels) and the
                // far field where a pixel spans metres of ground.
                float lo = d, hi = d;
                for (int j = -1; j <= 1; ++j)
                    for (int i = -1; i <= 1; ++i) {
                        lo = std::min(lo, D.at<float>(y + j, x + i));
                        hi = std::max(hi, D.at<float>(y + j, x + i));
                    }
                if (hi - lo > 0.5f || lo <= 0.0f || d < 2.0f)
                    continue;
                const synth::Vec3 ray = synth::pixel_ray(rig, cl, 0, x, y);
                const double depth = rig.f * rig.baseline / d;
                const synth::Vec3 p{cl.c.x + ray.x * depth, cl.c.y + ray.y * depth,
                                    cl.c.z + ray.z * depth};
                double ur, vr, dr;
                if (!synth::project(rig, cr, 1, p, ur, vr, dr))
                    continue;
                if (ur < 0 || vr < 0 || ur > rig.width - 2 || vr > rig.height - 2)
                    continue;
                // Visible from the right camera?
                const synth::Vec3 rd{(p.x - cr.c.x) / dr, (p.y - cr.c.y) / dr, (p.z - cr.c.z) / dr};
                double t;
                const int ri = scene.intersect(cr.c, rd, t);
                if (ri >= 0 && t < dr * (1.0 - 1e-4)) {
                    ++occluded;
                    continue;
                }
                // With zero roll and yaw the correspondence is (x - d, y + shift).
                if (wc.roll == 0.0 && wc.yaw == 0.0 &&
                    (std::fabs(ur - (x - d)) > 1e-3 || std::fabs(vr - (y + wc.vshift)) > 1e-6))
                    ++disp_err;
                const double e = std::fabs(bicubic(R, ur, vr) - L.at<float>(y, x));
                sum += e;
                row_err[static_cast<size_t>(y)] += e;
                row_n[static_cast<size_t>(y)] += 1;
                ++n;
                // Exact check without image interpolation: shade the right
                // camera's ray through (ur, vr) directly.
                if ((x + 7 * y) % 5 == 0) {
                    point_sum += std::fabs(
                        synth::render_point(scene, tex, rig, pose, 1, ur, vr, ro.sky) -
                        synth::render_point(scene, tex, rig, pose, 0, x, y, ro.sky));
                    ++point_n;
                }
            }
        }
        const double mae = n ? sum / static_cast<double>(n) : 1e9;
        if (std::getenv("SYNTH_DEBUG_ROWS"))
            for (size_t y = 0; y < row_err.size(); ++y)
                if (row_n[y] > 0)
                    std::printf("  row %zu: %.0f px, mae %.2f\n", y, row_n[y],
                                row_err[y] / row_n[y]);
        const double point_mae = point_n ? point_sum / static_cast<double>(point_n) : 1e9;
        std::printf("warp %-6s pitch %4.1f roll %4.1f yaw %5.1f vshift %5.2f ss %d blur %.1f: "
                    "%ld px compared, %ld occluded, mean abs err %.3f grey "
                    "(point samples %.3f)\n",
                    synth::hazard_name(wc.hazard), wc.pitch, wc.roll, wc.yaw, wc.vshift, wc.ss,
                    wc.blur, n, occluded, mae, point_mae);
        check(point_mae < 0.5,
              std::string("warp: point samples agree for ") + synth::hazard_name(wc.hazard));
        check(n > 20000, std::string("warp: enough pixels for ") + synth::hazard_name(wc.hazard));
        check(mae < 3.0,
              std::string("warp: mean abs error < 3 for ") + synth::hazard_name(wc.hazard));
        check(disp_err == 0, "warp: right position is (x - d, y + shift)");
        if (wc.distractors > 0) {
            // Distractors change the image but not the geometry.
            synth::SceneParams plain = sp;
            plain.distractors.clear();
            cv::Mat L2, D2;
            synth::render_view(synth::Scene(plain), tex, rig, pose, 0, ro, L2, &D2);
            check(cv::norm(D, D2, cv::NORM_INF) == 0.0, "warp: distractors leave GT disparity");
            check(cv::norm(L, L2, cv::NORM_L1) / static_cast<double>(L.total()) > 1.0,
                  "warp: distractors are visible");
        }
        if (wc.expect_occlusion)
            check(occluded > 10, "warp: pit wall occludes floor in the right view");
    }
    return failures;
}

// ------------------------------------------------------------------ determinism

int test_determinism()
{
    const std::string common = "--scene stairs --frames 3 --noise 2 --gain-right 1.05 "
                               "--vshift-right 0.3 --gt-disparity --gt-disparity-right --threads 2 "
                               "--quiet ";
    const fs::path a = scratch("det_a"), b = scratch("det_b"), c = scratch("det_c");
    check(run(common + "--seed 7 --out '" + a.string() + "'") == 0, "determinism: run a");
    check(run(common + "--seed 7 --out '" + b.string() + "'") == 0, "determinism: run b");
    check(run(common + "--seed 8 --out '" + c.string() + "'") == 0, "determinism: run c");
    int files = 0;
    for (const auto &e : fs::directory_iterator(a)) {
        const std::string name = e.path().filename().string();
        const std::string ba = slurp(e.path()), bb = slurp(b / name);
        check(!ba.empty() && ba == bb, "determinism: " + name + " identical for the same seed");
        ++files;
    }
    check(files == 13, "determinism: 3 x (left, right, disp, dispr) + gt.json written");
    check(slurp(a / "left_0002.png") != slurp(c / "left_0002.png"),
          "determinism: another seed gives another image");
    check(slurp(a / "gt.json") != slurp(c / "gt.json"),
          "determinism: another seed gives another camera motion");
    fs::remove_all(c);
    // The thread count must not change a byte.
    check(run(common + "--seed 7 --threads 1 --out '" + c.string() + "'") == 0,
          "determinism: single-thread run");
    check(slurp(a / "left_0001.png") == slurp(c / "left_0001.png") &&
              slurp(a / "dispr_0002.png") == slurp(c / "dispr_0002.png"),
          "determinism: 1 thread gives the same bytes as 2");
    fs::remove_all(a);
    fs::remove_all(b);
    fs::remove_all(c);

    // A photo texture (here a generated one) renders and is deterministic.
    const fs::path photo = scratch("photo.png");
    cv::Mat img(64, 96, CV_8U);
    synth::Rng rng(5);
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x)
            img.at<uint8_t>(y, x) = static_cast<uint8_t>(rng.next() & 255u);
    check(cv::imwrite(photo.string(), img), "determinism: write photo texture");
    const std::string pargs = "--single --texture '" + photo.string() + "' --texture-mm 5 --quiet ";
    check(run(pargs + "--out '" + a.string() + "'") == 0, "determinism: photo run a");
    check(run(pargs + "--out '" + b.string() + "'") == 0, "determinism: photo run b");
    const std::string pa = slurp(a / "left_0000.png");
    check(!pa.empty() && pa == slurp(b / "left_0000.png"), "determinism: photo texture");
    fs::remove_all(a);
    fs::remove_all(b);
    fs::remove(photo);
    return failures;
}

// ------------------------------------------------------------------ ramp_gt

// World Y of the ramp scene's surface at Z: level before ze, falling by
// grade per metre over len metres, level again after (written out here
// rather than taken from Scene::ground_y, which is what is tested).
double ramp_surface_y(double z, double ze, double grade, double len)
{
    if (z <= ze)
        return 0.0;
    return -grade * std::min(z - ze, len);
}

int test_ramp_gt()
{
    synth::Texture tex;
    std::string err;
    check(tex.make_procedural(5, "asphalt", err), "texture: " + err);
    for (double grade : {1.0 / 12.0, -1.0 / 12.0, 0.05}) {
        synth::SceneParams sp;
        sp.hazard = synth::Hazard::Ramp;
        sp.edge_z = 3.0;
        sp.ramp_grade = grade;
        sp.ramp_length = grade == 0.05 ? std::numeric_limits<double>::infinity() : 1.8;
        const synth::Scene scene(sp);
        synth::Rig rig;
        synth::Pose pose;
        pose.y = 1.2;
        pose.pitch = 12.0; // see the far level part too
        cv::Mat img, disp;
        synth::render_view(scene, tex, rig, pose, 0, synth::RenderOptions{}, img, &disp);
        const synth::CameraFrame cf = synth::camera_frame(rig, pose, 0);
        double worst = 0.0;
        int part[3] = {0, 0, 0};
        for (int v = 0; v < rig.height; ++v) {
            for (int u = 0; u < rig.width; u += 7) {
                const double d = disp.at<float>(v, u);
                if (d <= 0.0)
                    continue;
                // pixel_ray has z = 1 in the camera frame: scale by depth.
                const synth::Vec3 r = synth::pixel_ray(rig, cf, 0, u, v);
                const double depth = rig.f * rig.baseline / d;
                const double px = cf.c.x + r.x * depth, py = cf.c.y + r.y * depth,
                             pz = cf.c.z + r.z * depth;
                (void)px;
                const double want = ramp_surface_y(pz, sp.edge_z, grade, sp.ramp_length);
                worst = std::max(worst, std::fabs(py - want));
                part[pz <= sp.edge_z ? 0 : (pz <= sp.edge_z + sp.ramp_length ? 1 : 2)]++;
            }
        }
        const std::string g = " (grade " + std::to_string(grade) + ")";
        // The GT is float: 1e-7 relative of the depth.
        check(worst < 1e-4,
              "ramp_gt: point off the surface by " + std::to_string(worst) + " m" + g);
        check(part[0] > 100 && part[1] > 100, "ramp_gt: level and sloped parts seen" + g);
        if (std::isfinite(sp.ramp_length))
            check(part[2] > 20, "ramp_gt: level part after the slope seen" + g);
        else
            check(part[2] == 0, "ramp_gt: a slope that never ends" + g);
        for (double z : {0.0, 2.9, 3.0, 3.9, 4.8, 9.0})
            check(std::fabs(scene.ground_y(z) -
                            ramp_surface_y(z, sp.edge_z, grade, sp.ramp_length)) < 1e-12,
                  "ramp_gt: Scene::ground_y at " + std::to_string(z) + g);
    }

    // Through the CLI: the walker goes down the ramp, the camera stays
    // --height-mm above the surface under it (no bobbing).
    const fs::path seq = scratch("ramp_seq");
    const int rs = run("--scene ramp --grade-pct 8 --ramp-mm 1500 --edge-mm 1000 --frames 12 "
                       "--speed 1.0 --fps 4 --bob-mm 0 --sway-deg 0 --roll-sway-deg 0 --quiet "
                       "--out '" +
                       seq.string() + "'");
    check(rs == 0, "ramp_gt: CLI ramp sequence run");
    std::ifstream f(seq / "gt.json");
    std::string line;
    int frames = 0;
    double lowest = 0.0;
    while (std::getline(f, line)) {
        if (line.rfind("{\"i\": ", 0) != 0)
            continue;
        double z = 0, gy = 0, h = 0;
        check(json_number(line, "cam_z_mm", z) && json_number(line, "ground_y_mm", gy) &&
                  json_number(line, "H_mm", h),
              "ramp_gt: frame line has cam_z_mm, ground_y_mm, H_mm");
        check(std::fabs(gy - 1e3 * ramp_surface_y(z / 1e3, 1.0, 0.08, 1.5)) < 0.06,
              "ramp_gt: ground under the walker at z " + std::to_string(z));
        check(std::fabs(h - 1200.0) < 0.01, "ramp_gt: camera height over the surface");
        lowest = std::min(lowest, gy);
        ++frames;
    }
    check(frames == 12, "ramp_gt: 12 frame lines");
    check(std::fabs(lowest + 120.0) < 0.06, "ramp_gt: walked to the bottom (-120 mm)");
    const std::string gt = slurp(seq / "gt.json");
    check(gt.find("\"hazard\": \"ramp\", \"negative\": false") != std::string::npos,
          "ramp_gt: a ramp is not a negative obstacle");
    fs::remove_all(seq);
    return failures;
}

// ------------------------------------------------------------------ roll_gt

// Flat ground Y = 0 under pitch th and roll ph (camera height H): the
// centre ray of (u, v) has world Y component -(sin th + cos th (sin ph
// (u - cx) + cos ph (v - cy)) / f), so d = f B / t = (B/H) (f sin th +
// cos th (sin ph (u - cx) + cos ph (v - cy))).
double rolled_plane_disp(const synth::Rig &rig, double H, double pitch, double roll, double u,
                         double v)
{
    const double th = pitch * kPi / 180.0, ph = roll * kPi / 180.0;
    return rig.baseline / H *
           (rig.f * std::sin(th) +
            std::cos(th) * (std::sin(ph) * (u - rig.cx) + std::cos(ph) * (v - rig.cy)));
}

int test_roll_gt()
{
    synth::Texture tex;
    std::string err;
    check(tex.make_procedural(3, "asphalt", err), "texture: " + err);
    for (double roll : {-8.0, 3.0, 8.0}) {
        for (double pitch : {5.0, 45.0}) {
            synth::SceneParams sp;
            sp.hazard = synth::Hazard::Flat;
            const synth::Scene flat(sp);
            synth::Rig rig;
            synth::Pose pose;
            pose.y = 0.9;
            pose.pitch = pitch;
            pose.roll = roll;
            cv::Mat img, disp;
            synth::render_view(flat, tex, rig, pose, 0, synth::RenderOptions{}, img, &disp);
            double worst = 0.0;
            int n = 0;
            for (int v = 0; v < rig.height; v += 17) {
                for (int u = 0; u < rig.width; u += 23) {
                    const double e = rolled_plane_disp(rig, pose.y, pitch, roll, u, v);
                    if (e <= 0.05) { // at or above the horizon: sky
                        check(disp.at<float>(v, u) == 0.0f || e > -0.05,
                              "roll_gt: sky above the rolled horizon");
                        continue;
                    }
                    worst = std::max(worst, std::fabs(disp.at<float>(v, u) - e));
                    ++n;
                }
            }
            check(n >= 40, "roll_gt: enough ground samples");
            check(worst < 1e-3, "roll_gt: flat GT under roll " + std::to_string(roll) + " pitch " +
                                    std::to_string(pitch) + " off by " + std::to_string(worst) +
                                    " px");
        }
    }
    // A 15 cm curb 3 m ahead, camera rolled 8 deg: in every column where
    // gt.json puts the edge, 2 rows below it the ground is the near plane
    // (exact formula), 2 rows above it the lower level (disparity clearly
    // below the near plane's).
    const fs::path out = scratch("roll_curb");
    const int rc = run("--single --scene curb --edge-mm 3000 --drop-mm 150 --roll-deg 8 "
                       "--pitch-deg 30 --height-mm 1400 --gt-disparity --quiet --out '" +
                       out.string() + "'");
    check(rc == 0, "roll_gt: CLI rolled curb run");
    const std::string gt = slurp(out / "gt.json");
    const size_t k = gt.find("\"edge_line\": [");
    double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
    check(k != std::string::npos &&
              std::sscanf(gt.c_str() + k, "\"edge_line\": [%lf, %lf, %lf, %lf]", &u0, &v0, &u1,
                          &v1) == 4,
          "roll_gt: edge_line present");
    const cv::Mat d16 = cv::imread((out / "disp_0000.png").string(), cv::IMREAD_UNCHANGED);
    check(!d16.empty(), "roll_gt: disparity PNG");
    synth::Rig rig;
    int cols = 0;
    if (!d16.empty() && u1 > u0) {
        for (int u = static_cast<int>(u0) + 5; u <= static_cast<int>(u1) - 5; u += 20) {
            const double ve = v0 + (v1 - v0) * (u - u0) / (u1 - u0);
            const int below = static_cast<int>(std::lround(ve)) + 2;
            const int above = static_cast<int>(std::lround(ve)) - 2;
            if (below >= rig.height || above < 0)
                continue;
            const double near_b = rolled_plane_disp(rig, 1.4, 30.0, 8.0, u, below);
            const double near_a = rolled_plane_disp(rig, 1.4, 30.0, 8.0, u, above);
            check(std::fabs(d16.at<uint16_t>(below, u) / 16.0 - near_b) <= 1.0 / 32.0 + 1e-6,
                  "roll_gt: near ground below the edge at column " + std::to_string(u));
            check(near_a - d16.at<uint16_t>(above, u) / 16.0 > 0.3,
                  "roll_gt: lower level above the edge at column " + std::to_string(u));
            ++cols;
        }
    }
    check(cols >= 10, "roll_gt: edge checked in >= 10 columns");
    check(std::fabs(v1 - v0) > 20.0, "roll_gt: roll 8 slants the edge");
    fs::remove_all(out);
    return failures;
}

// ------------------------------------------------------------------ sensor

double mean_of(const cv::Mat &m)
{
    return cv::mean(m)[0];
}

int test_sensor()
{
    // Gain/offset mismatch: the left image is untouched, the right one is
    // gain * x + offset of the same render.
    const fs::path a = scratch("mm_a"), b = scratch("mm_b");
    const std::string base = "--single --scene curb --noise 0 --quiet --out ";
    check(run(base + "'" + a.string() + "'") == 0, "sensor: plain run");
    check(run(base + "'" + b.string() + "' --gain-right 1.15 --offset-right -9") == 0,
          "sensor: mismatch run");
    const cv::Mat la = cv::imread((a / "left_0000.png").string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat lb = cv::imread((b / "left_0000.png").string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat ra = cv::imread((a / "right_0000.png").string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat rb = cv::imread((b / "right_0000.png").string(), cv::IMREAD_GRAYSCALE);
    check(!la.empty() && !lb.empty() && !ra.empty() && !rb.empty(), "sensor: images read");
    if (!la.empty() && !lb.empty() && !ra.empty() && !rb.empty()) {
        check(cv::norm(la, lb, cv::NORM_INF) == 0.0, "sensor: mismatch leaves the left camera");
        int n = 0, bad = 0;
        for (int y = 0; y < ra.rows; ++y) {
            for (int x = 0; x < ra.cols; ++x) {
                const double e = 1.15 * ra.at<uint8_t>(y, x) - 9.0;
                if (e < 1.0 || e > 254.0)
                    continue; // clamped
                ++n;
                // the linear value was rounded once before and once after
                bad += std::fabs(rb.at<uint8_t>(y, x) - e) > 1.2 ? 1 : 0;
            }
        }
        check(n > 1000 && bad == 0, "sensor: right = 1.15 * right - 9 (" + std::to_string(bad) +
                                        " of " + std::to_string(n) + " off)");
    }
    fs::remove_all(a);
    fs::remove_all(b);

    // Exposure changes: a static camera (no motion, no noise) so every
    // frame renders the same linear image; each frame's mean must follow
    // gt.json's factors, the right camera 2 frames late.
    const fs::path e = scratch("expo");
    check(run("--scene flat --frames 14 --speed 0 --bob-mm 0 --sway-deg 0 --roll-sway-deg 0 "
              "--noise 0 --exposure-pct 30 --exposure-every 4 --exposure-lag-right 2 --seed 9 "
              "--quiet --out '" +
              e.string() + "'") == 0,
          "sensor: exposure run");
    std::ifstream f(e / "gt.json");
    std::string line;
    std::vector<double> el, er;
    while (std::getline(f, line)) {
        const size_t k = line.find("\"exposure\": [");
        double x = 0, y = 0;
        if (line.rfind("{\"i\": ", 0) == 0 && k != std::string::npos &&
            std::sscanf(line.c_str() + k, "\"exposure\": [%lf, %lf]", &x, &y) == 2) {
            el.push_back(x);
            er.push_back(y);
        }
    }
    check(el.size() == 14, "sensor: 14 frames with exposure factors");
    double spread = 0.0;
    if (el.size() == 14) {
        const double m0l = mean_of(
            cv::imread((e / "left_0000.png").string(), cv::IMREAD_GRAYSCALE));
        const double m0r = mean_of(
            cv::imread((e / "right_0000.png").string(), cv::IMREAD_GRAYSCALE));
        for (size_t i = 0; i < el.size(); ++i) {
            char nm[64];
            std::snprintf(nm, sizeof nm, "left_%04zu.png", i);
            const double ml = mean_of(cv::imread((e / nm).string(), cv::IMREAD_GRAYSCALE));
            std::snprintf(nm, sizeof nm, "right_%04zu.png", i);
            const double mr = mean_of(cv::imread((e / nm).string(), cv::IMREAD_GRAYSCALE));
            check(std::fabs(ml / m0l - el[i]) < 0.01,
                  "sensor: left mean follows exposure at frame " + std::to_string(i));
            check(std::fabs(mr / m0r - er[i]) < 0.01,
                  "sensor: right mean follows exposure at frame " + std::to_string(i));
            check(i < 2 || er[i] == el[i - 2], "sensor: right lags 2 frames");
            spread = std::max(spread, std::fabs(el[i] - 1.0));
        }
        check(el[3] == 1.0 && el[4] != 1.0, "sensor: first change at frame 4");
    }
    check(spread > 0.03 && spread <= 0.3, "sensor: exposure moves within +-30 %");
    fs::remove_all(e);

    // Weak textures: far less contrast than asphalt, at the pixel scale
    // (what the matcher sees) and overall.
    auto contrast = [](const std::string &kind, double &sd, double &grad) {
        synth::Texture tex;
        std::string err;
        check(tex.make_procedural(5, kind, err), "sensor: texture " + kind);
        synth::SceneParams sp;
        sp.hazard = synth::Hazard::Flat;
        const synth::Scene flat(sp);
        synth::Rig rig;
        synth::Pose pose;
        cv::Mat img;
        synth::render_view(flat, tex, rig, pose, 0, synth::RenderOptions{}, img, nullptr);
        const cv::Mat roi = img(cv::Rect(40, 120, 240, 120));
        cv::Scalar m, s;
        cv::meanStdDev(roi, m, s);
        sd = s[0];
        cv::Mat dx = roi(cv::Rect(1, 0, 239, 120)) - roi(cv::Rect(0, 0, 239, 120));
        grad = cv::mean(cv::abs(dx))[0];
    };
    double sd_a, g_a, sd_c, g_c, sd_w, g_w;
    contrast("asphalt", sd_a, g_a);
    contrast("concrete", sd_c, g_c);
    contrast("worn", sd_w, g_w);
    std::printf("texture sd / mean |dx|: asphalt %.1f / %.2f, worn %.1f / %.2f, concrete "
                "%.1f / %.2f\n",
                sd_a, g_a, sd_w, g_w, sd_c, g_c);
    check(sd_c < 0.4 * sd_a && g_c < 0.25 * g_a, "sensor: concrete is weak");
    check(sd_w < 0.7 * sd_a && g_w < 0.6 * g_a && g_w > g_c, "sensor: worn asphalt in between");
    return failures;
}

// ------------------------------------------------------------------ bad_options

int test_bad_options()
{
    const fs::path out = scratch("bad");
    const std::string o = " --out '" + out.string() + "'";
    const char *bad[] = {
        "--scene nope",
        "--f abc",
        "--frames 0",
        "--bogus 1",
        "--width",
        "--single --frames 3",
        "--noise -1",
        "--ss 9",
        "--seed -3",
        "--pitch-deg 95",
        "--texture /nonexistent/x.png",
        "--texture-kind marble",
        "--single=1",
        "stray",
        "--drop-mm 1e400",
        "--threads 0",
        "--grade-pct 60",
        "--grade-pct x",
        "--ramp-mm -1",
        "--exposure-pct -5",
        "--exposure-pct 95",
        "--exposure-every 0",
        "--exposure-lag-right x",
    };
    for (const char *args : bad) {
        std::string err;
        const int rc = run(std::string(args) + o, &err);
        // the common exit codes: 2 bad command line, 1 unreadable input
        const int want = std::strstr(args, "/nonexistent/") ? 1 : 2;
        check(rc == want, std::string("bad_options: '") + args + "' exits " + std::to_string(want) +
                              " (got " + std::to_string(rc) + ")");
        check(err.find("error") != std::string::npos,
              std::string("bad_options: '") + args + "' prints an error message");
    }
    std::string err;
    check(run("--single", &err) != 0 && err.find("--out") != std::string::npos,
          "bad_options: missing --out is reported");
    check(run("--help") == 0, "bad_options: --help exits 0");
    check(run("--version") == 0, "bad_options: --version exits 0");
    check(run("") == 2, "bad_options: no arguments exit 2 (usage)");
    // --opt=value and the short -o take the same values as --opt value
    check(run("--single --f=300 --width=64 --height 48 -q -o '" + out.string() + "'") == 0,
          "bad_options: --f=300 --width=64 -q -o DIR works");
    fs::remove_all(out);
    return failures;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: %s flat_gt|ramp_gt|roll_gt|warp|determinism|sensor|bad_options "
                     "NEGOBS_SYNTH\n",
                     argv[0]);
        return 2;
    }
    const std::string mode = argv[1];
    g_exe = argv[2];
    if (mode == "flat_gt")
        test_flat_gt();
    else if (mode == "ramp_gt")
        test_ramp_gt();
    else if (mode == "warp")
        test_warp();
    else if (mode == "determinism")
        test_determinism();
    else if (mode == "bad_options")
        test_bad_options();
    else if (mode == "roll_gt")
        test_roll_gt();
    else if (mode == "sensor")
        test_sensor();
    else {
        std::fprintf(stderr, "unknown mode %s\n", mode.c_str());
        return 2;
    }
    if (failures)
        std::fprintf(stderr, "%d check(s) failed\n", failures);
    else
        std::printf("%s: all checks passed\n", mode.c_str());
    return failures ? 1 : 0;
}
