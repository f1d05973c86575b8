/*
 * Cross-target determinism digest.
 *
 * Runs the core kernels on fixed, generated inputs and prints one FNV-1a
 * 64-bit digest of every output byte. tools/negobs runs it natively and on
 * aarch64/armhf under qemu-user and requires identical lines: the library
 * promises bit-identical results on every target.
 *
 *   negobs_digest              the digest lines (below)
 *   negobs_digest --perturb    same, with one input pixel changed
 *   negobs_digest --self-test  exit 1 unless every digest sees the change
 *
 * "digest": the kernels. The stereo engine runs on a generated pair
 * (tests/support/scene_pair.h: slanted ground, drop-off, box, 2-row vertical
 * offset); its Q4 disparities, confidences and statistics are fed into the
 * same digest as the box sums, integral images, valign and fixed-point
 * helpers.
 *
 * "walk": the whole pipeline (negobs_pipeline_process, default config,
 * 320x240) on the generated curb walk of walk.h, once without and once with
 * valign. One line per frame names what a wearer depends on: stereo status,
 * detector state and reasons, alert level, nearest range, every confirmed
 * hazard (type, level, range, lateral offset, drop) and the motor command,
 * with a 32-bit hash of that frame's disparity image; "pipeline" and
 * "pipeline-valign" hash all of it plus every candidate. The line
 * "walk-input" hashes the generated pairs themselves (the scene geometry is
 * computed in double), so a difference there is the generator's, not the
 * library's.
 *
 * "pool": the detector's frame pooling (detect/detect_pool.c) on six noisy
 * 320x240 disparity maps of a walk toward a 15 cm drop, 120 mm a tick:
 * every pooled map and its pooled share. The walk's own texture is not
 * fixed to the floor, so no travel is measured on it and the pipeline
 * lines never pool; this line covers that code on every target.
 */
#include <stdio.h>
#include <string.h>

#include <stdlib.h>

#include "negobs/negobs.h"
#include "negobs/pipeline.h"
#include "negobs/stereo.h"
#include "negobs/valign.h"

#include "walk.h"
#include "digest_pool.h"

#include "scene_pair.h"
#include "test_rng.h"
#include "fixed_int.h"
#include "integral.h"

#define W 96
#define H 72

static uint8_t pix[H * W];
static uint16_t sum[H * W];
static uint32_t sumsq[H * W];
static uint32_t colbuf[2 * W];
static uint32_t ii[(W + 1) * (H + 1)];
static uint32_t iiq[(W + 1) * (H + 1)];

#define SW 128
#define SH 96
#define SDMAX 31

static uint8_t s_left[SW * SH];
static uint8_t s_right[SW * SH];
static uint8_t s_tex[SW * SH];
static uint8_t s_occ[SW * SH];
static int16_t s_gt[SW * SH];
static int16_t s_disp[SW * SH];
static uint8_t s_conf[SW * SH];
static uint8_t s_vws[8192] __attribute__((aligned(16)));
static uint8_t s_ws[NEGOBS_STEREO_WORKSPACE_MAX(SW, SH, SDMAX)]
    __attribute__((aligned(16)));

typedef struct digest {
    uint64_t h;
} digest_t;

static void feed(digest_t *d, const void *p, size_t n)
{
    const uint8_t *b = (const uint8_t *)p;
    size_t i;
    for (i = 0; i < n; i++) {
        d->h ^= b[i];
        d->h *= 1099511628211ull;
    }
}

/* Feed integers byte by byte, little-endian, whatever the host order. */
static void feed_u32(digest_t *d, uint32_t v)
{
    uint8_t b[4];
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    b[2] = (uint8_t)(v >> 16);
    b[3] = (uint8_t)(v >> 24);
    feed(d, b, 4);
}

