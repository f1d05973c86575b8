// Command-line number parsing shared by the host tools (tools/common).
// Strict: the whole argument must be the number; no trailing text, no
// empty string, no inf/nan. Range checks stay with each option.
#ifndef NEGOBS_TOOLS_CLI_PARSE_HPP
#define NEGOBS_TOOLS_CLI_PARSE_HPP

#include <cmath>
#include <cstdlib>

namespace negobs_tools {

// A finite double, e.g. "1.5", "-3e2".
inline bool parse_double(const char *s, double &v)
{
    char *end = nullptr;
    v = std::strtod(s, &end);
    return end != s && *end == '\0' && std::isfinite(v);
}

// A decimal integer within +-1e6 (every option of the tools is far
// inside; the bound keeps the conversion to int exact).
inline bool parse_int(const char *s, int &v)
{
    char *end = nullptr;
    long x = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || x < -1000000 || x > 1000000) {
        return false;
    }
    v = static_cast<int>(x);
    return true;
}

} // namespace negobs_tools

#endif // NEGOBS_TOOLS_CLI_PARSE_HPP
