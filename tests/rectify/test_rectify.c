/*
 * Rectify tests: the table format (layout, CRC, every refusal path) and the
 * integer remap (identity, affine maps against a direct reference, exact
 * bilinear rounding, borders, row bands, workspace contract).
 *
 * References here may use double: they run on the host, outside lib/, and
 * every value they compare is exactly representable (sums of integers
 * below 2^24 divided by 2^16).
 */
#include <string.h>

#include "cmocka_all.h"
#include "negobs/rectify.h"

#define MAX_W 64
#define MAX_H 48
#define MAX_NODES (((MAX_W - 1) + 2) * ((MAX_H - 1) + 2))
#define MAX_TABLE (NEGOBS_RECTIFY_HEADER_BYTES + 2 * MAX_NODES * 8 + 4 + 64)
#define CANARY 0xC5u

/* Affine map in Q.8: src = (ax * x + bx * y + cx, ay * x + by * y + cy). */
typedef struct affine {
    int32_t ax, bx, cx;
    int32_t ay, by, cy;
} affine_t;

static const affine_t identity = {256, 0, 0, 0, 256, 0};

static int32_t nodes_l[2 * MAX_NODES];
static int32_t nodes_r[2 * MAX_NODES];
static uint8_t table[MAX_TABLE];
static uint8_t raw[MAX_H * (MAX_W + 8)];
static uint8_t out[MAX_H * (MAX_W + 8) + 32];
static uint8_t out2[MAX_H * (MAX_W + 8) + 32];
static union {
    uint8_t bytes[NEGOBS_RECTIFY_WORKSPACE_MAX(MAX_W) + 16];
    uint64_t align[2];
} ws __attribute__((aligned(16)));

static void fill_nodes(int32_t *nodes, int32_t w, int32_t h, int32_t shift,
                       const affine_t *m)
{
    int32_t gw = NEGOBS_RECTIFY_GRID_NODES(w, shift);
    int32_t gh = NEGOBS_RECTIFY_GRID_NODES(h, shift);
    int32_t gx;
    int32_t gy;
    for (gy = 0; gy < gh; gy++) {
        for (gx = 0; gx < gw; gx++) {
            int32_t x = gx << shift;
            int32_t y = gy << shift;
            int32_t *n = nodes + 2 * (gy * gw + gx);
            n[0] = m->ax * x + m->bx * y + m->cx;
            n[1] = m->ay * x + m->by * y + m->cy;
        }
    }
}

static negobs_rectify_info_t make_info(int32_t w, int32_t h, int32_t shift)
{
    negobs_rectify_info_t info;
    memset(&info, 0, sizeof info);
    info.width = w;
    info.height = h;
    info.grid_shift = shift;
    info.f_q16 = 700u << 16;
    info.baseline_um = 60000u;
    info.cx_q16 = (int32_t)(320u << 16) + 123;
    info.cy_q16 = -(240 << 16);
    info.doffs_q16 = 5;
    info.rms_mpx = 321u;
    return info;
}

/* Build a table with `ml` for the left and `mr` for the right camera. */
static size_t build_table(int32_t w, int32_t h, int32_t shift,
                          const affine_t *ml, const affine_t *mr)
{
    negobs_rectify_info_t info = make_info(w, h, shift);
    size_t n = 0;
    fill_nodes(nodes_l, w, h, shift, ml);
    fill_nodes(nodes_r, w, h, shift, mr);
    assert_int_equal(negobs_rectify_table_write(&info, nodes_l, nodes_r, table,
                                                sizeof table, &n),
                     NEGOBS_OK);
    return n;
}

static negobs_image_u8_t image(uint8_t *data, int32_t w, int32_t h,
                               int32_t stride)
{
    negobs_image_u8_t img;
    img.data = data;
    img.width = w;
    img.height = h;
    img.stride = stride;
    return img;
}

static void fill_random(negobs_image_u8_t *img, uint32_t seed)
{
    int32_t x;
    int32_t y;
    for (y = 0; y < img->height; y++) {
        for (x = 0; x < img->width; x++) {
            negobs_image_u8_row(img, y)[x] = (uint8_t)(test_lcg_next(&seed));
        }
    }
}

