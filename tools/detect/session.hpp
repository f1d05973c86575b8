// Sessions recorded by negobs_run --record, read on the host (negobs_png
// --seq): format in docs/RUNNING.md, "Replay folders and the
// recorded-session format".
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace negobs_detect_tools {

struct Session {
    int w = 0, h = 0;
    long frames = 0;                         // complete pairs in left.y/right.y
    std::vector<double> t_ms;                // capture time per pair, -1 unknown
    std::map<std::string, std::string> meta; // meta.txt, when present
};

// True when DIR holds a recorded session (session.txt).
bool is_session(const std::string &dir);

// Read session.txt, frames.txt, the sizes of left.y/right.y and meta.txt;
// "" or what is wrong.
std::string read_session(const std::string &dir, Session &s);

// Frame `index` of DIR/left.y or DIR/right.y (side "left" / "right").
bool read_session_frame(const std::string &dir, const char *side, long index,
                        const Session &s, cv::Mat &m, std::string &err);

// The rig geometry the device used (meta.txt), written into f, B, cx, cy
// where they are still < 0 (not given on the command line) and no --calib
// table is used; warns on stderr when the session was recorded with a
// calibration table and `calib_crc` (0: no --calib) is not that table.
void session_geometry(const Session &s, const std::string &dir, bool have_calib,
                      uint32_t calib_crc, double &f, double &B, double &cx, double &cy);

} // namespace negobs_detect_tools
