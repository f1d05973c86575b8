/*
 * Rectify table: CRC32, validation and serialisation.
 *
 * The format is specified byte by byte in docs/CALIBRATION.md. The reader
 * never trusts a length or an index from the table before checking it: it
 * first bounds the declared length by the buffer, then checks the CRC over
 * exactly those bytes, and only then derives geometry, which must agree
 * with the declared length.
 */
#include "negobs/rectify.h"

#include <string.h>

#include "table_le.h"

/*
 * CRC-32/IEEE, reflected, four bits at a time: a 16-entry table (64 bytes
 * of flash) instead of the usual 1 KiB, two lookups per byte. The whole
 * table is hashed once per init, so the slower rate does not matter.
 */
/* NEGOBS_RECTIFY_MAGIC without its terminator. */
static const uint8_t magic[8] = {'N', 'G', 'O', 'B', 'R', 'E', 'C', 'T'};

static const uint32_t crc_nibble[16] = {
    0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu,
    0x76DC4190u, 0x6B6B51F4u, 0x4DB26158u, 0x5005713Cu,
    0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
    0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu,
};

uint32_t negobs_rectify_crc32(uint32_t crc, const uint8_t *data, size_t len)
{
    size_t i;
    crc = ~crc;
    for (i = 0; i < len; i++) {
        crc ^= (uint32_t)data[i];
        crc = (crc >> 4) ^ crc_nibble[crc & 0x0Fu];
        crc = (crc >> 4) ^ crc_nibble[crc & 0x0Fu];
    }
    return ~crc;
}

/* Node bytes of one camera's map; sizes were bounded by the caller. */
static size_t map_bytes(int32_t grid_w, int32_t grid_h)
{
    return (size_t)grid_w * (size_t)grid_h * RT_NODE_BYTES;
}

negobs_status_t negobs_rectify_table_size(int32_t width, int32_t height,
                                          int32_t grid_shift,
                                          size_t *bytes_out)
{
    int32_t gw;
    int32_t gh;
    if (bytes_out == NULL || width < 1 || height < 1 ||
        width > NEGOBS_MAX_DIM || height > NEGOBS_MAX_DIM || grid_shift < 0 ||
        grid_shift > NEGOBS_RECTIFY_MAX_GRID_SHIFT) {
        return NEGOBS_ERR_INVAL;
    }
    gw = NEGOBS_RECTIFY_GRID_NODES(width, grid_shift);
    gh = NEGOBS_RECTIFY_GRID_NODES(height, grid_shift);
    *bytes_out = (size_t)NEGOBS_RECTIFY_HEADER_BYTES + 2u * map_bytes(gw, gh) +
                 4u;
    return NEGOBS_OK;
}

/* Every node of a map within +-NEGOBS_RECTIFY_COORD_LIMIT_Q8. */
static int nodes_in_range(const uint8_t *p, size_t bytes)
{
    size_t i;
    for (i = 0; i < bytes; i += 4u) {
        int32_t v = negobs_rd_s32le(p + i);
        if (v < -NEGOBS_RECTIFY_COORD_LIMIT_Q8 ||
            v > NEGOBS_RECTIFY_COORD_LIMIT_Q8) {
            return 0;
        }
    }
    return 1;
}

