/*
 * Helpers for fuzz targets: carve header fields from the fuzzer's bytes.
 * A target reads its geometry and parameters first, then uses the rest as
 * pixel data; short inputs read as zeros so every input is valid to run.
 */
#ifndef NEGOBS_FUZZ_INPUT_H
#define NEGOBS_FUZZ_INPUT_H

#include <stddef.h>
#include <stdint.h>

typedef struct fuzz_input {
    const uint8_t *data;
    size_t size;
    size_t pos;
} fuzz_input_t;

static inline uint8_t fuzz_u8(fuzz_input_t *in)
{
    return (in->pos < in->size) ? in->data[in->pos++] : 0u;
}

static inline uint16_t fuzz_u16(fuzz_input_t *in)
{
    uint16_t lo = fuzz_u8(in);
    uint16_t hi = fuzz_u8(in);
    return (uint16_t)(lo | (uint16_t)(hi << 8));
}

/* Signed value in [lo, hi] from 16 bits of input. */
static inline int32_t fuzz_range(fuzz_input_t *in, int32_t lo, int32_t hi)
{
    uint32_t span = (uint32_t)(hi - lo) + 1u;
    return lo + (int32_t)(fuzz_u16(in) % span);
}

/* Fill n bytes from the input; repeats the input's tail pattern. */
static inline void fuzz_fill(fuzz_input_t *in, uint8_t *dst, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        dst[i] = fuzz_u8(in);
        if (in->pos >= in->size && in->size > 0) {
            in->pos = 0; /* wrap: large frames from small inputs */
        }
    }
}

/* Every target defines this (libFuzzer's entry point). */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif
