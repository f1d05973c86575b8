#include "calib_common.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace negobs_calib {

bool file_exists(const std::string &path)
{
    std::ifstream f(path, std::ios::binary);
    return f.good();
}

static std::string dir_of(const std::string &path)
{
    const auto slash = path.find_last_of('/');
    return (slash == std::string::npos) ? std::string(".")
                                        : path.substr(0, slash);
}

bool read_image_list(const std::string &path, std::vector<ImagePair> &pairs,
                     std::string &err)
{
    pairs.clear();
    if (!file_exists(path)) {
        err = "image list not found: " + path;
        return false;
    }
    cv::FileStorage fs;
    try {
        if (!fs.open(path, cv::FileStorage::READ)) {
            err = "cannot parse image list: " + path;
            return false;
        }
    } catch (const cv::Exception &e) {
        err = "cannot parse image list " + path + ": " + e.what();
        return false;
    }
    cv::FileNode n = fs["imagelist"];
    if (n.empty()) {
        n = fs.getFirstTopLevelNode();
    }
    if (n.type() != cv::FileNode::SEQ) {
        err = path + ": no sequence of image names (expected <imagelist>)";
        return false;
    }
    std::vector<std::string> names;
    for (cv::FileNodeIterator it = n.begin(); it != n.end(); ++it) {
        names.push_back(static_cast<std::string>(*it));
    }
    if (names.empty() || names.size() % 2 != 0) {
        err = path +
              ": need an even, non-zero number of names (left, "
              "right, left, right, ...), got " +
              std::to_string(names.size());
        return false;
    }
    const std::string dir = dir_of(path);
    for (auto &s : names) {
        if (!s.empty() && s[0] != '/') {
            s = dir + "/" + s;
        }
    }
    for (size_t i = 0; i < names.size(); i += 2) {
        pairs.push_back({names[i], names[i + 1]});
    }
    return true;
}

bool parse_size(const std::string &text, cv::Size &size)
{
    int a = 0;
    int b = 0;
    char x = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &a, &x, &b, &extra) != 3 ||
        (x != 'x' && x != 'X') || a < 2 || b < 2 || a > 100000 || b > 100000) {
        return false;
    }
    size = cv::Size(a, b);
    return true;
}

bool find_corners(const cv::Mat &grey, cv::Size board,
                  std::vector<cv::Point2f> &corners)
{
    corners.clear();
    const bool found = cv::findChessboardCorners(
        grey, board, corners,
        cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
    if (!found) {
        return false;
    }
    cv::cornerSubPix(
        grey, corners, cv::Size(11, 11), cv::Size(-1, -1),
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30,
                         0.01));
    return true;
}

bool read_file(const std::string &path, std::vector<uint8_t> &bytes,
               std::string &err)
{
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        err = "cannot open " + path;
        return false;
    }
    bytes.assign(std::istreambuf_iterator<char>(f),
                 std::istreambuf_iterator<char>());
    return true;
}

bool write_file(const std::string &path, const std::vector<uint8_t> &bytes,
                std::string &err)
{
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) {
        err = "cannot create " + path;
        return false;
    }
    f.write(reinterpret_cast<const char *>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
    if (!f) {
        err = "write failed: " + path;
        return false;
    }
    return true;
}

} // namespace negobs_calib
