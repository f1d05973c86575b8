// profile_jump on generated disparity maps: a drop stands out of row noise,
// a flat map has no outstanding jump, and bad input gives ok = false.
#include <cstdio>
#include <cstdlib>

#include <opencv2/core.hpp>

#include "profile_jump.hpp"

namespace {

int failures = 0;

void check(bool c, const char *what)
{
    std::printf("%s: %s\n", c ? "ok" : "FAIL", what);
    failures += c ? 0 : 1;
}

// Ground d = 2 + v / 40 px; rows above drop_v read `drop_px` lower; each
// pixel gets uniform noise of +-noise_px, each row an offset of +-row_px
// (the row-correlated part).
cv::Mat make_map(int drop_v, double drop_px, double noise_px, double row_px,
                 unsigned seed)
{
    cv::Mat d(240, 320, CV_16SC1);
    cv::RNG rng(seed);
    for (int v = 0; v < d.rows; ++v) {
        const double ro = rng.uniform(-row_px, row_px);
        for (int u = 0; u < d.cols; ++u) {
            double x = 2.0 + v / 40.0 + ro + rng.uniform(-noise_px, noise_px);
            if (v < drop_v) {
                x -= drop_px;
            }
            d.at<int16_t>(v, u) = static_cast<int16_t>(cvRound(x * 16));
        }
    }
    return d;
}

} // namespace

int main()
{
    negobs_ground_plane_t plane{0, 1048576 / 40, 2 * 1048576};

    JumpStats a = profile_jump(make_map(150, 0.8, 0.3, 0.05, 1), plane, 80, 240, 60, 150);
    check(a.ok, "drop: measured");
    check(a.label_v >= 145 && a.label_v <= 155, "drop: jump found at the edge row");
    check(a.label_j > 0.6 && a.label_j < 1.0, "drop: jump close to the 0.8 px drop");
    check(a.label_z > 5 && a.label_j > a.other_j, "drop: separable");

    JumpStats b = profile_jump(make_map(150, 0.8, 0.3, 0.6, 2), plane, 80, 240, 60, 150);
    check(b.ok && b.sigma > 2 * a.sigma, "row noise raises the jump spread");
    check(b.label_z < a.label_z, "row noise lowers the separability");

    JumpStats c = profile_jump(make_map(-1, 0, 0.3, 0.05, 3), plane, 80, 240, 60, 150);
    check(c.ok && c.label_z < 3 && c.other_z < 5, "flat map: nothing stands out");

    JumpStats e = profile_jump(cv::Mat(), plane, 0, 10, 0, 5);
    check(!e.ok, "empty map: not ok");
    JumpStats f = profile_jump(make_map(150, 0.8, 0.3, 0.05, 1), plane, 200, 100, 0, 150);
    check(!f.ok, "bad column range: not ok");
    cv::Mat inv(240, 320, CV_16SC1, cv::Scalar(-32768));
    check(!profile_jump(inv, plane, 80, 240, 60, 150).ok, "no valid pixel: not ok");

    std::printf("%d failed\n", failures);
    return failures == 0 ? 0 : 1;
}
