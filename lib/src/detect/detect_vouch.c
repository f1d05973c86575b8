/* The vouched range (clear_to_mm, short_sight) and the frame's verdict
 * (docs/DETECTION.md section 10). */
#include "detect_internal.h"

/*
 * The vouched range (docs/DETECTION.md, "Verdicts and the vouched range"),
 * for the minimum drop of the definitions (VOUCH_H_NEAR_MM within
 * VOUCH_NEAR_RANGE_MM, VOUCH_H_FAR_MM beyond; detect_internal.h).
 */
/* A run of rows whose strip median cannot vote (fewer than a quarter of
 * the strip's pixels matched) ends a strip's support when it spans at
 * least VOUCH_GAP_ROWS rows and VOUCH_GAP_MM of floor. The rule itself
 * skips up to 2 such rows inside a deficit run, so shorter runs cost it
 * nothing; 100 mm is the width of a shoe: an unseen stretch narrower than
 * that cannot take a foot, a wider one may hide a hole. */
#define VOUCH_GAP_ROWS 3
#define VOUCH_GAP_MM 100
/* A cell (one strip, one band) with fewer seen rows than this has too
 * few values for a spread of its own; the band's pooled values stand. */
#define VOUCH_CELL_MIN 4

static inline int32_t vouch_h_mm(const scan_ctx_t *s, int32_t range_mm)
{
    return (range_mm <= VOUCH_NEAR_RANGE_MM || s->vouch_5cm) ? VOUCH_H_NEAR_MM
                                                             : VOUCH_H_FAR_MM;
}

static inline int32_t band_of(const scan_ctx_t *s, int32_t v)
{
    return negobs_clamp_s32((v - s->band_v0) / s->band_rows, 0,
                            NOISE_BANDS - 1);
}

/* Floor distance of the ground model at (u, v). */
static inline int32_t model_range_mm(const scan_ctx_t *s, int32_t u, int32_t v)
{
    int32_t r = 0;
    det_model_point(s, u, v, negobs_ground_disp_q4(s->plane, u, v), &r, NULL,
                    NULL);
    return r;
}

/*
 * Second pass over the rows a strip's cells counted (the bottom row up to
 * its support limit sup_v; the same in-corridor, seen rows): the sum of
 * |e - the cell's own mean|. The cell's offset from the model is tested
 * on its own (|o_cell| in vouch_cell_ok); measured about the band's
 * median, as a one-pass sum, the spread also carried the cell's offset
 * from the rest of the band, so one offset counted k x 1.25 + 1 times.
 * The mean is rounded to whole 1/32 px, which adds at most 1/64 px to the
 * mean deviation.
 */
static void vouch_cell_spread(const scan_ctx_t *s, detect_priv_t *p,
                              int32_t si, int32_t *rr)
{
    const int32_t hgt = s->cfg->rig.height;
    vouch_cell_t *c = p->cells + (size_t)si * NOISE_BANDS;
    int32_t v;
    for (v = hgt - 1; v >= s->band_v0 && v >= p->hits[si].sup_v; v--) {
        int32_t e;
        int32_t b;
        int32_t mean_q5;
        if (v <= p->hits[si].blocked_v || v >= p->hits[si].occl_v ||
            !det_strip_in_corridor(s, p->n_strips, si, v) ||
            !det_strip_row_e(s, p, v, si, rr, &e)) {
            continue;
        }
        b = band_of(s, v);
        e = negobs_clamp_s32(e, -STRIP_BINS / 2, STRIP_BINS / 2);
        mean_q5 = (int32_t)negobs_div_round_s64(c[b].sum, c[b].n);
        c[b].sum_abs += negobs_abs_s32(e - mean_q5);
    }
}

/*
 * Pass over every corridor strip from the bottom row up to the row of
 * range_max: the cells' statistics (seen rows, sum of e, then in a
 * second pass the sum of |e - the cell's mean|, vouch_cell_spread; e
 * clamped to +-2 px like det_strip_noise's histogram, so one wild row
 * weighs as a 2 px error, not as infinity) and each strip's support limit
 * sup_v. Rows past a closure (wall, up-step) are not read. Runs after
 * det_strip_noise (the band medians) and det_merge_strips
 * (rows past a reported drop's edge are compared with its plateau,
 * det_strip_row_e).
 */