static uint64_t run(int perturb)
{
    digest_t d;
    uint32_t seed = 12345u;
    negobs_image_u8_t img;
    size_t i;
    int32_t r;
    int32_t x;

    d.h = 14695981039346656037ull;
    for (i = 0; i < sizeof pix; i++) {
        pix[i] = (uint8_t)(test_lcg_next(&seed) >> 16);
    }
    if (perturb) {
        pix[(H / 2) * W + W / 2] ^= 1u;
    }
    img.data = pix;
    img.width = W;
    img.height = H;
    img.stride = W;

    for (r = 1; r <= NEGOBS_BOXSUM_MAX_RADIUS; r++) {
        if (negobs_boxsum_u8(&img, r, sum, W, sumsq, W, colbuf) != NEGOBS_OK) {
            return 0;
        }
        for (i = 0; i < (size_t)(W * H); i++) {
            feed_u32(&d, sum[i]);
            feed_u32(&d, sumsq[i]);
        }
    }
    if (negobs_integral_u8(&img, ii, iiq, sizeof ii / sizeof ii[0]) !=
        NEGOBS_OK) {
        return 0;
    }
    for (i = 0; i < sizeof ii / sizeof ii[0]; i++) {
        feed_u32(&d, ii[i]);
        feed_u32(&d, iiq[i]);
    }
    {
        synth_scene_t sc;
        negobs_stereo_config_t cfg;
        negobs_stereo_t ctx;
        negobs_stereo_stats_t st;
        negobs_image_u8_t li;
        negobs_image_u8_t ri;
        negobs_image_u8_t ci;
        negobs_image_s16_t di;
        sc.w = SW;
        sc.h = SH;
        sc.d_top_q8 = 6 * 256;
        sc.d_bottom_q8 = 22 * 256;
        sc.drop_q8 = 4 * 256;
        sc.box_q8 = 27 * 256;
        sc.voff = 2;
        sc.seed = 2024u;
        synth_render(&sc, s_left, s_right, s_gt, s_occ, s_tex);
        if (perturb) {
            s_left[(SH / 2) * SW + SW / 2] ^= 1u;
        }
        negobs_stereo_config_default(&cfg, SW, SH);
        cfg.max_disp = SDMAX;
        cfg.lr_check = 1;
        li.data = s_left;
        li.width = SW;
        li.height = SH;
        li.stride = SW;
        ri = li;
        ri.data = s_right;
        ci = li;
        ci.data = s_conf;
        di.data = s_disp;
        di.width = SW;
        di.height = SH;
        di.stride = SW;
        if (negobs_stereo_init(&ctx, &cfg, s_ws, sizeof s_ws) != NEGOBS_OK ||
            negobs_stereo_process(&ctx, &li, &ri, &di, &ci, &st) !=
                NEGOBS_OK) {
            return 0;
        }
        for (i = 0; i < (size_t)(SW * SH); i++) {
            feed_u32(&d, (uint32_t)(uint16_t)s_disp[i]);
        }
        feed(&d, s_conf, sizeof s_conf);
        feed_u32(&d, st.seeds);
        feed_u32(&d, st.grown);
        feed_u32(&d, st.visited_cells);
        feed_u32(&d, st.gcs_matched);
        feed_u32(&d, st.valid);
        feed_u32(&d, (uint32_t)st.vertical_offset);
        feed_u32(&d, (uint32_t)st.range_min);
        feed_u32(&d, (uint32_t)st.range_max);
        /* vertical alignment: the model estimated on the same pair (rows
         * off by 2) and the resampled right image */
        {
            negobs_valign_config_t vc;
            negobs_valign_t vctx;
            negobs_valign_stats_t vs;
            negobs_image_u8_t oi = li;
            size_t vn = 0;
            oi.data = s_tex; /* free after the render */
            negobs_valign_config_default(&vc, SW, SH);
            vc.max_disp = SDMAX;
            if (negobs_valign_workspace_size(&vc, &vn) != NEGOBS_OK ||
                vn > sizeof s_vws ||
                negobs_valign_init(&vctx, &vc, s_vws, vn) != NEGOBS_OK ||
                negobs_valign_process(&vctx, &li, &ri, &oi, &vs) !=
                    NEGOBS_OK) {
                return 0;
            }
            feed_u32(&d, (uint32_t)vs.model.offset_q16);
            feed_u32(&d, (uint32_t)vs.model.slope_y_q16);
            feed_u32(&d, (uint32_t)vs.model.slope_x_q16);
            feed_u32(&d, (uint32_t)vs.tiles_used);
            feed(&d, s_tex, sizeof s_tex);
        }
    }
    for (x = -3000; x < 3000; x += 7) {
        feed_u32(&d, (uint32_t)negobs_rshift_round_s32(x * 977, 5));
        feed_u32(&d, negobs_isqrt_u32((uint32_t)(x + 3000) * 104729u));
        feed_u32(&d, (uint32_t)negobs_div_round_s64((int64_t)x * 1000003, 97));
    }
    return d.h;
}

#define WW 320
#define WH 240

static uint8_t w_left[WW * WH];
static uint8_t w_right[WW * WH];

static void feed_s32(digest_t *d, int32_t v)
{
    feed_u32(d, (uint32_t)v);
}

