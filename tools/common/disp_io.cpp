#include "disp_io.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace negobs_cli {

namespace {

bool host_little_endian()
{
    const uint16_t one = 1;
    uint8_t b = 0;
    std::memcpy(&b, &one, 1);
    return b == 1;
}

bool ends_with_ci(const std::string &s, const char *suffix)
{
    const size_t n = std::strlen(suffix);
    if (s.size() < n) {
        return false;
    }
    for (size_t i = 0; i < n; ++i) {
        const char c = s[s.size() - n + i];
        if (std::tolower(static_cast<unsigned char>(c)) != suffix[i]) {
            return false;
        }
    }
    return true;
}

// One whitespace-separated header token of a PFM file.
bool pfm_token(std::istream &in, std::string &tok)
{
    tok.clear();
    int c = in.get();
    while (c != EOF && std::isspace(c)) {
        c = in.get();
    }
    while (c != EOF && !std::isspace(c)) {
        tok.push_back(static_cast<char>(c));
        if (tok.size() > 32) {
            return false;
        }
        c = in.get();
    }
    // the one whitespace character after the token is consumed: after the
    // scale it separates the header from the raster
    return !tok.empty() && c != EOF;
}

} // namespace

bool parse_disp_format(const std::string &name, DispFormat &out)
{
    if (name == "png16") {
        out = DispFormat::Png16;
    } else if (name == "kitti") {
        out = DispFormat::Kitti;
    } else if (name == "pfm") {
        out = DispFormat::Pfm;
    } else {
        return false;
    }
    return true;
}

const char *disp_format_name(DispFormat f)
{
    switch (f) {
    case DispFormat::Png16: return "png16";
    case DispFormat::Kitti: return "kitti";
    case DispFormat::Pfm: return "pfm";
    default: return "auto";
    }
}

double disp_format_max(DispFormat f)
{
    switch (f) {
    case DispFormat::Png16: return 65535.0 / 16.0;
    case DispFormat::Kitti: return 65535.0 / 256.0;
    default: return static_cast<double>(std::numeric_limits<float>::max());
    }
}

bool write_pfm(const std::string &path, const cv::Mat &img, std::string &err)
{
    if (img.type() != CV_32FC1 || img.empty()) {
        err = "PFM writer needs a non-empty one-channel float map";
        return false;
    }
    std::ofstream out(path, std::ios::binary);
    if (!out) {
        err = "cannot write '" + path + "'";
        return false;
    }
    // scale -1: little endian (the byte order Middlebury's files use)
    out << "Pf\n" << img.cols << " " << img.rows << "\n-1\n";
    const bool swap = !host_little_endian();
    std::vector<uint8_t> row(static_cast<size_t>(img.cols) * 4);
    for (int y = img.rows - 1; y >= 0; --y) { // bottom row first
        std::memcpy(row.data(), img.ptr<float>(y), row.size());
        if (swap) {
            for (size_t i = 0; i < row.size(); i += 4) {
                std::swap(row[i], row[i + 3]);
                std::swap(row[i + 1], row[i + 2]);
            }
        }
        out.write(reinterpret_cast<const char *>(row.data()),
                  static_cast<std::streamsize>(row.size()));
    }
    out.flush();
    if (!out) {
        err = "cannot write '" + path + "' (disk full?)";
        return false;
    }
    return true;
}

bool read_pfm(const std::string &path, cv::Mat &out, std::string &err)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        err = "cannot read '" + path + "'";
        return false;
    }
    std::string magic, ws, hs, ss;
    if (!pfm_token(in, magic) || (magic != "Pf" && magic != "PF") ||
        !pfm_token(in, ws) || !pfm_token(in, hs) || !pfm_token(in, ss)) {
        err = "'" + path + "' is not a PFM file (header Pf|PF W H SCALE)";
        return false;
    }
    char *end = nullptr;
    const long w = std::strtol(ws.c_str(), &end, 10);
    const bool w_ok = *end == '\0';
    const long h = std::strtol(hs.c_str(), &end, 10);
    const bool h_ok = *end == '\0';
    const double scale = std::strtod(ss.c_str(), &end);
    if (!w_ok || !h_ok || *end != '\0' || w < 1 || h < 1 || w > 65536 ||
        h > 65536 || !std::isfinite(scale) || scale == 0.0) {
        err = "'" + path + "': bad PFM size or scale";
        return false;
    }
    const int ch = magic == "PF" ? 3 : 1;
    const bool file_le = scale < 0;
    const bool swap = file_le != host_little_endian();
    cv::Mat img(static_cast<int>(h), static_cast<int>(w), CV_32FC(ch));
    const size_t row_bytes = static_cast<size_t>(w) * 4u * ch;
    for (int y = img.rows - 1; y >= 0; --y) {
        char *dst = reinterpret_cast<char *>(img.ptr(y));
        if (!in.read(dst, static_cast<std::streamsize>(row_bytes))) {
            err = "'" + path + "': PFM raster is shorter than " +
                  std::to_string(w) + "x" + std::to_string(h);
            return false;
        }
        if (swap) {
            for (size_t i = 0; i < row_bytes; i += 4) {
                std::swap(dst[i], dst[i + 3]);
                std::swap(dst[i + 1], dst[i + 2]);
            }
        }
    }
    if (ch == 3) {
        cv::Mat g;
        cv::transform(img, g, cv::Matx13f(1.f / 3, 1.f / 3, 1.f / 3));
        img = g;
    }
    out = img;
    return true;
}

