/*
 * Disparity engine: elementary low-res range -> Canny seeds -> Growing
 * Correspondence Seeds (integer 5x5 NCC, bounded queue) -> banded two-stage
 * DP -> sub-pixel refinement and denoising.
 *
 * API CONTRACT (tools/stereo and tools/detect code against these names; add
 * fields freely, do not rename or remove these):
 *   negobs_stereo_config_t: width, height, min_disp, max_disp (pixels)
 *   negobs_stereo_config_default(cfg, width, height)
 *   negobs_stereo_workspace_size(cfg, &bytes)
 *   negobs_stereo_init(ctx, cfg, workspace, bytes)
 *   negobs_stereo_process(ctx, left, right, disp_q4, confidence, stats)
 *   disp_q4 values: disparity * 16, NEGOBS_DISP_INVALID (INT16_MIN) = none
 *   stats: seeds, queue_peak, queue_overflows, visited_cells, band
 *
 * Conventions: left is the reference; a scene point at column x of the left
 * image is at column x - d of the right image (d >= 0) and, with a vertical
 * misalignment `off`, at row y + off. docs/DISPARITY.md describes every
 * stage, format and default.
 */
#ifndef NEGOBS_STEREO_H
#define NEGOBS_STEREO_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/executor.h"
#include "negobs/fixed.h"
#include "negobs/image.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Configuration; zero it, then call negobs_stereo_config_default().
 *
 * Units: pixels unless the name says otherwise; `_q14` fields are
 * correlation values with 16384 = 1.0; `_q8` fields 256 = 1.0; `_q4`
 * fields 1/16 px. Defaults in parentheses. The config is copied by init.
 */
typedef struct negobs_stereo_config {
    int32_t width;    /**< frame width (pixels)                    */
    int32_t height;   /**< frame height (pixels)                   */
    int32_t min_disp; /**< smallest disparity searched (pixels)    */
    int32_t max_disp; /**< largest disparity searched (pixels)     */

    /* search range (stage 1) */
    int32_t auto_range;   /**< 1: narrow the range from a 1/4-scale map (1) */
    int32_t range_margin; /**< px added around the estimated range (4)   */
    int32_t tile_size;    /**< px, side of a per-tile seed range (32)    */

    /* vertical misalignment (stage 6) */
    int32_t vertical_search; /**< estimate |offset| <= this, 0..4 (4)     */
    int32_t vertical_offset; /**< rows, used when vertical_search == 0:
                                  left row y matches right row y + offset */

    /* seeds (stage 2) */
    /** A strip whose strongest canny_top_permille of gradients lie below
     *  canny_high takes that share's magnitude as its strong threshold
     *  and the weak one in proportion (low-contrast floors still get
     *  seeds); 0 = the fixed thresholds. Per mille (3). */
    int32_t canny_top_permille;
    int32_t canny_low;       /**< L1 Sobel magnitude of a weak edge (60)    */
    int32_t canny_high;      /**< L1 Sobel magnitude of a strong edge (120) */
    int32_t seed_step;       /**< try every n-th edge pixel of a row (4)    */
    int32_t seed_tau_q14;    /**< seed MNCC floor (0.8 = 13107)             */
    int32_t seed_margin_q14; /**< best minus 2nd best (|dd| >= 2) (819)   */

    /* growing (stage 3) */
    int32_t ncc_tau_q14;    /**< growing MNCC threshold tau (0.5 = 8192)   */
    int32_t ncc_mu_q14;     /**< growth margin mu (0.1 = 1638)             */
    int32_t ssk_beta_q8;    /**< stable-matching margin, share of c (0)    */
    int32_t zonegap;        /**< d difference that does not inhibit (1)    */
    int32_t texture_min;    /**< VL+VR floor, n^2 x variance units (100)   */
    int32_t queue_capacity; /**< seed queue entries (8192)               */
    int32_t strip_rows;     /**< rows per processing strip, 8..255 (32)    */

    /* DP (stage 4) */
    int32_t band;           /**< DP band half-width around GCS d, 1..16 (2) */
    int32_t dp_neutral_q14; /**< score of unvisited band cells (0)       */
    int32_t dp_jump_q14;    /**< penalty of a jump |dd| > 1 (8192)         */
    int32_t dp_rescore;     /**< 1: score every band cell with MNCC, 0: only
                               the GCS cell (1.0), the rest neutral (0)  */

    /* sub-pixel (stage 5a) */
    int32_t subpixel_halfshift; /**< 1: average the parabola's offset with
                               a second one on the right image shifted by
                               half a pixel, which cancels the first
                               one's pull towards whole pixels (0; the
                               pipeline's half-size pass sets 1:
                               docs/DISPARITY.md, stage 5)              */

    /* refinement (stage 5) */
    int32_t lr_check; /**< 1: drop pixels occluded in the right view (1) */
    int32_t
        speckle_size; /**< regions below this many px removed, 0..256 (100) */
    int32_t speckle_diff_q4;  /**< largest step inside a region (12)     */
    int32_t adaptive_mean;    /**< 1: adaptive mean filter (1)              */
    int32_t gap_fill;         /**< row gaps up to this many px filled from
                               their ends, 0 = off, 0..1024 (64)          */
    int32_t keep_out_of_view; /**< 1: keep the values whose match x - d
                               falls left of the right image (a dense map;
                               they are fills or guesses, mostly wrong);
                               0: they get no value, the right camera never
                               saw those points (1: the dropped pixels are
                               counted as errors by the bad1all benchmarks,
                               docs/DISPARITY.md)                         */

    /* memory/speed trade-off; the output does not depend on it */
    int32_t memory_profile; /**< NEGOBS_STEREO_PROFILE_* (see below;
                                 NEGOBS_STEREO_PROFILE_DEFAULT)          */

    /* row bands (docs/DISPARITY.md, "Row bands and threads") */
    int32_t bands;        /**< row bands of a frame, 1..NEGOBS_STEREO_MAX_BANDS
                               (NEGOBS_STEREO_BANDS_DEFAULT). Seeds grow
                               inside their band only, so the output
                               depends on this count (and on nothing
                               else of the threading)                   */
    int32_t band_workers; /**< scratch areas for bands run at once,
                               1..NEGOBS_STEREO_MAX_BANDS (1); the most
                               workers an executor may use. Memory only:
                               the output does not depend on it         */
} negobs_stereo_config_t;