static void init_ctx(negobs_rectify_t *ctx, negobs_rectify_config_t *cfg,
                     int32_t w, int32_t h, size_t table_len)
{
    size_t bytes = 0;
    negobs_rectify_config_default(cfg, w, h);
    cfg->table = table;
    cfg->table_bytes = table_len;
    assert_int_equal(negobs_rectify_workspace_size(cfg, &bytes), NEGOBS_OK);
    assert_true(bytes <= sizeof ws.bytes);
    assert_int_equal(negobs_rectify_init(ctx, cfg, ws.bytes, bytes),
                     NEGOBS_OK);
}

/* Correctly rounded bilinear value at a Q.8 coordinate, or border. */
static uint8_t ref_sample(const negobs_image_u8_t *img, int32_t cx_q8,
                          int32_t cy_q8, uint8_t border)
{
    double fx;
    double fy;
    double v;
    int32_t x0;
    int32_t y0;
    int32_t x1;
    int32_t y1;
    if (cx_q8 < 0 || cy_q8 < 0 || cx_q8 > (img->width - 1) * 256 ||
        cy_q8 > (img->height - 1) * 256) {
        return border;
    }
    x0 = cx_q8 / 256;
    y0 = cy_q8 / 256;
    fx = (double)(cx_q8 % 256) / 256.0;
    fy = (double)(cy_q8 % 256) / 256.0;
    x1 = (x0 + 1 < img->width) ? x0 + 1 : x0;
    y1 = (y0 + 1 < img->height) ? y0 + 1 : y0;
    v = (1.0 - fx) * (1.0 - fy) * negobs_image_u8_row(img, y0)[x0] +
        fx * (1.0 - fy) * negobs_image_u8_row(img, y0)[x1] +
        (1.0 - fx) * fy * negobs_image_u8_row(img, y1)[x0] +
        fx * fy * negobs_image_u8_row(img, y1)[x1];
    return (uint8_t)(v + 0.5); /* v >= 0: truncation is floor */
}

/* ---- format ---------------------------------------------------------- */

static void test_rectify_crc32_known_answer(void **state)
{
    const uint8_t msg[] = "123456789";
    (void)state;
    assert_int_equal(negobs_rectify_crc32(0, msg, 9), 0xCBF43926u);
    /* Streaming in two parts gives the same value. */
    assert_int_equal(
        negobs_rectify_crc32(negobs_rectify_crc32(0, msg, 4), msg + 4, 5),
        0xCBF43926u);
    assert_int_equal(negobs_rectify_crc32(0, msg, 0), 0u);
}

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
           ((uint32_t)p[3] << 24);
}

static uint16_t le16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

/* The bytes match docs/CALIBRATION.md, offset by offset. */
static void test_rectify_table_layout_matches_documentation(void **state)
{
    size_t n;
    size_t expect = 0;
    (void)state;
    n = build_table(20, 10, 2, &identity, &identity);
    /* grid ((20-1)>>2)+2 = 6 x ((10-1)>>2)+2 = 4 nodes, 2 maps of 24 * 8 B */
    assert_int_equal(negobs_rectify_table_size(20, 10, 2, &expect), NEGOBS_OK);
    assert_int_equal(n, 64 + 2 * 24 * 8 + 4);
    assert_int_equal(n, expect);
    assert_memory_equal(table, "NGOBRECT", 8);
    assert_int_equal(le16(table + 8), 1);
    assert_int_equal(le16(table + 10), 0);
    assert_int_equal(le32(table + 12), 64);
    assert_int_equal(le32(table + 16), n);
    assert_int_equal(le16(table + 20), 20);
    assert_int_equal(le16(table + 22), 10);
    assert_int_equal(table[24], 2);
    assert_int_equal(table[25], 8);
    assert_int_equal(le16(table + 26), 0);
    assert_int_equal(le16(table + 28), 6);
    assert_int_equal(le16(table + 30), 4);
    assert_int_equal(le32(table + 32), 700u << 16);
    assert_int_equal(le32(table + 36), 60000u);
    assert_int_equal(le32(table + 40), (320u << 16) + 123u);
    assert_int_equal(le32(table + 44), (uint32_t)(-(240 << 16)));
    assert_int_equal(le32(table + 48), 5u);
    assert_int_equal(le32(table + 52), 321u);
    assert_int_equal(le32(table + 56), 0u);
    assert_int_equal(le32(table + 60), 0u);
    /* Left node (1, 1) = pixel (4, 4) = (1024, 1024) in Q.8. */
    assert_int_equal(le32(table + 64 + (1 * 6 + 1) * 8), 1024u);
    assert_int_equal(le32(table + 64 + (1 * 6 + 1) * 8 + 4), 1024u);
    assert_int_equal(le32(table + n - 4),
                     negobs_rectify_crc32(0, table, n - 4));
}

