// The command-line conventions every negobs host tool shares: exit codes,
// checked number parsing, --version, the top-level exception boundary and
// a progress line with an ETA. One copy here instead of one per tool, so
// a fix (a range check, a message) reaches them all.
#ifndef NEGOBS_TOOLS_CLI_HPP
#define NEGOBS_TOOLS_CLI_HPP

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace negobs_cli {

// Exit codes common to every tool (docs/TOOLS.md). A tool may document
// more codes of its own (3..76); 77 is Meson's "skipped".
enum Exit {
    kExitOk = 0,
    kExitData = 1,  // unreadable or invalid input, unwritable output
    kExitUsage = 2, // bad command line
    kExitSkip = 77, // nothing to do here (data absent): a skipped test
};

// A bad command line: main_guard() prints it with a pointer to --help and
// exits kExitUsage.
struct UsageError : std::runtime_error {
    explicit UsageError(const std::string &what) : std::runtime_error(what) {}
};

// Whole-string parses in [lo, hi]: "12x", "", "nan" and out-of-range
// values are refused (false), never truncated or wrapped.
bool parse_int(const char *s, long lo, long hi, int &out);
bool parse_double(const char *s, double lo, double hi, double &out);

// The matcher's memory profile by name: "compact" or "fast" into the
// NEGOBS_STEREO_PROFILE_* value; anything else is refused (false).
bool parse_memory_profile(const char *s, int &out);

// The same, throwing UsageError naming the option and the accepted range.
int int_arg(const char *opt, const char *s, long lo, long hi);
double double_arg(const char *opt, const char *s, double lo, double hi);

// "negobs 0.1.0": the version of meson.build's project(), via the
// library's generated negobs/version.h.
const char *version();
// Prints "TOOL (negobs X.Y.Z)" to stdout, the --version line of every tool.
void print_version(const char *tool);

// The data folder a tool reads when not told: $NEGOBS_DATA; else, for a
// binary running inside the build tree it was built in, the source
// tree's ../shared/data; else "" (an installed binary has no source tree
// and must not keep the build machine's paths).
std::string default_data_dir();

// Runs run(argc, argv) and turns what escapes it into a message and an
// exit code: UsageError -> kExitUsage, any other exception -> error_code
// (kExitData unless the tool documents another). No OpenCV error can end
// a tool with an abort.
int main_guard(const char *tool, int argc, char **argv,
               int (*run)(int, char **), int error_code = kExitData);

// A one-line progress report on stderr ("TOOL: 12/273 sets, 1m20s left"),
// redrawn in place. Enabled on a terminal, or always with --progress
// (then one line per step, for logs); silent otherwise, so pipes and test
// logs stay clean.
class Progress {
public:
    // force: 1 = always (--progress), 0 = never, -1 = when stderr is a TTY
    Progress(const char *tool, const char *unit, long total, int force = -1);
    ~Progress();
    void step(long done, const std::string &label = std::string());
    void finish();
    bool enabled() const { return enabled_; }
    // "1h02m", "3m05s", "42s"
    static std::string format_seconds(double s);

private:
    std::string tool_, unit_;
    long total_;
    bool enabled_, tty_, open_ = false;
    std::chrono::steady_clock::time_point start_;
};

// s as a JSON string body: quotes and backslashes escaped, control
// characters as \u00XX (no surrounding quotes). The one escaper of the
// tools' JSON writers.
std::string json_escape(const std::string &s);

} // namespace negobs_cli

#endif