/** Largest bands / band_workers. */
#define NEGOBS_STEREO_MAX_BANDS 64
/** The band count negobs_stereo_config_default() picks: 4 on every
 *  target, so a 4-core board can run every band at once and a
 *  microcontroller (one worker) gives the same disparities. */
#ifndef NEGOBS_STEREO_BANDS_DEFAULT
#define NEGOBS_STEREO_BANDS_DEFAULT 4
#endif

/*
 * Memory profiles (negobs_stereo_config_t.memory_profile). Both give the
 * same disparities, confidences and statistics, bit for bit; they differ in
 * workspace and instructions only (docs/DISPARITY.md, "Memory profiles").
 */
/** Today's strip-sized workspace: <= 512 KB at 320x240 with 64
 *  disparities. For microcontrollers (Cortex-M7 SRAM). */
#define NEGOBS_STEREO_PROFILE_COMPACT 0
/** Adds a per-strip memo of the growth's correlation numerators over a
 *  band of up to NEGOBS_STEREO_MEMO_LEVELS disparities around each tile's
 *  coarse range, so the growth correlates no cell of that band twice in a
 *  strip:
 *  strip_rows x width x levels x 4 bytes more (1.3 MB at 320x240x64,
 *  2.6 MB at 640x480x64; <= 4 MB in all at 640x480x64). */
#define NEGOBS_STEREO_PROFILE_FAST 1
/** Width of the fast profile's memo band (disparity levels) with one
 *  band worker. */
#define NEGOBS_STEREO_MEMO_LEVELS 32
/** The fast profile's workspace budget: every worker needs its own memo,
 *  so with band_workers > 1 the memo band narrows until the workspace
 *  holds within this (or within one worker's workspace where that is
 *  larger): 4 MiB keeps 640x480x64 with 4 workers, per-worker scratch
 *  included, inside the 4 MB the Linux board grants the matcher. */
#define NEGOBS_STEREO_FAST_BUDGET ((size_t)4u * 1024u * 1024u)
/** Narrower than this the memo band is dropped (no memo): on Cones
 *  (release, callgrind, one frame) 32 levels save 7.6 % of the matcher's
 *  instructions, 23 levels 4.9 %, 12 levels 1.8 %: a narrow band misses
 *  most lookups and is not worth its memory. */
