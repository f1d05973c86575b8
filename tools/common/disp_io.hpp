// Disparity maps in the file formats other stereo tools read and write:
//   png16  16-bit grey PNG, value = disparity * 16, 0 = no value
//          (OpenCV's StereoBM/SGBM fixed point; negobs_stereo's default)
//   kitti  16-bit grey PNG, value = disparity * 256, 0 = no value
//          (KITTI 2012/2015 devkit; largest disparity 255.996 px)
//   pfm    Portable Float Map, one channel ("Pf"), scale -1 = little
//          endian, rows stored bottom to top, +inf = no value
//          (Middlebury 2014 ground truth, SceneFlow)
// A disparity map in memory is a CV_32F map in pixels plus a CV_8U mask
// (255 = has a value).
#ifndef NEGOBS_TOOLS_DISP_IO_HPP
#define NEGOBS_TOOLS_DISP_IO_HPP

#include <string>

#include <opencv2/core.hpp>

namespace negobs_cli {

enum class DispFormat { Png16, Kitti, Pfm, Auto };

// "png16" / "kitti" / "pfm" (false for anything else).
bool parse_disp_format(const std::string &name, DispFormat &out);
const char *disp_format_name(DispFormat f);
// The largest disparity a format stores (png16 4095.9, kitti 255.996).
double disp_format_max(DispFormat f);

// Writes disp (CV_32F px) where valid != 0; disparities <= 0 are written
// as "no value" in the PNG formats (0 is their marker). A value above
// disp_format_max() is an error (err set), not a silent clip.
bool write_disparity(const std::string &path, const cv::Mat &disp,
                     const cv::Mat &valid, DispFormat f, std::string &err);

// Reads a map. Auto: .pfm -> pfm, otherwise an image OpenCV reads whose
// values are divided by scale (png16 = 16, kitti = 256, an 8-bit Middlebury
// GT = 1 or 4 ...; scale <= 0 takes the format's own). PNG value 0 and
// non-finite PFM values are "no value".
bool read_disparity(const std::string &path, DispFormat f, double scale,
                    cv::Mat &disp, cv::Mat &valid, std::string &err);

// PFM alone (one or three channels; three are averaged), for tests and
// tools that need the raw float image.
bool read_pfm(const std::string &path, cv::Mat &out, std::string &err);
bool write_pfm(const std::string &path, const cv::Mat &img_f32,
               std::string &err);

} // namespace negobs_cli

#endif
