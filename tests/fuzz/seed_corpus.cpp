// Seed corpora for the fuzz targets, generated when the fuzzers run (never
// stored): real frames (the opencv-doc aloe pair; Middlebury Cones from
// $NEGOBS_DATA when present) and the project's own curb walk
// (tests/support/walk.h), cut to each target's input layout
// (tests/fuzz/fuzz_*.c). Real texture and real disparities let libFuzzer
// start inside the matcher's growing, DP and detection paths instead of
// having to find a matching pair by mutation.
//
//   seed_corpus OUTDIR   writes OUTDIR/{pipeline,core,rectify,pgm,image}/
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include <sys/stat.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../support/walk.h"

namespace {

struct Pair {
    std::string name;
    cv::Mat left, right; // CV_8UC1
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
        out.emplace_back("crop",
                         Pair{p.name, p.left(r).clone(), p.right(r).clone()});
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
    negobs_rig_t cam;
    negobs_rig_default(&cam, 320, 240);
    for (int f = 0; f < WALK_FRAMES; f += 6) {
        Pair p{"walk" + std::to_string(f), cv::Mat(240, 320, CV_8UC1),
               cv::Mat(240, 320, CV_8UC1)};
        if (walk_render(&cam, f, p.left.data, p.right.data) == 0) {
            pairs.push_back(p);
        }
    }
}

// Writes the seeds of every target for one pair; counts them in n.
class Writer {
public:
    explicit Writer(std::string out) : out_(std::move(out)) {}

    // fuzz_pipeline: w, h, shift, mode, max_disp, min_disp,
    // vertical_search, queue_capacity, band, left pixels, right pixels.
    // mode 4: the right image comes from the input; 1 auto range, 2 LR.
    void pipeline(const Pair &p)
    {
        const int sizes[][2] = {{96, 64}, {64, 48}, {48, 32}};
        for (int si = 0; si < 3; si++) {
            for (const auto &v : views(p, sizes[si][0], sizes[si][1])) {
                for (int mode : {4, 6, 5}) {
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
                    write("pipeline",
                          p.name + "-" + v.first + "-" + std::to_string(si) +
                              "-m" + std::to_string(mode),
                          b);
                }
            }
        }
    }

    // fuzz_core: width, height, stride, radius, NULL flag, pixels.
    void core(const Pair &p)
    {
        for (const auto &v : views(p, 64, 48)) {
            for (int r : {1, 4}) {
                Bytes b;
                put_range(b, 64, -2);
                put_range(b, 48, -2);
                put_range(b, 64, -2);
                put_range(b, r, -1);
                b.push_back(0);
                put_pixels(b, v.second.left);
                write("core",
                      p.name + "-" + v.first + "-r" + std::to_string(r), b);
            }
        }
    }

    // fuzz_rectify, well-formed-table mode: mode, w, h, 48x32 source
    // pixels, grid shift, f, baseline, then (x, y) of every node for the
    // left and right maps interleaved: the identity, and the right camera
    // 1.5 px off and rotated by about 0.5 deg, like a real rig. Mode 6
    // also corrupts one byte and patches the CRC.
    void rectify(const Pair &p)
    {
        const int shift = 3;
        const int gw = ((48 - 1) >> shift) + 2;
        const int gh = ((32 - 1) >> shift) + 2;
        for (const auto &v : views(p, 48, 32)) {
            for (int mode : {0, 6}) {
                Bytes b;
                b.push_back(static_cast<uint8_t>(mode));
                put_range(b, 48, 1);
                put_range(b, 32, 1);
                put_pixels(b, v.second.left);
                put_range(b, shift, 0);
                put_range(b, 250 * 256, 0); // f_q16 >> 8: 250 px
                put_range(b, 60000, 0);     // baseline (um)
                for (int k = 0; k < 2 * gw * gh; k++) {
                    const int node = k / 2;
                    const int x = ((node % gw) << shift) * 256;
                    const int y = ((node / gw) << shift) * 256;
                    const bool is_x = k % 2 == 0;
                    put_range(b, is_x ? x : y, -20000);
                    put_range(b, is_x ? x + 384 - y / 110 : y + x / 110,
                              -20000);
                }
                if (mode & 2) { // which byte to corrupt, and how
                    put_range(b, 40, 0);
                    b.push_back(4);
                }
                write("rectify",
                      p.name + "-" + v.first + "-m" + std::to_string(mode), b);
            }
        }
    }

    // fuzz_pgm and fuzz_image: real files, small enough to run fast.
    void files(const Pair &p)
    {
        for (const auto &v : views(p, 64, 48)) {
            std::vector<uint8_t> enc;
            for (const char *ext : {".pgm", ".png", ".jpg", ".bmp"}) {
                if (cv::imencode(ext, v.second.left, enc)) {
                    write(std::string(ext) == ".pgm" ? "pgm" : "image",
                          p.name + "-" + v.first + ext, enc);
                }
            }
        }
    }

    int count() const { return n_; }
    bool ok() const { return ok_; }

private:
    void write(const char *target, const std::string &name, const Bytes &b)
    {
        ok_ = save(out_ + "/" + target, name, b) && ok_;
        n_++;
    }

    std::string out_;
    int n_ = 0;
    bool ok_ = true;
};

} // namespace

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
    if (!load_pair(docdir + "/aloeL.jpg", docdir + "/aloeR.jpg", "aloe",
                   pairs)) {
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
    Writer wr(out);
    for (const Pair &p : pairs) {
        wr.pipeline(p);
        wr.core(p);
        wr.rectify(p);
        wr.files(p);
    }
    std::printf("seed_corpus: %d seeds from %zu pairs in %s\n", wr.count(),
                pairs.size(), out.c_str());
    return wr.ok() && !pairs.empty() ? 0 : 1;
}