void det_vouch_collect(const scan_ctx_t *s, detect_priv_t *p)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t rr[MAX_STRIP_PX];
    int32_t si;
    memset(p->cells, 0,
           (size_t)p->n_strips * NOISE_BANDS * sizeof(vouch_cell_t));
    for (si = 0; si < p->n_strips; si++) {
        strip_hit_t *hs = &p->hits[si];
        vouch_cell_t *c = p->cells + (size_t)si * NOISE_BANDS;
        int32_t uc = det_strip_u0(cfg, p->n_strips, si) + cfg->strip_px / 2;
        int32_t last_seen = cfg->rig.height - 1;
        int32_t run = 0;
        int32_t v;
        hs->sup_v = s->band_v0;
        for (v = cfg->rig.height - 1; v >= s->band_v0; v--) {
            int32_t e;
            if (v <= hs->blocked_v) {
                hs->sup_v = v + 1;
                break;
            }
            if (v >= hs->occl_v ||
                !det_strip_in_corridor(s, p->n_strips, si, v)) {
                continue; /* out of view: a near occluder, or the corridor */
            }
            if (det_strip_row_e(s, p, v, si, rr, &e)) {
                int32_t b = band_of(s, v);
                e = negobs_clamp_s32(e, -STRIP_BINS / 2, STRIP_BINS / 2);
                c[b].n++;
                c[b].sum += e;
                last_seen = v;
                run = 0;
                continue;
            }
            if (++run >= VOUCH_GAP_ROWS &&
                model_range_mm(s, uc, v) - model_range_mm(s, uc, last_seen) >=
                    VOUCH_GAP_MM) {
                hs->sup_v = (run == hs->occl_v - v) ? cfg->rig.height
                                                    : last_seen;
                break;
            }
        }
        vouch_cell_spread(s, p, si, rr);
    }
}

enum vouch_verdict { VOUCH_OK = 0, VOUCH_NOISE = 1, VOUCH_UNSEEN = 2 };

/* 1 when a minimum drop at range_mm would show its lower surface before
 * the scan's end. Past an edge at R the camera first sees the lower
 * surface at R * (H + h) / H (the edge hides the rest); the scan stops
 * at range_max, so an edge nearer than range_max but whose lower surface
 * lies beyond it shows no deficit row at all, and the rows up to it
 * cannot be vouched (a 10 cm curb at 4.37 m, crossed at 30 deg, stood
 * under a vouched 4.89 m: its lower surface lay past 5 m in most
 * strips). */
static inline int vouch_in_scan(const scan_ctx_t *s, int32_t range_mm)
{
    const int64_t hgt = s->frame->height_mm;
    return (int64_t)range_mm * (hgt + vouch_h_mm(s, range_mm)) <=
           (int64_t)s->cfg->range_max_mm * hgt;
}

/*
 * Can strip si see a minimum drop at row v? The drop's deficit there is
 * D = d_g * h / (H + h) (h the minimum drop at that range); the rule tests
 * strip medians, so D must exceed k times their measured spread plus the
 * ground's offset from the model (either sign: above the model it hides
 * deficits, below it reads as a drop that is not one). The spread is the
 * larger of the band's pooled 1.4826 * MAD (det_strip_noise) and the cell's
 * own mean absolute deviation about its mean x 1.2533 (the
 * normal-distribution factor); the offset is counted once, as |o_cell|.
 * The rule's
 * geometric threshold must stay below the minimum drop, or it never fires
 * on one, and the per-pixel noise is capped by sigma_max as before.
 */