#define NEGOBS_STEREO_MEMO_MIN_LEVELS 16
/** The profile negobs_stereo_config_default() picks: compact on every
 *  target. The fast profile's memo saves about 9 % of the instructions
 *  where the cross sum has SIMD (SSE2, NEON), and its size depends on the
 *  frame and the band workers, so the caller that owns the memory
 *  chooses: negobs_run takes it wherever its static workspace holds it
 *  beside the threads. Others set memory_profile, or build with
 *  -DNEGOBS_STEREO_PROFILE_DEFAULT=1. */
#ifndef NEGOBS_STEREO_PROFILE_DEFAULT
#define NEGOBS_STEREO_PROFILE_DEFAULT NEGOBS_STEREO_PROFILE_COMPACT
#endif

/** Largest disparity range (max_disp - min_disp + 1). */
#define NEGOBS_STEREO_MAX_RANGE 256

/*
 * Confidence map values (negobs_stereo_process). 0 means "no value" and
 * is used exactly where disp_q4 is NEGOBS_DISP_INVALID; every pixel with a
 * value has a confidence of at least NEGOBS_STEREO_CONF_FILLED. Consumers
 * that only want measured disparities threshold at
 * NEGOBS_STEREO_CONF_MATCHED_MIN or above.
 */
/** No value. */
#define NEGOBS_STEREO_CONF_NONE 0
/** Interpolated from neighbouring values (row gap fill, adaptive mean):
 *  not measured at this pixel. */
#define NEGOBS_STEREO_CONF_FILLED 2
/** Chosen by the DP through a window without texture. */
#define NEGOBS_STEREO_CONF_FLAT 4
/** Matched pixels: 255 * MNCC of the chosen disparity, halved where the
 *  DP left the GCS band, and never below this floor (8 .. 255). */
#define NEGOBS_STEREO_CONF_MATCHED_MIN 8
/** Smallest frame accepted (pixels). */
#define NEGOBS_STEREO_MIN_WIDTH 32
#define NEGOBS_STEREO_MIN_HEIGHT 16
/** Largest band half-width. */
#define NEGOBS_STEREO_MAX_BAND 16

/**
 * Constant-expression upper bound of negobs_stereo_workspace_size() for a
 * w x h frame searched over [0, dmax] (or any narrower range), valid for
 * configs with strip_rows <= 32, queue_capacity <= 8192 and
 * speckle_size <= 256 (the defaults are inside), compact profile.
 * Includes debug guards and alignment slack. Use it to size a static workspace; the unit tests check
 * it against the exact query over a grid of sizes.
 */
#define NEGOBS_STEREO_WORKSPACE_MAX_COMPACT(w, h, dmax)                       \
    ((size_t)(w)*36u * 22u +                                                  \
     (size_t)(w)*32u * (((size_t)(dmax) + 1u) / 8u + 2u) +                    \
     (size_t)8192u * 8u + 257u * 4u + 2048u * 12u +                           \
     (size_t)(w) * (size_t)(h) / 16u * 3u +                                   \
     ((size_t)(w) / 8u + 2u) * ((size_t)(h) / 8u + 2u) * 4u +                 \
     ((size_t)(dmax) + 4u) * 32u + (size_t)(w) * ((size_t)(dmax) + 1u) * 3u + \
     (size_t)(w)*12u + (size_t)(h) * ((size_t)(dmax) + 4u) +                  \
     ((size_t)(w) + (size_t)(h) + 16u) * 4u +                                 \
     (size_t)(w) * (size_t)(h) / 4u + 257u * 4u + 8192u)

/** The same bound for the fast profile: the compact one plus the memo
 *  (strip_rows x w x NEGOBS_STEREO_MEMO_LEVELS words and a byte per strip
 *  pixel) with its guards and alignment. */
#define NEGOBS_STEREO_WORKSPACE_MAX_FAST(w, h, dmax)                          \
    (NEGOBS_STEREO_WORKSPACE_MAX_COMPACT(w, h, dmax) +                        \
     (size_t)(w)*32u * (4u * NEGOBS_STEREO_MEMO_LEVELS + 1u) + 128u)

/** Upper bound of the workspace each band worker beyond the first adds
 *  (band_workers - 1 of them), for the compact profile and the limits of
 *  NEGOBS_STEREO_WORKSPACE_MAX_COMPACT (the fast profile adds its memo,
 *  w x 32 x (4 x NEGOBS_STEREO_MEMO_LEVELS + 1) bytes, per worker). */