static void test_rectify_info_round_trips_header_values(void **state)
{
    negobs_rectify_info_t in = make_info(33, 17, 3);
    negobs_rectify_info_t info;
    size_t n = build_table(33, 17, 3, &identity, &identity);
    (void)state;
    assert_int_equal(negobs_rectify_table_check(table, n, 33, 17, &info),
                     NEGOBS_OK);
    assert_int_equal(info.version_major, 1);
    assert_int_equal(info.width, 33);
    assert_int_equal(info.height, 17);
    assert_int_equal(info.grid_shift, 3);
    assert_int_equal(info.grid_w, 6);
    assert_int_equal(info.grid_h, 4);
    assert_int_equal(info.f_q16, in.f_q16);
    assert_int_equal(info.baseline_um, in.baseline_um);
    assert_int_equal(info.cx_q16, in.cx_q16);
    assert_int_equal(info.cy_q16, in.cy_q16);
    assert_int_equal(info.doffs_q16, in.doffs_q16);
    assert_int_equal(info.rms_mpx, in.rms_mpx);
    assert_int_equal(info.total_bytes, n);
    /* 0 x 0 means "any frame size". */
    assert_int_equal(negobs_rectify_table_check(table, n, 0, 0, NULL),
                     NEGOBS_OK);
}

static void test_rectify_rejects_truncated_table(void **state)
{
    size_t n = build_table(20, 10, 1, &identity, &identity);
    size_t len;
    (void)state;
    for (len = 0; len < n; len++) {
        assert_int_equal(negobs_rectify_table_check(table, len, 20, 10, NULL),
                         NEGOBS_ERR_CORRUPT);
    }
    assert_int_equal(negobs_rectify_table_check(table, n, 20, 10, NULL),
                     NEGOBS_OK);
    /* Trailing bytes (a table in a larger flash partition) are ignored. */
    assert_int_equal(negobs_rectify_table_check(table, n + 50, 20, 10, NULL),
                     NEGOBS_OK);
}

/* Every single-bit error anywhere is caught; the major version field is
 * checked before the CRC so a future table reads as UNSUPPORTED. */
static void test_rectify_rejects_any_single_bit_flip(void **state)
{
    size_t n = build_table(12, 9, 2, &identity, &identity);
    size_t i;
    int bit;
    (void)state;
    for (i = 0; i < n; i++) {
        for (bit = 0; bit < 8; bit++) {
            negobs_status_t want = (i == 8 || i == 9) ? NEGOBS_ERR_UNSUPPORTED
                                                      : NEGOBS_ERR_CORRUPT;
            table[i] ^= (uint8_t)(1u << bit);
            assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                             want);
            table[i] ^= (uint8_t)(1u << bit);
        }
    }
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_OK);
}

static void test_rectify_rejects_bad_magic_and_bad_crc(void **state)
{
    size_t n = build_table(12, 9, 0, &identity, &identity);
    (void)state;
    memcpy(table, "NGOBRECX", 8);
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_CORRUPT);
    memcpy(table, "NGOBRECT", 8);
    table[n - 1] ^= 0xFFu;
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_CORRUPT);
    table[n - 1] ^= 0xFFu;
    assert_int_equal(negobs_rectify_table_check(NULL, n, 12, 9, NULL),
                     NEGOBS_ERR_INVAL);
}

/* Patch a header byte and re-seal the CRC, as a well-formed writer of a
 * different (future or foreign) table would. */
static void patch_and_reseal(size_t n, size_t off, uint8_t value)
{
    table[off] = value;
    table[n - 4] = 0; /* recompute below */
    {
        uint32_t crc = negobs_rectify_crc32(0, table, n - 4);
        table[n - 4] = (uint8_t)(crc & 0xFFu);
        table[n - 3] = (uint8_t)((crc >> 8) & 0xFFu);
        table[n - 2] = (uint8_t)((crc >> 16) & 0xFFu);
        table[n - 1] = (uint8_t)(crc >> 24);
    }
}