static enum vouch_verdict vouch_cell_sees(const scan_ctx_t *s,
                                          const detect_priv_t *p, int32_t si,
                                          int32_t v, int32_t range_mm,
                                          int32_t dg, int64_t rel_num,
                                          int64_t rel_den)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int32_t b = band_of(s, v);
    const vouch_cell_t *c = p->cells + (size_t)si * NOISE_BANDS + b;
    /* The band whose spread and offset stand for this one: every band is
     * pooled with its nearer neighbour (det_strip_noise), the nearest has
     * none. Its rows are what is left after the others' rounded-up share
     * (3 rows of a 73-row scan), and the image's last two are never
     * matched (the 5x5 window), so it may hold too few strip rows for a
     * spread: it then takes the next farther band's, which is pooled
     * with it. (Unmeasured, it ended the walk at the bottom row on 4 of
     * 45 frames of a flat walk at 3 deg of pitch: NO_INFO, FEW_GROUND.) */
    const int32_t bs = (s->band_strip_q8[b] <= 0 && b == NOISE_BANDS - 1)
                           ? b - 1
                           : b;
    int32_t h = vouch_h_mm(s, range_mm);
    int32_t h_t = det_h_t_at(cfg, range_mm);
    int32_t sig_q8 = s->band_strip_q8[bs];
    int32_t bias_q8 = geom_max_s32(s->band_bias_q8[bs], 0);
    if (sig_q8 <= 0 || c->n <= 0) {
        return VOUCH_UNSEEN; /* the band or the cell holds no measurement */
    }
    if (h_t >= h || det_sigma_at(s, v) > cfg->sigma_max_q4) {
        return VOUCH_NOISE;
    }
    /* a deficit the rule does not count (DEFICIT_MIN_Q4) cannot show */
    if ((int64_t)dg * rel_num < (int64_t)DEFICIT_MIN_Q4 * rel_den) {
        return VOUCH_NOISE;
    }
    if (c->n >= VOUCH_CELL_MIN) {
        /* 1/32 px -> 1/256 px: x 8; x 1.2533 = x 1283 / 1024. */
        int32_t sd_q8 = (int32_t)(((int64_t)c->sum_abs * 8 * 1283) /
                                  ((int64_t)c->n * 1024));
        sig_q8 = geom_max_s32(sig_q8, sd_q8);
        bias_q8 = negobs_abs_s32((c->sum * 8) / c->n);
    }
    /* k_q4/16 * sig/256 + bias/256 <= dg/16 * rel_num / rel_den. */
    if (((int64_t)cfg->k_sigma_q4 * sig_q8 + 16 * (int64_t)bias_q8) * rel_den >
        (int64_t)dg * rel_num * 256) {
        return VOUCH_NOISE;
    }
    return VOUCH_OK;
}

static enum vouch_verdict vouch_cell_ok(const scan_ctx_t *s,
                                        const detect_priv_t *p, int32_t si,
                                        int32_t v, int32_t range_mm)
{
    const negobs_detect_config_t *cfg = s->cfg;
    int32_t uc = det_strip_u0(cfg, p->n_strips, si) + cfg->strip_px / 2;
    int32_t h = vouch_h_mm(s, range_mm);
    return vouch_cell_sees(s, p, si, v, range_mm,
                           negobs_ground_disp_q4(s->plane, uc, v), h,
                           (int64_t)s->frame->height_mm + h);
}

/* One row of the walk: its corridor strips' tallies, with the strips
 * past the foot of an obstacle that bars their lane (bars) counted apart. */
typedef struct walk_row {
    int32_t n_open;       /* corridor strips not barred                      */
    int32_t n_barred;     /* corridor strips past the foot of a barring face */
    int32_t n_ok;         /* strips that can see a minimum drop there        */
    int32_t max_bad;      /* longest run of failing strips, barred ones fail */
    int32_t max_bad_open; /* the same, barred strips left out            */
    uint32_t why;         /* NOISY / FEW_GROUND of the failing strips    */
    int32_t any_alive;    /* some strip still vouched from the bottom    */
    int32_t n_occl;       /* strips covered by a near occluder          */
} walk_row_t;