#define NEGOBS_STEREO_WORKSPACE_WORKER_MAX(w, dmax)                           \
    ((size_t)(w)*32u * 21u +                                                  \
     (size_t)(w)*32u * (((size_t)(dmax) + 1u) / 8u + 2u) +                    \
     (size_t)8192u * 8u + 257u * 4u + 2048u * 12u +                           \
     ((size_t)(dmax) + 4u) * 8u + (size_t)(w) * ((size_t)(dmax) + 1u) * 3u +  \
     (size_t)(w)*16u + 4096u + 2u * (258u * 4u + 48u))

/** Upper bound of the once-only cost of band_workers > 1: the stage-1 end
 *  scores of every row, kept for the second DP stage, and the bands'
 *  partial results of the vertical search and the 1/4-scale map (up to
 *  NEGOBS_STEREO_MAX_BANDS bands). */
#define NEGOBS_STEREO_WORKSPACE_BANDS_MAX(h, dmax)                            \
    ((size_t)(h) * ((size_t)(dmax) + 1u) * 4u + (size_t)(h) + 128u +          \
     (size_t)NEGOBS_STEREO_MAX_BANDS *                                        \
         (9u * 8u + 4u + ((size_t)(dmax) / 4u + 4u) * 4u) +                   \
     3u * 48u)

/** The bound for the profile negobs_stereo_config_default() picks
 *  (NEGOBS_STEREO_PROFILE_DEFAULT). */
#if NEGOBS_STEREO_PROFILE_DEFAULT == NEGOBS_STEREO_PROFILE_FAST
#define NEGOBS_STEREO_WORKSPACE_MAX(w, h, dmax)                               \
    NEGOBS_STEREO_WORKSPACE_MAX_FAST(w, h, dmax)
#else
#define NEGOBS_STEREO_WORKSPACE_MAX(w, h, dmax)                               \
    NEGOBS_STEREO_WORKSPACE_MAX_COMPACT(w, h, dmax)
#endif

/**
 * Stages timed by the optional profiling clock (negobs_stereo_set_clock).
 * Every tick between the clock reads at the start and the end of
 * negobs_stereo_process() is attributed to exactly one of them.
 */
typedef enum negobs_stereo_stage {
    NEGOBS_STEREO_STAGE_VERTICAL = 0, /**< vertical offset search (6)    */
    NEGOBS_STEREO_STAGE_RANGE,        /**< 1/4-scale map, ranges (1)     */
    NEGOBS_STEREO_STAGE_WINDOWS,      /**< 5x5 window sums, both passes  */
    NEGOBS_STEREO_STAGE_CANNY,        /**< edges (2)                     */
    NEGOBS_STEREO_STAGE_GCS,          /**< seeds, growth, selection (3)  */
    NEGOBS_STEREO_STAGE_DP,           /**< both DP passes, sub-pixel (4) */
    NEGOBS_STEREO_STAGE_LR,           /**< left-right check (5)          */
    NEGOBS_STEREO_STAGE_SPECKLE,      /**< speckle removal (5)           */
    NEGOBS_STEREO_STAGE_GAP_FILL,     /**< row gap fill (5)              */
    NEGOBS_STEREO_STAGE_MEAN,         /**< adaptive mean (5)             */
    NEGOBS_STEREO_STAGE_OUTPUT,       /**< counting, clearing the crop   */
    NEGOBS_STEREO_STAGE_COUNT
} negobs_stereo_stage_t;

/**
 * Caller's clock for per-stage profiling: any 32-bit counter that keeps
 * counting by itself (microseconds, nanoseconds, CPU cycles, ...).
 * Differences of successive reads are taken modulo 2^32, so the counter
 * may wrap; only one interval (one stage on one strip, or one whole-frame
 * stage) must stay below one period (4.29 s for a nanosecond counter).
 * The per-stage sums are 64-bit.
 * Read about 4 times per strip plus 8 times per frame.
 */
typedef uint32_t (*negobs_stereo_clock_fn)(void *user);