static void test_rectify_unsupported_version_and_format(void **state)
{
    size_t n;
    (void)state;
    n = build_table(12, 9, 0, &identity, &identity);
    patch_and_reseal(n, 8, 2); /* major version 2 */
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_UNSUPPORTED);
    n = build_table(12, 9, 0, &identity, &identity);
    patch_and_reseal(n, 10, 7); /* minor version 7: still readable */
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_OK);
    n = build_table(12, 9, 0, &identity, &identity);
    patch_and_reseal(n, 24, 5); /* grid shift 5 */
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_UNSUPPORTED);
    n = build_table(12, 9, 0, &identity, &identity);
    patch_and_reseal(n, 25, 10); /* Q.10 coordinates */
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_UNSUPPORTED);
    n = build_table(12, 9, 0, &identity, &identity);
    patch_and_reseal(n, 26, 1); /* unknown flag */
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_UNSUPPORTED);
    n = build_table(12, 9, 0, &identity, &identity);
    patch_and_reseal(n, 28, 99); /* grid width disagrees with width */
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_CORRUPT);
    n = build_table(12, 9, 0, &identity, &identity);
    patch_and_reseal(n, 20, 0); /* width 0 */
    patch_and_reseal(n, 21, 0);
    assert_int_equal(negobs_rectify_table_check(table, n, 0, 0, NULL),
                     NEGOBS_ERR_CORRUPT);
}

static void test_rectify_node_out_of_range_is_refused(void **state)
{
    size_t n = build_table(12, 9, 0, &identity, &identity);
    negobs_rectify_info_t info = make_info(12, 9, 0);
    (void)state;
    /* Most significant byte of the right map's last y: 0x7F.. = huge. */
    patch_and_reseal(n, n - 5, 0x7Fu);
    assert_int_equal(negobs_rectify_table_check(table, n, 12, 9, NULL),
                     NEGOBS_ERR_CORRUPT);
    /* The writer refuses such a node before it reaches a device. */
    nodes_r[5] = NEGOBS_RECTIFY_COORD_LIMIT_Q8 + 1;
    assert_int_equal(negobs_rectify_table_write(&info, nodes_l, nodes_r, table,
                                                sizeof table, NULL),
                     NEGOBS_ERR_RANGE);
    nodes_r[5] = -NEGOBS_RECTIFY_COORD_LIMIT_Q8;
    assert_int_equal(negobs_rectify_table_write(&info, nodes_l, nodes_r, table,
                                                sizeof table, NULL),
                     NEGOBS_OK);
    assert_int_equal(negobs_rectify_table_write(&info, nodes_l, nodes_r, table,
                                                n - 1, NULL),
                     NEGOBS_ERR_NOSPACE);
    info.grid_shift = 5;
    assert_int_equal(negobs_rectify_table_write(&info, nodes_l, nodes_r, table,
                                                sizeof table, NULL),
                     NEGOBS_ERR_INVAL);
}

static void test_rectify_rejects_table_for_other_frame_size(void **state)
{
    size_t n = build_table(20, 10, 1, &identity, &identity);
    negobs_rectify_config_t cfg;
    negobs_rectify_t ctx;
    size_t bytes = 0;
    (void)state;
    assert_int_equal(negobs_rectify_table_check(table, n, 21, 10, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_table_check(table, n, 20, 11, NULL),
                     NEGOBS_ERR_INVAL);
    negobs_rectify_config_default(&cfg, 22, 10);
    cfg.table = table;
    cfg.table_bytes = n;
    assert_int_equal(negobs_rectify_workspace_size(&cfg, &bytes), NEGOBS_OK);
    assert_int_equal(negobs_rectify_init(&ctx, &cfg, ws.bytes, bytes),
                     NEGOBS_ERR_INVAL);
    /* A failed init leaves a context that refuses to run. */
    {
        negobs_image_u8_t a = image(raw, 22, 10, 22);
        negobs_image_u8_t b = image(out, 22, 10, 22);
        assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT,
                                             &a, &b, 0, 10, NULL),
                         NEGOBS_ERR_STATE);
    }
    /* A corrupt table fails init with the checker's status. */
    cfg.width = 20;
    table[100] ^= 1u;
    assert_int_equal(negobs_rectify_init(&ctx, &cfg, ws.bytes, bytes),
                     NEGOBS_ERR_CORRUPT);
    table[100] ^= 1u;
}

