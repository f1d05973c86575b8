/*
 * Image-quality gate: the stand-in for the full pipeline (see the header).
 *
 * Each image is first subsampled by an integer factor to at most
 * APP_DEC_MAX_W x APP_DEC_MAX_H, so the static scratch is a few hundred
 * kilobytes whatever the camera size and the cost is bounded. On that
 * small image we measure the mean grey level, the share of saturated
 * pixels (>= 250) and the share of 5x5 windows whose standard deviation
 * reaches texture_std_min (from negobs_boxsum_u8: 25 * Q - S^2 >=
 * (5 * std)^2, all in int32: S <= 6375, Q <= 1 625 625).
 */
#include <stddef.h>
#include <string.h>

#include "app_pipeline.h"
#include "negobs/boxsum.h"

#define APP_DEC_MAX_W 320
#define APP_DEC_MAX_H 240
#define APP_TEX_RADIUS 2
#define APP_SAT_LEVEL 250

static uint8_t dec_img[APP_DEC_MAX_W * APP_DEC_MAX_H];
static uint16_t box_sum[APP_DEC_MAX_W * APP_DEC_MAX_H];
static uint32_t box_sq[APP_DEC_MAX_W * APP_DEC_MAX_H];
static uint32_t col_buf[2 * APP_DEC_MAX_W];

void app_pipeline_config_default(app_pipeline_config_t *cfg)
{
    cfg->dark_mean_min = 20;
    cfg->sat_permille_max = 300;
    cfg->texture_std_min = 4;
    cfg->texture_permille_min = 20;
    cfg->lr_mean_diff_max = 60;
}

negobs_status_t app_pipeline_init(app_pipeline_t *p,
                                  const app_pipeline_config_t *cfg)
{
    if (p == NULL || cfg == NULL || cfg->dark_mean_min < 0 ||
        cfg->dark_mean_min > 255 || cfg->sat_permille_max < 0 ||
        cfg->sat_permille_max > 1000 || cfg->texture_std_min < 0 ||
        cfg->texture_std_min > 127 || cfg->texture_permille_min < 0 ||
        cfg->texture_permille_min > 1000 || cfg->lr_mean_diff_max < 0 ||
        cfg->lr_mean_diff_max > 255) {
        return NEGOBS_ERR_INVAL;
    }
    memset(p, 0, sizeof *p);
    p->cfg = *cfg;
    return NEGOBS_OK;
}

static int32_t ceil_div(int32_t a, int32_t b)
{
    return (a + b - 1) / b;
}

