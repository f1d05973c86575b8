// Seed corpora for the fuzz targets, generated when the fuzzers run (never
// stored): real frames (the opencv-doc aloe pair; Middlebury Cones from
// $NEGOBS_DATA when present) and the project's own curb walk
// (tests/digest/walk.h), cut to each target's input layout
// (tests/fuzz/fuzz_*.c). Real texture and real disparities let libFuzzer
// start inside the matcher's growing, DP and detection paths instead of
// having to find a matching pair by mutation.
//
//   seed_corpus OUTDIR   writes OUTDIR/{pipeline,core,rectify,pgm,image}/
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <sys/stat.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../digest/walk.h"

namespace {

struct Pair {
    std::string name;
    cv::Mat left, right;  // CV_8UC1
};

using Bytes = std::vector<uint8_t>;

// fuzz_range(lo, hi) reads lo + u16 % (hi - lo + 1): store value - lo.
void put_range(Bytes &b, int value, int lo)
{
    unsigned v = static_cast<unsigned>(value - lo);
    b.push_back(static_cast<uint8_t>(v & 255u));
    b.push_back(static_cast<uint8_t>(v >> 8));
}

void put_pixels(Bytes &b, const cv::Mat &m)
{
    for (int y = 0; y < m.rows; y++) {
        b.insert(b.end(), m.ptr<uint8_t>(y), m.ptr<uint8_t>(y) + m.cols);
    }
}

bool save(const std::string &dir, const std::string &name, const Bytes &b)
{
    std::string path = dir + "/" + name;
    FILE *f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        std::fprintf(stderr, "seed_corpus: cannot write %s\n", path.c_str());
        return false;
    }
    bool ok = std::fwrite(b.data(), 1, b.size(), f) == b.size();
    return std::fclose(f) == 0 && ok;
}