/* ---- workspace -------------------------------------------------------- */

static void test_rectify_workspace_exact_size(void **state)
{
    size_t n = build_table(40, 30, 2, &identity, &identity);
    negobs_rectify_config_t cfg;
    negobs_rectify_t ctx;
    size_t bytes = 0;
    int32_t w;
    (void)state;
    negobs_rectify_config_default(&cfg, 40, 30);
    cfg.table = table;
    cfg.table_bytes = n;
    assert_int_equal(negobs_rectify_workspace_size(&cfg, &bytes), NEGOBS_OK);
    assert_int_equal(negobs_rectify_init(&ctx, &cfg, ws.bytes, bytes - 1),
                     NEGOBS_ERR_NOSPACE);
    assert_int_equal(negobs_rectify_init(&ctx, &cfg, ws.bytes + 1, bytes),
                     NEGOBS_ERR_ALIGN);
    assert_int_equal(negobs_rectify_init(&ctx, &cfg, ws.bytes, bytes),
                     NEGOBS_OK);
    /* Runtime size never exceeds the static-array macro. */
    for (w = 1; w <= NEGOBS_MAX_DIM; w = w * 3 + 1) {
        negobs_rectify_config_default(&cfg, w, 7);
        assert_int_equal(negobs_rectify_workspace_size(&cfg, &bytes),
                         NEGOBS_OK);
        assert_true(bytes <= NEGOBS_RECTIFY_WORKSPACE_MAX(w));
    }
    negobs_rectify_config_default(&cfg, 0, 7);
    assert_int_equal(negobs_rectify_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
    negobs_rectify_config_default(&cfg, NEGOBS_MAX_DIM + 1, 7);
    assert_int_equal(negobs_rectify_workspace_size(&cfg, &bytes),
                     NEGOBS_ERR_INVAL);
}

/* ---- remap ------------------------------------------------------------ */

static void check_canaries(const uint8_t *buf, size_t from, size_t to)
{
    size_t i;
    for (i = from; i < to; i++) {
        assert_int_equal(buf[i], CANARY);
    }
}

/* Identity at every grid spacing, odd sizes and padded strides: exact
 * copy, padding and canaries untouched. */
static void test_rectify_identity_table_reproduces_image(void **state)
{
    static const int32_t sizes[][2] = {
        {1, 1}, {2, 3}, {17, 5}, {37, 23}, {64, 48}};
    size_t si;
    int32_t shift;
    (void)state;
    for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        int32_t w = sizes[si][0];
        int32_t h = sizes[si][1];
        for (shift = 0; shift <= NEGOBS_RECTIFY_MAX_GRID_SHIFT; shift++) {
            negobs_rectify_config_t cfg;
            negobs_rectify_t ctx;
            negobs_rectify_stats_t st;
            negobs_image_u8_t in = image(raw, w, h, w + 3);
            negobs_image_u8_t o = image(out, w, h, w + 5);
            size_t used = (size_t)(h - 1) * (size_t)(w + 5) + (size_t)w;
            int32_t y;
            size_t n = build_table(w, h, shift, &identity, &identity);
            init_ctx(&ctx, &cfg, w, h, n);
            fill_random(&in, (uint32_t)(w * 31 + h + shift));
            memset(out, CANARY, sizeof out);
            assert_int_equal(negobs_rectify_rows(&ctx,
                                                 NEGOBS_RECTIFY_CAMERA_RIGHT,
                                                 &in, &o, 0, h, &st),
                             NEGOBS_OK);
            assert_int_equal(st.border_pixels, 0);
            for (y = 0; y < h; y++) {
                assert_memory_equal(negobs_image_u8_row(&o, y),
                                    negobs_image_u8_row(&in, y), (size_t)w);
                if (y + 1 < h) {
                    check_canaries(out,
                                   (size_t)y * (size_t)(w + 5) + (size_t)w,
                                   (size_t)(y + 1) * (size_t)(w + 5));
                }
            }
            check_canaries(out, used, sizeof out);
        }
    }
}

/* Affine maps (shift, zoom, shear, partly outside the frame) are
 * reproduced exactly by the node grid, so the remap must equal a direct
 * per-pixel reference at every grid spacing. */