/* Measure one image; returns NEGOBS_OK or _INVAL. */
static negobs_status_t measure(const negobs_image_u8_t *img, int32_t tex_std,
                               int32_t *mean, int32_t *sat_pm,
                               int32_t *tex_pm)
{
    negobs_image_u8_t d;
    int32_t f;
    int32_t x;
    int32_t y;
    uint32_t total = 0;
    uint32_t sat = 0;
    uint32_t textured = 0;
    uint32_t windows = 0;
    int32_t thr = (5 * tex_std) * (5 * tex_std);
    if (negobs_image_u8_check(img) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    f = ceil_div(img->width, APP_DEC_MAX_W);
    if (ceil_div(img->height, APP_DEC_MAX_H) > f) {
        f = ceil_div(img->height, APP_DEC_MAX_H);
    }
    d.data = dec_img;
    d.width = img->width / f;
    d.height = img->height / f;
    d.stride = d.width;
    if (d.width < 2 * APP_TEX_RADIUS + 1 || d.height < 2 * APP_TEX_RADIUS + 1) {
        return NEGOBS_ERR_INVAL;
    }
    for (y = 0; y < d.height; y++) {
        const uint8_t *src = negobs_image_u8_row(img, y * f);
        uint8_t *dst = negobs_image_u8_row(&d, y);
        for (x = 0; x < d.width; x++) {
            uint8_t v = src[x * f];
            dst[x] = v;
            total += v;
            sat += v >= APP_SAT_LEVEL ? 1u : 0u;
        }
    }
    if (negobs_boxsum_u8(&d, APP_TEX_RADIUS, box_sum, d.width, box_sq,
                         d.width, col_buf) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    for (y = APP_TEX_RADIUS; y < d.height - APP_TEX_RADIUS; y++) {
        for (x = APP_TEX_RADIUS; x < d.width - APP_TEX_RADIUS; x++) {
            size_t i = (size_t)y * (size_t)d.width + (size_t)x;
            int32_t s = (int32_t)box_sum[i];
            int32_t var25 = 25 * (int32_t)box_sq[i] - s * s;
            windows++;
            textured += var25 >= thr ? 1u : 0u;
        }
    }
    *mean = (int32_t)(total / ((uint32_t)d.width * (uint32_t)d.height));
    *sat_pm = (int32_t)((uint64_t)sat * 1000u /
                        ((uint32_t)d.width * (uint32_t)d.height));
    *tex_pm = (int32_t)((uint64_t)textured * 1000u / windows);
    return NEGOBS_OK;
}

app_verdict_t app_process_pair(app_pipeline_t *p,
                               const negobs_image_u8_t *left,
                               const negobs_image_u8_t *right)
{
    const negobs_image_u8_t *img[2];
    app_frame_stats_t *st = &p->last;
    int i;
    img[0] = left;
    img[1] = right;
    memset(st, 0, sizeof *st);
    if (left == NULL || right == NULL || left->width != right->width ||
        left->height != right->height) {
        st->reason = APP_REASON_BAD_INPUT;
        return APP_VERDICT_NO_INFO;
    }
    for (i = 0; i < 2; i++) {
        if (measure(img[i], p->cfg.texture_std_min, &st->mean[i],
                    &st->sat_permille[i],
                    &st->texture_permille[i]) != NEGOBS_OK) {
            st->reason = APP_REASON_BAD_INPUT;
            return APP_VERDICT_NO_INFO;
        }
    }
    for (i = 0; i < 2 && st->reason == APP_REASON_NONE; i++) {
        if (st->mean[i] < p->cfg.dark_mean_min) {
            st->reason = APP_REASON_DARK;
        } else if (st->sat_permille[i] > p->cfg.sat_permille_max) {
            st->reason = APP_REASON_SATURATED;
        } else if (st->texture_permille[i] < p->cfg.texture_permille_min) {
            st->reason = APP_REASON_TEXTURELESS;
        }
    }
    if (st->reason == APP_REASON_NONE) {
        int32_t d = st->mean[0] - st->mean[1];
        if (d < 0) {
            d = -d;
        }
        if (d > p->cfg.lr_mean_diff_max) {
            st->reason = APP_REASON_MISMATCH;
        }
    }
    if (st->reason != APP_REASON_NONE) {
        return APP_VERDICT_NO_INFO;
    }
    /* NOT WIRED: stereo matching, ground fit and drop-off detection go
     * here. Until then a usable pair is reported as CLEAR. */
    return APP_VERDICT_CLEAR;
}

const char *app_verdict_name(app_verdict_t v)
{
    switch (v) {
    case APP_VERDICT_NO_INFO: return "no-info";
    case APP_VERDICT_CLEAR: return "clear";
    case APP_VERDICT_CAUTION: return "caution";
    case APP_VERDICT_IMMINENT: return "imminent";
    default: return "?";
    }
}

const char *app_reason_name(app_reason_t r)
{
    switch (r) {
    case APP_REASON_NONE: return "-";
    case APP_REASON_BAD_INPUT: return "bad-input";
    case APP_REASON_DARK: return "dark";
    case APP_REASON_SATURATED: return "saturated";
    case APP_REASON_TEXTURELESS: return "textureless";
    case APP_REASON_MISMATCH: return "lr-mismatch";
    default: return "?";
    }
}
