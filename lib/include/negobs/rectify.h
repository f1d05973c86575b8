/*
 * Stereo rectification from a versioned, checksummed remap table.
 *
 * A host tool (tools/calib/negobs_calib) calibrates the rig with OpenCV and
 * writes a binary table; the device hands the table bytes to this module,
 * which validates them (magic, version, sizes, CRC32, value ranges) and then
 * rectifies each frame with integer bilinear interpolation into caller
 * memory. docs/CALIBRATION.md describes the table byte by byte.
 *
 * Remap model. For each camera the table stores, on a grid of nodes every
 * 2^grid_shift pixels, the source coordinate (x, y) in the raw image that
 * lands on the rectified pixel at the node, in 1/256 pixel (Q.8). Between
 * nodes the map is interpolated bilinearly in exact integer arithmetic,
 * then the raw image is sampled bilinearly at that Q.8 coordinate. A
 * rectified pixel whose source lies outside the raw image gets
 * `border_u8`.
 *
 * Scaling and overflow. Nodes are int32 Q.8 limited to
 * |c| <= NEGOBS_RECTIFY_COORD_LIMIT_Q8 (8192 px = 2^21 raw). Vertical
 * interpolation between node rows gives Q.(8+s) (<= 2^25 for s <= 4), the
 * horizontal one Q.(8+2s) (<= 2^29): both fit int32 with guard bits. The
 * per-pixel coordinate is rounded half-up back to Q.8. Sampling weights are
 * 8-bit (0..256): a row blend of two u8 pixels is <= 255 * 256 (Q.8), the
 * column blend <= 255 * 2^16 (Q.16, 24 bits), rounded half-up to u8. The
 * result is the correctly rounded bilinear value at the Q.8 coordinate, so
 * every build and target gives bit-identical output.
 *
 * Typical use:
 *   negobs_rectify_config_default(&cfg, 640, 480);
 *   cfg.table = bytes; cfg.table_bytes = n;     (stays valid, see below)
 *   negobs_rectify_workspace_size(&cfg, &ws);
 *   negobs_rectify_init(&ctx, &cfg, workspace, ws);
 *   per frame: negobs_rectify_process(&ctx, &raw_l, &raw_r, &rect_l,
 *                                     &rect_r, &stats);
 */
#ifndef NEGOBS_RECTIFY_H
#define NEGOBS_RECTIFY_H

#include <stddef.h>
#include <stdint.h>

#include "negobs/image.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Table magic, the first 8 bytes of every table: "NGOBRECT". */
#define NEGOBS_RECTIFY_MAGIC "NGOBRECT"
/** Major version this library reads and writes (incompatible changes). */
#define NEGOBS_RECTIFY_VERSION_MAJOR 1
/** Minor version written (compatible additions; any minor is read). */
#define NEGOBS_RECTIFY_VERSION_MINOR 0
/** Header bytes written by this version (maps start here). */
#define NEGOBS_RECTIFY_HEADER_BYTES 64
/** Fractional bits of map coordinates (Q.8, 1/256 pixel). */
#define NEGOBS_RECTIFY_FRAC_BITS 8
/** One pixel in map units. */
#define NEGOBS_RECTIFY_ONE_Q8 256
/** Largest grid shift (node spacing 2^4 = 16 pixels). */
#define NEGOBS_RECTIFY_MAX_GRID_SHIFT 4
/** Largest |coordinate| a node may hold, Q.8 (8192 pixels). */
#define NEGOBS_RECTIFY_COORD_LIMIT_Q8 ((int32_t)8192 * 256)
/** Marker in rms_mpx when the table carries no reprojection error. */
#define NEGOBS_RECTIFY_RMS_UNKNOWN 0xFFFFFFFFu

/** Camera index in a table. */
typedef enum negobs_rectify_camera {
    NEGOBS_RECTIFY_CAMERA_LEFT = 0,
    NEGOBS_RECTIFY_CAMERA_RIGHT = 1
} negobs_rectify_camera_t;

/** Grid nodes along a side of `n` pixels: ((n - 1) >> shift) + 2. */
#define NEGOBS_RECTIFY_GRID_NODES(n, shift) ((((n)-1) >> (shift)) + 2)

/**
 * Upper bound of negobs_rectify_workspace_size() for frames up to `width`
 * pixels wide, as a constant expression for static arrays: one row of
 * interpolated nodes (x and y, int32) for the finest grid, plus alignment
 * and debug guard slack.
 */
