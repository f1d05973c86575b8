/*
 * Fuzz target: the whole per-frame job (stereo -> detect -> alert) on
 * arbitrary frame sizes, pixels, search ranges and matcher bounds. The
 * right image is often the left one shifted (so matches happen and the
 * growing, DP and detection paths run), sometimes unrelated bytes.
 * Invariants: every call returns a status; disparities are invalid or in
 * the searched range; the verdict is a known state.
 */
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "negobs/pipeline.h"

#define MAXW 96
#define MAXH 64

static uint8_t lpx[MAXW * MAXH];
static uint8_t rpx[MAXW * MAXH];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input_t in = {data, size, 0};
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t *ctx;
    negobs_pipeline_result_t res;
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t left;
    negobs_image_u8_t right;
    size_t bytes = 0;
    void *raw;
    uint8_t *ws;
    int32_t w = fuzz_range(&in, 8, MAXW);
    int32_t h = fuzz_range(&in, 8, MAXH);
    int32_t shift = fuzz_range(&in, 0, 20);
    uint8_t mode = fuzz_u8(&in);
    int32_t x;
    int32_t y;
    int frame;

    negobs_pipeline_config_default(&cfg, w, h);
    cfg.stereo.max_disp = fuzz_range(&in, -2, 40);
    cfg.stereo.min_disp = fuzz_range(&in, -2, 8);
    cfg.stereo.vertical_search = fuzz_range(&in, -1, 5);
    cfg.stereo.queue_capacity = fuzz_range(&in, 0, 600);
    cfg.stereo.band = fuzz_range(&in, 0, 17);
    cfg.stereo.auto_range = (mode & 1u) != 0u;
    cfg.stereo.lr_check = (mode & 2u) != 0u;
    cfg.detect.max_disp_q4 = (cfg.stereo.max_disp + 1) * 16;
    if (negobs_pipeline_workspace_size(&cfg, &bytes) != NEGOBS_OK) {
        return 0; /* a refused configuration is a valid outcome */
    }
    raw = malloc(bytes + 16u + sizeof *ctx);
    if (raw == NULL) {
        return 0;
    }
    ctx = (negobs_pipeline_t *)raw;
    ws = (uint8_t *)(((uintptr_t)((uint8_t *)raw + sizeof *ctx) + 15u) &
                     ~(uintptr_t)15u);
    if (negobs_pipeline_init(ctx, &cfg, ws, bytes) != NEGOBS_OK) {
        abort(); /* the size query said this configuration fits */
    }
    fuzz_fill(&in, lpx, (size_t)(w * h));
    if (mode & 4u) {
        fuzz_fill(&in, rpx, (size_t)(w * h));
    } else {
        for (y = 0; y < h; y++) {
            for (x = 0; x < w; x++) {
                int32_t sx = x + shift;
                rpx[y * w + x] = lpx[y * w + (sx < w ? sx : w - 1)];
            }
        }
    }
    left.data = lpx;
    left.width = w;
    left.height = h;
    left.stride = w;
    right = left;
    right.data = rpx;
    memset(&fr, 0, sizeof fr);
    fr.left = &left;
    fr.right = (mode & 8u) ? NULL : &right;
    for (frame = 0; frame < 2; frame++) {
        const negobs_image_s16_t *d;
        fr.now_ms = (uint32_t)frame * 100u;
        fr.t_left_ms = fr.now_ms;
        fr.t_right_ms = fr.now_ms + (uint32_t)(mode >> 5);
        if (negobs_pipeline_process(ctx, &fr, &res) != NEGOBS_OK) {
            abort();
        }
        if ((unsigned)res.detect.state > (unsigned)NEGOBS_DETECT_NO_INFO ||
            res.detect.n_hazards > NEGOBS_DETECT_MAX_HAZARDS) {
            abort();
        }
        if (res.stereo_status != NEGOBS_OK) {
            if (res.detect.state != NEGOBS_DETECT_NO_INFO) {
                abort(); /* no disparity must never read as "clear" */
            }
            continue;
        }
        d = negobs_pipeline_disparity(ctx);
        for (y = 0; y < h; y++) {
            for (x = 0; x < w; x++) {
                int32_t v = d->data[y * d->stride + x];
                if (v != NEGOBS_DISP_INVALID &&
                    (v < (cfg.stereo.min_disp - 1) * 16 ||
                     v > (cfg.stereo.max_disp + 1) * 16)) {
                    abort();
                }
            }
        }
    }
    free(raw);
    return 0;
}
