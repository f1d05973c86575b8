/* Is there texture under a candidate? The sensor noise of the left image
 * and the local contrast in a hazard's box (docs/DETECTION.md section 10,
 * "Texture under a candidate"). */
#include "detect_internal.h"

/* The largest median reported: 24 is a sensor noise of 6 grey levels
 * (4.05 sigma), about the most a camera shows in the dim light the
 * photometric gate still lets through. An image that reads more is
 * covered by texture as fine as the pixels, which the estimator cannot
 * tell from noise; capped, the box test then still passes windows of
 * twelve grey levels' deviation, rather than failing a textured floor. */
enum { NOISE_MEDIAN_MAX = 24, NOISE_BINS_MAX = NOISE_MEDIAN_MAX + 1 };

/*
 * Median of |N * I| over every second pixel of every second row, N the
 * 3x3 mask (1 -2 1; -2 4 -2; 1 -2 1). The mask cancels constant and
 * linear intensity, and for pure noise of sigma s its response is normal
 * with a deviation of 6 s (the mask's L2 norm), so the median of |N * I|
 * is 6 x 0.6745 s = 4.05 s (Immerkaer's estimator, with the median in
 * place of the mean: texture adds a tail, which moves the median less).
 * Fine texture still raises it, so this is an upper bound of the noise,
 * which makes the texture test below stricter, never looser. Returns
 * the median in grey levels, at most NOISE_MEDIAN_MAX (0 for an image
 * too small to measure).
 */
int32_t det_noise_median(const negobs_image_u8_t *img)
{
    uint32_t hist[NOISE_BINS_MAX];
    uint32_t n = 0;
    uint32_t acc = 0;
    int32_t x;
    int32_t y;
    int32_t i;
    memset(hist, 0, sizeof hist);
    for (y = 1; y + 1 < img->height; y += 2) {
        const uint8_t *a = negobs_image_u8_row(img, y - 1);
        const uint8_t *b = negobs_image_u8_row(img, y);
        const uint8_t *c = negobs_image_u8_row(img, y + 1);
        for (x = 1; x + 1 < img->width; x += 2) {
            int32_t r = (int32_t)a[x - 1] - 2 * a[x] + a[x + 1] -
                        2 * (b[x - 1] - 2 * b[x] + b[x + 1]) + c[x - 1] -
                        2 * c[x] + c[x + 1];
            hist[geom_min_s32(negobs_abs_s32(r), NOISE_BINS_MAX - 1)]++;
            n++;
        }
    }
    if (n == 0u) {
        return 0;
    }
    for (i = 0; i < NOISE_BINS_MAX; i++) {
        acc += hist[i];
        if (2u * acc >= n) {
            return i;
        }
    }
    return NOISE_MEDIAN_MAX;
}

/*
 * Texture of one 5x5 window (det_window_textured), and of a box: 1 when at
 * least half of the windows centred in the box (every second pixel and
 * row) hold it. A textured window holds a variance of at least four
 * times the noise variance: texture with a signal-to-noise power of 3 or
 * more, for which a window's expected NCC at the true match is at least
 * 0.75. Below that the match wanders by tenths of a pixel (flat paint, a
 * smooth slab), as much as a minimum drop's deficit on a narrow rig, so
 * a deficit there is no evidence of a drop. With noise_med = 0 (no noise
 * measured) the variance test passes every window.
 *
 * A window must also show horizontal structure (window_sees_columns):
 * variance alone passes the long edge of a painted stripe across the
 * path, where every disparity along the row matches about as well (the
 * aperture problem) and the matcher returns confident disparities
 * pixels off, which read as a deep deficit.
 *
 * Scaling: v = 25 * sum(p^2) - (sum p)^2 = 625 * var (at most 1.02e7);
 * sigma = noise_med / 4.047, so var >= 4 sigma^2 is
 * v * 4095 >= 625000 * noise_med^2 (noise_med <= 24: at most 3.6e8;
 * v * 4095 at most 4.2e10, in 64 bits).
 */
/*
 * 1 when the 5x5 window centred at (x, y) holds horizontal gradient
 * energy of at least 1/APERTURE_RATIO_INV of its vertical one, both from
 * 2-pixel central differences (the scale the 5x5 NCC matches at; a
 * 1-pixel difference misses the 2-5 px contrast of real optics and
 * rendered texture): gxx over the window's inner 3 columns x 5 rows,
 * gyy over its 5 columns x inner 3 rows, 15 differences each. A
 * horizontal edge has gxx near 0 and fails; an upright one passes.
 *
 * Why 1/10, and not 1: a floor seen at a slant is foreshortened
 * vertically by about sin(grazing angle), so its own texture shows
 * several times more vertical than horizontal gradient; 1/10 keeps
 * floors seen at grazing angles down to about 18 deg (sin^2 = 0.1),
 * and still fails a stripe's edge, whose horizontal energy is the noise
 * alone. Scaling: each squared difference is at most 255^2, each sum at
 * most 15 * 65025 = 975 375, times 10 fits in 32 bits.
 */
enum { APERTURE_RATIO_INV = 10 };

static inline int window_sees_columns(const negobs_image_u8_t *img, int32_t x,
                                      int32_t y)
{
    int32_t gxx = 0;
    int32_t gyy = 0;
    int32_t j;
    int32_t i;
    for (j = -2; j <= 2; j++) {
        const uint8_t *row = negobs_image_u8_row(img, y + j);
        for (i = -1; i <= 1; i++) {
            int32_t g = (int32_t)row[x + i + 1] - row[x + i - 1];
            gxx += g * g;
        }
    }
    for (j = -1; j <= 1; j++) {
        const uint8_t *up = negobs_image_u8_row(img, y + j - 1);
        const uint8_t *dn = negobs_image_u8_row(img, y + j + 1);
        for (i = -2; i <= 2; i++) {
            int32_t g = (int32_t)dn[x + i] - up[x + i];
            gyy += g * g;
        }
    }
    return APERTURE_RATIO_INV * gxx >= gyy;
}

