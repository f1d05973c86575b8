/*
 * Public API: exact workspace size, size macro, config and image checks,
 * and defined output on degenerate content (black, saturated, noise,
 * stripes), determinism, stride padding and the queue bound end to end.
 */
#include <stdio.h>
#include <string.h>

#include "cmocka_all.h"
#include "negobs/stereo.h"
#include "scene_pair.h"

#define W 128
#define H 96
#define PAD 8
#define DMAX 31

static uint8_t left[H * (W + PAD)];
static uint8_t right[H * (W + PAD)];
static uint8_t tex[W * H];
static uint8_t occ[W * H];
static int16_t gt[W * H];
static int16_t disp[H * (W + PAD)];
static int16_t disp2[H * (W + PAD)];
static uint8_t conf[W * H];
static uint8_t ws[NEGOBS_STEREO_WORKSPACE_MAX(W, H, DMAX) + 32]
    __attribute__((aligned(16)));

static negobs_image_u8_t u8img(uint8_t *p, int32_t w, int32_t h, int32_t st)
{
    negobs_image_u8_t i;
    i.data = p;
    i.width = w;
    i.height = h;
    i.stride = st;
    return i;
}

static negobs_image_s16_t s16img(int16_t *p, int32_t w, int32_t h, int32_t st)
{
    negobs_image_s16_t i;
    i.data = p;
    i.width = w;
    i.height = h;
    i.stride = st;
    return i;
}

static void config(negobs_stereo_config_t *c)
{
    negobs_stereo_config_default(c, W, H);
    c->max_disp = DMAX;
}

static void test_workspace_size_is_exact(void **state)
{
    negobs_stereo_config_t c;
    negobs_stereo_t ctx;
    size_t need;
    (void)state;
    config(&c);
    assert_int_equal(negobs_stereo_workspace_size(&c, &need), NEGOBS_OK);
    assert_true(need <= sizeof ws);
    assert_int_equal(negobs_stereo_init(&ctx, &c, ws, need - 1),
                     NEGOBS_ERR_NOSPACE);
    assert_null(ctx.priv);
    assert_int_equal(negobs_stereo_init(&ctx, &c, ws, need), NEGOBS_OK);
    assert_int_equal(negobs_stereo_init(&ctx, &c, ws + 1, need),
                     NEGOBS_ERR_ALIGN);
    assert_int_equal(negobs_stereo_init(&ctx, &c, NULL, need),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_stereo_workspace_size(&c, NULL), NEGOBS_ERR_INVAL);
}

static void test_workspace_macro_bounds_exact_size(void **state)
{
    static const int32_t ws_[] = {32, 64, 160, 320, 450, 641, 752, 1344};
    static const int32_t hs[] = {16, 120, 240, 375, 480, 555};
    static const int32_t ds[] = {0, 15, 63, 127, 255};
    size_t i;
    size_t j;
    size_t k;
    (void)state;
    for (i = 0; i < sizeof ws_ / sizeof ws_[0]; i++) {
        for (j = 0; j < sizeof hs / sizeof hs[0]; j++) {
            for (k = 0; k < sizeof ds / sizeof ds[0]; k++) {
                negobs_stereo_config_t c;
                size_t need;
                negobs_stereo_config_default(&c, ws_[i], hs[j]);
                c.max_disp = ds[k];
                if (negobs_stereo_workspace_size(&c, &need) != NEGOBS_OK) {
                    assert_true(ds[k] > ws_[i] - 6);
                    continue;
                }
                assert_true(need <=
                            NEGOBS_STEREO_WORKSPACE_MAX(ws_[i], hs[j], ds[k]));
            }
        }
    }
}

static void test_workspace_320x240x64_fits_512k(void **state)
{
    negobs_stereo_config_t c;
    size_t need;
    (void)state;
    negobs_stereo_config_default(&c, 320, 240);
    assert_int_equal(c.max_disp, 63);
    /* the budget of the compact profile (microcontrollers); the fast
     * one's is test_stereo_profile's */
    c.memory_profile = NEGOBS_STEREO_PROFILE_COMPACT;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need), NEGOBS_OK);
    printf("# workspace 320x240 d0..63 (compact): %u bytes\n", (unsigned)need);
    assert_true(need <= 512u * 1024u);
}

