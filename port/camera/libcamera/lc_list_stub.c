/* libcamera discovery in a build without libcamera. */
#include "negobs_port/camera_list.h"

int negobs_libcamera_list(FILE *out)
{
    fprintf(out, "libcamera: not in this build (libcamera-dev not found "
                 "or -Dlibcamera=disabled)\n");
    return -1;
}