/* 1 when the 5x5 window at (x, y) holds a variance of at least
 * ratio_q2 / 4 times the noise variance (sigma = noise_med / 4.047) and
 * horizontal structure. v = 625 * var; ratio_q2 <= 16: v * 4095 * 16 is
 * at most 6.7e11 and ratio_q2 * 625000 * noise_med^2 at most 5.8e9, in
 * 64 bits. */
static int window_holds(const negobs_image_u8_t *img, int32_t noise_med,
                        int32_t x, int32_t y, int32_t ratio_q2)
{
    const int64_t need = (int64_t)ratio_q2 * 625000 * noise_med * noise_med;
    int32_t s = 0;
    int32_t q = 0;
    int32_t j;
    int32_t i;
    for (j = -2; j <= 2; j++) {
        const uint8_t *row = negobs_image_u8_row(img, y + j);
        for (i = -2; i <= 2; i++) {
            int32_t p = row[x + i];
            s += p;
            q += p * p;
        }
    }
    return (int64_t)(25 * q - s * s) * 4095 * 16 >= need &&
           window_sees_columns(img, x, y);
}

/* Four times the noise variance, in quarters (the test above). Weak
 * texture: one and a half times. A window of sensor noise alone holds a
 * sample variance of chi-square with 24 degrees of freedom over 24, whose
 * 95th percentile is 1.52: a bland box (flat paint, a smooth slab) has
 * about 5 % of its windows above it, never half, while a floor whose grain
 * holds a third of the noise's variance or more has most of them. */
enum { TEXTURE_RATIO_Q2 = 16, WEAK_TEXTURE_RATIO_Q2 = 6 };

/* The window must lie inside the image: 2 <= x < width - 2, the same for y. */
int det_window_textured(const negobs_image_u8_t *img, int32_t noise_med,
                        int32_t x, int32_t y)
{
    return window_holds(img, noise_med, x, y, TEXTURE_RATIO_Q2);
}

/* Windows of the box (every second pixel and row, inside the image) and
 * how many of them hold ratio_q2 / 4 times the noise variance, added to
 * *ok and *n. */
static void box_counts(const negobs_image_u8_t *img, int32_t noise_med,
                       int32_t u0, int32_t v0, int32_t u1, int32_t v1,
                       int32_t ratio_q2, int32_t *ok, int32_t *n)
{
    int32_t x;
    int32_t y;
    u0 = geom_max_s32(u0, 2);
    v0 = geom_max_s32(v0, 2);
    u1 = geom_min_s32(u1, img->width - 3);
    v1 = geom_min_s32(v1, img->height - 3);
    for (y = v0; y <= v1; y += 2) {
        for (x = u0; x <= u1; x += 2) {
            (*n)++;
            *ok += window_holds(img, noise_med, x, y, ratio_q2);
        }
    }
}

int det_box_textured(const negobs_image_u8_t *img, int32_t noise_med,
                     int32_t u0, int32_t v0, int32_t u1, int32_t v1)
{
    int32_t n = 0;
    int32_t ok = 0;
    box_counts(img, noise_med, u0, v0, u1, v1, TEXTURE_RATIO_Q2, &ok, &n);
    return n == 0 || 2 * ok >= n;
}

int det_box_weak_textured(const negobs_image_u8_t *img, int32_t noise_med,
                          int32_t u0, int32_t v0, int32_t u1, int32_t v1)
{
    int32_t n = 0;
    int32_t ok = 0;
    box_counts(img, noise_med, u0, v0, u1, v1, WEAK_TEXTURE_RATIO_Q2, &ok, &n);
    return n > 0 && 2 * ok >= n;
}

int det_run_textured(const negobs_image_u8_t *img, int32_t noise_med,
                     const strip_hit_t *hits, int32_t k0, int32_t k1,
                     int32_t run)
{
    int32_t k;
    for (k = k0; run >= 1 && k + run <= k1; k++) {
        int32_t ok = 0;
        int32_t n = 0;
        int32_t j;
        for (j = k; j < k + run; j++) {
            box_counts(img, noise_med, hits[j].u0, hits[j].top_v,
                       hits[j].u1 - 1, hits[j].edge_v, TEXTURE_RATIO_Q2, &ok,
                       &n);
        }
        if (n > 0 && 2 * ok >= n) {
            return 1;
        }
    }
    return 0;
}

int det_box_from_half(const negobs_image_s16_t *disp,
                      const negobs_image_s16_t *disp_half, int32_t u0,
                      int32_t v0, int32_t u1, int32_t v1)
{
    int32_t n = 0;
    int32_t half = 0;
    int32_t x;
    int32_t y;
    u0 = geom_max_s32(u0, 0);
    v0 = geom_max_s32(v0, 0);
    u1 = geom_min_s32(u1, geom_min_s32(disp->width, 2 * disp_half->width) - 1);
    v1 = geom_min_s32(v1,
                      geom_min_s32(disp->height, 2 * disp_half->height) - 1);
    for (y = v0; y <= v1; y++) {
        const int16_t *d = negobs_image_s16_row(disp, y);
        const int16_t *h = negobs_image_s16_row(disp_half, y / 2);
        for (x = u0; x <= u1; x++) {
            if (d[x] == NEGOBS_DISP_INVALID) {
                continue;
            }
            n++;
            half += h[x / 2] != NEGOBS_DISP_INVALID &&
                    (int32_t)d[x] == 2 * (int32_t)h[x / 2];
        }
    }
    return n > 0 && 2 * half >= n;
}