static void feed_hazard(digest_t *d, const negobs_hazard_t *hz)
{
    feed_u32(d, (uint32_t)hz->type);
    feed_u32(d, (uint32_t)hz->level);
    feed_u32(d, hz->flags);
    feed_u32(d, hz->track_id);
    feed_s32(d, hz->range_mm);
    feed_s32(d, hz->lateral_mm);
    feed_s32(d, hz->bearing_mdeg);
    feed_s32(d, hz->depth_mm);
    feed_s32(d, hz->drop_mm);
    feed_s32(d, hz->u0);
    feed_s32(d, hz->v0);
    feed_s32(d, hz->u1);
    feed_s32(d, hz->v1);
    feed_s32(d, hz->conf_q15);
}

/* The first `frames` frames of the curb walk through the pipeline; prints
 * one line per frame when verbose, returns the run's digest (0: the
 * pipeline refused to run). */
static uint64_t run_walk(int valign, int perturb, int verbose, int32_t frames,
                         uint64_t *input_hash)
{
    negobs_pipeline_config_t cfg;
    negobs_pipeline_t ctx;
    negobs_pipeline_result_t res;
    negobs_pipeline_frame_t fr;
    negobs_image_u8_t li;
    negobs_image_u8_t ri;
    digest_t d;
    digest_t in;
    size_t bytes = 0;
    void *raw;
    void *ws;
    int32_t f;
    uint32_t i;

    negobs_pipeline_config_default(&cfg, WW, WH);
    cfg.valign.enable = valign;
    if (negobs_pipeline_workspace_size(&cfg, &bytes) != NEGOBS_OK) {
        return 0;
    }
    raw = malloc(bytes + 16u);
    if (raw == NULL) {
        return 0;
    }
    ws = (void *)(((uintptr_t)raw + 15u) & ~(uintptr_t)15u);
    if (negobs_pipeline_init(&ctx, &cfg, ws, bytes) != NEGOBS_OK) {
        free(raw);
        return 0;
    }
    d.h = 14695981039346656037ull;
    in.h = 14695981039346656037ull;
    li.data = w_left;
    li.width = WW;
    li.height = WH;
    li.stride = WW;
    ri = li;
    ri.data = w_right;
    memset(&fr, 0, sizeof fr);
    fr.left = &li;
    fr.right = &ri;
    for (f = 0; f < frames; f++) {
        const negobs_image_s16_t *disp;
        digest_t dd;
        int32_t y;
        if (walk_render(&cfg.detect.rig, f, w_left, w_right) != 0) {
            free(raw);
            return 0;
        }
        if (perturb && f == 0) {
            /* one flipped grey level is below what the matcher resolves
             * (the disparity stays the same); a ground pixel made a quite
             * different grey must change it */
            w_left[(WH * 3 / 4) * WW + WW / 2] ^= 0x55u;
        }
        feed(&in, w_left, sizeof w_left);
        feed(&in, w_right, sizeof w_right);
        fr.now_ms = 1000u + 100u * (uint32_t)f;
        fr.t_left_ms = fr.now_ms - 40u;
        fr.t_right_ms = fr.now_ms - 40u;
        if (negobs_pipeline_process(&ctx, &fr, &res) != NEGOBS_OK) {
            free(raw);
            return 0;
        }
        disp = negobs_pipeline_disparity(&ctx);
        dd.h = 14695981039346656037ull;
        for (y = 0; y < disp->height; y++) {
            const int16_t *row = disp->data + y * disp->stride;
            int32_t x;
            for (x = 0; x < disp->width; x++) {
                feed_u32(&dd, (uint32_t)(uint16_t)row[x]);
            }
        }
        feed_u32(&d, (uint32_t)dd.h);
        feed_u32(&d, (uint32_t)(dd.h >> 32));
        feed_s32(&d, (int32_t)res.stereo_status);
        feed_u32(&d, (uint32_t)res.detect.state);
        feed_u32(&d, res.detect.reasons);
        feed_u32(&d, (uint32_t)res.detect.level);
        feed_s32(&d, res.detect.nearest_range_mm);
        feed_u32(&d, res.detect.n_hazards);
        for (i = 0; i < res.detect.n_hazards && i < NEGOBS_DETECT_MAX_HAZARDS;
             i++) {
            feed_hazard(&d, &res.detect.hazards[i]);
        }
        feed_u32(&d, res.detect.n_candidates);
        for (i = 0;
             i < res.detect.n_candidates && i < NEGOBS_DETECT_MAX_HAZARDS;
             i++) {
            feed_hazard(&d, &res.detect.candidates[i]);
        }
        feed_s32(&d, res.motor.on);
        feed_s32(&d, res.motor.duty_permille);
        feed_u32(&d, (uint32_t)res.motor.pattern);
        feed_u32(&d, res.motor.next_change_ms);
        if (valign) {
            feed_s32(&d, res.valign.model.offset_q16);
            feed_s32(&d, res.valign.model.slope_y_q16);
            feed_s32(&d, res.valign.model.slope_x_q16);
        }
        if (verbose) {
            printf("walk valign=%d frame=%02d stereo=%d state=%u "
                   "reasons=%08x level=%u nearest_mm=%d hazards=%u",
                   valign, (int)f, (int)res.stereo_status,
                   (unsigned)res.detect.state, (unsigned)res.detect.reasons,
                   (unsigned)res.detect.level,
                   (int)res.detect.nearest_range_mm,
                   (unsigned)res.detect.n_hazards);
            for (i = 0;
                 i < res.detect.n_hazards && i < NEGOBS_DETECT_MAX_HAZARDS;
                 i++) {
                const negobs_hazard_t *hz = &res.detect.hazards[i];
                printf(" [t%u l%u %d/%d/%d]", (unsigned)hz->type,
                       (unsigned)hz->level, (int)hz->range_mm,
                       (int)hz->lateral_mm, (int)hz->drop_mm);
            }
            printf(" motor=%d/%d/p%u disp=%08lx\n", (int)res.motor.on,
                   (int)res.motor.duty_permille, (unsigned)res.motor.pattern,
                   (unsigned long)(uint32_t)(dd.h ^ (dd.h >> 32)));
        }
    }
    free(raw);
    *input_hash = in.h;
    return d.h;
}

