// nonocc_from_right_gt on a generated scene whose occlusion is known
// exactly, and right_gt_path on Middlebury's file naming.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

#include <opencv2/core.hpp>

#include "occlusion.hpp"

namespace {

int failures = 0;

void check(bool c, const char *what)
{
    std::printf("%s: %s\n", c ? "ok" : "FAIL", what);
    failures += c ? 0 : 1;
}

// Background at 5 px, a box at 15 px over columns [40, 60) of rows [10,
// 30). The right view's GT is the left one forward-warped (nearest wins).
void make_scene(cv::Mat &gl, cv::Mat &kl, cv::Mat &gr, cv::Mat &kr)
{
    const int w = 100, h = 40;
    gl = cv::Mat(h, w, CV_32F, cv::Scalar(5.0f));
    gl(cv::Rect(40, 10, 20, 20)).setTo(15.0f);
    kl = cv::Mat(h, w, CV_8U, cv::Scalar(1));
    gr = cv::Mat(h, w, CV_32F, cv::Scalar(-1.0f));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float d = gl.at<float>(y, x);
            const int xr = x - static_cast<int>(d);
            if (xr >= 0 && d > gr.at<float>(y, xr)) {
                gr.at<float>(y, xr) = d;
            }
        }
    }
    kr = gr >= 0.0f;
}

void touch(const std::string &p)
{
    std::ofstream(p) << "x";
}

} // namespace

int main()
{
    cv::Mat gl, kl, gr, kr;
    make_scene(gl, kl, gr, kr);
    cv::Mat m = negobs_tools::nonocc_from_right_gt(gl, kl, gr, kr);
    check(!m.empty() && m.type() == CV_8U, "a mask comes back");
    if (!m.empty()) {
        // box rows: background columns 30..39 are hidden by the box in the
        // right view (as wide as the 10 px step) and 0..4 have no right
        // pixel; other rows lose only the border strip
        check(cv::countNonZero(m.row(20)) == 100 - 10 - 5,
              "a box row loses the 10 px occlusion and the 5 px border");
        check(cv::countNonZero(m.row(20).colRange(30, 40)) == 0,
              "the occluded run left of the box is masked");
        check(cv::countNonZero(m.row(20).colRange(40, 60)) == 20,
              "the box itself is visible");
        check(cv::countNonZero(m.row(0)) == 95,
              "a background row loses only its border strip");
        // unknown right GT or a left GT unknown: not counted as visible
        cv::Mat kr2 = kr.clone();
        kr2.row(0).setTo(0);
        kl.at<uint8_t>(1, 50) = 0;
        cv::Mat m2 = negobs_tools::nonocc_from_right_gt(gl, kl, gr, kr2);
        check(cv::countNonZero(m2.row(0)) == 0 && m2.at<uint8_t>(1, 50) == 0,
              "unknown GT on either side is not non-occluded");
        // a right GT off by 2 px is inconsistent at tol 1, consistent at 2
        cv::Mat gr3 = gr + 2.0f;
        check(cv::countNonZero(
                  negobs_tools::nonocc_from_right_gt(gl, kl, gr3, kr)) == 0,
              "a right GT 2 px off matches nothing at 1 px tolerance");
        check(cv::countNonZero(negobs_tools::nonocc_from_right_gt(
                  gl, kl, gr3, kr, 2.0)) > 0,
              "... and matches at 2 px");
    }
    check(negobs_tools::nonocc_from_right_gt(gl, kl, gr.colRange(0, 50), kr)
              .empty(),
          "size mismatch: empty");
    check(negobs_tools::nonocc_from_right_gt(gl, kl, kr, kr).empty(),
          "wrong type: empty");

    char tmpl[] = "/tmp/negobs-occl-XXXXXX";
    const char *dir = mkdtemp(tmpl);
    check(dir != nullptr, "temporary folder");
    if (dir != nullptr) {
        const std::string d = std::string(dir) + "/";
        for (const char *f :
             {"view1.png", "view5.png", "disp1.png", "disp5.png", "im2.ppm",
              "im6.ppm", "disp2.pgm", "disp6.pgm", "aloeL.jpg", "aloeR.jpg",
              "aloeGT.png", "a3.png", "b4.png", "gt3.png"}) {
            touch(d + f);
        }
        using negobs_tools::right_gt_path;
        check(right_gt_path(d + "view1.png", d + "view5.png",
                            d + "disp1.png") == d + "disp5.png",
              "2006 naming: disp1 -> disp5");
        check(right_gt_path(d + "im2.ppm", d + "im6.ppm", d + "disp2.pgm") ==
                  d + "disp6.pgm",
              "2001 naming: disp2.pgm -> disp6.pgm");
        check(right_gt_path(d + "aloeL.jpg", d + "aloeR.jpg", d + "aloeGT.png")
                  .empty(),
              "no view numbers: none");
        check(right_gt_path(d + "a3.png", d + "b4.png", d + "gt3.png").empty(),
              "the right GT file is absent: none");
        check(right_gt_path(d + "view1.png", d + "view1.png", d + "disp1.png")
                  .empty(),
              "the same view twice: none");
        for (const char *f :
             {"view1.png", "view5.png", "disp1.png", "disp5.png", "im2.ppm",
              "im6.ppm", "disp2.pgm", "disp6.pgm", "aloeL.jpg", "aloeR.jpg",
              "aloeGT.png", "a3.png", "b4.png", "gt3.png"}) {
            std::remove((d + f).c_str());
        }
        rmdir(dir);
    }
    std::printf("%d failure(s)\n", failures);
    return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