static void test_rectify_affine_table_matches_direct_reference(void **state)
{
    static const affine_t maps[] = {
        {256, 0, 3 * 256 + 64, 0, 256, -2 * 256 + 128}, /* shift */
        {250, 7, 300, -5, 262, -100},                   /* shear, zoom */
        {-256, 0, 40 * 256, 0, 256, 0},                 /* mirror */
        {200, -30, 1000, 25, 230, 500},
    };
    const int32_t w = 45;
    const int32_t h = 31;
    size_t mi;
    int32_t shift;
    (void)state;
    for (mi = 0; mi < sizeof maps / sizeof maps[0]; mi++) {
        for (shift = 0; shift <= NEGOBS_RECTIFY_MAX_GRID_SHIFT; shift++) {
            const affine_t *m = &maps[mi];
            const affine_t *other = &maps[(mi + 1) % 4];
            negobs_rectify_config_t cfg;
            negobs_rectify_t ctx;
            negobs_rectify_stats_t st;
            negobs_image_u8_t inl = image(raw, w, h, w);
            negobs_image_u8_t inr = image(raw + w * h, w, h, w);
            negobs_image_u8_t ol = image(out, w, h, w);
            negobs_image_u8_t orr = image(out2, w, h, w + 1);
            uint32_t border = 0;
            int32_t x;
            int32_t y;
            size_t n = build_table(w, h, shift, m, other);
            init_ctx(&ctx, &cfg, w, h, n);
            cfg.border_u8 = 77;
            fill_random(&inl, 99u + (uint32_t)mi);
            fill_random(&inr, 7u + (uint32_t)mi);
            assert_int_equal(
                negobs_rectify_process(&ctx, &inl, &inr, &ol, &orr, &st),
                NEGOBS_OK);
            for (y = 0; y < h; y++) {
                for (x = 0; x < w; x++) {
                    int32_t sxl = m->ax * x + m->bx * y + m->cx;
                    int32_t syl = m->ay * x + m->by * y + m->cy;
                    int32_t sxr = other->ax * x + other->bx * y + other->cx;
                    int32_t syr = other->ay * x + other->by * y + other->cy;
                    uint8_t el = ref_sample(&inl, sxl, syl, 77);
                    uint8_t er = ref_sample(&inr, sxr, syr, 77);
                    assert_int_equal(negobs_image_u8_row(&ol, y)[x], el);
                    assert_int_equal(negobs_image_u8_row(&orr, y)[x], er);
                    border += (sxl < 0 || syl < 0 || sxl > (w - 1) * 256 ||
                               syl > (h - 1) * 256);
                    border += (sxr < 0 || syr < 0 || sxr > (w - 1) * 256 ||
                               syr > (h - 1) * 256);
                }
            }
            assert_int_equal(st.border_pixels, border);
        }
    }
}

/* Every fractional position 0..255 in x and y: the integer result is the
 * correctly rounded (half up) bilinear value. */
static void test_rectify_integer_bilinear_is_exact(void **state)
{
    const int32_t w = 8;
    const int32_t h = 8;
    int32_t fx;
    int32_t fy;
    (void)state;
    for (fy = 0; fy < 256; fy += 5) {
        for (fx = 0; fx < 256; fx++) {
            affine_t m = {256, 0, fx, 0, 256, fy};
            negobs_rectify_config_t cfg;
            negobs_rectify_t ctx;
            negobs_image_u8_t in = image(raw, w, h, w);
            negobs_image_u8_t o = image(out, w, h, w);
            int32_t x;
            int32_t y;
            size_t n = build_table(w, h, 0, &m, &m);
            init_ctx(&ctx, &cfg, w, h, n);
            fill_random(&in, (uint32_t)(fx * 256 + fy));
            assert_int_equal(negobs_rectify_rows(&ctx,
                                                 NEGOBS_RECTIFY_CAMERA_LEFT,
                                                 &in, &o, 0, h, NULL),
                             NEGOBS_OK);
            for (y = 0; y < h; y++) {
                for (x = 0; x < w; x++) {
                    assert_int_equal(
                        negobs_image_u8_row(&o, y)[x],
                        ref_sample(&in, x * 256 + fx, y * 256 + fy, 0));
                }
            }
        }
    }
    /* A tie rounds up: halfway between 0 and 1 is 1. */
    {
        affine_t half = {256, 0, 128, 0, 256, 0};
        negobs_rectify_config_t cfg;
        negobs_rectify_t ctx;
        negobs_image_u8_t in = image(raw, 2, 1, 2);
        negobs_image_u8_t o = image(out, 2, 1, 2);
        size_t n = build_table(2, 1, 0, &half, &half);
        init_ctx(&ctx, &cfg, 2, 1, n);
        raw[0] = 0;
        raw[1] = 1;
        assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT,
                                             &in, &o, 0, 1, NULL),
                         NEGOBS_OK);
        assert_int_equal(out[0], 1);
        assert_int_equal(out[1], 0); /* x = 1.5 is outside: border */
    }
}

