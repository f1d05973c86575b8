// Recorded sessions on the host; see session.hpp.
#include "session.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace negobs_detect_tools {

namespace {

std::string trim(const std::string &x)
{
    const auto a = x.find_first_not_of(" \t");
    const auto b = x.find_last_not_of(" \t\r");
    return a == std::string::npos ? std::string() : x.substr(a, b - a + 1);
}

} // namespace

bool is_session(const std::string &dir)
{
    return fs::exists(fs::path(dir) / "session.txt");
}

std::string read_session(const std::string &dir_s, Session &s)
{
    const fs::path dir(dir_s);
    std::ifstream st(dir / "session.txt");
    std::string word;
    int version = 0;
    if (!(st >> word >> version) || word != "negobs-session" || version != 1) {
        return (dir / "session.txt").string() + ": not a negobs-session 1 header";
    }
    std::string line;
    while (std::getline(st, line)) {
        std::istringstream ls(line);
        std::string k;
        long v = 0;
        if (!(ls >> k) || k[0] == '#') {
            continue;
        }
        if ((k == "width" || k == "height") && (ls >> v) && v >= 16 && v <= 4096) {
            (k == "width" ? s.w : s.h) = static_cast<int>(v);
        }
    }
    if (s.w == 0 || s.h == 0) {
        return (dir / "session.txt").string() + ": no valid width/height";
    }
    std::error_code ec;
    const auto lb = fs::file_size(dir / "left.y", ec);
    const auto rb = ec ? 0 : fs::file_size(dir / "right.y", ec);
    if (ec) {
        return (dir / "left.y").string() + " or right.y: " + ec.message();
    }
    const uintmax_t fb = static_cast<uintmax_t>(s.w) * static_cast<uintmax_t>(s.h);
    s.frames = static_cast<long>(std::min(lb, rb) / fb); // complete pairs only
    s.t_ms.assign(static_cast<size_t>(s.frames), -1.0);
    std::ifstream ft(dir / "frames.txt");
    double t0 = -1;
    while (std::getline(ft, line)) {
        std::istringstream ls(line);
        long idx = 0;
        unsigned long long tl = 0;
        if (line.empty() || line[0] == '#' || !(ls >> idx >> tl)) {
            continue;
        }
        if (t0 < 0) {
            t0 = static_cast<double>(tl);
        }
        if (idx >= 0 && idx < s.frames) {
            s.t_ms[static_cast<size_t>(idx)] = (static_cast<double>(tl) - t0) / 1e6;
        }
    }
    std::ifstream mt(dir / "meta.txt");
    while (std::getline(mt, line)) {
        const auto eq = line.find('=');
        if (line.empty() || line[0] == '#' || eq == std::string::npos) {
            continue;
        }
        s.meta[trim(line.substr(0, eq))] = trim(line.substr(eq + 1));
    }
    return s.frames > 0 ? std::string() : "no complete pair in " + dir.string();
}

bool read_session_frame(const std::string &dir, const char *side, long index,
                        const Session &s, cv::Mat &m, std::string &err)
{
    const std::string path = (fs::path(dir) / (std::string(side) + ".y")).string();
    std::ifstream f(path, std::ios::binary);
    m.create(s.h, s.w, CV_8UC1);
    f.seekg(static_cast<std::streamoff>(index) * s.w * s.h);
    if (!f.read(reinterpret_cast<char *>(m.data),
                static_cast<std::streamsize>(s.w) * s.h)) {
        err = path + ": cannot read frame " + std::to_string(index);
        return false;
    }
    return true;
}

void session_geometry(const Session &s, const std::string &dir, bool have_calib,
                      uint32_t calib_crc, double &f, double &B, double &cx, double &cy)
{
    auto num = [&](const char *k, double div, double &dst) {
        const auto m = s.meta.find(k);
        if (dst < 0 && m != s.meta.end()) {
            const double v = std::strtod(m->second.c_str(), nullptr) / div;
            if (std::isfinite(v) && v > 0) {
                dst = v;
            }
        }
    };
    if (!have_calib) {
        num("focal_q4", 16.0, f);
        num("baseline_um", 1000.0, B);
        num("cx_q4", 16.0, cx);
        num("cy_q4", 16.0, cy);
    }
    const auto cf = s.meta.find("calib_file");
    if (cf == s.meta.end() || cf->second.empty()) {
        return;
    }
    const auto cc = s.meta.find("calib_crc32");
    const std::string crc = cc != s.meta.end() ? cc->second : "?";
    if (!have_calib) {
        std::fprintf(stderr,
                     "negobs_png: warning: %s was recorded raw with the "
                     "calibration table %s (CRC %s): give it with --calib\n",
                     dir.c_str(), cf->second.c_str(), crc.c_str());
    } else if (std::strtoul(crc.c_str(), nullptr, 16) != calib_crc) {
        std::fprintf(stderr,
                     "negobs_png: warning: --calib is not the table the "
                     "session was recorded with (%s, CRC %s)\n",
                     cf->second.c_str(), crc.c_str());
    }
}

} // namespace negobs_detect_tools
