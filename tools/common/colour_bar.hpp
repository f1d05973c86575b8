// A colour bar with a scale beside a false-colour picture, so a reader
// can tell which disparity a colour stands for (and that black is "no
// value") without knowing the colour map or the range it spans.
#ifndef NEGOBS_TOOLS_COLOUR_BAR_HPP
#define NEGOBS_TOOLS_COLOUR_BAR_HPP

#include <string>

#include <opencv2/core.hpp>

namespace negobs_cli {

// picture (CV_8UC3) with a strip on its right: the OpenCV colour map
// `colormap` from hi (top) to lo (bottom) with labelled ticks in `unit`,
// and a black swatch labelled "none". The strip is as tall as the
// picture and about 60 px wide for a 240-row picture (scaled with it).
cv::Mat with_colour_bar(const cv::Mat &picture, int colormap, double lo,
                        double hi, const std::string &unit);

// The strip alone, h rows tall (for pictures that place it themselves).
cv::Mat colour_bar(int h, int colormap, double lo, double hi,
                   const std::string &unit);

} // namespace negobs_cli

#endif