/* floor(a / 2^n) for any sign, n in 0..8 (reference, no shifts). */
static int64_t floor_div_pow2(int64_t a, int n)
{
    int64_t d = (int64_t)1 << n;
    int64_t q = a / d;
    return (a % d != 0 && a < 0) ? q - 1 : q;
}

/* A non-affine (random) node grid: the per-pixel coordinate must be the
 * exact bilinear blend of the four nodes, rounded half up to Q.8, then
 * sampled; checked against a direct 64-bit evaluation at every pixel. */
static void test_rectify_random_grid_matches_reference(void **state)
{
    const int32_t w = 41;
    const int32_t h = 27;
    int32_t shift;
    (void)state;
    for (shift = 0; shift <= NEGOBS_RECTIFY_MAX_GRID_SHIFT; shift++) {
        const int32_t gw = NEGOBS_RECTIFY_GRID_NODES(w, shift);
        const int32_t gh = NEGOBS_RECTIFY_GRID_NODES(h, shift);
        const int32_t step = 1 << shift;
        negobs_rectify_info_t info = make_info(w, h, shift);
        negobs_rectify_config_t cfg;
        negobs_rectify_t ctx;
        negobs_image_u8_t in = image(raw, w, h, w);
        negobs_image_u8_t o = image(out, w, h, w);
        uint32_t seed = 1234u + (uint32_t)shift;
        size_t n = 0;
        int32_t i;
        int32_t x;
        int32_t y;
        for (i = 0; i < gw * gh; i++) {
            int32_t gx = i % gw;
            int32_t gy = i / gw;
            /* identity plus up to +-3 px of noise, some nodes outside */
            nodes_l[2 * i] = (gx << shift) * 256 +
                             (int32_t)(test_lcg_next(&seed) % 1537u) - 768;
            nodes_l[2 * i + 1] = (gy << shift) * 256 +
                                 (int32_t)(test_lcg_next(&seed) % 1537u) - 768;
        }
        memcpy(nodes_r, nodes_l, sizeof nodes_l);
        assert_int_equal(negobs_rectify_table_write(&info, nodes_l, nodes_r,
                                                    table, sizeof table, &n),
                         NEGOBS_OK);
        init_ctx(&ctx, &cfg, w, h, n);
        fill_random(&in, seed);
        assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT,
                                             &in, &o, 0, h, NULL),
                         NEGOBS_OK);
        for (y = 0; y < h; y++) {
            for (x = 0; x < w; x++) {
                int32_t gx = x / step;
                int32_t gy = y / step;
                int64_t fx = x % step;
                int64_t fy = y % step;
                int32_t c[2];
                int k;
                for (k = 0; k < 2; k++) {
                    const int32_t *n00 = nodes_l + 2 * (gy * gw + gx) + k;
                    int64_t v = (step - fx) * (step - fy) * n00[0] +
                                fx * (step - fy) * n00[2] +
                                (step - fx) * fy * n00[2 * gw] +
                                fx * fy * n00[2 * gw + 2];
                    int64_t half = (shift > 0)
                                       ? ((int64_t)1 << (2 * shift - 1))
                                       : 0;
                    c[k] = (int32_t)floor_div_pow2(v + half, 2 * shift);
                }
                assert_int_equal(negobs_image_u8_row(&o, y)[x],
                                 ref_sample(&in, c[0], c[1], 0));
            }
        }
    }
}