// A pair at w x h: the whole view scaled (INTER_AREA keeps the texture
// honest) and a native-resolution crop of its centre.
std::vector<std::pair<std::string, Pair>> views(const Pair &p, int w, int h)
{
    std::vector<std::pair<std::string, Pair>> out;
    Pair s{p.name, {}, {}};
    cv::resize(p.left, s.left, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    cv::resize(p.right, s.right, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    out.emplace_back("scaled", s);
    if (p.left.cols >= w && p.left.rows >= h) {
        cv::Rect r((p.left.cols - w) / 2, (p.left.rows - h) * 2 / 3, w, h);
        out.emplace_back("crop", Pair{p.name, p.left(r).clone(), p.right(r).clone()});
    }
    return out;
}

bool load_pair(const std::string &l, const std::string &r, const char *name,
               std::vector<Pair> &pairs)
{
    Pair p{name, cv::imread(l, cv::IMREAD_GRAYSCALE),
           cv::imread(r, cv::IMREAD_GRAYSCALE)};
    if (p.left.empty() || p.right.empty() || p.left.size() != p.right.size()) {
        return false;
    }
    pairs.push_back(p);
    return true;
}

void walk_pairs(std::vector<Pair> &pairs)
{
    negobs_camera_t cam;
    negobs_camera_default(&cam, 320, 240);
    for (int f = 0; f < WALK_FRAMES; f += 6) {
        Pair p{"walk" + std::to_string(f), cv::Mat(240, 320, CV_8UC1),
               cv::Mat(240, 320, CV_8UC1)};
        if (walk_render(&cam, f, p.left.data, p.right.data) == 0) {
            pairs.push_back(p);
        }
    }
}

}  // namespace

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    std::string out = argv[1];
    std::vector<Pair> pairs;
    const char *doc = std::getenv("OPENCV_DOC");
    std::string docdir = doc ? doc : "/usr/share/doc/opencv-doc/examples/data";
    if (!load_pair(docdir + "/aloeL.jpg", docdir + "/aloeR.jpg", "aloe", pairs)) {
        std::fprintf(stderr, "seed_corpus: no aloe pair in %s (opencv-doc)\n",
                     docdir.c_str());
    }
    if (const char *data = std::getenv("NEGOBS_DATA")) {
        std::string c = std::string(data) + "/middlebury/cones/";
        load_pair(c + "im2.png", c + "im6.png", "cones", pairs);
    }
    walk_pairs(pairs);

    const char *targets[] = {"pipeline", "core", "rectify", "pgm", "image"};
    mkdir(out.c_str(), 0755);
    for (const char *t : targets) {
        mkdir((out + "/" + t).c_str(), 0755);
    }
    int n = 0;
    bool ok = true;
    for (const Pair &p : pairs) {
        // fuzz_pipeline: w, h, shift, mode, max_disp, min_disp,
        // vertical_search, queue_capacity, band, left pixels, right pixels.
        // mode 4: the right image comes from the input; 1 auto range, 2 LR.
        const int sizes[][2] = {{96, 64}, {64, 48}, {48, 32}};
        const int modes[] = {4, 6, 5};
        for (int si = 0; si < 3; si++) {
            for (const auto &v : views(p, sizes[si][0], sizes[si][1])) {
                for (int mode : modes) {
                    Bytes b;
                    put_range(b, v.second.left.cols, 8);
                    put_range(b, v.second.left.rows, 8);
                    put_range(b, 0, 0);
                    b.push_back(static_cast<uint8_t>(mode));
                    put_range(b, si == 0 ? 31 : 15, -2);
                    put_range(b, 0, -2);
                    put_range(b, 1, -1);
                    put_range(b, 512, 0);
                    put_range(b, 2, 0);
                    put_pixels(b, v.second.left);
                    put_pixels(b, v.second.right);
                    ok &= save(out + "/pipeline",
                               p.name + "-" + v.first + "-" + std::to_string(si) +
                                   "-m" + std::to_string(mode),
                               b);
                    n++;
                }
            }
        }
        // fuzz_core: width, height, stride, radius, NULL flag, pixels.
        for (const auto &v : views(p, 64, 48)) {
            for (int r = 1; r <= 4; r += 3) {
                Bytes b;
                put_range(b, 64, -2);
                put_range(b, 48, -2);
                put_range(b, 64, -2);
                put_range(b, r, -1);
                b.push_back(0);
                put_pixels(b, v.second.left);
                ok &= save(out + "/core", p.name + "-" + v.first + "-r" + std::to_string(r), b);
                n++;
            }
        }
        // fuzz_rectify, well-formed-table mode: mode, w, h, 48x32 source
        // pixels, grid shift, f, baseline, then (x, y) of every node for
        // the left and right maps interleaved: the identity, the right
        // camera 1.5 px off and rotated by about 0.5 deg, like a real rig.
        for (const auto &v : views(p, 48, 32)) {
            for (int mode : {0, 6}) {
                Bytes b;
                const int shift = 3;
                const int gw = ((48 - 1) >> shift) + 2;
                const int gh = ((32 - 1) >> shift) + 2;
                b.push_back(static_cast<uint8_t>(mode));
                put_range(b, 48, 1);
                put_range(b, 32, 1);
                put_pixels(b, v.second.left);
                put_range(b, shift, 0);
                put_range(b, 250 * 256, 0);
                put_range(b, 60000, 0);
                for (int k = 0; k < 2 * gw * gh; k++) {
                    int node = k / 2;
                    int i = node % gw;
                    int j = node / gw;
                    int x = (i << shift) * 256;
                    int y = (j << shift) * 256;
                    int lv = (k % 2 == 0) ? x : y;
                    int rv = (k % 2 == 0) ? x + 384 - y / 110 : y + x / 110;
                    put_range(b, lv, -20000);
                    put_range(b, rv, -20000);
                }
                if (mode & 2) {  // which byte to corrupt, and how
                    put_range(b, 40, 0);
                    b.push_back(4);
                }
                ok &= save(out + "/rectify", p.name + "-" + v.first + "-m" + std::to_string(mode), b);
                n++;
            }
        }
        // fuzz_pgm and fuzz_image: real files, small enough to run fast.
        for (const auto &v : views(p, 64, 48)) {
            std::vector<uint8_t> enc;
            if (cv::imencode(".pgm", v.second.left, enc)) {
                ok &= save(out + "/pgm", p.name + "-" + v.first + ".pgm", enc);
                n++;
            }
            for (const char *ext : {".png", ".jpg", ".bmp"}) {
                if (cv::imencode(ext, v.second.left, enc)) {
                    ok &= save(out + "/image", p.name + "-" + v.first + ext, enc);
                    n++;
                }
            }
        }
    }
    std::printf("seed_corpus: %d seeds from %zu pairs in %s\n", n, pairs.size(),
                out.c_str());
    return ok && !pairs.empty() ? 0 : 1;
}
