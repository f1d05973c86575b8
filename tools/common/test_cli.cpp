// The shared command-line helpers (cli.hpp): whole-string number parsing
// with ranges, the usage-error boundary and the progress line.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

extern "C" {
#include "negobs/stereo.h"
}

#include "cli.hpp"

namespace {

int failures = 0;

void check(bool ok, const std::string &what)
{
    std::printf("%s - %s\n", ok ? "ok" : "FAIL", what.c_str());
    failures += ok ? 0 : 1;
}

int throws_usage(int, char **)
{
    (void)negobs_cli::int_arg("--jobs", "0", 1, 64);
    return 0;
}

int throws_runtime(int, char **)
{
    throw std::runtime_error("disk on fire");
}

} // namespace

int main(int argc, char **argv)
{
    using namespace negobs_cli;
    int i = -1;
    double d = -1;
    check(parse_int("42", 0, 100, i) && i == 42, "42 in 0..100");
    check(parse_memory_profile("fast", i) && i == NEGOBS_STEREO_PROFILE_FAST &&
              parse_memory_profile("compact", i) &&
              i == NEGOBS_STEREO_PROFILE_COMPACT,
          "memory profiles by name");
    check(!parse_memory_profile("Fast", i) && !parse_memory_profile("", i) &&
              !parse_memory_profile(nullptr, i),
          "unknown memory profile names refused");
    check(!parse_int("42x", 0, 100, i) && !parse_int("", 0, 100, i) &&
              !parse_int("101", 0, 100, i) && !parse_int("-1", 0, 100, i) &&
              !parse_int("99999999999999999999", 0, 100, i) &&
              !parse_int(nullptr, 0, 100, i),
          "trailing text, empty, out of range, overflow and null are refused");
    check(parse_double("-2.5e1", -30, 0, d) && d == -25.0, "-2.5e1 in -30..0");
    check(
        !parse_double("nan", -1e9, 1e9, d) &&
            !parse_double("inf", -1e9, 1e300, d) &&
            !parse_double("1e400", 0, 1e308, d) &&
            !parse_double("3.5 ", 0, 10, d) && !parse_double("0.5", 1, 2, d),
        "NaN, infinity, overflow, trailing space and out of range are refused");
    bool threw = false;
    try {
        (void)double_arg("--alpha", "2", -1, 1);
    } catch (const UsageError &e) {
        threw = std::string(e.what()).find(
                    "--alpha '2' is not a number in -1..1") !=
                std::string::npos;
    }
    check(threw, "double_arg names the option, the value and the range");

    // main_guard's codes: usage errors 2, anything else the given code
    check(main_guard("t", argc, argv, throws_usage) == kExitUsage,
          "UsageError -> exit 2");
    check(main_guard("t", argc, argv, throws_runtime) == kExitData,
          "an exception -> exit 1");
    check(main_guard("t", argc, argv, throws_runtime, 4) == 4,
          "... or the tool's own code");

    check(json_escape("a\"b\\c\n") == "a\\\"b\\\\c\\u000a",
          "json_escape: quote, backslash and a control character");
    check(Progress::format_seconds(42) == "42s" &&
              Progress::format_seconds(185) == "3m05s" &&
              Progress::format_seconds(3720) == "1h02m" &&
              Progress::format_seconds(-1) == "?",
          "durations read 42s, 3m05s, 1h02m");

    // --progress on a pipe: one line per step with the count and an ETA;
    // off (0) prints nothing
    const std::string log = std::string(argc > 1 ? argv[1] : "/tmp") +
                            "/progress.txt";
    std::fflush(stderr);
    const int saved = ::dup(2);
    if (std::freopen(log.c_str(), "w", stderr) == nullptr) {
        check(false, "redirect stderr");
        return 1;
    }
    {
        Progress on("negobs_eval", "sets", 4, 1);
        on.step(0, "a");
        on.step(2, "b");
        Progress off("negobs_eval", "sets", 4, 0);
        off.step(1);
    }
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    std::printf("# progress log:\n%s", text.c_str());
    check(text.find("negobs_eval: 0/4 sets, 0s elapsed, ETA ? (a)\n") !=
                  std::string::npos &&
              text.find("negobs_eval: 2/4 sets, ") != std::string::npos &&
              text.find("ETA 0s (b)\n") != std::string::npos,
          "forced progress: one line per step, count, elapsed and ETA");
    check(text.find("1/4") == std::string::npos,
          "disabled progress prints nothing");
    return failures ? 1 : 0;
}
