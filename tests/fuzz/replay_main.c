/*
 * Driver for builds without libFuzzer: runs a target on the files named on
 * the command line, or, with no arguments, on a fixed set of generated
 * inputs (deterministic, same on every target), so every fuzz target is
 * also a plain test under ASan/UBSan and qemu.
 */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_input.h"

#define GENERATED 400
#define MAXLEN 4096

static uint8_t buf[1 << 20];

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    size_t n;
    if (f == NULL) {
        fprintf(stderr, "cannot open %s\n", path);
        return 1;
    }
    n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    LLVMFuzzerTestOneInput(buf, n);
    return 0;
}

int main(int argc, char **argv)
{
    int i;
    uint32_t s = 2463534242u;
    if (argc > 1) {
        for (i = 1; i < argc; i++) {
            if (run_file(argv[i]) != 0) {
                return 1;
            }
        }
        printf("%d file(s) ran cleanly\n", argc - 1);
        return 0;
    }
    for (i = 0; i < GENERATED; i++) {
        size_t len = (size_t)(i * 37) % MAXLEN;
        size_t k;
        for (k = 0; k < len; k++) {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            /* Mostly small header values so geometry is often legal. */
            buf[k] = (k < 12 && (i & 1)) ? (uint8_t)(s % 80u)
                                         : (uint8_t)(s >> 24);
        }
        LLVMFuzzerTestOneInput(buf, len);
    }
    printf("%d generated inputs ran cleanly\n", GENERATED);
    return 0;
}