negobs_status_t negobs_rectify_table_check(const uint8_t *table, size_t len,
                                           int32_t width, int32_t height,
                                           negobs_rectify_info_t *info)
{
    negobs_rectify_info_t in;
    uint32_t header_bytes;
    uint32_t total;
    uint32_t shift;
    size_t maps;

    if (table == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    /* 1. Framing: header present, magic, a version we read. */
    if (len < (size_t)NEGOBS_RECTIFY_HEADER_BYTES) {
        return NEGOBS_ERR_CORRUPT;
    }
    if (memcmp(table + RT_OFF_MAGIC, magic, sizeof magic) != 0) {
        return NEGOBS_ERR_CORRUPT;
    }
    memset(&in, 0, sizeof in);
    in.version_major = negobs_rd_u16le(table + RT_OFF_VMAJOR);
    in.version_minor = negobs_rd_u16le(table + RT_OFF_VMINOR);
    if (in.version_major != NEGOBS_RECTIFY_VERSION_MAJOR) {
        return NEGOBS_ERR_UNSUPPORTED;
    }

    /* 2. Declared length within the buffer, then the checksum over it. */
    header_bytes = negobs_rd_u32le(table + RT_OFF_HEADER_BYTES);
    total = negobs_rd_u32le(table + RT_OFF_TOTAL_BYTES);
    if (header_bytes < (uint32_t)NEGOBS_RECTIFY_HEADER_BYTES ||
        (header_bytes % 4u) != 0u || total < 4u || header_bytes > total - 4u ||
        (size_t)total > len) {
        return NEGOBS_ERR_CORRUPT;
    }
    if (negobs_rectify_crc32(0, table, (size_t)total - 4u) !=
        negobs_rd_u32le(table + total - 4u)) {
        return NEGOBS_ERR_CORRUPT;
    }

    /* 3. Geometry: what this build can apply, then self-consistency. */
    in.width = (int32_t)negobs_rd_u16le(table + RT_OFF_WIDTH);
    in.height = (int32_t)negobs_rd_u16le(table + RT_OFF_HEIGHT);
    shift = (uint32_t)table[RT_OFF_GRID_SHIFT];
    if (in.width < 1 || in.height < 1) {
        return NEGOBS_ERR_CORRUPT;
    }
    if (in.width > NEGOBS_MAX_DIM || in.height > NEGOBS_MAX_DIM ||
        shift > (uint32_t)NEGOBS_RECTIFY_MAX_GRID_SHIFT ||
        table[RT_OFF_FRAC_BITS] != (uint8_t)NEGOBS_RECTIFY_FRAC_BITS ||
        negobs_rd_u16le(table + RT_OFF_FLAGS) != 0u) {
        return NEGOBS_ERR_UNSUPPORTED;
    }
    in.grid_shift = (int32_t)shift;
    in.grid_w = NEGOBS_RECTIFY_GRID_NODES(in.width, in.grid_shift);
    in.grid_h = NEGOBS_RECTIFY_GRID_NODES(in.height, in.grid_shift);
    if ((int32_t)negobs_rd_u16le(table + RT_OFF_GRID_W) != in.grid_w ||
        (int32_t)negobs_rd_u16le(table + RT_OFF_GRID_H) != in.grid_h) {
        return NEGOBS_ERR_CORRUPT;
    }
    maps = 2u * map_bytes(in.grid_w, in.grid_h);
    if ((size_t)total != (size_t)header_bytes + maps + 4u) {
        return NEGOBS_ERR_CORRUPT;
    }
    if (!nodes_in_range(table + header_bytes, maps)) {
        return NEGOBS_ERR_CORRUPT;
    }

    /* 4. Calibration values are carried, not interpreted. */
    in.f_q16 = negobs_rd_u32le(table + RT_OFF_F_Q16);
    in.baseline_um = negobs_rd_u32le(table + RT_OFF_BASELINE_UM);
    in.cx_q16 = negobs_rd_s32le(table + RT_OFF_CX_Q16);
    in.cy_q16 = negobs_rd_s32le(table + RT_OFF_CY_Q16);
    in.doffs_q16 = negobs_rd_s32le(table + RT_OFF_DOFFS_Q16);
    in.rms_mpx = negobs_rd_u32le(table + RT_OFF_RMS_MPX);
    in.total_bytes = (size_t)total;

    /* 5. The table must describe the frame the caller configured. */
    if ((width != 0 || height != 0) &&
        (width != in.width || height != in.height)) {
        return NEGOBS_ERR_INVAL;
    }
    if (info != NULL) {
        *info = in;
    }
    return NEGOBS_OK;
}

/* Write one camera's nodes; NEGOBS_ERR_RANGE when one is out of limits. */
static negobs_status_t write_map(uint8_t *dst, const int32_t *q8, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        if (q8[i] < -NEGOBS_RECTIFY_COORD_LIMIT_Q8 ||
            q8[i] > NEGOBS_RECTIFY_COORD_LIMIT_Q8) {
            return NEGOBS_ERR_RANGE;
        }
        negobs_wr_s32le(dst + 4u * i, q8[i]);
    }
    return NEGOBS_OK;
}