static void test_bad_configs_are_rejected(void **state)
{
    negobs_stereo_config_t c;
    size_t need;
    (void)state;
    config(&c);
    c.width = 31;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.height = 8;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.max_disp = W; /* range wider than the image */
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.min_disp = 10;
    c.max_disp = 9;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.min_disp = -1;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.band = 0;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.queue_capacity = 0;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.vertical_search = 5;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.strip_rows = 4;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    config(&c);
    c.canny_top_permille = -1;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    c.canny_top_permille = 1001;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    c.canny_top_permille = 1000;
    assert_int_equal(negobs_stereo_workspace_size(&c, &need), NEGOBS_OK);
    negobs_stereo_config_default(&c, 2000, 100);
    c.max_disp = 300; /* more than 256 levels */
    assert_int_equal(negobs_stereo_workspace_size(&c, &need),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_stereo_workspace_size(NULL, &need),
                     NEGOBS_ERR_INVAL);
}

static negobs_stereo_t ready(void)
{
    negobs_stereo_config_t c;
    negobs_stereo_t ctx;
    config(&c);
    assert_int_equal(negobs_stereo_init(&ctx, &c, ws, sizeof ws), NEGOBS_OK);
    return ctx;
}

static void test_bad_images_are_rejected(void **state)
{
    negobs_stereo_t ctx = ready();
    negobs_stereo_t none;
    negobs_image_u8_t l = u8img(left, W, H, W);
    negobs_image_u8_t r = u8img(right, W, H, W);
    negobs_image_s16_t d = s16img(disp, W, H, W);
    negobs_image_u8_t c = u8img(conf, W, H, W);
    negobs_image_u8_t bad;
    negobs_image_s16_t badd;
    (void)state;
    bad = u8img(right, W - 1, H, W);
    assert_int_equal(negobs_stereo_process(&ctx, &l, &bad, &d, &c, NULL),
                     NEGOBS_ERR_INVAL);
    bad = u8img(right, W, H - 1, W);
    assert_int_equal(negobs_stereo_process(&ctx, &bad, &r, &d, &c, NULL),
                     NEGOBS_ERR_INVAL);
    bad = u8img(right, W, H, W - 1); /* stride < width */
    assert_int_equal(negobs_stereo_process(&ctx, &l, &bad, &d, &c, NULL),
                     NEGOBS_ERR_INVAL);
    bad = u8img(NULL, W, H, W);
    assert_int_equal(negobs_stereo_process(&ctx, &l, &bad, &d, &c, NULL),
                     NEGOBS_ERR_INVAL);
    badd = s16img(disp, W, H - 2, W);
    assert_int_equal(negobs_stereo_process(&ctx, &l, &r, &badd, &c, NULL),
                     NEGOBS_ERR_INVAL);
    bad = u8img(conf, W / 2, H, W);
    assert_int_equal(negobs_stereo_process(&ctx, &l, &r, &d, &bad, NULL),
                     NEGOBS_ERR_INVAL);
    assert_int_equal(negobs_stereo_process(&ctx, NULL, &r, &d, &c, NULL),
                     NEGOBS_ERR_INVAL);
    none.priv = NULL;
    assert_int_equal(negobs_stereo_process(&none, &l, &r, &d, &c, NULL),
                     NEGOBS_ERR_STATE);
    assert_int_equal(negobs_stereo_process(NULL, &l, &r, &d, &c, NULL),
                     NEGOBS_ERR_STATE);
}

/* Every output value is INVALID or inside the searched range. */
static void check_defined(const negobs_stereo_stats_t *st)
{
    int32_t i;
    uint32_t valid = 0;
    for (i = 0; i < W * H; i++) {
        if (disp[i] == NEGOBS_DISP_INVALID) {
            assert_int_equal(conf[i], 0);
            continue;
        }
        valid++;
        assert_true(disp[i] >= -8 && disp[i] <= DMAX * 16 + 8);
    }
    assert_int_equal(valid, st->valid);
}

static void content_case(int kind, negobs_stereo_stats_t *st)
{
    negobs_stereo_t ctx = ready();
    negobs_image_u8_t l = u8img(left, W, H, W);
    negobs_image_u8_t r = u8img(right, W, H, W);
    negobs_image_s16_t d = s16img(disp, W, H, W);
    negobs_image_u8_t c = u8img(conf, W, H, W);
    uint32_t seed = 99u;
    int32_t i;
    for (i = 0; i < W * H; i++) {
        switch (kind) {
        case 0: left[i] = right[i] = 0; break;
        case 1: left[i] = right[i] = 255; break;
        case 2:
            left[i] = (uint8_t)test_lcg_next(&seed);
            right[i] = (uint8_t)test_lcg_next(&seed);
            break;
        default:
            /* vertical stripes, period 8: every 8 px looks the same */
            left[i] = (uint8_t)(((i % W) / 4) % 2 ? 200 : 40);
            right[i] = left[i];
            break;
        }
    }
    assert_int_equal(negobs_stereo_process(&ctx, &l, &r, &d, &c, st),
                     NEGOBS_OK);
    check_defined(st);
}

