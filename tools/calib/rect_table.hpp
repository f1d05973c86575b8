// A negobs_calib rectification table applied on the host, with the
// library's own integer remap (the one negobs_run uses on the device), for
// negobs_png --calib and negobs_stereo --calib. Header-only: each tool
// includes it once.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

extern "C" {
#include "negobs/rectify.h"
}

namespace negobs_rect_tools {

class RectTable {
public:
    // Read and check the table (CRC, version, header); "" or the reason.
    std::string load(const std::string &path)
    {
        std::ifstream f(path, std::ios::binary);
        if (!f) {
            return "cannot read calibration table " + path;
        }
        table_.assign(std::istreambuf_iterator<char>(f),
                      std::istreambuf_iterator<char>());
        const negobs_status_t st = negobs_rectify_table_check(
            table_.data(), table_.size(), 0, 0, &info_);
        if (st != NEGOBS_OK) {
            return "calibration table " + path +
                   " refused: " + negobs_status_str(st);
        }
        crc_ = table_.size() >= 4
                   ? static_cast<uint32_t>(table_[table_.size() - 4]) |
                         static_cast<uint32_t>(table_[table_.size() - 3])
                             << 8 |
                         static_cast<uint32_t>(table_[table_.size() - 2])
                             << 16 |
                         static_cast<uint32_t>(table_[table_.size() - 1]) << 24
                   : 0u;
        negobs_rectify_config_default(&cfg_, info_.width, info_.height);
        cfg_.table = table_.data();
        cfg_.table_bytes = table_.size();
        size_t ws_bytes = 0;
        negobs_status_t s2 = negobs_rectify_workspace_size(&cfg_, &ws_bytes);
        if (s2 == NEGOBS_OK) {
            ws_.assign((ws_bytes + 15) / 16 + 1, Block{});
            s2 = negobs_rectify_init(&ctx_, &cfg_, ws_.data(), ws_bytes);
        }
        if (s2 != NEGOBS_OK) {
            return std::string("rectification set-up: ") +
                   negobs_status_str(s2);
        }
        return std::string();
    }

    // Rectify a grey pair in place; "" or the reason (e.g. another size).
    std::string apply(cv::Mat &left, cv::Mat &right)
    {
        if (left.cols != info_.width || left.rows != info_.height) {
            return "size mismatch: the calibration table is for " +
                   std::to_string(info_.width) + "x" +
                   std::to_string(info_.height) + ", the images are " +
                   std::to_string(left.cols) + "x" + std::to_string(left.rows);
        }
        cv::Mat ol(left.size(), CV_8UC1), orr(right.size(), CV_8UC1);
        negobs_image_u8_t il = view(left), ir = view(right), vl = view(ol),
                          vr = view(orr);
        const negobs_status_t st = negobs_rectify_process(&ctx_, &il, &ir, &vl,
                                                          &vr, nullptr);
        if (st != NEGOBS_OK) {
            return std::string("rectify: ") + negobs_status_str(st);
        }
        left = ol;
        right = orr;
        return std::string();
    }

    const negobs_rectify_info_t &info() const { return info_; }
    uint32_t crc32() const { return crc_; }
    double f_px() const { return info_.f_q16 / 65536.0; }
    double baseline_mm() const { return info_.baseline_um / 1000.0; }
    double cx() const { return info_.cx_q16 / 65536.0; }
    double cy() const { return info_.cy_q16 / 65536.0; }

private:
    struct alignas(16) Block {
        unsigned char b[16];
    };
    static negobs_image_u8_t view(cv::Mat &m)
    {
        negobs_image_u8_t v;
        v.data = m.data;
        v.width = m.cols;
        v.height = m.rows;
        v.stride = static_cast<int32_t>(m.step[0]);
        return v;
    }
    std::vector<uint8_t> table_;
    std::vector<Block> ws_;
    negobs_rectify_info_t info_ = {};
    negobs_rectify_config_t cfg_ = {};
    negobs_rectify_t ctx_ = {};
    uint32_t crc_ = 0;
};

} // namespace negobs_rect_tools