/* Every digest of one run; 0 in any means something refused to run. */
typedef struct digests {
    uint64_t kernels;
    uint64_t walk;
    uint64_t walk_valign;
    uint64_t walk_input;
    uint64_t pool;
} digests_t;

static void run_all(int perturb, int verbose, int32_t frames, digests_t *out)
{
    uint64_t in2 = 0;
    out->kernels = run(perturb);
    out->pool = digest_pool(perturb);
    out->walk = run_walk(0, perturb, verbose, frames, &out->walk_input);
    out->walk_valign = run_walk(1, perturb, verbose, frames, &in2);
    if (in2 != out->walk_input) {
        out->walk_input = 0; /* the generator is not repeatable */
    }
}

int main(int argc, char **argv)
{
    const char *mode = (argc > 1) ? argv[1] : "";
    digests_t a;
    if (strcmp(mode, "--self-test") == 0) {
        digests_t b;
        /* the change is in frame 0: two frames show it, and keep the
         * test short under qemu (four walks) */
        run_all(0, 0, 2, &a);
        run_all(1, 0, 2, &b);
        if (a.kernels == 0 || b.kernels == 0 || a.kernels == b.kernels ||
            a.walk == 0 || b.walk == 0 || a.walk == b.walk ||
            a.walk_valign == 0 || b.walk_valign == 0 ||
            a.walk_valign == b.walk_valign || a.walk_input == 0 ||
            a.pool == 0 || b.pool == 0 || a.pool == b.pool) {
            fprintf(stderr, "a digest does not see a one-pixel change\n");
            return 1;
        }
        printf("every digest sees a one-pixel change: %016llx != %016llx, "
               "%016llx != %016llx, %016llx != %016llx, %016llx != %016llx\n",
               (unsigned long long)a.kernels, (unsigned long long)b.kernels,
               (unsigned long long)a.walk, (unsigned long long)b.walk,
               (unsigned long long)a.walk_valign,
               (unsigned long long)b.walk_valign, (unsigned long long)a.pool,
               (unsigned long long)b.pool);
        return 0;
    }
    if (argc > 1 && strcmp(mode, "--perturb") != 0) {
        fprintf(stderr, "usage: %s [--perturb | --self-test]\n", argv[0]);
        return 2;
    }
    run_all(strcmp(mode, "--perturb") == 0, 1, WALK_FRAMES, &a);
    if (a.kernels == 0 || a.walk == 0 || a.walk_valign == 0 ||
        a.walk_input == 0 || a.pool == 0) {
        fprintf(stderr, "a kernel or the pipeline refused its input\n");
        return 1;
    }
    printf("walk-input %016llx\n", (unsigned long long)a.walk_input);
    printf("pipeline %016llx\n", (unsigned long long)a.walk);
    printf("pipeline-valign %016llx\n", (unsigned long long)a.walk_valign);
    printf("digest %016llx\n", (unsigned long long)a.kernels);
    printf("pool %016llx\n", (unsigned long long)a.pool);
    return 0;
}