bool write_disparity(const std::string &path, const cv::Mat &disp,
                     const cv::Mat &valid, DispFormat f, std::string &err)
{
    if (disp.type() != CV_32FC1 || valid.type() != CV_8UC1 ||
        disp.size() != valid.size()) {
        err = "internal: disparity map and mask do not match";
        return false;
    }
    const double top = disp_format_max(f);
    if (f == DispFormat::Pfm) {
        cv::Mat o(disp.size(), CV_32F);
        for (int y = 0; y < disp.rows; ++y) {
            const float *d = disp.ptr<float>(y);
            const uint8_t *v = valid.ptr<uint8_t>(y);
            float *p = o.ptr<float>(y);
            for (int x = 0; x < disp.cols; ++x) {
                p[x] = v[x] ? d[x] : std::numeric_limits<float>::infinity();
            }
        }
        return write_pfm(path, o, err);
    }
    const double k = f == DispFormat::Kitti ? 256.0 : 16.0;
    cv::Mat o(disp.size(), CV_16U);
    for (int y = 0; y < disp.rows; ++y) {
        const float *d = disp.ptr<float>(y);
        const uint8_t *v = valid.ptr<uint8_t>(y);
        uint16_t *p = o.ptr<uint16_t>(y);
        for (int x = 0; x < disp.cols; ++x) {
            if (!v[x] || !(d[x] > 0.f)) {
                p[x] = 0;
                continue;
            }
            if (d[x] > top) {
                char buf[160];
                std::snprintf(buf, sizeof buf,
                              "disparity %.2f px at (%d, %d) does not fit "
                              "the %s format (at most %.3f px)",
                              d[x], x, y, disp_format_name(f), top);
                err = buf;
                return false;
            }
            // a value that rounds to 0 would read back as "no value"
            const long q = std::lround(d[x] * k);
            p[x] = static_cast<uint16_t>(q < 1 ? 1 : q);
        }
    }
    try {
        if (!ends_with_ci(path, ".png") || !cv::imwrite(path, o)) {
            err = "cannot write '" + path + "' (a .png name is required)";
            return false;
        }
    } catch (const cv::Exception &e) {
        err = "cannot write '" + path + "': " + e.err;
        return false;
    }
    return true;
}

bool read_disparity(const std::string &path, DispFormat f, double scale,
                    cv::Mat &disp, cv::Mat &valid, std::string &err)
{
    if (f == DispFormat::Auto) {
        f = ends_with_ci(path, ".pfm") ? DispFormat::Pfm : DispFormat::Png16;
    }
    if (f == DispFormat::Pfm) {
        cv::Mat img;
        if (!read_pfm(path, img, err)) {
            return false;
        }
        if (scale > 0 && scale != 1.0) {
            img /= scale;
        }
        disp = img;
        valid = cv::Mat(img.size(), CV_8U);
        for (int y = 0; y < img.rows; ++y) {
            const float *d = img.ptr<float>(y);
            uint8_t *v = valid.ptr<uint8_t>(y);
            for (int x = 0; x < img.cols; ++x) {
                v[x] = std::isfinite(d[x]) ? 255 : 0;
            }
        }
        disp.setTo(0.f, valid == 0);
        return true;
    }
    if (!(scale > 0)) {
        scale = f == DispFormat::Kitti ? 256.0 : 16.0;
    }
    cv::Mat raw;
    try {
        raw = cv::imread(path, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception &e) {
        err = "cannot read '" + path + "': " + e.err;
        return false;
    }
    if (raw.empty()) {
        err = "cannot read '" + path + "'";
        return false;
    }
    if (raw.channels() == 3) {
        cv::cvtColor(raw, raw, cv::COLOR_BGR2GRAY);
    } else if (raw.channels() == 4) {
        cv::cvtColor(raw, raw, cv::COLOR_BGRA2GRAY);
    }
    if (raw.channels() != 1 ||
        (raw.depth() != CV_8U && raw.depth() != CV_16U)) {
        err = "'" + path + "': not an 8- or 16-bit grey disparity image";
        return false;
    }
    raw.convertTo(disp, CV_32F, 1.0 / scale);
    valid = raw > 0;
    return true;
}

} // namespace negobs_cli
