/*
 * Little-endian field access for the rectify table (internal).
 *
 * Tables are byte streams of any alignment, so fields are assembled byte by
 * byte; this is endian-independent and costs nothing measurable because
 * the remap reads one node row per output row, not per pixel.
 */
#ifndef NEGOBS_RECTIFY_TABLE_LE_H
#define NEGOBS_RECTIFY_TABLE_LE_H

#include <stdint.h>

static inline uint16_t negobs_rd_u16le(const uint8_t *p)
{
    return (uint16_t)((uint32_t)p[0] | ((uint32_t)p[1] << 8));
}

static inline uint32_t negobs_rd_u32le(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
           ((uint32_t)p[3] << 24);
}

/* Two's complement int32 from its 32 bits, without implementation-defined
 * conversion of values above INT32_MAX. */
static inline int32_t negobs_rd_s32le(const uint8_t *p)
{
    uint32_t u = negobs_rd_u32le(p);
    if (u <= (uint32_t)INT32_MAX) {
        return (int32_t)u;
    }
    return -(int32_t)(~u) - 1;
}

static inline void negobs_wr_u16le(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

static inline void negobs_wr_u32le(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)((v >> 8) & 0xFFu);
    p[2] = (uint8_t)((v >> 16) & 0xFFu);
    p[3] = (uint8_t)(v >> 24);
}

static inline void negobs_wr_s32le(uint8_t *p, int32_t v)
{
    negobs_wr_u32le(p, (uint32_t)v);
}

/* Byte offsets of the v1 header fields (docs/CALIBRATION.md). */
enum negobs_rectify_offsets {
    RT_OFF_MAGIC = 0,
    RT_OFF_VMAJOR = 8,
    RT_OFF_VMINOR = 10,
    RT_OFF_HEADER_BYTES = 12,
    RT_OFF_TOTAL_BYTES = 16,
    RT_OFF_WIDTH = 20,
    RT_OFF_HEIGHT = 22,
    RT_OFF_GRID_SHIFT = 24,
    RT_OFF_FRAC_BITS = 25,
    RT_OFF_FLAGS = 26,
    RT_OFF_GRID_W = 28,
    RT_OFF_GRID_H = 30,
    RT_OFF_F_Q16 = 32,
    RT_OFF_BASELINE_UM = 36,
    RT_OFF_CX_Q16 = 40,
    RT_OFF_CY_Q16 = 44,
    RT_OFF_DOFFS_Q16 = 48,
    RT_OFF_RMS_MPX = 52,
    RT_OFF_RESERVED = 56
};

/* Bytes per node: x then y, int32 each. */
#define RT_NODE_BYTES 8u

#endif /* NEGOBS_RECTIFY_TABLE_LE_H */
