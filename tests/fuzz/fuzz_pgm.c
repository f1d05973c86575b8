/*
 * Fuzz target: the replay reader's PGM parser (port/camera/replay) on
 * arbitrary file contents, through a real file as the runtime reads it.
 * Invariant: an accepted image fits the buffer and has a legal size.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "fuzz_input.h"
#include "negobs_port/camera_replay.h"

static uint8_t img[64 * 1024];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[64];
    FILE *f;
    int32_t w = -1;
    int32_t h = -1;
    char err[128];

    if (path[0] == '\0') {
        snprintf(path, sizeof path, "/tmp/negobs-fuzz-pgm-%ld.pgm",
                 (long)getpid());
    }
    f = fopen(path, "wb");
    if (f == NULL) {
        return 0;
    }
    if (size > 0 && fwrite(data, 1, size, f) != size) {
        fclose(f);
        return 0;
    }
    fclose(f);
    if (negobs_pgm_read(path, img, sizeof img, &w, &h, err, sizeof err) ==
        NEGOBS_OK) {
        if (w < 1 || h < 1 || (size_t)w * (size_t)h > sizeof img) {
            abort();
        }
    }
    return 0;
}