/**
 * Observer of intermediate maps (tuning and documentation tools): called
 * with the disparity map as it stands after a stage, in this order:
 * NEGOBS_STEREO_STAGE_GCS (all strips grown and selected), _DP (both
 * passes and sub-pixel), then _LR, _SPECKLE, _GAP_FILL and _MEAN for the
 * refinements that are switched on. Values are disparity * 16 or
 * NEGOBS_DISP_INVALID, except after _GCS, where they are whole pixels
 * (the DP reads them as such). With negobs_stereo_set_first_row the map
 * passed is the view of the rows being matched. The map must not be
 * written; the observer's time is not counted in stage_ticks.
 */
typedef void (*negobs_stereo_observer_fn)(void *user,
                                          negobs_stereo_stage_t stage,
                                          const negobs_image_s16_t *disp);

/** Per-frame statistics. */
typedef struct negobs_stereo_stats {
    uint32_t seeds;            /**< seeds accepted                  */
    uint32_t queue_peak;       /**< largest queue fill              */
    uint32_t queue_overflows;  /**< pushes dropped by the bound     */
    uint32_t visited_cells;    /**< disparity-space cells scored    */
    int32_t band;              /**< DP band half-width used (px)    */
    uint32_t edges;            /**< Canny edge pixels               */
    uint32_t grown;            /**< candidates accepted by growing  */
    uint32_t gcs_matched;      /**< pixels matched after GCS        */
    uint32_t valid;            /**< valid output pixels             */
    uint32_t lr_rejected;      /**< pixels dropped by the LR check  */
    uint32_t speckles_removed; /**< pixels dropped as speckles     */
    uint32_t gap_filled;       /**< pixels filled by the gap fill   */
    uint32_t out_of_view;      /**< values dropped because their match
                                   lies left of the right image
                                   (keep_out_of_view 0), summed over
                                   the drops after the DP and after
                                   each refinement: a pixel a later
                                   stage refills counts again        */
    int32_t range_min;         /**< search range used (pixels)      */
    int32_t range_max;
    int32_t vertical_offset; /**< rows: left y matches right y+off */
    int32_t first_row;       /**< first row matched (set_first_row) */
    uint32_t seam_regrown;   /**< bands grown again with the matches
                                  above their border as seeds (the seam
                                  rule, docs/DISPARITY.md)          */
    /** clock ticks per stage (negobs_stereo_set_clock); all 0 without a
     *  clock. Not part of the output: timings differ from run to run. */
    uint64_t stage_ticks[NEGOBS_STEREO_STAGE_COUNT];
} negobs_stereo_stats_t;

/** Context; place it anywhere (static is fine). Fields are private. */
typedef struct negobs_stereo {
    negobs_stereo_config_t cfg;
    void *priv;
} negobs_stereo_t;

/** @brief Defaults for a width x height frame, range [0, 63]. */
void negobs_stereo_config_default(negobs_stereo_config_t *cfg, int32_t width,
                                  int32_t height);
/**
 * @brief Exact workspace bytes init will consume for this config.
 * @return NEGOBS_OK, or NEGOBS_ERR_INVAL for a bad config.
 */
negobs_status_t negobs_stereo_workspace_size(const negobs_stereo_config_t *cfg,
                                             size_t *bytes_out);
/**
 * @brief Validate cfg and carve the workspace (16-byte aligned).
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL, NEGOBS_ERR_ALIGN or
 *         NEGOBS_ERR_NOSPACE (workspace_bytes too small).
 */
negobs_status_t negobs_stereo_init(negobs_stereo_t *ctx,
                                   const negobs_stereo_config_t *cfg,
                                   void *workspace, size_t workspace_bytes);
/**
 * @brief Match only rows [first_row, height) from the next frame on; rows
 * above get NEGOBS_DISP_INVALID and confidence 0. The engine then runs
 * on that crop as on a smaller frame (no copy), so the time falls with
 * the rows skipped. For consumers that need no disparity above a known
 * row, e.g. the detector above the ground at its farthest range
 * (negobs/pipeline.h, stereo_roi). 0 (the state after init) matches
 * every row. The crop's first rows are matched without the rows above
 * them, so they can differ from a full-frame run.
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL unless 0 <= first_row <= height -
 *         NEGOBS_STEREO_MIN_HEIGHT; NEGOBS_ERR_STATE without init.
 */
negobs_status_t negobs_stereo_set_first_row(negobs_stereo_t *ctx,
                                            int32_t first_row);