#define NEGOBS_RECTIFY_WORKSPACE_MAX(width)                                   \
    ((size_t)8 * (size_t)((width) + 1) + (size_t)64)

/** Decoded table header (everything but the maps). */
typedef struct negobs_rectify_info {
    uint16_t version_major; /**< NEGOBS_RECTIFY_VERSION_MAJOR          */
    uint16_t version_minor; /**< writer's minor version                 */
    int32_t width;          /**< frame width (pixels)                   */
    int32_t height;         /**< frame height (pixels)                  */
    int32_t grid_shift;     /**< node spacing 2^grid_shift px, 0..4     */
    int32_t grid_w;         /**< nodes per grid row                     */
    int32_t grid_h;         /**< node rows                              */
    uint32_t f_q16;         /**< rectified focal length, px * 65536     */
    uint32_t baseline_um;   /**< camera distance (micrometres)          */
    int32_t cx_q16;         /**< rectified principal point x, px*65536  */
    int32_t cy_q16;         /**< rectified principal point y, px*65536  */
    int32_t doffs_q16;      /**< cx(right) - cx(left), px * 65536       */
    uint32_t rms_mpx;       /**< calibration RMS reprojection error,
                                 milli-pixels, or RECTIFY_RMS_UNKNOWN   */
    size_t total_bytes;     /**< table length including the CRC          */
} negobs_rectify_info_t;

/**
 * @brief CRC-32 (IEEE 802.3: reflected polynomial 0xEDB88320, initial
 *        value and final XOR 0xFFFFFFFF) of `len` bytes.
 *
 * Pass crc = 0 to start; feed the previous result to continue a stream.
 * Check value: "123456789" -> 0xCBF43926.
 */
uint32_t negobs_rectify_crc32(uint32_t crc, const uint8_t *data, size_t len);

/**
 * @brief Table length for a frame size and grid:
 *        64 + 2 * grid_w * grid_h * 8 + 4 bytes.
 * @return NEGOBS_OK, or NEGOBS_ERR_INVAL (size outside 1..NEGOBS_MAX_DIM,
 *         grid_shift outside 0..NEGOBS_RECTIFY_MAX_GRID_SHIFT, NULL out).
 */
negobs_status_t negobs_rectify_table_size(int32_t width, int32_t height,
                                          int32_t grid_shift,
                                          size_t *bytes_out);

/**
 * @brief Validate a table and decode its header, without a context.
 *
 * Checks, in this order: buffer present and at least the 64-byte header
 * (else CORRUPT), magic (CORRUPT), major version and the bytes it declares
 * (UNSUPPORTED), declared length <= len (CORRUPT: truncated), CRC32
 * (CORRUPT), header consistency and every node within
 * NEGOBS_RECTIFY_COORD_LIMIT_Q8 (CORRUPT), grid shift, coordinate format
 * and flags this build can apply (UNSUPPORTED), and finally the frame size
 * against width x height when both are non-zero (INVAL: mismatched table).
 * Bytes after the declared length are ignored (a table may sit in a larger
 * flash partition).
 *
 * @param[in]  table   table bytes (any alignment)
 * @param[in]  len     bytes available at table
 * @param[in]  width   expected frame width, or 0 to accept any
 * @param[in]  height  expected frame height, or 0 to accept any
 * @param[out] info    decoded header; may be NULL
 * @return NEGOBS_OK, NEGOBS_ERR_CORRUPT, NEGOBS_ERR_UNSUPPORTED or
 *         NEGOBS_ERR_INVAL (NULL table, or size mismatch).
 */
negobs_status_t negobs_rectify_table_check(const uint8_t *table, size_t len,
                                           int32_t width, int32_t height,
                                           negobs_rectify_info_t *info);

/**
 * @brief Serialise a table (header, both maps, CRC32) into `out`.
 *
 * The header fields come from `info` (width, height, grid_shift, f_q16,
 * baseline_um, cx_q16, cy_q16, doffs_q16, rms_mpx; the rest is derived).
 * Each map is grid_h * grid_w pairs (x, y), row-major, interleaved, in Q.8
 * source pixels; node (i, j) is the rectified pixel (i << s, j << s).
 *
 * @param[in]  info     header values
 * @param[in]  left_q8  2 * grid_w * grid_h int32 for the left camera
 * @param[in]  right_q8 the same for the right camera
 * @param[out] out      receives negobs_rectify_table_size() bytes
 * @param[in]  out_len  bytes available at out
 * @param[out] written  bytes written; may be NULL
 * @return NEGOBS_OK, NEGOBS_ERR_INVAL (bad geometry or NULL),
 *         NEGOBS_ERR_RANGE (a node beyond NEGOBS_RECTIFY_COORD_LIMIT_Q8)
 *         or NEGOBS_ERR_NOSPACE (out_len too small).
 */
