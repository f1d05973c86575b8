/* A body-attached near occluder at the view's bottom edge (hands, a held
 * phone, a cane's handle, a sleeve; docs/DETECTION.md 10.2, "Near
 * occluders"). */
#include "detect_internal.h"

/* The occluder must show in the bottom OCCL_LEAD_ROWS rows: it covers the
 * view from its bottom edge, so its foot is never in view (one or two
 * rows may be unmatched at the image border). */
#define OCCL_LEAD_ROWS 2
/* Rows between its last tall row and the resumed floor that read above
 * the floor but below BAR_H_MM: the matcher's 5x5 window bleeds the near
 * disparity 2 rows past the occluder's edge and growing from its seeds
 * carries it further (on the OAK-D hands at 320x240, 6 rows above the
 * hands read 0.25-0.56 px high). They are taken with the occluder: they
 * stand above the floor, so they hide no lower surface. */
#define OCCL_EDGE_ROWS 8
/* Unseen rows inside the occluder's run (the rule's own skip). */
#define OCCL_GAP_ROWS 2
/* Seen rows in a row on the ground plane above it: the floor resumes. The
 * closure's run (BLOCK_ROWS), so one or two rows of chance agreement do
 * not make an occluder. */
#define OCCL_FLOOR_ROWS BLOCK_ROWS

/* Strip median of row v's matched disparities (q4, times 2), 0: the row
 * cannot vote (fewer than a quarter of the strip, as the rule). */
static int32_t strip_median2_q4(const scan_ctx_t *s, int32_t u0, int32_t u1,
                                int32_t v)
{
    const int16_t *row = negobs_image_s16_row(s->disp, v);
    const uint8_t *crow = (s->conf != NULL) ? negobs_image_u8_row(s->conf, v)
                                            : NULL;
    int32_t rr[MAX_STRIP_PX];
    int32_t n = 0;
    int32_t u;
    for (u = u0; u < u1; u++) {
        int32_t d = row[u];
        if (d == NEGOBS_DISP_INVALID || d <= 0 ||
            (crow != NULL && (int32_t)crow[u] < s->cfg->min_confidence)) {
            continue;
        }
        rr[n++] = d;
    }
    if (n * 4 < (u1 - u0) || n < 3) {
        return 0;
    }
    return det_median2_s32(rr, n);
}

/*
 * First row of the strip's view: rows v >= the returned row are covered
 * by a near occluder and are out of view for the strip, like floor below
 * the image's bottom row; cfg->rig.height when there is none. An occluder
 * is, reading the strip upward from the bottom row:
 *  - a run that starts within the bottom OCCL_LEAD_ROWS rows, of at least
 *    BLOCK_ROWS seen rows whose strip median d is a point at least
 *    BAR_H_MM above the floor: h = H (d - d_g) / d (the barring height,
 *    docs/DETECTION.md 10.2); up to OCCL_GAP_ROWS unseen rows in a row
 *    inside it are allowed, they lie below a tall row;
 *  - then, within OCCL_EDGE_ROWS rows of its last tall row, the floor
 *    resumes: OCCL_FLOOR_ROWS seen rows in a row whose strip median lies
 *    within the closure's foot threshold of the ground model (a quarter of
 *    max(1 px, 3 sigma)). The rows between may only read above the floor
 *    (the occluder's edge); an unseen row or one under the floor (a lower
 *    surface) there means no occluder. The view starts at the first row
 *    of that floor.
 * Unmatched rows never make an occluder: a strip whose bottom rows are
 * unseen has none (a textureless floor stays unseen floor). A seen row
 * below BAR_H_MM before BLOCK_ROWS tall rows (a low object, a step, the
 * floor itself) means no occluder; above the run, rows that are neither
 * tall nor floor (its edge) are allowed only within OCCL_EDGE_ROWS.
 */
int32_t det_strip_occluder(const scan_ctx_t *s, int32_t u0, int32_t u1)
{
    const int32_t hgt = s->cfg->rig.height;
    const int64_t h_mm = s->frame->height_mm;
    const int32_t uc = (u0 + u1) / 2;
    int32_t n_tall = 0;
    int32_t top = hgt;  /* last tall row */
    int32_t unseen = 0; /* unseen rows since the last tall row */
    int32_t floor_run = 0;
    int32_t v;
    for (v = hgt - 1; v >= 0; v--) {
        int32_t dg_q4 = negobs_ground_disp_q4(s->plane, uc, v);
        int32_t m2 = strip_median2_q4(s, u0, u1, v);
        int32_t e_q5 = m2 - 2 * dg_q4; /* the strip median's residual */
        int32_t thr_q5 = geom_max_s32(BLOCK_MIN_Q5, 6 * det_sigma_at(s, v));
        if (dg_q4 <= 0 ||
            (n_tall > 0 && top - v > OCCL_EDGE_ROWS + OCCL_FLOOR_ROWS)) {
            return hgt; /* the horizon, or no floor above it */
        }
        if (m2 == 0) {
            if ((n_tall == 0 && v < hgt - OCCL_LEAD_ROWS) ||
                (n_tall > 0 && ++unseen > OCCL_GAP_ROWS)) {
                return hgt; /* unseen rows are unseen floor */
            }
            floor_run = 0;
            continue;
        }
        /* H (d - d_g) >= BAR_H_MM d, d = m2 / 2 (q4) */
        if (h_mm * e_q5 >= (int64_t)BAR_H_MM * m2) {
            n_tall++;
            top = v;
            unseen = 0;
            floor_run = 0;
            continue;
        }
        if (n_tall < BLOCK_ROWS || unseen > 0 || e_q5 * 4 <= -thr_q5) {
            /* no occluder at the bottom, too short, unseen rows or a
             * lower surface between it and the floor above */
            return hgt;
        }
        if (e_q5 * 4 >= thr_q5) {
            floor_run = 0; /* its edge, read high (OCCL_EDGE_ROWS) */
        } else if (++floor_run >= OCCL_FLOOR_ROWS) {
            return v + OCCL_FLOOR_ROWS; /* the first row of floor */
        }
    }
    return hgt;
}
