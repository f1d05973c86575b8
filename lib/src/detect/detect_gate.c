/* Step 0, the image gate: photometric statistics and their reasons
 * (docs/DETECTION.md section 7). */
#include "detect_internal.h"

negobs_status_t negobs_detect_photo_stats(const negobs_image_u8_t *img,
                                          negobs_photo_stats_t *out)
{
    int32_t x;
    int32_t y;
    uint64_t sum = 0;
    uint64_t grad = 0;
    uint32_t n = 0;
    uint32_t ng = 0;
    uint32_t dark = 0;
    uint32_t sat = 0;
    if (out == NULL || negobs_image_u8_check(img) != NEGOBS_OK) {
        return NEGOBS_ERR_INVAL;
    }
    for (y = 0; y < img->height; y += 2) {
        const uint8_t *row = negobs_image_u8_row(img, y);
        for (x = 0; x < img->width; x += 2) {
            uint32_t p = row[x];
            sum += p;
            n++;
            dark += (p <= 8u) ? 1u : 0u;
            sat += (p >= 250u) ? 1u : 0u;
            if (x + 1 < img->width) {
                int32_t g = (int32_t)row[x + 1] - (int32_t)p;
                grad += (uint32_t)negobs_abs_s32(g);
                ng++;
            }
        }
    }
    if (n == 0) {
        return NEGOBS_ERR_INVAL; /* no pixel sampled */
    }
    out->mean = (int32_t)(sum / n);
    out->dark_permille = (int32_t)(((uint64_t)dark * 1000u) / n);
    out->saturated_permille = (int32_t)(((uint64_t)sat * 1000u) / n);
    out->texture_q4 = ng ? (int32_t)((grad * 16u) / ng) : 0;
    return NEGOBS_OK;
}

uint32_t det_photo_reasons(const negobs_detect_config_t *cfg,
                           const negobs_photo_stats_t *s)
{
    uint32_t r = 0;
    if (s->mean < cfg->dark_mean_min ||
        s->dark_permille > cfg->dark_max_permille) {
        r |= NEGOBS_DEGRADED_TOO_DARK;
    }
    if (s->saturated_permille > cfg->saturated_max_permille) {
        r |= NEGOBS_DEGRADED_SATURATED;
    }
    if (s->texture_q4 < cfg->texture_min_q4) {
        r |= NEGOBS_DEGRADED_LOW_TEXTURE;
    }
    return r;
}