static void walk_tally(const scan_ctx_t *s, detect_priv_t *p,
                       int32_t first_row, int32_t v, int32_t range,
                       walk_row_t *w)
{
    int32_t bad_run = 0;
    int32_t open_run = 0;
    int32_t si;
    memset(w, 0, sizeof *w);
    for (si = 0; si < p->n_strips; si++) {
        enum vouch_verdict vd;
        if (!det_strip_in_walk(s, p->n_strips, si, v) ||
            v >= p->hits[si].occl_v) {
            w->n_occl += v >= p->hits[si].occl_v;
            bad_run = 0;
            open_run = 0;
            if (!s->vouch_5cm && p->reach_v[si] == v + 1) {
                p->reach_v[si] = v; /* outside: nothing to vouch */
            }
            continue;
        }
        if (p->hits[si].bars && v <= p->hits[si].blocked_v) {
            /* the walker meets the obstacle before this floor */
            w->n_barred++;
            w->why |= NEGOBS_DEGRADED_FEW_GROUND;
            w->max_bad = geom_max_s32(w->max_bad, ++bad_run);
            open_run = 0;
            continue;
        }
        w->n_open++;
        if (v < first_row + 2 || v < p->hits[si].sup_v ||
            !vouch_in_scan(s, range)) {
            vd = VOUCH_UNSEEN;
        } else {
            vd = vouch_cell_ok(s, p, si, v, range);
        }
        if (vd == VOUCH_OK) {
            w->n_ok++;
            bad_run = 0;
            open_run = 0;
            if (!s->vouch_5cm && p->reach_v[si] == v + 1) {
                p->reach_v[si] = v;
            }
        } else {
            w->why |= (vd == VOUCH_NOISE) ? NEGOBS_DEGRADED_NOISY
                                          : NEGOBS_DEGRADED_FEW_GROUND;
            w->max_bad = geom_max_s32(w->max_bad, ++bad_run);
            w->max_bad_open = geom_max_s32(w->max_bad_open, ++open_run);
        }
        w->any_alive |= p->reach_v[si] == v;
    }
}

/*
 * Walk outward from the bottom row: a row is vouched when at least half
 * of its corridor strips can see a minimum drop there (vouch_cell_ok,
 * within the strip's support) and no min_strips adjacent ones cannot (the
 * rule reports nothing narrower, so that is the detector's resolution).
 * Where that fails and some strips are past the foot of an obstacle that
 * bars their lane (bars), the walk goes on for at most BAR_RUN_MM of
 * floor with those strips left out (the feet of one wall, seen through
 * noise and roll, spread over a few rows); if every corridor strip is
 * barred within that band, the walk ends there barred (*barred = 1): the
 * floor up to the obstacle is vouched and nothing beyond it is reached
 * without meeting it. Otherwise it ends where it first failed: an
 * obstacle that leaves a lane open (a post) is walked past, and the floor
 * behind it is not vouched.
 * Returns the floor distance of the last row of the contiguous vouched
 * stretch (0: not even the bottom row), and in *cause the reason it
 * stopped (NOISY or FEW_GROUND; 0 when it reached range_max or ended
 * barred). Rows above
 * first_row + 2 were not matched. Fills p->reach_v: how far each strip
 * alone stays vouched (the local check of a hazard's own strips).
 */
static int vouch_band_ok(const scan_ctx_t *s, int32_t v, int32_t range_mm);

