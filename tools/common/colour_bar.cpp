#include "colour_bar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

namespace negobs_cli {

namespace {

// A tick step of 1, 2 or 5 x 10^k giving about `want` ticks over span.
double nice_step(double span, int want)
{
    const double raw = span / std::max(1, want);
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (const double m : {1.0, 2.0, 5.0, 10.0}) {
        if (m * p >= raw) {
            return m * p;
        }
    }
    return 10.0 * p;
}

} // namespace

cv::Mat colour_bar(int h, int colormap, double lo, double hi,
                   const std::string &unit)
{
    h = std::max(h, 48);
    if (!(hi > lo)) {
        hi = lo + 1.0;
    }
    // sizes follow the picture so labels stay legible on 240-row frames
    // and do not dominate 1000-row ones
    const double fs = std::clamp(h / 600.0, 0.33, 0.6);
    const int font = cv::FONT_HERSHEY_SIMPLEX;
    int base = 0;
    const cv::Size digit = cv::getTextSize("000", font, fs, 1, &base);
    const int pad = std::max(3, digit.height / 2);
    const int bar_w = std::max(10, digit.height + 4);
    const int swatch = bar_w;
    const int top = digit.height + 2 * pad;                 // unit label
    const int bottom = h - swatch - digit.height - 3 * pad; // "none"
    const int w = pad + bar_w + pad + digit.width + 2 * pad;
    cv::Mat out(h, w, CV_8UC3, cv::Scalar::all(255));
    if (bottom - top < 8) {
        return out;
    }
    // the gradient: row y shows the value its tick would read
    cv::Mat grey(bottom - top, 1, CV_8UC1);
    for (int y = 0; y < grey.rows; ++y) {
        const double f = 1.0 - double(y) / double(grey.rows - 1);
        grey.at<uint8_t>(y, 0) = cv::saturate_cast<uint8_t>(f * 255.0);
    }
    cv::Mat col;
    cv::applyColorMap(grey, col, colormap);
    cv::resize(col, col, cv::Size(bar_w, grey.rows), 0, 0, cv::INTER_NEAREST);
    col.copyTo(out(cv::Rect(pad, top, bar_w, grey.rows)));
    // the frame goes around the gradient, not over its end rows (they
    // hold the range's two ends)
    cv::rectangle(out, cv::Rect(pad - 1, top - 1, bar_w + 2, grey.rows + 2),
                  cv::Scalar::all(0), 1);
    const cv::Scalar ink(0, 0, 0);
    cv::putText(out, unit, cv::Point(pad, top - pad), font, fs, ink, 1,
                cv::LINE_AA);
    const double step = nice_step(hi - lo, std::max(2, grey.rows / 70));
    for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9; v += step) {
        const int y = top +
                      static_cast<int>(std::lround(
                          (1.0 - (v - lo) / (hi - lo)) * (grey.rows - 1)));
        cv::line(out, cv::Point(pad + bar_w, y), cv::Point(pad + bar_w + 3, y),
                 ink, 1);
        char txt[32];
        std::snprintf(txt, sizeof txt, "%g", v);
        cv::putText(out, txt, cv::Point(pad + bar_w + 5, y + digit.height / 2),
                    font, fs, ink, 1, cv::LINE_AA);
    }
    const int sy = bottom + pad;
    cv::rectangle(out, cv::Rect(pad, sy, bar_w, swatch), cv::Scalar::all(0),
                  cv::FILLED);
    cv::putText(out, "none", cv::Point(pad, sy + swatch + pad + digit.height),
                font, fs, ink, 1, cv::LINE_AA);
    return out;
}

cv::Mat with_colour_bar(const cv::Mat &picture, int colormap, double lo,
                        double hi, const std::string &unit)
{
    CV_Assert(picture.type() == CV_8UC3);
    cv::Mat bar = colour_bar(picture.rows, colormap, lo, hi, unit);
    if (bar.rows != picture.rows) {
        // a picture shorter than the bar's minimum: pad it
        cv::Mat p(bar.rows, picture.cols, CV_8UC3, cv::Scalar::all(255));
        picture.copyTo(p(cv::Rect(0, 0, picture.cols, picture.rows)));
        cv::Mat out;
        cv::hconcat(p, bar, out);
        return out;
    }
    cv::Mat out;
    cv::hconcat(picture, bar, out);
    return out;
}

} // namespace negobs_cli
