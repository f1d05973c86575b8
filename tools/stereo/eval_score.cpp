#include "eval_score.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

#include <opencv2/imgcodecs.hpp>

#include "cli.hpp"
#include "disp_io.hpp"

namespace negobs_tools {

namespace {

// An output stream on a file, or on stdout for "-".
struct Out {
    std::unique_ptr<std::ofstream> file;
    std::ostream *os = nullptr;
    explicit Out(const std::string &path)
    {
        if (path == "-") {
            os = &std::cout;
        } else {
            file.reset(new std::ofstream(path));
            if (*file) {
                os = file.get();
            }
        }
    }
    bool ok() const { return os != nullptr && static_cast<bool>(*os); }
};

std::string num(double v, int decimals)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

std::string json_str(const std::string &s)
{
    return "\"" + negobs_cli::json_escape(s) + "\"";
}

std::string csv_field(const std::string &s)
{
    if (s.find_first_of(",\"\n") == std::string::npos) {
        return s;
    }
    std::string o = "\"";
    for (const char c : s) {
        o += c;
        if (c == '"') {
            o += '"';
        }
    }
    return o + "\"";
}

std::string base_name(const std::string &p)
{
    const size_t k = p.find_last_of('/');
    return k == std::string::npos ? p : p.substr(k + 1);
}

} // namespace

DispScore score_disparity(const cv::Mat &disp, const cv::Mat &valid,
                          const cv::Mat &gt, const cv::Mat &eval_mask)
{
    DispScore m;
    long n = 0, with = 0, b1 = 0, b2 = 0;
    double se = 0.0;
    for (int y = 0; y < gt.rows; ++y) {
        const float *d = disp.ptr<float>(y);
        const uint8_t *v = valid.ptr<uint8_t>(y);
        const float *g = gt.ptr<float>(y);
        const uint8_t *e = eval_mask.ptr<uint8_t>(y);
        for (int x = 0; x < gt.cols; ++x) {
            if (!e[x])
                continue;
            ++n;
            if (!v[x])
                continue;
            ++with;
            const double err = std::fabs(double(d[x]) - double(g[x]));
            b1 += err > 1.0;
            b2 += err > 2.0;
            se += err * err;
        }
    }
    m.evaluated = n;
    m.with_value = with;
    m.density = n ? 100.0 * double(with) / double(n) : 0.0;
    m.bad1 = with ? 100.0 * double(b1) / double(with) : 100.0;
    m.bad2 = with ? 100.0 * double(b2) / double(with) : 100.0;
    m.bad1all = n ? 100.0 * double(b1 + (n - with)) / double(n) : 100.0;
    m.rms = with ? std::sqrt(se / double(with)) : 0.0;
    return m;
}

bool write_score_csv(const std::string &path,
                     const std::vector<ScoreRow> &rows)
{
    Out o(path);
    if (!o.ok()) {
        return false;
    }
    *o.os << "set,matcher,width,height,evaluated_px,density_pct,bad1_pct,"
             "bad1all_pct,bad2_pct,rms_px,cpu_ms\n";
    for (const ScoreRow &r : rows) {
        *o.os << csv_field(r.set) << ',' << csv_field(r.matcher) << ','
              << r.width << ',' << r.height << ',' << r.s.evaluated << ','
              << num(r.s.density, 3) << ',' << num(r.s.bad1, 3) << ','
              << num(r.s.bad1all, 3) << ',' << num(r.s.bad2, 3) << ','
              << num(r.s.rms, 4) << ','
              << (r.cpu_ms >= 0 ? num(r.cpu_ms, 2) : std::string()) << '\n';
    }
    o.os->flush();
    return static_cast<bool>(*o.os);
}

bool write_score_json(const std::string &path,
                      const std::vector<ScoreRow> &rows)
{
    Out o(path);
    if (!o.ok()) {
        return false;
    }
    *o.os << "[\n";
    for (size_t i = 0; i < rows.size(); ++i) {
        const ScoreRow &r = rows[i];
        *o.os << "  {\"set\": " << json_str(r.set)
              << ", \"matcher\": " << json_str(r.matcher)
              << ", \"width\": " << r.width << ", \"height\": " << r.height
              << ", \"evaluated_px\": " << r.s.evaluated
              << ", \"density_pct\": " << num(r.s.density, 3)
              << ", \"bad1_pct\": " << num(r.s.bad1, 3)
              << ", \"bad1all_pct\": " << num(r.s.bad1all, 3)
              << ", \"bad2_pct\": " << num(r.s.bad2, 3)
              << ", \"rms_px\": " << num(r.s.rms, 4) << ", \"cpu_ms\": "
              << (r.cpu_ms >= 0 ? num(r.cpu_ms, 2) : std::string("null"))
              << "}" << (i + 1 < rows.size() ? "," : "") << "\n";
    }
    *o.os << "]\n";
    o.os->flush();
    return static_cast<bool>(*o.os);
}

bool write_score_markdown(const std::string &path,
                          const std::vector<ScoreRow> &rows,
                          const std::string &command_line)
{
    Out o(path);
    if (!o.ok()) {
        return false;
    }
    *o.os << "Command: `" << command_line << "`\n\n"
          << "| set | matcher | size | eval px | density % | bad1 % | "
             "bad1all % | bad2 % | RMS px |\n"
          << "|---|---|---|---:|---:|---:|---:|---:|---:|\n";
    for (const ScoreRow &r : rows) {
        *o.os << "| " << r.set << " | " << r.matcher << " | " << r.width << "x"
              << r.height << " | " << r.s.evaluated << " | "
              << num(r.s.density, 1) << " | " << num(r.s.bad1, 2) << " | "
              << num(r.s.bad1all, 2) << " | " << num(r.s.bad2, 2) << " | "
              << num(r.s.rms, 3) << " |\n";
    }
    o.os->flush();
    return static_cast<bool>(*o.os);
}

int score_map_main(const ScoreOptions &o)
{
    using negobs_cli::DispFormat;
    DispFormat mf = DispFormat::Auto;
    if (o.map_format != "auto" &&
        !negobs_cli::parse_disp_format(o.map_format, mf)) {
        std::fprintf(stderr,
                     "negobs_eval: --format '%s' is not auto, png16, kitti "
                     "or pfm\n",
                     o.map_format.c_str());
        return negobs_cli::kExitUsage;
    }
    std::string err;
    cv::Mat disp, valid;
    if (!negobs_cli::read_disparity(o.map, mf, o.map_scale, disp, valid,
                                    err)) {
        std::fprintf(stderr, "negobs_eval: map: %s\n", err.c_str());
        return negobs_cli::kExitData;
    }
    // GT scale when not given: 1 for PFM and 8-bit images (Middlebury
    // full size), 256 for 16-bit PNGs (KITTI's ground truth); quarter-
    // or half-size Middlebury GT needs --gt-scale 4 / 2.
    double gs = o.gt_scale;
    const bool gt_pfm = o.gt.size() > 4 &&
                        (o.gt.compare(o.gt.size() - 4, 4, ".pfm") == 0 ||
                         o.gt.compare(o.gt.size() - 4, 4, ".PFM") == 0);
    if (!(gs > 0)) {
        gs = 1.0;
        if (!gt_pfm) {
            const cv::Mat probe = cv::imread(o.gt, cv::IMREAD_UNCHANGED);
            if (!probe.empty() && probe.depth() == CV_16U) {
                gs = 256.0;
            }
        }
    }
    cv::Mat gt, known;
    if (!negobs_cli::read_disparity(
            o.gt, gt_pfm ? DispFormat::Pfm : DispFormat::Png16, gs, gt, known,
            err)) {
        std::fprintf(stderr, "negobs_eval: GT: %s\n", err.c_str());
        return negobs_cli::kExitData;
    }
    if (disp.size() != gt.size()) {
        std::fprintf(stderr,
                     "negobs_eval: size mismatch: map %dx%d, GT %dx%d\n",
                     disp.cols, disp.rows, gt.cols, gt.rows);
        return negobs_cli::kExitData;
    }
    cv::Mat eval_mask = known.clone();
    if (!o.mask.empty()) {
        cv::Mat mask = cv::imread(o.mask, cv::IMREAD_GRAYSCALE);
        if (mask.empty() || mask.size() != gt.size()) {
            std::fprintf(stderr,
                         "negobs_eval: cannot read mask '%s' or its size "
                         "differs from the GT\n",
                         o.mask.c_str());
            return negobs_cli::kExitData;
        }
        // Middlebury's masks: 255 = evaluated (non-occluded), 128 =
        // occluded, 0 = unknown
        eval_mask &= (mask == 255);
    }
    ScoreRow row;
    row.set = o.name.empty() ? base_name(o.map) : o.name;
    row.matcher = "map";
    row.width = gt.cols;
    row.height = gt.rows;
    row.s = score_disparity(disp, valid, gt, eval_mask);
    if (row.s.evaluated == 0) {
        std::fprintf(stderr,
                     "negobs_eval: no pixel to evaluate: the GT%s has no "
                     "known value\n",
                     o.mask.empty() ? "" : " (inside the mask)");
        return negobs_cli::kExitData;
    }
    // stdout is free for a table written to "-"
    const bool quiet = o.csv == "-" || o.json == "-" || o.markdown == "-";
    if (!quiet) {
        std::printf("%s: %dx%d, %ld px evaluated (GT scale %g): density "
                    "%.2f %%, bad1 %.2f %%, bad1all %.2f %%, bad2 %.2f %%, "
                    "rms %.3f px\n",
                    row.set.c_str(), row.width, row.height, row.s.evaluated,
                    gs, row.s.density, row.s.bad1, row.s.bad1all, row.s.bad2,
                    row.s.rms);
    }
    const std::vector<ScoreRow> rows{row};
    int rc = negobs_cli::kExitOk;
    if (!o.csv.empty() && !write_score_csv(o.csv, rows)) {
        std::fprintf(stderr, "negobs_eval: cannot write '%s'\n",
                     o.csv.c_str());
        rc = negobs_cli::kExitData;
    }
    if (!o.json.empty() && !write_score_json(o.json, rows)) {
        std::fprintf(stderr, "negobs_eval: cannot write '%s'\n",
                     o.json.c_str());
        rc = negobs_cli::kExitData;
    }
    if (!o.markdown.empty() &&
        !write_score_markdown(o.markdown, rows, o.command_line)) {
        std::fprintf(stderr, "negobs_eval: cannot write '%s'\n",
                     o.markdown.c_str());
        rc = negobs_cli::kExitData;
    }
    return rc;
}

} // namespace negobs_tools