int32_t det_vouch_walk(const scan_ctx_t *s, detect_priv_t *p,
                       int32_t first_row, int candidates, uint32_t *cause,
                       int32_t *barred)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int32_t hgt = cfg->rig.height;
    int32_t walk_v = hgt; /* last vouched row, hgt: none yet */
    int32_t walking = 1;
    int32_t close_mm = -1; /* floor distance where the barred band began */
    int32_t close_walk_v = hgt;
    uint32_t close_why = 0;
    int32_t local = 0; /* the walk stopped on a minority of its strips */
    int32_t si;
    int32_t v;
    *cause = 0;
    *barred = 0;
    for (si = 0; si < p->n_strips && !s->vouch_5cm; si++) {
        p->reach_v[si] = hgt;
    }
    for (v = hgt - 1; v >= s->band_v0; v--) {
        int32_t range = model_range_mm(s, cfg->rig.width / 2, v);
        int32_t n_corr;
        walk_row_t w;
        if (s->vouch_5cm && range > cfg->h_near_range_mm) {
            /* the rule looks for 5 cm no farther: the walk's end, not
             * noise */
            break;
        }
        walk_tally(s, p, first_row, v, range, &w);
        n_corr = w.n_open + w.n_barred;
        if (walking && n_corr == 0 && w.n_occl > 0 && walk_v == hgt) {
            continue; /* every lane covered by a near occluder: the walk
                         starts above it, as above the bottom row */
        }
        if (walking && close_mm < 0) {
            if (n_corr > 0 && 2 * w.n_ok >= n_corr &&
                w.max_bad < cfg->min_strips) {
                walk_v = v;
            } else if (w.n_barred > 0) {
                close_mm = range; /* the barred band begins */
                close_walk_v = walk_v;
                close_why = w.why;
            } else {
                walking = 0;
                local = n_corr > 0 && 2 * w.n_ok >= n_corr &&
                        vouch_band_ok(s, v, range);
                *cause = (w.why & NEGOBS_DEGRADED_NOISY) != 0u
                             ? NEGOBS_DEGRADED_NOISY
                             : NEGOBS_DEGRADED_FEW_GROUND;
            }
        }
        if (walking && close_mm >= 0) {
            if (w.n_open == 0 && w.n_barred > 0) {
                walking = 0; /* every lane of the corridor is barred */
                *barred = walk_v < hgt;
            } else if (range - close_mm <= BAR_RUN_MM &&
                       2 * w.n_ok >= w.n_open &&
                       w.max_bad_open < cfg->min_strips) {
                walk_v = v;
            } else {
                walking = 0; /* a lane stays open: back to where it failed */
                walk_v = close_walk_v;
                *cause = (close_why & NEGOBS_DEGRADED_NOISY) != 0u
                             ? NEGOBS_DEGRADED_NOISY
                             : NEGOBS_DEGRADED_FEW_GROUND;
            }
        }
        if (!walking && (s->vouch_5cm || !w.any_alive)) {
            break; /* the 5 cm walk fills no strip's reach */
        }
    }
    /* Noise that stops the walk inside the ground fit's own rows (the
     * bottom fit_rows_pct) says the model does not describe the rows it
     * was fitted to: its ranges are not to be trusted either (a fit that
     * locked onto a 0.95 m / 8 deg line under a 1.2 m / 20 deg camera
     * vouched for 1.5 m of floor with a 15 cm drop at 1.3 m). A gap in
     * support there is only unknown ground and ends the walk as usual; so
     * does noise on a frame with a candidate: a drop found there is what
     * stops the walk (clear_to_mm is cut at it anyway). So does noise
     * that is local: a row where at least half of the corridor's strips
     * still vouch (only min_strips adjacent ones failed) and whose band,
     * pooled over every strip, passes the same test. A wrong model is
     * wrong across the width, in the band's median; one stain or painted
     * patch the matcher reads off is not (a dark patch in two strips of a
     * 1.38 m / 11 deg camera's fit rows, 1.8-2.6 m ahead, zeroed a walk to
     * 2.1 m). The 5 cm walk runs only where this one passed those rows
     * for the minimum drop: its noise is about sensitivity, not the
     * model. */
    if (*cause == NEGOBS_DEGRADED_NOISY && !candidates && !local &&
        !s->vouch_5cm && walk_v > hgt - 1 - (hgt * cfg->fit_rows_pct) / 100) {
        return 0;
    }
    return (walk_v < hgt) ? model_range_mm(s, cfg->rig.width / 2, walk_v) : 0;
}

/*
 * The floor within VOUCH_NEAR_RANGE_MM of the feet must be clear of 5 cm
 * drops, and once it is below the view only earlier frames can have
 * checked it (detect_near.c): floor seen beyond that range was checked
 * by det_vouch_walk for 10 cm. This walk checks it for 5 cm, as far as
 * the rule itself can report a 5 cm drop (h_near_range_mm; beyond, its
 * threshold is h_min_far_mm's and a 5 cm drop cannot be vouched against).
 * Within VOUCH_NEAR_RANGE_MM both walks are the same walk.
 */