static void test_rectify_rows_in_bands_equal_whole_frame(void **state)
{
    static const affine_t m = {250, 7, 300, -5, 262, -100};
    const int32_t w = 50;
    const int32_t h = 40;
    negobs_rectify_config_t cfg;
    negobs_rectify_t ctx;
    negobs_image_u8_t in = image(raw, w, h, w);
    negobs_image_u8_t a = image(out, w, h, w);
    negobs_image_u8_t b = image(out2, w, h, w);
    negobs_rectify_stats_t st;
    uint32_t total = 0;
    uint32_t whole;
    int32_t y;
    size_t n = build_table(w, h, 3, &m, &m);
    (void)state;
    init_ctx(&ctx, &cfg, w, h, n);
    fill_random(&in, 5u);
    assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT, &in,
                                         &a, 0, h, &st),
                     NEGOBS_OK);
    whole = st.border_pixels;
    for (y = 0; y < h; y += 7) {
        int32_t y1 = (y + 7 < h) ? y + 7 : h;
        assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT,
                                             &in, &b, y, y1, &st),
                         NEGOBS_OK);
        total += st.border_pixels;
    }
    assert_memory_equal(out, out2, (size_t)(w * h));
    assert_int_equal(total, whole);
    assert_true(whole > 0);
}

static void test_rectify_process_checks_arguments(void **state)
{
    const int32_t w = 16;
    const int32_t h = 12;
    negobs_rectify_config_t cfg;
    negobs_rectify_t ctx;
    negobs_rectify_t zero;
    negobs_image_u8_t in = image(raw, w, h, w);
    negobs_image_u8_t o = image(out, w, h, w);
    negobs_image_u8_t o2 = image(out2, w, h, w);
    negobs_image_u8_t small = image(out, w - 1, h, w);
    negobs_image_u8_t alias = image(raw + 5, w, h, w);
    size_t n = build_table(w, h, 2, &identity, &identity);
    (void)state;
    memset(&zero, 0, sizeof zero);
    assert_int_equal(negobs_rectify_process(&zero, &in, &in, &o, &o2, NULL),
                     NEGOBS_ERR_STATE);
    init_ctx(&ctx, &cfg, w, h, n);
    assert_int_equal(negobs_rectify_process(NULL, &in, &in, &o, &o2, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_process(&ctx, NULL, &in, &o, &o2, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_process(&ctx, &in, &in, &small, &o2, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_process(&ctx, &in, &in, &o, &alias, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_rows(&ctx, (negobs_rectify_camera_t)2, &in,
                                         &o, 0, h, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT, &in,
                                         &o, 3, 2, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT, &in,
                                         &o, 0, h + 1, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_rows(&ctx, NEGOBS_RECTIFY_CAMERA_LEFT, &in,
                                         &o, 4, 4, NULL),
                     NEGOBS_OK);
    assert_int_equal(negobs_rectify_process(&ctx, &in, &in, &o, &o2, NULL),
                     NEGOBS_OK);
    assert_int_equal(negobs_rectify_init(&ctx, NULL, ws.bytes, 1000),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_rectify_init(NULL, &cfg, ws.bytes, 1000),
                     NEGOBS_ERR_INVAL);
    cfg.table = NULL;
    assert_int_equal(negobs_rectify_init(&ctx, &cfg, ws.bytes, 1000),
                     NEGOBS_ERR_INVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rectify_crc32_known_answer),
        cmocka_unit_test(test_rectify_table_layout_matches_documentation),
        cmocka_unit_test(test_rectify_info_round_trips_header_values),
        cmocka_unit_test(test_rectify_rejects_truncated_table),
        cmocka_unit_test(test_rectify_rejects_any_single_bit_flip),
        cmocka_unit_test(test_rectify_rejects_bad_magic_and_bad_crc),
        cmocka_unit_test(test_rectify_unsupported_version_and_format),
        cmocka_unit_test(test_rectify_node_out_of_range_is_refused),
        cmocka_unit_test(test_rectify_rejects_table_for_other_frame_size),
        cmocka_unit_test(test_rectify_workspace_exact_size),
        cmocka_unit_test(test_rectify_identity_table_reproduces_image),
        cmocka_unit_test(test_rectify_affine_table_matches_direct_reference),
        cmocka_unit_test(test_rectify_integer_bilinear_is_exact),
        cmocka_unit_test(test_rectify_random_grid_matches_reference),
        cmocka_unit_test(test_rectify_rows_in_bands_equal_whole_frame),
        cmocka_unit_test(test_rectify_process_checks_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