static void test_black_and_saturated_give_empty_maps(void **state)
{
    negobs_stereo_stats_t st;
    (void)state;
    content_case(0, &st);
    assert_int_equal(st.valid, 0);
    assert_int_equal(st.seeds, 0);
    content_case(1, &st);
    assert_int_equal(st.valid, 0);
    assert_int_equal(st.seeds, 0);
}

static void test_noise_gives_low_confidence(void **state)
{
    negobs_stereo_stats_t st;
    int32_t i;
    uint32_t high = 0;
    (void)state;
    content_case(2, &st);
    for (i = 0; i < W * H; i++) {
        if (conf[i] >= 160) {
            high++;
        }
    }
    printf("# noise: valid %u, seeds %u, confident %u\n", (unsigned)st.valid,
           (unsigned)st.seeds, (unsigned)high);
    assert_true(high * 50u <= (uint32_t)(W * H)); /* < 2 % confident */
}

static void test_stripes_are_defined(void **state)
{
    negobs_stereo_stats_t st;
    (void)state;
    content_case(3, &st);
}

static void render(void)
{
    synth_scene_t sc;
    sc.w = W;
    sc.h = H;
    sc.d_top_q8 = 6 * 256;
    sc.d_bottom_q8 = 20 * 256;
    sc.drop_q8 = 4 * 256;
    sc.box_q8 = 26 * 256;
    sc.voff = 0;
    sc.seed = 7u;
    synth_render(&sc, left, right, gt, occ, tex);
}

static void test_output_is_deterministic_and_stride_independent(void **state)
{
    negobs_stereo_t ctx = ready();
    negobs_image_u8_t l = u8img(left, W, H, W);
    negobs_image_u8_t r = u8img(right, W, H, W);
    negobs_image_s16_t d = s16img(disp, W, H, W);
    negobs_image_s16_t d2 = s16img(disp2, W, H, W + PAD);
    negobs_stereo_stats_t st;
    negobs_stereo_stats_t st2;
    int32_t x;
    int32_t y;
    (void)state;
    render();
    assert_int_equal(negobs_stereo_process(&ctx, &l, &r, &d, NULL, &st),
                     NEGOBS_OK);
    assert_true(st.valid > (uint32_t)(W * H / 2));
    /* same frame again, through padded rows (stride > width) */
    for (y = H - 1; y >= 0; y--) {
        memmove(left + y * (W + PAD), left + y * W, W);
        memmove(right + y * (W + PAD), right + y * W, W);
        memset(left + y * (W + PAD) + W, 0xEE, PAD);
        memset(right + y * (W + PAD) + W, 0x11, PAD);
    }
    l.stride = W + PAD;
    r.stride = W + PAD;
    assert_int_equal(negobs_stereo_process(&ctx, &l, &r, &d2, NULL, &st2),
                     NEGOBS_OK);
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            assert_int_equal(disp[y * W + x], disp2[y * (W + PAD) + x]);
        }
    }
    assert_memory_equal(&st, &st2, sizeof st);
}

static void test_tiny_queue_overflows_gracefully(void **state)
{
    negobs_stereo_config_t c;
    negobs_stereo_t ctx;
    negobs_image_u8_t l = u8img(left, W, H, W);
    negobs_image_u8_t r = u8img(right, W, H, W);
    negobs_image_s16_t d = s16img(disp, W, H, W);
    negobs_stereo_stats_t st;
    (void)state;
    render();
    config(&c);
    c.queue_capacity = 16;
    assert_int_equal(negobs_stereo_init(&ctx, &c, ws, sizeof ws), NEGOBS_OK);
    assert_int_equal(negobs_stereo_process(&ctx, &l, &r, &d, NULL, &st),
                     NEGOBS_OK);
    assert_true(st.queue_overflows > 0);
    assert_true(st.queue_peak <= 16u);
    assert_true(st.valid > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_workspace_size_is_exact),
        cmocka_unit_test(test_workspace_macro_bounds_exact_size),
        cmocka_unit_test(test_workspace_320x240x64_fits_512k),
        cmocka_unit_test(test_bad_configs_are_rejected),
        cmocka_unit_test(test_bad_images_are_rejected),
        cmocka_unit_test(test_black_and_saturated_give_empty_maps),
        cmocka_unit_test(test_noise_gives_low_confidence),
        cmocka_unit_test(test_stripes_are_defined),
        cmocka_unit_test(test_output_is_deterministic_and_stride_independent),
        cmocka_unit_test(test_tiny_queue_overflows_gracefully),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