int32_t det_vouch_walk_5cm(const scan_ctx_t *s, detect_priv_t *p,
                           int32_t first_row, int candidates, int32_t walk_to)
{
    scan_ctx_t s5;
    uint32_t cause = 0;
    int32_t barred = 0;
    if (walk_to <= VOUCH_NEAR_RANGE_MM) {
        return walk_to;
    }
    s5 = *s;
    s5.vouch_5cm = 1;
    return geom_min_s32(
        det_vouch_walk(&s5, p, first_row, candidates, &cause, &barred),
        walk_to);
}

/* The band-pooled test of vouch_cell_ok at row v (no cell): the band's
 * 1.4826 * MAD of strip medians and its positive offset. Robust to the
 * few blurred rows just past an edge, which a cell's mean deviation is
 * not. */
static int vouch_band_sees(const scan_ctx_t *s, int32_t v, int32_t dg,
                           int64_t rel_num, int64_t rel_den)
{
    const negobs_detect_config_t *cfg = s->cfg;
    const int32_t b = band_of(s, v);
    return s->band_strip_q8[b] > 0 &&
           ((int64_t)cfg->k_sigma_q4 * s->band_strip_q8[b] +
            16 * (int64_t)geom_max_s32(s->band_bias_q8[b], 0)) *
                   rel_den <=
               (int64_t)dg * rel_num * 256;
}

static int vouch_band_ok(const scan_ctx_t *s, int32_t v, int32_t range_mm)
{
    int32_t h = vouch_h_mm(s, range_mm);
    return vouch_band_sees(
        s, v, negobs_ground_disp_q4(s->plane, s->cfg->rig.width / 2, v), h,
        (int64_t)s->frame->height_mm + h);
}

/* The local check with the strip's own deficit in place of a minimum
 * drop's: its first plateau lies rho1 (relative) below the ground at its
 * edge, and that deficit must stand out of the same noise and offset by
 * the same k (in the cell one band nearer and in the band-pooled test at
 * the edge row). A drop deeper than the minimum is seen in noise that
 * would hide the minimum; the ground disparity is taken at the edge, the
 * smaller one, where the deficit was measured. */
static int vouch_own_deficit(const scan_ctx_t *s, const detect_priv_t *p,
                             int32_t si, const strip_hit_t *sh, int32_t vn,
                             int32_t uc)
{
    int32_t dg = negobs_ground_disp_q4(s->plane, uc, sh->edge_v);
    if (sh->rho1_q15 <= 0) {
        return 0;
    }
    return vouch_cell_sees(s, p, si, vn, model_range_mm(s, uc, vn), dg,
                           sh->rho1_q15, 32768) == VOUCH_OK &&
           vouch_band_sees(s, sh->edge_v, dg, sh->rho1_q15, 32768);
}

/* 1 when a candidate's own strips pass the local check around its edge:
 * at least half of them, and at least min_strips, can see a minimum drop
 * in the cell one band nearer than their edge (the ground it stands out
 * from, within their support), and the band-pooled noise at the edge row
 * allows it; or their own deficit stands out there (vouch_own_deficit).
 * Noise farther off, or under the feet, does not make a drop in clean
 * strips unknown. min_strips, because the rule reports nothing
 * narrower: one clean strip of a two-strip candidate is evidence below
 * the detector's resolution (on a flat worn-asphalt walk of the suite,
 * such candidates on frames vouching 0-840 mm, three in five frames at
 * 1.58, 1.38 and 1.05 m, confirmed a HOLE held IMMINENT to the feet). */