negobs_status_t negobs_rectify_table_write(const negobs_rectify_info_t *info,
                                           const int32_t *left_q8,
                                           const int32_t *right_q8,
                                           uint8_t *out, size_t out_len,
                                           size_t *written)
{
    size_t total;
    size_t per_map;
    size_t nvals;
    int32_t gw;
    int32_t gh;
    uint8_t *p;
    negobs_status_t st;

    if (info == NULL || left_q8 == NULL || right_q8 == NULL || out == NULL) {
        return NEGOBS_ERR_INVAL;
    }
    st = negobs_rectify_table_size(info->width, info->height, info->grid_shift,
                                   &total);
    if (st != NEGOBS_OK) {
        return st;
    }
    if (total > (size_t)UINT32_MAX) {
        return NEGOBS_ERR_RANGE;
    }
    if (out_len < total) {
        return NEGOBS_ERR_NOSPACE;
    }
    gw = NEGOBS_RECTIFY_GRID_NODES(info->width, info->grid_shift);
    gh = NEGOBS_RECTIFY_GRID_NODES(info->height, info->grid_shift);
    per_map = map_bytes(gw, gh);
    nvals = per_map / 4u;

    p = out;
    memset(p, 0, (size_t)NEGOBS_RECTIFY_HEADER_BYTES);
    memcpy(p + RT_OFF_MAGIC, magic, sizeof magic);
    negobs_wr_u16le(p + RT_OFF_VMAJOR, (uint16_t)NEGOBS_RECTIFY_VERSION_MAJOR);
    negobs_wr_u16le(p + RT_OFF_VMINOR, (uint16_t)NEGOBS_RECTIFY_VERSION_MINOR);
    negobs_wr_u32le(p + RT_OFF_HEADER_BYTES,
                    (uint32_t)NEGOBS_RECTIFY_HEADER_BYTES);
    negobs_wr_u32le(p + RT_OFF_TOTAL_BYTES, (uint32_t)total);
    negobs_wr_u16le(p + RT_OFF_WIDTH, (uint16_t)info->width);
    negobs_wr_u16le(p + RT_OFF_HEIGHT, (uint16_t)info->height);
    p[RT_OFF_GRID_SHIFT] = (uint8_t)info->grid_shift;
    p[RT_OFF_FRAC_BITS] = (uint8_t)NEGOBS_RECTIFY_FRAC_BITS;
    negobs_wr_u16le(p + RT_OFF_FLAGS, 0u);
    negobs_wr_u16le(p + RT_OFF_GRID_W, (uint16_t)gw);
    negobs_wr_u16le(p + RT_OFF_GRID_H, (uint16_t)gh);
    negobs_wr_u32le(p + RT_OFF_F_Q16, info->f_q16);
    negobs_wr_u32le(p + RT_OFF_BASELINE_UM, info->baseline_um);
    negobs_wr_s32le(p + RT_OFF_CX_Q16, info->cx_q16);
    negobs_wr_s32le(p + RT_OFF_CY_Q16, info->cy_q16);
    negobs_wr_s32le(p + RT_OFF_DOFFS_Q16, info->doffs_q16);
    negobs_wr_u32le(p + RT_OFF_RMS_MPX, info->rms_mpx);

    p += NEGOBS_RECTIFY_HEADER_BYTES;
    st = write_map(p, left_q8, nvals);
    if (st != NEGOBS_OK) {
        return st;
    }
    st = write_map(p + per_map, right_q8, nvals);
    if (st != NEGOBS_OK) {
        return st;
    }
    negobs_wr_u32le(out + total - 4u,
                    negobs_rectify_crc32(0, out, total - 4u));
    if (written != NULL) {
        *written = total;
    }
    return NEGOBS_OK;
}
