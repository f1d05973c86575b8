/*
 * libcamera discovery for negobs_run --list-cameras: each camera's id,
 * model and the formats and sizes of a video-recording stream (the role the source opens), as `cam -l`
 * and `cam -I` print them, each format marked usable or not by
 * negobs_libcamera_format_rank(). Runs alone (before any libcamera
 * source is open), so it has its own camera manager.
 */
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

#include <libcamera/libcamera.h>

#include "negobs_port/camera_libcamera.h"
#include "negobs_port/camera_list.h"

namespace {

int list_impl(FILE *out)
{
    using namespace libcamera;
    /* The listing is the output; libcamera's INFO/WARN lines (version,
     * missing IPA modules) would bury it. LIBCAMERA_LOG_LEVELS, when
     * set, still rules. */
    (void)setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0);
    logSetLevel("*", "ERROR");
    CameraManager cm;
    int rc = cm.start();
    if (rc != 0) {
        std::fprintf(out, "libcamera: camera manager did not start (%d)\n",
                     rc);
        return -1;
    }
    int usable = 0;
    auto cams = cm.cameras();
    if (cams.empty()) {
        std::fprintf(out, "libcamera: no cameras\n");
    }
    int index = 0;
    for (const std::shared_ptr<Camera> &cam : cams) {
        std::optional<std::string> model = cam->properties().get(
            properties::Model);
        std::fprintf(out, "libcamera:%d: '%s' (%s)\n", index,
                     cam->id().c_str(), model ? model->c_str() : "no model");
        index++;
        std::unique_ptr<CameraConfiguration> cfg = cam->generateConfiguration(
            {StreamRole::VideoRecording});
        if (!cfg || cfg->size() == 0) {
            std::fprintf(out, "    nothing usable: no video stream\n");
            continue;
        }
        const StreamFormats &formats = cfg->at(0).formats();
        int ok = 0;
        for (const PixelFormat &pf : formats.pixelformats()) {
            bool use = negobs_libcamera_format_rank(pf.fourcc()) >= 0;
            ok += use ? 1 : 0;
            std::fprintf(out, "    %s %s:", pf.toString().c_str(),
                         use ? "usable" : "not usable");
            for (const Size &s : formats.sizes(pf)) {
                std::fprintf(out, " %ux%u", s.width, s.height);
            }
            if (formats.sizes(pf).empty()) {
                std::fprintf(out, " %s", formats.range(pf).toString().c_str());
            }
            std::fputc('\n', out);
        }
        if (ok == 0) {
            std::fprintf(out, "    nothing usable: no format with a luma "
                              "plane, packed YUV or RGB (raw Bayer needs "
                              "an ISP)\n");
        }
        usable += ok > 0 ? 1 : 0;
    }
    cams.clear(); /* no reference may outlive the manager's stop */
    cm.stop();
    return usable;
}

} // namespace

extern "C" int negobs_libcamera_list(FILE *out)
{
    try {
        return list_impl(out);
    } catch (const std::exception &e) {
        std::fprintf(out, "libcamera: %s\n", e.what());
    } catch (...) {
        std::fprintf(out, "libcamera: unknown error\n");
    }
    return -1;
}
