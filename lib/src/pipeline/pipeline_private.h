/*
 * The pipeline context's layout. Only the library and its unit tests
 * include this header: tools and the app see negobs_pipeline_t as storage
 * of the right size and alignment (negobs/pipeline.h) and reach the
 * stages through the pipeline's functions only, so a stage can change
 * its context without touching any caller.
 */
#ifndef NEGOBS_PIPELINE_PRIVATE_H
#define NEGOBS_PIPELINE_PRIVATE_H

#include "negobs/pipeline.h"

typedef struct negobs_pipeline_priv {
    negobs_pipeline_config_t cfg;
    negobs_valign_t valign;
    negobs_image_u8_t right_aligned; /* valign.enable: the matcher's right */
    negobs_stereo_t stereo;
    negobs_detect_t detect;
    negobs_alert_t alert;
    negobs_image_s16_t disp_q4;
    negobs_image_u8_t confidence;
    negobs_pipeline_clock_fn clock; /* NULL: no stage timings */
    void *clock_user;
    uint32_t magic;
    uint32_t vframes;             /* frames since the last vertical search   */
    int32_t voff;                 /* the offset that search found (rows)     */
    int32_t coarse;               /* 1: the half-resolution pass is set up   */
    negobs_stereo_t stereo_half;  /* the matcher on the half-size pair */
    negobs_image_u8_t left_half;  /* 2x2 averages of the left image    */
    negobs_image_u8_t right_half; /* ... of the right image matched    */
    negobs_image_s16_t disp_half; /* its map (disp_q4 of the half size) */
    negobs_image_u8_t conf_half;  /* its confidence                    */
} negobs_pipeline_priv_t;

/* The public storage is declared with the same members in the same order
 * (negobs_pipeline_t.opaque_), so size and alignment follow every stage
 * context on every target; pipeline.c checks it at compile time. */
static inline negobs_pipeline_priv_t *negobs_pipeline_priv(
    negobs_pipeline_t *ctx)
{
    return (negobs_pipeline_priv_t *)(void *)ctx;
}

static inline const negobs_pipeline_priv_t *negobs_pipeline_priv_const(
    const negobs_pipeline_t *ctx)
{
    return (const negobs_pipeline_priv_t *)(const void *)ctx;
}

#endif /* NEGOBS_PIPELINE_PRIVATE_H */
