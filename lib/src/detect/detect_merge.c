/* Step 3: adjacent strips with a hit -> hazards (docs/DETECTION.md
 * section 5). */
#include "detect_internal.h"

/* Merge adjacent strips into hazards; nearest kept when over the bound. */
void det_merge_strips(const scan_ctx_t *s, detect_priv_t *p,
                      negobs_detect_result_t *res)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t i = 0;
    while (i < p->n_strips) {
        int32_t j;
        int32_t k;
        int32_t cnt;
        int32_t nearest;
        int64_t drop_sum = 0;
        int32_t types[4] = {0, 0, 0, 0};
        int32_t margin = 0;
        int32_t n_textured = 0;
        int64_t unit_sum = 0;
        int64_t unit_plateau = 0;
        int32_t n_unit = 0;
        negobs_hazard_t h;
        if (!p->hits[i].found) {
            i++;
            continue;
        }
        j = i + 1;
        while (j < p->n_strips && p->hits[j].found &&
               negobs_abs_s32(p->hits[j].range_mm - p->hits[j - 1].range_mm) <=
                   cfg->merge_range_mm &&
               (p->hits[j].type == NEGOBS_HAZARD_UNKNOWN) ==
                   (p->hits[j - 1].type == NEGOBS_HAZARD_UNKNOWN)) {
            j++;
        }
        cnt = j - i;
        if (cnt < cfg->min_strips) {
            i = j;
            continue;
        }
        memset(&h, 0, sizeof h);
        nearest = i;
        h.u0 = (int16_t)p->hits[i].u0;
        h.u1 = (int16_t)(p->hits[j - 1].u1 - 1);
        h.v0 = (int16_t)p->hits[i].top_v;
        h.v1 = (int16_t)p->hits[i].edge_v;
        for (k = i; k < j; k++) {
            if (p->hits[k].range_mm < p->hits[nearest].range_mm) {
                nearest = k;
            }
        }
        /* Among strips within 50 mm of the nearest, report the one most
         * ahead (a straight curb across the path is "straight ahead"). */
        {
            int32_t rmin = p->hits[nearest].range_mm;
            for (k = i; k < j; k++) {
                if (p->hits[k].range_mm <= rmin + 50 &&
                    negobs_abs_s32(p->hits[k].lateral_mm) <
                        negobs_abs_s32(p->hits[nearest].lateral_mm)) {
                    nearest = k;
                }
            }
        }
        for (k = i; k < j; k++) {
            const strip_hit_t *sh = &p->hits[k];
            drop_sum += sh->drop_mm;
            types[sh->type]++;
            margin += sh->margin_q8;
            h.v0 = (int16_t)geom_min_s32(h.v0, sh->top_v);
            h.v1 = (int16_t)geom_max_s32(h.v1, sh->edge_v);
            if (sh->h_lower) {
                h.flags |= NEGOBS_HAZARD_F_H_LOWER;
            }
            n_textured += sh->textured;
            if (sh->unit_drop_mm >= 0) {
                unit_sum += sh->unit_drop_mm;
                unit_plateau += sh->drop_mm;
                n_unit++;
            }
        }
        if (2 * n_textured > cnt) {
            h.flags |= NEGOBS_HAZARD_F_TEXTURED;
        }
        h.type = NEGOBS_HAZARD_DROP;
        if (types[NEGOBS_HAZARD_UNKNOWN] == cnt) {
            h.type = NEGOBS_HAZARD_UNKNOWN;
        } else if (types[NEGOBS_HAZARD_STAIRS] * 2 >= cnt) {
            h.type = NEGOBS_HAZARD_STAIRS;
        } else if (types[NEGOBS_HAZARD_HOLE] * 2 >= cnt) {
            h.type = NEGOBS_HAZARD_HOLE;
        }
        h.range_mm = p->hits[nearest].range_mm;
        h.lateral_mm = p->hits[nearest].lateral_mm;
        h.depth_mm = p->hits[nearest].depth_mm;
        h.bearing_mdeg = negobs_bearing_mdeg(h.lateral_mm, h.range_mm);
        h.drop_mm = (int32_t)(drop_sum / cnt);
        h.strips = (int16_t)cnt;
        /* the strips that measured a whole pixel of floor past the edge
         * (detect_unit.c, det_unit_drop_mm): over it a lower surface keeps
         * about its plateau, the ripple at most half of it; a mean that
         * reaches h_t there is a drop whatever the plateau read */
        if (h.type != NEGOBS_HAZARD_UNKNOWN && 2 * unit_sum < unit_plateau &&
            unit_sum < (int64_t)n_unit * det_h_t_at(cfg, h.range_mm)) {
            h.flags |= NEGOBS_HAZARD_F_UNIT_SHALLOW;
        }
        /* Edge orientation: least-squares line range = m * lateral + q
         * through the strips' edge points; angle = atan(m). */
        {
            int64_t n = 0;
            int64_t sx = 0;
            int64_t sy = 0;
            int64_t sxx = 0;
            int64_t sxy = 0;
            for (k = i; k < j; k++) {
                int64_t x = p->hits[k].lateral_mm;
                int64_t y = p->hits[k].range_mm;
                n++;
                sx += x;
                sy += y;
                sxx += x * x;
                sxy += x * y;
            }
            if (n >= 2 && n * sxx - sx * sx > 0) {
                h.edge_angle_mdeg = negobs_atan2_mdeg(n * sxy - sx * sy,
                                                      n * sxx - sx * sx);
            }
        }
        /* Confidence: agreement across strips (4 strips = full) times the
         * mean threshold margin (2x tau = full). Canny adds support. */
        {
            int64_t a = (int64_t)geom_min_s32(cnt, 4) * 8192;
            int64_t m = geom_clamp_s64((int64_t)(margin / cnt), 0, 512);
            h.conf_q15 = (int16_t)geom_clamp_s64((a * m) / 512, 0, 32767);
        }
        for (k = i; k < j; k++) {
            p->hits[k].reported = 1;
        }
        if (res->n_candidates < NEGOBS_DETECT_MAX_HAZARDS) {
            res->candidates[res->n_candidates++] = h;
        } else {
            /* Replace the farthest when this one is nearer. */
            uint32_t far = 0;
            uint32_t q;
            for (q = 1; q < res->n_candidates; q++) {
                if (res->candidates[q].range_mm >
                    res->candidates[far].range_mm) {
                    far = q;
                }
            }
            if (res->candidates[far].range_mm > h.range_mm) {
                res->candidates[far] = h;
            }
            res->candidates_dropped++;
        }
        i = j;
    }
}
