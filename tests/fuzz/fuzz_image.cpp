// Fuzz target: the host tools' image input. negobs_stereo and negobs_eval
// read every image through negobs_tools::load_grey() (tools/stereo/
// stereo_common.cpp: cv::imread, 16-bit scaling, channel checks, grey
// conversion); here it gets arbitrary file contents through a real file,
// as the tools read them.
//
// Invariant: either false with a message, or a continuous CV_8UC1 image
// of the size cv::imdecode reports for the same bytes (when it decodes
// them), accepted by negobs_image_u8_check exactly when it is within the
// library's NEGOBS_MAX_DIM limit the tools check next.
//
// Random bytes almost never form an image header, so the target brings a
// small generated seed corpus (seeds.hpp: PNG, PGM/PPM, BMP, JPEG, TIFF of
// 1, 3 and 4 channels, 8 and 16 bits, odd sizes): with libFuzzer it is
// written to a temporary folder added to the corpus folders at start;
// without libFuzzer (fuzz_image_replay.cpp) the seeds, their truncations
// and bit flips are the plain test's inputs.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "fuzz_image_seeds.hpp"
#include "stereo_common.hpp"

extern "C" {
#include "negobs/image.h"
}

namespace {

// Decoders believe the sizes in headers; the defaults let a 60-byte file
// ask for a gigapixel. The tools keep OpenCV's defaults (their inputs are
// the user's own files); the fuzzer caps it so that a memory limit hit is
// a finding of ours, not a decoder allocating what it was told to. OpenCV
// 4.6 reads the size caps (OPENCV_IO_MAX_IMAGE_PIXELS, _WIDTH, _HEIGHT)
// into statics when libopencv_imgcodecs loads, before this code runs, so
// they are set by the runner (tools/negobs fuzz_run); a setenv here would
// be too late. What is set here is read on first use: no OpenEXR, and no
// decoder complaints in the log.
void quiet_decoders()
{
    setenv("OPENCV_IO_ENABLE_OPENEXR", "0", 0);
    setenv("OPENCV_LOG_LEVEL", "SILENT", 0); // decoders' complaints
}

void remove_scratch();

std::string &scratch_path()
{
    static std::string p;
    if (p.empty()) {
        // No extension: imread picks the decoder from the content.
        p = "/tmp/negobs-fuzz-image-" + std::to_string(getpid());
        std::atexit(remove_scratch);
    }
    return p;
}

void remove_scratch()
{
    (void)unlink(scratch_path().c_str());
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    quiet_decoders();
    const std::string &path = scratch_path();
    FILE *f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        return 0;
    }
    if (size > 0 && std::fwrite(data, 1, size, f) != size) {
        std::fclose(f);
        return 0;
    }
    std::fclose(f);

    cv::Mat grey;
    std::string err;
    bool ok = negobs_tools::load_grey(path, grey, err);
    if (!ok) {
        if (err.empty()) {
            std::fprintf(stderr, "load_grey failed without a message\n");
            std::abort();
        }
        return 0;
    }
    if (!err.empty() || grey.empty() || grey.type() != CV_8UC1 ||
        !grey.isContinuous() || grey.dims != 2) {
        std::fprintf(stderr,
                     "load_grey accepted a bad image: type %d, "
                     "%dx%d, continuous %d, err '%s'\n",
                     grey.type(), grey.cols, grey.rows,
                     grey.isContinuous() ? 1 : 0, err.c_str());
        std::abort();
    }
    // The size is the one the decoder reports for these bytes. OpenCV's
    // file and memory paths do not always agree on damaged data (the first
    // fuzz run found a corrupt JPEG that imread recovers as 16x8 and
    // imdecode refuses): sizes are compared when both decode.
    std::vector<uint8_t> bytes(data, data + size);
    cv::Mat raw = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
    if (!raw.empty() && (raw.cols != grey.cols || raw.rows != grey.rows)) {
        std::fprintf(stderr, "size %dx%d differs from the decoder's %dx%d\n",
                     grey.cols, grey.rows, raw.cols, raw.rows);
        std::abort();
    }
    // What the tools hand to the library next: a legal negobs image, or a
    // size the library refuses (they check it before).
    negobs_image_u8_t img;
    img.data = grey.data;
    img.width = grey.cols;
    img.height = grey.rows;
    img.stride = grey.cols;
    negobs_status_t st = negobs_image_u8_check(&img);
    bool legal = grey.cols <= NEGOBS_MAX_DIM && grey.rows <= NEGOBS_MAX_DIM;
    if ((st == NEGOBS_OK) != legal) {
        std::fprintf(stderr, "negobs_image_u8_check %d for %dx%d\n", st,
                     grey.cols, grey.rows);
        std::abort();
    }
    // Touch both ends of every row: a short buffer shows up under ASan.
    // (Not every pixel: a header may ask for 16 M of them, and an
    // instrumented loop over that took more than libFuzzer's 10 s in the
    // second run, a timeout of this check, not of the loader.)
    unsigned sum = 0;
    for (int y = 0; y < grey.rows; y++) {
        const uint8_t *row = grey.ptr<uint8_t>(y);
        sum += row[0] + row[grey.cols - 1];
    }
    return sum == 0xFFFFFFFFu ? 1 : 0;
}

#ifdef NEGOBS_FUZZ_LIBFUZZER
// libFuzzer calls this once before fuzzing: write the generated seeds to a
// temporary folder and add it to the corpus folders on the command line.
extern "C" int LLVMFuzzerInitialize(int *argc, char ***argv);

extern "C" int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    static std::vector<char *> args;
    static std::string dir;
    quiet_decoders();
    // Files on the command line mean "run these" (reproducing a finding):
    // then no corpus folder may be added.
    for (int i = 1; i < *argc; i++) {
        struct stat sb;
        if ((*argv)[i][0] != '-' && stat((*argv)[i], &sb) == 0 &&
            S_ISREG(sb.st_mode)) {
            return 0;
        }
    }
    dir = "/tmp/negobs-fuzz-image-seeds-" + std::to_string(getpid());
    if (!negobs_fuzz::write_image_seeds(dir)) {
        return 0;
    }
    args.assign(*argv, *argv + *argc);
    args.push_back(&dir[0]);
    args.push_back(nullptr);
    *argc = static_cast<int>(args.size()) - 1;
    *argv = args.data();
    return 0;
}
#endif