/**
 * @brief Match the next frame with a vertical offset already known instead
 * of searching it (cfg.vertical_search > 0): for a caller that
 * re-estimates the rig's misalignment only now and then, as the pipeline
 * does (vertical_every_frames). Applies to one frame; the frame after it
 * searches again unless held again. With vertical_search == 0 the
 * configured vertical_offset is used and the hold is ignored.
 * @param offset rows, |offset| <= cfg.vertical_search (the range the search
 *        would have looked in)
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL for an offset outside that range;
 *         NEGOBS_ERR_STATE without init.
 */
negobs_status_t negobs_stereo_hold_vertical_offset(negobs_stereo_t *ctx,
                                                   int32_t offset);

/**
 * @brief Time every stage of the next frames with the caller's clock
 * (stats.stage_ticks). NULL (the state after init) turns it off. The
 * clock is only read, never waited on: the disparities and every other
 * statistic are the same with and without it.
 * @return NEGOBS_OK; NEGOBS_ERR_STATE without init.
 */
negobs_status_t negobs_stereo_set_clock(negobs_stereo_t *ctx,
                                        negobs_stereo_clock_fn clock,
                                        void *user);

/**
 * @brief Call `observer` after the stages listed at
 * negobs_stereo_observer_fn on every following frame; NULL (the state
 * after init) turns it off. The output does not depend on it.
 * @return NEGOBS_OK; NEGOBS_ERR_STATE without init.
 */
negobs_status_t negobs_stereo_set_observer(negobs_stereo_t *ctx,
                                           negobs_stereo_observer_fn observer,
                                           void *user);

/**
 * @brief Run the row bands of the following frames on `exec` (copied);
 * NULL (the state after init) runs them on the caller's thread, in order.
 * The disparities, confidences and statistics are the same either way and
 * for every exec->workers: only cfg.bands shapes the output. The clock
 * (negobs_stereo_set_clock) is then read from the executor's threads too,
 * and the band stages' ticks add up the workers' time; each worker other
 * than the caller reads it on its own thread from the start of each job,
 * so a per-thread clock (thread CPU time) works too.
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL when exec->run is NULL or
 *         exec->workers is outside [1, cfg.band_workers]; NEGOBS_ERR_STATE
 *         without init.
 */
negobs_status_t negobs_stereo_set_executor(negobs_stereo_t *ctx,
                                           const negobs_executor_t *exec);

/**
 * @brief Row bands of a frame of `rows` rows (a crop matches rows -
 * first_row): cfg.bands, or fewer when the frame has fewer strips. Each
 * band is a run of whole strips (strip_rows); the layout depends on the
 * config and the rows only, never on the threads.
 * @return the band count (>= 1), 0 for a NULL cfg or rows < 1.
 */
int32_t negobs_stereo_band_count(const negobs_stereo_config_t *cfg,
                                 int32_t rows);

/**
 * @brief Rows [*y0, *y1) of band `band` (0 .. band_count - 1).
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL for a bad band or argument.
 */
negobs_status_t negobs_stereo_band_rows(const negobs_stereo_config_t *cfg,
                                        int32_t rows, int32_t band,
                                        int32_t *y0, int32_t *y1);

/**
 * @param[in]  left, right rectified grey images of cfg width x height
 * @param[out] disp_q4    width x height, disparity * 16 or
 *                        NEGOBS_DISP_INVALID
 * @param[out] confidence width x height, NEGOBS_STEREO_CONF_* scale (0 =
 *                        no value, 2 filled, 4 textureless, 8..255
 *                        matched); may be NULL
 * @param[out] stats      may be NULL
 * @return NEGOBS_OK (also for textureless input: the map is then invalid),
 *         NEGOBS_ERR_INVAL for mismatched or bad images, NEGOBS_ERR_STATE
 *         without a successful init or when the executor
 *         (negobs_stereo_set_executor) skipped a job or named a worker
 *         outside [0, workers) (the map is then not to be used),
 *         NEGOBS_ERR_CORRUPT if a debug guard of the workspace was
 *         overwritten.
 */
negobs_status_t negobs_stereo_process(negobs_stereo_t *ctx,
                                      const negobs_image_u8_t *left,
                                      const negobs_image_u8_t *right,
                                      negobs_image_s16_t *disp_q4,
                                      negobs_image_u8_t *confidence,
                                      negobs_stereo_stats_t *stats);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_STEREO_H */
