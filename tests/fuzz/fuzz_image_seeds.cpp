#include "fuzz_image_seeds.hpp"

#include <cstdio>

#include <sys/stat.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace negobs_fuzz {

namespace {

// A textured test card: gradients plus a checker, per channel.
cv::Mat card(int w, int h, int type)
{
    cv::Mat m(h, w, type);
    int ch = m.channels();
    bool wide = m.depth() == CV_16U;
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            for (int c = 0; c < ch; c++) {
                int v = (x * 5 + y * 3 + c * 60 + ((x / 4 + y / 4) % 2) * 90) &
                        255;
                if (wide) {
                    m.ptr<uint16_t>(y)[x * ch + c] = static_cast<uint16_t>(
                        v * 257);
                } else {
                    m.ptr<uint8_t>(y)[x * ch + c] = static_cast<uint8_t>(v);
                }
            }
        }
    }
    return m;
}

} // namespace

std::vector<std::vector<uint8_t>> image_seeds()
{
    struct Spec {
        const char *ext;
        int w, h, type;
    };
    static const Spec specs[] = {
        {".png", 7, 5, CV_8UC1},  {".png", 9, 3, CV_8UC3},
        {".png", 5, 4, CV_8UC4},  {".png", 6, 6, CV_16UC1},
        {".png", 3, 7, CV_16UC3}, {".pgm", 11, 3, CV_8UC1},
        {".pgm", 4, 4, CV_16UC1}, {".ppm", 5, 5, CV_8UC3},
        {".bmp", 7, 3, CV_8UC1},  {".bmp", 5, 2, CV_8UC3},
        {".jpg", 16, 8, CV_8UC1}, {".jpg", 9, 9, CV_8UC3},
        {".tiff", 4, 3, CV_8UC1}, {".tiff", 3, 3, CV_16UC1},
        {".png", 1, 1, CV_8UC1},
    };
    std::vector<std::vector<uint8_t>> out;
    for (const Spec &s : specs) {
        std::vector<uint8_t> buf;
        try {
            if (cv::imencode(s.ext, card(s.w, s.h, s.type), buf)) {
                out.push_back(buf);
            }
        } catch (const cv::Exception &) {
            // a codec this OpenCV build lacks: no seed of that kind
        }
    }
    // A plain-text PGM written by hand (OpenCV writes binary ones).
    static const char ascii_pgm[] = "P2\n3 2\n255\n0 128 255\n255 128 0\n";
    out.emplace_back(ascii_pgm, ascii_pgm + sizeof ascii_pgm - 1);
    return out;
}

bool write_image_seeds(const std::string &dir)
{
    if (mkdir(dir.c_str(), 0700) != 0) {
        return false;
    }
    std::vector<std::vector<uint8_t>> seeds = image_seeds();
    for (size_t i = 0; i < seeds.size(); i++) {
        char name[32];
        std::snprintf(name, sizeof name, "/seed_%02u",
                      static_cast<unsigned>(i));
        FILE *f = std::fopen((dir + name).c_str(), "wb");
        if (f == nullptr) {
            return false;
        }
        bool ok = std::fwrite(seeds[i].data(), 1, seeds[i].size(), f) ==
                  seeds[i].size();
        std::fclose(f);
        if (!ok) {
            return false;
        }
    }
    return true;
}

} // namespace negobs_fuzz
