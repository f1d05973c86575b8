#include "profile_jump.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

double median_of(std::vector<double> v)
{
    if (v.empty()) {
        return NAN;
    }
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

double ground_px(const negobs_ground_plane_t &p, int u, int v)
{
    return (static_cast<double>(p.a_q20) * u + static_cast<double>(p.b_q20) * v +
            static_cast<double>(p.c_q20)) /
           1048576.0;
}

} // namespace

JumpStats profile_jump(const cv::Mat &disp, const negobs_ground_plane_t &plane, int u0,
                       int u1, int v0, int label_v, int window, int n)
{
    JumpStats js;
    if (disp.empty() || disp.type() != CV_16SC1 || u0 < 0 || u1 > disp.cols || u0 >= u1 ||
        n < 2) {
        return js;
    }
    v0 = std::max(v0, 0);
    const int rows = disp.rows;
    std::vector<double> prof(static_cast<size_t>(rows), NAN);
    std::vector<double> r;
    for (int v = v0; v < rows; ++v) {
        const int16_t *row = disp.ptr<int16_t>(v);
        r.clear();
        for (int u = u0; u < u1; ++u) {
            if (row[u] >= 0) {
                r.push_back(row[u] / 16.0 - ground_px(plane, u, v));
            }
        }
        if (2 * static_cast<int>(r.size()) > u1 - u0) {
            prof[static_cast<size_t>(v)] = median_of(r);
        }
    }
    std::vector<double> jump(static_cast<size_t>(rows), NAN);
    std::vector<double> all;
    for (int v = v0 + n; v + n < rows; ++v) {
        std::vector<double> nearer, farther;
        for (int k = 1; k <= n; ++k) {
            if (!std::isnan(prof[static_cast<size_t>(v + k)])) {
                nearer.push_back(prof[static_cast<size_t>(v + k)]);
            }
            if (!std::isnan(prof[static_cast<size_t>(v - k)])) {
                farther.push_back(prof[static_cast<size_t>(v - k)]);
            }
        }
        if (2 * static_cast<int>(nearer.size()) < n ||
            2 * static_cast<int>(farther.size()) < n) {
            continue;
        }
        jump[static_cast<size_t>(v)] = median_of(nearer) - median_of(farther);
        all.push_back(jump[static_cast<size_t>(v)]);
    }
    if (all.size() < 16) {
        return js;
    }
    const double mid = median_of(all);
    std::vector<double> dev;
    dev.reserve(all.size());
    for (double j : all) {
        dev.push_back(std::fabs(j - mid));
    }
    js.sigma = 1.4826 * median_of(dev);
    if (!(js.sigma > 0)) {
        return js;
    }
    js.ok = true;
    js.label_j = js.other_j = -1e9;
    for (int v = 0; v < rows; ++v) {
        const double j = jump[static_cast<size_t>(v)];
        if (std::isnan(j)) {
            continue;
        }
        if (label_v >= 0 && std::abs(v - label_v) <= window) {
            if (j > js.label_j) {
                js.label_j = j;
                js.label_v = v;
            }
        } else if (j > js.other_j) {
            js.other_j = j;
            js.other_v = v;
        }
    }
    if (js.label_v >= 0) {
        js.label_z = (js.label_j - mid) / js.sigma;
        const double g = ground_px(plane, (u0 + u1) / 2, js.label_v);
        js.label_rel = (g > 0) ? js.label_j / g : 0;
    } else {
        js.label_j = 0;
    }
    if (js.other_v >= 0) {
        js.other_z = (js.other_j - mid) / js.sigma;
    } else {
        js.other_j = 0;
    }
    return js;
}
