#include "cli.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <unistd.h>

#include <opencv2/core.hpp>

extern "C" {
#include "negobs/stereo.h"
#include "negobs/version.h"
}

namespace negobs_cli {

bool parse_memory_profile(const char *s, int &out)
{
    const std::string name = (s != nullptr) ? s : "";
    if (name == "compact") {
        out = NEGOBS_STEREO_PROFILE_COMPACT;
    } else if (name == "fast") {
        out = NEGOBS_STEREO_PROFILE_FAST;
    } else {
        return false;
    }
    return true;
}

bool parse_int(const char *s, long lo, long hi, int &out)
{
    if (s == nullptr || *s == '\0') {
        return false;
    }
    char *end = nullptr;
    errno = 0;
    const long v = std::strtol(s, &end, 10);
    if (errno != 0 || *end != '\0' || v < lo || v > hi) {
        return false;
    }
    out = static_cast<int>(v);
    return true;
}

bool parse_double(const char *s, double lo, double hi, double &out)
{
    if (s == nullptr || *s == '\0') {
        return false;
    }
    char *end = nullptr;
    errno = 0;
    const double v = std::strtod(s, &end);
    // !(v >= lo) also refuses NaN, which every comparison fails
    if (errno != 0 || *end != '\0' || !std::isfinite(v) || !(v >= lo) ||
        !(v <= hi)) {
        return false;
    }
    out = v;
    return true;
}

int int_arg(const char *opt, const char *s, long lo, long hi)
{
    int v = 0;
    if (!parse_int(s, lo, hi, v)) {
        throw UsageError(std::string(opt) + " '" + (s ? s : "") +
                         "' is not an integer in " + std::to_string(lo) +
                         ".." + std::to_string(hi));
    }
    return v;
}

double double_arg(const char *opt, const char *s, double lo, double hi)
{
    double v = 0;
    if (!parse_double(s, lo, hi, v)) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "' is not a number in %g..%g", lo, hi);
        throw UsageError(std::string(opt) + " '" + (s ? s : "") + buf);
    }
    return v;
}

std::string default_data_dir()
{
    const char *env = std::getenv("NEGOBS_DATA");
    if (env != nullptr && *env != '\0') {
        return env;
    }
#if defined(NEGOBS_SOURCE_ROOT) && defined(NEGOBS_BUILD_ROOT)
    char self[4096];
    const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
        self[n] = '\0';
        const std::string exe(self);
        const std::string build = std::string(NEGOBS_BUILD_ROOT) + "/";
        if (exe.compare(0, build.size(), build) == 0) {
            return std::string(NEGOBS_SOURCE_ROOT) + "/../shared/data";
        }
    }
#endif
    return std::string();
}

const char *version()
{
    return negobs_version();
}

void print_version(const char *tool)
{
    std::printf("%s (negobs %s)\n", tool, version());
}

int main_guard(const char *tool, int argc, char **argv,
               int (*run)(int, char **), int error_code)
{
    try {
        return run(argc, argv);
    } catch (const UsageError &e) {
        std::fprintf(stderr, "%s: %s (see %s --help)\n", tool, e.what(), tool);
        return kExitUsage;
    } catch (const cv::Exception &e) {
        std::fprintf(stderr, "%s: OpenCV error: %s\n", tool, e.err.c_str());
    } catch (const std::exception &e) {
        std::fprintf(stderr, "%s: error: %s\n", tool, e.what());
    } catch (...) {
        std::fprintf(stderr, "%s: unknown error\n", tool);
    }
    return error_code;
}

Progress::Progress(const char *tool, const char *unit, long total, int force)
    : tool_(tool), unit_(unit), total_(total),
      enabled_(force == 1 || (force < 0 && ::isatty(2) == 1)),
      tty_(::isatty(2) == 1), start_(std::chrono::steady_clock::now())
{
}

Progress::~Progress()
{
    finish();
}

std::string Progress::format_seconds(double s)
{
    if (!(s >= 0) || s > 1e7) {
        return "?";
    }
    const long t = std::lround(s);
    char buf[32];
    if (t >= 3600) {
        std::snprintf(buf, sizeof buf, "%ldh%02ldm", t / 3600, t / 60 % 60);
    } else if (t >= 60) {
        std::snprintf(buf, sizeof buf, "%ldm%02lds", t / 60, t % 60);
    } else {
        std::snprintf(buf, sizeof buf, "%lds", t);
    }
    return buf;
}

void Progress::step(long done, const std::string &label)
{
    if (!enabled_) {
        return;
    }
    const double el = std::chrono::duration<double>(
                          std::chrono::steady_clock::now() - start_)
                          .count();
    // the mean time per finished item so far, times the items left
    const std::string eta = done > 0 && total_ > 0
                                ? format_seconds(
                                      el / static_cast<double>(done) *
                                      static_cast<double>(total_ - done))
                                : std::string("?");
    std::fprintf(stderr, "%s%s: %ld/%ld %s, %s elapsed, ETA %s%s%s%s",
                 tty_ ? "\r\033[K" : "", tool_.c_str(), done, total_,
                 unit_.c_str(), format_seconds(el).c_str(), eta.c_str(),
                 label.empty() ? "" : " (", label.c_str(),
                 label.empty() ? "" : ")");
    if (!tty_) {
        std::fputc('\n', stderr);
    }
    std::fflush(stderr);
    open_ = tty_;
}

void Progress::finish()
{
    if (open_) {
        std::fputc('\n', stderr);
        open_ = false;
    }
}

std::string json_escape(const std::string &s)
{
    std::string o;
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\';
            o += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x",
                          static_cast<unsigned>(c));
            o += buf;
        } else {
            o += c;
        }
    }
    return o;
}

} // namespace negobs_cli