int det_vouch_candidate(const scan_ctx_t *s, const detect_priv_t *p,
                        const negobs_hazard_t *hz)
{
    const int32_t hgt = s->cfg->rig.height;
    int32_t cnt = 0;
    int32_t pass = 0;
    int32_t si;
    for (si = 0; si < p->n_strips; si++) {
        const strip_hit_t *sh = &p->hits[si];
        int32_t uc = (sh->u0 + sh->u1) / 2;
        int32_t vn;
        if (!sh->found || !sh->reported || sh->u0 < hz->u0 ||
            sh->u1 - 1 > hz->u1 || sh->edge_v >= hgt ||
            sh->edge_v < sh->sup_v) {
            cnt += sh->found && sh->reported && sh->u0 >= hz->u0 &&
                   sh->u1 - 1 <= hz->u1;
            continue;
        }
        cnt++;
        vn = geom_min_s32(sh->edge_v + s->band_rows, hgt - 1);
        pass += (vouch_cell_ok(s, p, si, vn, model_range_mm(s, uc, vn)) ==
                     VOUCH_OK &&
                 vouch_band_ok(s, sh->edge_v,
                               model_range_mm(s, uc, sh->edge_v))) ||
                vouch_own_deficit(s, p, si, sh, vn, uc);
    }
    return pass >= s->cfg->min_strips && 2 * pass >= cnt;
}

/*
 * The det_verdict (docs/DETECTION.md, "Verdicts and the vouched range"):
 * clear_to_mm is the vouched walk, cut at the nearest candidate of this
 * frame (a suspected drop is not vouched past, confirmed or not), at
 * sight_mm (the recent frames' candidates, det_sight_bound) and at the
 * nearest reported hazard. A gating or ground reason, unverified ground
 * included, is NO_INFO with clear_to_mm 0; a
 * confirmed or held hazard is HAZARD; a vouched range
 * below near_min_mm is NO_INFO (with the reason the walk stopped) unless
 * the walk reached the foot of an obstacle barring every lane
 * (res->blocked_at_mm > 0, set by the caller, kept only when nothing cut
 * the walk short of it); else CLEAR, short-sighted below range_warn_mm.
 */
int32_t det_vouch_cut(const negobs_detect_result_t *res, int32_t walk_to,
                      int32_t sight_mm)
{
    int32_t clear_to = geom_min_s32(walk_to, sight_mm);
    uint32_t i;
    for (i = 0; i < res->n_candidates; i++) {
        clear_to = geom_min_s32(clear_to,
                                geom_max_s32(res->candidates[i].range_mm, 0));
    }
    for (i = 0; i < res->n_hazards; i++) {
        clear_to = geom_min_s32(clear_to,
                                geom_max_s32(res->hazards[i].range_mm, 0));
    }
    return clear_to;
}

void det_verdict(const negobs_detect_config_t *cfg,
                 negobs_detect_result_t *res, uint32_t reasons,
                 int32_t walk_to, uint32_t walk_cause, int32_t sight_mm)
{
    int32_t clear_to = det_vouch_cut(res, walk_to, sight_mm);
    res->short_sight = 0;
    if (reasons != 0u || clear_to < walk_to) {
        res->blocked_at_mm = 0; /* not vouched up to the obstacle */
    }
    if (reasons != 0u) {
        res->state = NEGOBS_DETECT_NO_INFO;
        /* Unverified ground (detect_cue.c) vouches nothing either: the
         * fit may rest on the lower floor past an edge at the bottom of
         * the view, where the rule, with no floor in view before the edge,
         * cannot see it (a 5 cm curb entering a 7 deg camera's bottom
         * rows at 1.44 m under a vouched 3.3 m). noise_vouch_mm still
         * reports what the floor in view would vouch for. */
        clear_to = 0;
    } else if (res->n_hazards > 0u) {
        res->state = NEGOBS_DETECT_HAZARD;
    } else if (clear_to < cfg->near_min_mm && res->blocked_at_mm <= 0) {
        res->state = NEGOBS_DETECT_NO_INFO;
        reasons = (clear_to < walk_to) ? NEGOBS_DEGRADED_NOISY
                  : (walk_cause != 0u) ? walk_cause
                                       : NEGOBS_DEGRADED_FEW_GROUND;
    } else {
        res->state = NEGOBS_DETECT_CLEAR;
        res->short_sight = clear_to < cfg->range_warn_mm;
    }
    res->clear_to_mm = clear_to;
    res->noise_vouch_mm = walk_to;
    res->reasons = reasons;
}