negobs_status_t negobs_rectify_table_write(const negobs_rectify_info_t *info,
                                           const int32_t *left_q8,
                                           const int32_t *right_q8,
                                           uint8_t *out, size_t out_len,
                                           size_t *written);

/** Configuration; zero it, then call negobs_rectify_config_default(). */
typedef struct negobs_rectify_config {
    int32_t width;        /**< frame width, raw = rectified (pixels)   */
    int32_t height;       /**< frame height (pixels)                   */
    const uint8_t *table; /**< table bytes; must stay valid and unchanged
                               while the context is used (no copy)     */
    size_t table_bytes;   /**< bytes available at table                */
    uint8_t border_u8;    /**< value of pixels whose source is outside
                               the raw image (default 0)               */
} negobs_rectify_config_t;

/** Per-call statistics. */
typedef struct negobs_rectify_stats {
    uint32_t border_pixels; /**< output pixels set to border_u8          */
} negobs_rectify_stats_t;

/** Context; place it anywhere (static is fine). Fields are private. */
typedef struct negobs_rectify {
    const negobs_rectify_config_t *cfg;
    negobs_rectify_info_t info;
    const uint8_t *map[2]; /* first node of each camera's map in table */
    int32_t *row_q;        /* workspace: 2 * grid_w interpolated nodes  */
    uint32_t ready;        /* magic once init succeeded                  */
} negobs_rectify_t;

/** @brief Defaults for a width x height frame (no table, border 0). */
void negobs_rectify_config_default(negobs_rectify_config_t *cfg, int32_t width,
                                   int32_t height);

/**
 * @brief Exact workspace bytes for cfg (depends on width only; <=
 *        NEGOBS_RECTIFY_WORKSPACE_MAX(width)).
 * @return NEGOBS_OK or NEGOBS_ERR_INVAL (bad size, NULL).
 */
negobs_status_t negobs_rectify_workspace_size(
    const negobs_rectify_config_t *cfg, size_t *bytes_out);

/**
 * @brief Validate cfg and its table (see negobs_rectify_table_check()) and
 *        carve the workspace.
 *
 * cfg and cfg->table must outlive the context.
 * @param[in] workspace 16-byte aligned, workspace_bytes long
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL (bad cfg, NULL, table for another
 *         frame size); NEGOBS_ERR_CORRUPT / NEGOBS_ERR_UNSUPPORTED (table);
 *         NEGOBS_ERR_ALIGN; NEGOBS_ERR_NOSPACE (workspace too small).
 */
negobs_status_t negobs_rectify_init(negobs_rectify_t *ctx,
                                    const negobs_rectify_config_t *cfg,
                                    void *workspace, size_t workspace_bytes);

/**
 * @brief Rectify rows [y0, y1) of one camera's frame (bounded latency).
 *
 * @param[in]  raw  width x height raw image of that camera
 * @param[out] rect width x height; only rows y0..y1-1 are written; must
 *                  not overlap raw
 * @param[out] stats border count of these rows; may be NULL
 * @return NEGOBS_OK, NEGOBS_ERR_STATE (no successful init),
 *         NEGOBS_ERR_INVAL (bad image, size, overlap, camera or rows).
 */
negobs_status_t negobs_rectify_rows(negobs_rectify_t *ctx,
                                    negobs_rectify_camera_t camera,
                                    const negobs_image_u8_t *raw,
                                    negobs_image_u8_t *rect, int32_t y0,
                                    int32_t y1, negobs_rectify_stats_t *stats);

/**
 * @brief Rectify a stereo pair (both cameras, all rows).
 * @param[out] stats border pixels of both images; may be NULL
 * @return as negobs_rectify_rows().
 */
negobs_status_t negobs_rectify_process(negobs_rectify_t *ctx,
                                       const negobs_image_u8_t *left,
                                       const negobs_image_u8_t *right,
                                       negobs_image_u8_t *left_rect,
                                       negobs_image_u8_t *right_rect,
                                       negobs_rectify_stats_t *stats);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_RECTIFY_H */
