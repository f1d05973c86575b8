// The colour bar beside false-colour pictures (colour_bar.hpp): the
// picture is kept as it is, the bar runs from the top of the range (top)
// to the bottom, in the picture's colour map, with a black "none" swatch.
#include <cstdio>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "colour_bar.hpp"

namespace {

int failures = 0;

void check(bool ok, const std::string &what)
{
    std::printf("%s - %s\n", ok ? "ok" : "FAIL", what.c_str());
    failures += ok ? 0 : 1;
}

// First row from y0 down where a pixel of the bar equals c; -1 if none.
int first_row_with(const cv::Mat &bar, const cv::Vec3b &c, int y0 = 0)
{
    for (int y = y0; y < bar.rows; ++y) {
        for (int x = 0; x < bar.cols; ++x) {
            if (bar.at<cv::Vec3b>(y, x) == c) {
                return y;
            }
        }
    }
    return -1;
}

} // namespace

int main()
{
    for (const int map : {cv::COLORMAP_TURBO, cv::COLORMAP_JET}) {
        cv::Mat pic(240, 320, CV_8UC3);
        cv::randu(pic, 0, 256);
        const cv::Mat out = negobs_cli::with_colour_bar(pic, map, 0, 63, "px");
        check(out.rows == pic.rows && out.cols > pic.cols &&
                  out.cols < pic.cols + 120,
              "the bar adds a strip on the right (" +
                  std::to_string(out.cols - pic.cols) + " px), same height");
        check(cv::norm(out(cv::Rect(0, 0, pic.cols, pic.rows)), pic,
                       cv::NORM_INF) == 0,
              "the picture itself is unchanged");
        const cv::Mat bar = out(
            cv::Rect(pic.cols, 0, out.cols - pic.cols, out.rows));
        cv::Mat ends(2, 1, CV_8UC1), col;
        ends.at<uint8_t>(0) = 255;
        ends.at<uint8_t>(1) = 0;
        cv::applyColorMap(ends, col, map);
        const int y_hi = first_row_with(bar, col.at<cv::Vec3b>(0));
        const int y_lo = first_row_with(bar, col.at<cv::Vec3b>(1));
        check(y_hi >= 0 && y_lo >= 0 && y_hi < y_lo,
              "the colour of the range's top is above its bottom's (rows " +
                  std::to_string(y_hi) + ", " + std::to_string(y_lo) + ")");
        // below the scale's frame (one row under its last colour row)
        const int y_none = first_row_with(bar, cv::Vec3b(0, 0, 0), y_lo + 2);
        check(y_none > y_lo + 2, "a black 'none' swatch below the scale");
    }
    // tiny pictures are padded to the bar's minimum height, not cut
    const cv::Mat small(20, 30, CV_8UC3, cv::Scalar(1, 2, 3));
    const cv::Mat out = negobs_cli::with_colour_bar(small, cv::COLORMAP_TURBO,
                                                    5, 5, "px");
    check(out.rows >= 48 && out.at<cv::Vec3b>(0, 0) == cv::Vec3b(1, 2, 3),
          "a 20-row picture is padded, an empty range does not fail");
    return failures ? 1 : 0;
}
