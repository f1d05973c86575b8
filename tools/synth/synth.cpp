// negobs_synth renderer; see synth.hpp and docs/SYNTH.md.
#include "synth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace synth {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

double deg2rad(double d)
{
    return d * kPi / 180.0;
}

Vec3 add(const Vec3 &a, const Vec3 &b)
{
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
Vec3 sub(const Vec3 &a, const Vec3 &b)
{
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
Vec3 mul(const Vec3 &a, double s)
{
    return {a.x * s, a.y * s, a.z * s};
}
double dot(const Vec3 &a, const Vec3 &b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
Vec3 cross(const Vec3 &a, const Vec3 &b)
{
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double comp(const Vec3 &v, int axis)
{
    return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

Rect make_rect(int axis, double pos, double lo_a, double hi_a, double lo_b, double hi_b,
               float shade, double tex_offset)
{
    // lo_a/hi_a bound the first other axis ((axis+1)%3), lo_b/hi_b the
    // second ((axis+2)%3).
    Rect r;
    r.axis = axis;
    r.pos = pos;
    const int a = (axis + 1) % 3;
    const int b = (axis + 2) % 3;
    r.lo[a] = lo_a;
    r.hi[a] = hi_a;
    r.lo[b] = lo_b;
    r.hi[b] = hi_b;
    r.shade = shade;
    r.tex_offset = tex_offset;
    return r;
}

// Horizontal rect: Y = y, X in [x0, x1], Z in [z0, z1].
Rect horiz(double y, double x0, double x1, double z0, double z1, float shade)
{
    // axis 1: first other axis is Z (2), second is X (0).
    return make_rect(1, y, z0, z1, x0, x1, shade, 0.0);
}
// Face of constant Z: X in [x0, x1], Y in [y0, y1].
Rect zface(double z, double x0, double x1, double y0, double y1, float shade, double off)
{
    // axis 2: first other axis is X (0), second is Y (1).
    return make_rect(2, z, x0, x1, y0, y1, shade, off);
}
// Face of constant X: Y in [y0, y1], Z in [z0, z1].
Rect xface(double x, double y0, double y1, double z0, double z1, float shade, double off)
{
    // axis 0: first other axis is Y (1), second is Z (2).
    return make_rect(0, x, y0, y1, z0, z1, shade, off);
}

// Ramp surface: Y = y0 - grade * (Z - z0) for Z in [z0, z1].
Rect ramp(double y0, double grade, double z0, double z1, float shade)
{
    Rect r = horiz(y0, -kInf, kInf, z0, z1, shade);
    r.slope = -grade;
    r.slope_z = z0;
    return r;
}

// Component of v along the normal of r's plane (0, 1, -slope) for a tilted
// horizontal rect, the plain axis component otherwise.
double normal_comp(const Rect &r, const Vec3 &v)
{
    return r.slope != 0.0 ? v.y - r.slope * v.z : comp(v, r.axis);
}

constexpr float kRiserShade = 0.78f;
constexpr float kSideShade = 0.62f;

} // namespace

// ---------------------------------------------------------------- Rng

uint64_t Rng::next()
{
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double Rng::uniform()
{
    return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0);
}

double Rng::gauss()
{
    double u1 = uniform();
    const double u2 = uniform();
    if (u1 < 1e-300)
        u1 = 1e-300;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// ---------------------------------------------------------------- Scene

const char *hazard_name(Hazard h)
{
    switch (h) {
    case Hazard::Curb: return "curb";
    case Hazard::Stairs: return "stairs";
    case Hazard::Hole: return "hole";
    case Hazard::Upstep: return "upstep";
    case Hazard::Wall: return "wall";
    case Hazard::Flat: return "flat";
    case Hazard::Ramp: return "ramp";
    }
    return "?";
}

bool hazard_from_name(const std::string &s, Hazard &out)
{
    const Hazard all[] = {Hazard::Curb, Hazard::Stairs, Hazard::Hole, Hazard::Upstep,
                          Hazard::Wall, Hazard::Flat,   Hazard::Ramp};
    for (Hazard h : all) {
        if (s == hazard_name(h)) {
            out = h;
            return true;
        }
    }
    return false;
}

Scene::Scene(const SceneParams &p) : p_(p)
{
    const double ze = p.edge_z;
    const auto lower = static_cast<float>(p.lower_shade);
    switch (p.hazard) {
    case Hazard::Flat: rects_.push_back(horiz(0.0, -kInf, kInf, -kInf, kInf, 1.0f)); break;
    case Hazard::Curb:
        rects_.push_back(horiz(0.0, -kInf, kInf, -kInf, ze, 1.0f));
        rects_.push_back(horiz(-p.drop, -kInf, kInf, ze, kInf, lower));
        rects_.push_back(zface(ze, -kInf, kInf, -p.drop, 0.0, kRiserShade, 3.3));
        break;
    case Hazard::Stairs: {
        rects_.push_back(horiz(0.0, -kInf, kInf, -kInf, ze, 1.0f));
        for (int k = 0; k < p.steps; ++k) {
            const double z0 = ze + k * p.run;
            const double z1 = (k == p.steps - 1) ? kInf : z0 + p.run;
            const double y = -(k + 1) * p.rise;
            rects_.push_back(horiz(y, -kInf, kInf, z0, z1, lower));
            rects_.push_back(zface(z0, -kInf, kInf, y, y + p.rise, kRiserShade, 3.3 + 0.7 * k));
        }
        break;
    }
    case Hazard::Hole: {
        const double x0 = p.hole_offset - 0.5 * p.hole_width;
        const double x1 = p.hole_offset + 0.5 * p.hole_width;
        const double z1 = ze + p.hole_length;
        const double h = p.drop;
        rects_.push_back(horiz(0.0, -kInf, kInf, -kInf, ze, 1.0f));
        rects_.push_back(horiz(0.0, -kInf, kInf, z1, kInf, 1.0f));
        rects_.push_back(horiz(0.0, -kInf, x0, ze, z1, 1.0f));
        rects_.push_back(horiz(0.0, x1, kInf, ze, z1, 1.0f));
        rects_.push_back(horiz(-h, x0, x1, ze, z1, lower * 0.8f));
        rects_.push_back(zface(ze, x0, x1, -h, 0.0, kRiserShade * lower, 3.3));
        rects_.push_back(zface(z1, x0, x1, -h, 0.0, kRiserShade * lower, 5.1));
        rects_.push_back(xface(x0, -h, 0.0, ze, z1, kSideShade * lower, 7.9));
        rects_.push_back(xface(x1, -h, 0.0, ze, z1, kSideShade * lower, 9.7));
        break;
    }
    case Hazard::Upstep:
        rects_.push_back(horiz(0.0, -kInf, kInf, -kInf, ze, 1.0f));
        rects_.push_back(horiz(p.drop, -kInf, kInf, ze, kInf, 1.0f));
        rects_.push_back(zface(ze, -kInf, kInf, 0.0, p.drop, kRiserShade, 3.3));
        break;
    case Hazard::Wall:
        rects_.push_back(horiz(0.0, -kInf, kInf, -kInf, ze, 1.0f));
        rects_.push_back(zface(ze, -kInf, kInf, 0.0, p.wall_height, kRiserShade, 3.3));
        break;
    case Hazard::Ramp: {
        // Same texture coordinates (X, Z) on all three parts, so the
        // surface is continuous in the image: only its slope changes.
        const double z1 = ze + p.ramp_length;
        rects_.push_back(horiz(0.0, -kInf, kInf, -kInf, ze, 1.0f));
        rects_.push_back(ramp(0.0, p.ramp_grade, ze, z1, 1.0f));
        if (std::isfinite(z1))
            rects_.push_back(horiz(-p.ramp_grade * p.ramp_length, -kInf, kInf, z1, kInf, 1.0f));
        break;
    }
    }
}

double Scene::ground_y(double z) const
{
    if (p_.hazard != Hazard::Ramp || z <= p_.edge_z)
        return 0.0;
    return -p_.ramp_grade * std::min(z - p_.edge_z, p_.ramp_length);
}

int Scene::intersect(const Vec3 &c, const Vec3 &d, double &t) const
{
    int best = -1;
    double tbest = kInf;
    const double cv[3] = {c.x, c.y, c.z};
    const double dv[3] = {d.x, d.y, d.z};
    const int n = static_cast<int>(rects_.size());
    for (int i = 0; i < n; ++i) {
        const Rect &r = rects_[static_cast<size_t>(i)];
        const double den = normal_comp(r, d);
        if (den == 0.0)
            continue;
        // n.(c + t d) = n.p0 with n = (0, 1, -slope), p0 = (0, pos, slope_z)
        const double tt = (r.pos - r.slope * r.slope_z - normal_comp(r, c)) / den;
        if (!(tt > 1e-9) || !(tt < tbest))
            continue;
        const int a = (r.axis + 1) % 3;
        const int b = (r.axis + 2) % 3;
        const double pa = cv[a] + tt * dv[a];
        if (pa < r.lo[a] || pa > r.hi[a])
            continue;
        const double pb = cv[b] + tt * dv[b];
        if (pb < r.lo[b] || pb > r.hi[b])
            continue;
        tbest = tt;
        best = i;
    }
    t = tbest;
    return best;
}

bool Scene::edge_segment(double &x0, double &x1) const
{
    switch (p_.hazard) {
    case Hazard::Flat: return false;
    case Hazard::Hole:
        x0 = p_.hole_offset - 0.5 * p_.hole_width;
        x1 = p_.hole_offset + 0.5 * p_.hole_width;
        return true;
    default:
        x0 = -kInf;
        x1 = kInf;
        return true;
    }
}

const char *distractor_name(Distractor::Kind k)
{
    switch (k) {
    case Distractor::Stripe: return "stripe";
    case Distractor::Shadow: return "shadow";
    case Distractor::Patch: return "patch";
    case Distractor::Manhole: return "manhole";
    }
    return "?";
}

std::vector<Distractor> random_distractors(int n, double z_near, double z_far, uint64_t seed)
{
    std::vector<Distractor> out;
    Rng rng(seed * 0x94D049BB133111EBull + 99);
    for (int i = 0; i < n; ++i) {
        Distractor d;
        const double zc = z_near + (z_far - z_near) * rng.uniform();
        const double xc = -2.0 + 4.0 * rng.uniform();
        d.kind = static_cast<Distractor::Kind>(rng.next() % 4u);
        switch (d.kind) {
        case Distractor::Stripe: { // painted line across the path
            const double w = 0.1 + 0.4 * rng.uniform();
            d.x0 = xc - 1.0 - 3.0 * rng.uniform();
            d.x1 = xc + 1.0 + 3.0 * rng.uniform();
            d.z0 = zc;
            d.z1 = zc + w;
            d.value = 200.0 + 40.0 * rng.uniform();
            break;
        }
        case Distractor::Shadow: // hard shadow of a building or pole
            d.x0 = xc - 0.5 - 2.0 * rng.uniform();
            d.x1 = xc + 0.5 + 2.0 * rng.uniform();
            d.z0 = zc;
            d.z1 = zc + 0.3 + 2.5 * rng.uniform();
            d.value = 0.35 + 0.25 * rng.uniform();
            break;
        case Distractor::Patch: { // dark tile, repair patch, wet spot
            const double a = 0.3 + 0.8 * rng.uniform(), b = 0.3 + 0.8 * rng.uniform();
            d.x0 = xc - a / 2;
            d.x1 = xc + a / 2;
            d.z0 = zc;
            d.z1 = zc + b;
            d.value = 0.3 + 0.4 * rng.uniform();
            break;
        }
        case Distractor::Manhole:
            d.x0 = xc;
            d.z0 = zc;
            d.x1 = 0.3 + 0.1 * rng.uniform();
            d.value = 0.45 + 0.2 * rng.uniform();
            break;
        }
        out.push_back(d);
    }
    return out;
}

// ---------------------------------------------------------------- Texture

namespace {

// Periodic cubic B-spline value noise on an n x n texel grid with lattice
// cell `cell` (n % cell == 0), added to `acc` with weight `amp`.
void add_octave(std::vector<float> &acc, int n, int cell, double amp, Rng &rng)
{
    const int g = n / cell;
    std::vector<float> lat(static_cast<size_t>(g) * static_cast<size_t>(g));
    for (float &v : lat)
        v = static_cast<float>(2.0 * rng.uniform() - 1.0);
    if (cell == 1) {
        for (size_t i = 0; i < acc.size(); ++i)
            acc[i] += static_cast<float>(amp) * lat[i];
        return;
    }
    // Per-texel weights (same for rows and columns).
    std::vector<int> idx(static_cast<size_t>(n));
    std::vector<float> w(4 * static_cast<size_t>(n));
    for (int x = 0; x < n; ++x) {
        const double p = (x + 0.5) / cell - 0.5;
        const double fl = std::floor(p);
        const double f = p - fl;
        idx[static_cast<size_t>(x)] = static_cast<int>(fl);
        const double f2 = f * f, f3 = f2 * f;
        float *wx = &w[4 * static_cast<size_t>(x)];
        wx[0] = static_cast<float>((1 - f) * (1 - f) * (1 - f) / 6.0);
        wx[1] = static_cast<float>((3 * f3 - 6 * f2 + 4) / 6.0);
        wx[2] = static_cast<float>((-3 * f3 + 3 * f2 + 3 * f + 1) / 6.0);
        wx[3] = static_cast<float>(f3 / 6.0);
    }
    auto wrap = [g](int i) { return ((i % g) + g) % g; };
    std::vector<int> widx(4 * static_cast<size_t>(n));
    for (int x = 0; x < n; ++x)
        for (int k = 0; k < 4; ++k)
            widx[4 * static_cast<size_t>(x) + static_cast<size_t>(k)] = wrap(
                idx[static_cast<size_t>(x)] - 1 + k);
    // Rows: tmp[gy][x].
    std::vector<float> tmp(static_cast<size_t>(g) * static_cast<size_t>(n));
    for (int gy = 0; gy < g; ++gy) {
        const float *row = &lat[static_cast<size_t>(gy) * static_cast<size_t>(g)];
        float *out = &tmp[static_cast<size_t>(gy) * static_cast<size_t>(n)];
        for (int x = 0; x < n; ++x) {
            const float *wx = &w[4 * static_cast<size_t>(x)];
            const int *ix = &widx[4 * static_cast<size_t>(x)];
            out[x] = wx[0] * row[ix[0]] + wx[1] * row[ix[1]] + wx[2] * row[ix[2]] +
                     wx[3] * row[ix[3]];
        }
    }
    const auto a = static_cast<float>(amp);
    for (int y = 0; y < n; ++y) {
        const float *wy = &w[4 * static_cast<size_t>(y)];
        const int *iy = &widx[4 * static_cast<size_t>(y)];
        const float *r[4];
        for (int k = 0; k < 4; ++k)
            r[k] = &tmp[static_cast<size_t>(iy[k]) * static_cast<size_t>(n)];
        float *out = &acc[static_cast<size_t>(y) * static_cast<size_t>(n)];
        const float w0 = a * wy[0], w1 = a * wy[1], w2 = a * wy[2], w3 = a * wy[3];
        for (int x = 0; x < n; ++x)
            out[x] += w0 * r[0][x] + w1 * r[1][x] + w2 * r[2][x] + w3 * r[3][x];
    }
}

void normalise(std::vector<float> &v, double mean, double sd, double lo, double hi)
{
    double s = 0.0, s2 = 0.0;
    for (float x : v) {
        s += x;
        s2 += static_cast<double>(x) * x;
    }
    const double n = static_cast<double>(v.size());
    const double m = s / n;
    const double d = std::sqrt(std::max(1e-12, s2 / n - m * m));
    for (float &x : v)
        x = static_cast<float>(std::clamp(mean + (x - m) * sd / d, lo, hi));
}

} // namespace

bool Texture::make_procedural(uint64_t seed, const std::string &kind, std::string &err)
{
    const bool paving = (kind == "paving");
    const bool concrete = (kind == "concrete");
    const bool worn = (kind == "worn");
    if (!paving && !concrete && !worn && kind != "asphalt") {
        err = "unknown texture kind '" + kind + "' (asphalt|paving|concrete|worn)";
        return false;
    }
    const int n = 2048; // 2048 texels of 4 mm: 8.19 m period
    texel_s_ = texel_t_ = 0.004;
    Rng rng(seed * 0x2545F4914F6CDD1Dull + 0x1234567ull);
    std::vector<float> acc(static_cast<size_t>(n) * static_cast<size_t>(n), 0.0f);
    // Multi-scale noise from 4 mm grain to 2 m patches; coarse octaves keep
    // contrast at 8 m where a pixel covers ~35 mm x 200 mm of ground.
    const int cells[] = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512};
    const double amps_asphalt[] = {0.35, 0.45, 0.55, 0.7, 0.8, 0.85, 0.8, 0.7, 0.55, 0.45};
    // Weak textures (docs/SYNTH.md "Texture"): smooth concrete keeps
    // little but its 0.1-2 m mottling (fine octaves at a third of
    // asphalt's weight relative to the coarse ones); worn asphalt has its
    // grain polished to about half.
    const double amps_concrete[] = {0.12, 0.15, 0.2, 0.25, 0.35, 0.5, 0.7, 0.8, 0.75, 0.6};
    const double amps_worn[] = {0.15, 0.2, 0.25, 0.45, 0.7, 0.85, 0.8, 0.7, 0.55, 0.45};
    const double *amps = concrete ? amps_concrete : (worn ? amps_worn : amps_asphalt);
    for (size_t k = 0; k < sizeof cells / sizeof cells[0]; ++k)
        add_octave(acc, n, cells[k], amps[k], rng);
    // Aggregate: sparse light and dark stones of 1-3 texels (asphalt,
    // paving); concrete has rare small pores instead, worn asphalt a
    // quarter of the stones, the rest worn flush.
    const int stones = concrete ? n * n / 2000 : (worn ? n * n / 240 : n * n / 60);
    for (int k = 0; k < stones; ++k) {
        const int x = static_cast<int>(rng.next() % static_cast<uint64_t>(n));
        const int y = static_cast<int>(rng.next() % static_cast<uint64_t>(n));
        const int r = 1 + static_cast<int>(rng.next() % 3u);
        float v = static_cast<float>((rng.uniform() < 0.5 ? -1.0 : 1.0) *
                                     (0.8 + 0.8 * rng.uniform()));
        if (concrete)
            v = -std::fabs(v); // pores are dark
        for (int dy = 0; dy < r; ++dy)
            for (int dx = 0; dx < r; ++dx)
                acc[static_cast<size_t>((y + dy) % n) * static_cast<size_t>(n) +
                    static_cast<size_t>((x + dx) % n)] += v;
    }
    if (paving) {
        // 512 mm slabs (16 per period) with 8 mm dark joints and a per-slab
        // brightness offset.
        const int slab = 128;
        const int ns = n / slab;
        std::vector<float> off(static_cast<size_t>(ns) * static_cast<size_t>(ns));
        for (float &o : off)
            o = static_cast<float>(1.2 * (rng.uniform() - 0.5));
        for (int y = 0; y < n; ++y) {
            for (int x = 0; x < n; ++x) {
                float &a =
                    acc[static_cast<size_t>(y) * static_cast<size_t>(n) + static_cast<size_t>(x)];
                a = 0.7f * a + off[static_cast<size_t>(y / slab) * static_cast<size_t>(ns) +
                                   static_cast<size_t>(x / slab)];
                if (x % slab < 2 || y % slab < 2)
                    a -= 3.0f;
            }
        }
    }
    // Grey level statistics: asphalt/paving mean 125, sd 42; smooth
    // concrete is light and flat (150, sd 14); worn asphalt greyer and
    // flatter than new (115, sd 22).
    if (concrete)
        normalise(acc, 150.0, 14.0, 60.0, 230.0);
    else if (worn)
        normalise(acc, 115.0, 22.0, 20.0, 230.0);
    else
        normalise(acc, 125.0, 42.0, 8.0, 247.0);
    build_mips(std::move(acc), n, n);
    return true;
}

bool Texture::load_photo(const std::string &path, double mm_per_px, std::string &err)
{
    cv::Mat img = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (img.empty()) {
        err = "cannot read texture image '" + path + "'";
        return false;
    }
    if (img.cols < 8 || img.rows < 8) {
        err = "texture image '" + path + "' is smaller than 8x8";
        return false;
    }
    // Mirror to 2w x 2h so the tiling is seamless, then resample to powers
    // of two (at most 4096) for the wrap-around mip chain.
    cv::Mat f, row, tile;
    img.convertTo(f, CV_32F);
    cv::Mat fx, fy, fxy;
    cv::flip(f, fx, 1);
    cv::flip(f, fy, 0);
    cv::flip(f, fxy, -1);
    cv::hconcat(f, fx, row);
    cv::Mat row2;
    cv::hconcat(fy, fxy, row2);
    cv::vconcat(row, row2, tile);
    auto pow2 = [](int v) {
        int p = 1;
        while (p * 2 <= v && p < 4096)
            p *= 2;
        return p;
    };
    const int w = pow2(tile.cols), h = pow2(tile.rows);
    texel_s_ = tile.cols * mm_per_px * 1e-3 / w;
    texel_t_ = tile.rows * mm_per_px * 1e-3 / h;
    cv::Mat rs;
    cv::resize(tile, rs, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    std::vector<float> base(static_cast<size_t>(w) * static_cast<size_t>(h));
    for (int y = 0; y < h; ++y)
        std::copy(rs.ptr<float>(y), rs.ptr<float>(y) + w,
                  base.begin() + static_cast<std::ptrdiff_t>(y) * w);
    build_mips(std::move(base), w, h);
    return true;
}

void Texture::build_mips(std::vector<float> base, int w, int h)
{
    levels_.clear();
    Level l0;
    l0.w = w;
    l0.h = h;
    l0.px = std::move(base);
    levels_.push_back(std::move(l0));
    while (levels_.back().w > 1 || levels_.back().h > 1) {
        const Level &p = levels_.back();
        Level q;
        q.w = std::max(1, p.w / 2);
        q.h = std::max(1, p.h / 2);
        q.px.resize(static_cast<size_t>(q.w) * static_cast<size_t>(q.h));
        const int sx = p.w > 1 ? 2 : 1, sy = p.h > 1 ? 2 : 1;
        for (int y = 0; y < q.h; ++y) {
            for (int x = 0; x < q.w; ++x) {
                float s = 0.0f;
                for (int dy = 0; dy < sy; ++dy)
                    for (int dx = 0; dx < sx; ++dx)
                        s += p.px[static_cast<size_t>(y * sy + dy) * static_cast<size_t>(p.w) +
                                  static_cast<size_t>(x * sx + dx)];
                q.px[static_cast<size_t>(y) * static_cast<size_t>(q.w) + static_cast<size_t>(x)] =
                    s / static_cast<float>(sx * sy);
            }
        }
        levels_.push_back(std::move(q));
    }
}

inline float Texture::bilinear(int level, float x, float y) const
{
    // x, y are already wrapped into [0, w) x [0, h) up to one period of
    // slack; sizes are powers of two, so wrap with a mask.
    const Level &l = levels_[static_cast<size_t>(level)];
    int ix = static_cast<int>(x), iy = static_cast<int>(y); // floor, also < 0
    ix -= (x < static_cast<float>(ix)) ? 1 : 0;
    iy -= (y < static_cast<float>(iy)) ? 1 : 0;
    const float ax = x - static_cast<float>(ix), ay = y - static_cast<float>(iy);
    const int mx = l.w - 1, my = l.h - 1;
    const size_t x0 = static_cast<size_t>(ix & mx), x1 = static_cast<size_t>((ix + 1) & mx);
    const size_t y0 = static_cast<size_t>(iy & my), y1 = static_cast<size_t>((iy + 1) & my);
    const size_t w = static_cast<size_t>(l.w);
    const float *r0 = &l.px[y0 * w];
    const float *r1 = &l.px[y1 * w];
    const float top = r0[x0] + ax * (r0[x1] - r0[x0]);
    const float bot = r1[x0] + ax * (r1[x1] - r1[x0]);
    return top + ay * (bot - top);
}

float Texture::sample(double s, double t, double a_s, double a_t, double b_s, double b_t) const
{
    // Footprint in level-0 texels; anisotropic filtering: up to 16 trilinear
    // probes along the longer footprint axis, mip level from the shorter.
    const double ax = a_s / texel_s_, ay = a_t / texel_t_;
    const double bx = b_s / texel_s_, by = b_t / texel_t_;
    const double la = std::sqrt(ax * ax + ay * ay);
    const double lb = std::sqrt(bx * bx + by * by);
    double mx = ax, my = ay, lmaj = la, lmin = lb;
    if (lb > la) {
        mx = bx;
        my = by;
        lmaj = lb;
        lmin = la;
    }
    if (lmaj > 1e6) {
        // Beyond this the top mip level (the mean) is used anyway; keeps
        // the probe coordinates inside float and int range.
        mx *= 1e6 / lmaj;
        my *= 1e6 / lmaj;
        lmaj = 1e6;
        lmin = std::min(lmin, lmaj);
    }
    int n = 1;
    if (lmaj > 1.0) {
        const double ratio = lmaj / std::max(lmin, 1e-6);
        n = static_cast<int>(std::min(16.0, std::ceil(ratio)));
        n = std::max(n, 1);
    }
    const double width = std::max(lmin, lmaj / n);
    const int top = static_cast<int>(levels_.size()) - 1;
    double lod = width > 1.0 ? static_cast<double>(std::log2(static_cast<float>(width))) : 0.0;
    lod = std::min(lod, static_cast<double>(top));
    const int l0 = static_cast<int>(lod);
    const int l1 = std::min(l0 + 1, top);
    const auto fr = static_cast<float>(lod - l0);
    // Reduce to one period (plus 3 periods of slack for the probe
    // offsets, which never exceed 16 * 2^top texels) before going to float.
    const double pw = levels_[0].w, ph = levels_[0].h;
    const double x = s / texel_s_ - std::floor(s / texel_s_ / pw) * pw + pw;
    const double y = t / texel_t_ - std::floor(t / texel_t_ / ph) * ph + ph;
    const auto sc0 = static_cast<float>(1.0 / static_cast<double>(1 << l0));
    const auto sc1 = static_cast<float>(1.0 / static_cast<double>(1 << l1));
    const float inv_n = 1.0f / static_cast<float>(n);
    const auto fx = static_cast<float>(x), fy = static_cast<float>(y);
    const auto fmx = static_cast<float>(mx), fmy = static_cast<float>(my);
    float acc0 = 0.0f, acc1 = 0.0f;
    for (int k = 0; k < n; ++k) {
        const float o = (static_cast<float>(k) + 0.5f) * inv_n - 0.5f;
        const float px = fx + o * fmx, py = fy + o * fmy;
        acc0 += bilinear(l0, px * sc0 - 0.5f, py * sc0 - 0.5f);
        if (fr > 0.0f)
            acc1 += bilinear(l1, px * sc1 - 0.5f, py * sc1 - 0.5f);
    }
    return (acc0 + fr * (acc1 - acc0)) * inv_n;
}

// ---------------------------------------------------------------- Camera

CameraFrame camera_frame(const Rig &rig, const Pose &pose, int which)
{
    const double th = deg2rad(pose.pitch), ph = deg2rad(pose.roll), ps = deg2rad(pose.yaw);
    // Pitch about X (down positive), camera y axis = image down.
    Vec3 x{1, 0, 0};
    Vec3 y{0, -std::cos(th), -std::sin(th)};
    Vec3 z{0, -std::sin(th), std::cos(th)};
    // Roll about the optical axis: positive turns the x axis towards y
    // (right side of the camera down).
    const Vec3 xr = add(mul(x, std::cos(ph)), mul(y, std::sin(ph)));
    const Vec3 yr = sub(mul(y, std::cos(ph)), mul(x, std::sin(ph)));
    // Yaw about world Y: positive turns the heading towards +X.
    auto yaw = [ps](const Vec3 &v) {
        return Vec3{v.x * std::cos(ps) + v.z * std::sin(ps), v.y,
                    -v.x * std::sin(ps) + v.z * std::cos(ps)};
    };
    CameraFrame cf;
    cf.ax = yaw(xr);
    cf.ay = yaw(yr);
    cf.az = yaw(z);
    cf.c = {pose.x, pose.y, pose.z};
    if (which == 1)
        cf.c = add(cf.c, mul(cf.ax, rig.baseline));
    return cf;
}

static double cy_of(const Rig &rig, int which)
{
    return which == 1 ? rig.cy + rig.right_row_shift : rig.cy;
}

Vec3 pixel_ray(const Rig &rig, const CameraFrame &cf, int which, double u, double v)
{
    const double xn = (u - rig.cx) / rig.f;
    const double yn = (v - cy_of(rig, which)) / rig.f;
    return add(cf.az, add(mul(cf.ax, xn), mul(cf.ay, yn)));
}

bool project(const Rig &rig, const CameraFrame &cf, int which, const Vec3 &p, double &u, double &v,
             double &depth)
{
    const Vec3 q = sub(p, cf.c);
    depth = dot(q, cf.az);
    if (!(depth > 1e-9))
        return false;
    u = rig.cx + rig.f * dot(q, cf.ax) / depth;
    v = cy_of(rig, which) + rig.f * dot(q, cf.ay) / depth;
    return true;
}

// ---------------------------------------------------------------- Render

namespace {

struct RowJob {
    const Scene *scene;
    const Texture *tex;
    const Rig *rig;
    CameraFrame cf;
    int which;
    int ss;
    double sky;
    cv::Mat *img;
    cv::Mat *disp;
    cv::Mat *hit;   // CV_32S, rect index of the centre ray (-1 = sky)
    cv::Mat *hit_t; // CV_64F, its depth
};

// Texture value of a hit on rect `r` at ray parameter t, with the footprint
// of the ray differentials du, dv (per step in u and v) on the plane:
// dP = t*(dD - D*(n.dD)/(n.D)).
// Fraction of [c - e, c + e] inside [a, b] (box-filtered step edges).
double cover1(double c, double e, double a, double b)
{
    if (e < 1e-9)
        return (c >= a && c <= b) ? 1.0 : 0.0;
    const double lo = std::max(c - e, a), hi = std::min(c + e, b);
    return hi > lo ? (hi - lo) / (2.0 * e) : 0.0;
}

// Paint, shadows and patches on the near ground, filtered over the
// footprint half-extents (ex, ez).
float distract(const std::vector<Distractor> &ds, double x, double z, double ex, double ez, float v)
{
    for (const Distractor &d : ds) {
        double c;
        if (d.kind == Distractor::Manhole) {
            const double e = std::max(ex, ez);
            if (std::fabs(x - d.x0) > d.x1 + e || std::fabs(z - d.z0) > d.x1 + e)
                continue;
            const double r = std::sqrt((x - d.x0) * (x - d.x0) + (z - d.z0) * (z - d.z0));
            c = cover1(r, e, -1.0, d.x1);
        } else {
            if (x + ex < d.x0 || x - ex > d.x1 || z + ez < d.z0 || z - ez > d.z1)
                continue;
            c = cover1(x, ex, d.x0, d.x1) * cover1(z, ez, d.z0, d.z1);
        }
        if (c <= 0.0)
            continue;
        const auto cf = static_cast<float>(c);
        float target;
        if (d.kind == Distractor::Stripe) // paint keeps a little of the grain
            target = static_cast<float>(d.value) + 0.25f * (v - 125.0f);
        else
            target = v * static_cast<float>(d.value);
        v += cf * (target - v);
    }
    return v;
}

float shade_hit(const Texture &tex, const std::vector<Distractor> &ds, const Rect &r, const Vec3 &c,
                const Vec3 &d, double t, const Vec3 &du, const Vec3 &dv)
{
    const Vec3 p = add(c, mul(d, t));
    const double dn = normal_comp(r, d);
    const double kdu = normal_comp(r, du) / dn, kdv = normal_comp(r, dv) / dn;
    const Vec3 fu = mul(sub(du, mul(d, kdu)), t);
    const Vec3 fv = mul(sub(dv, mul(d, kdv)), t);
    float v;
    switch (r.axis) {
    case 1: // horizontal: (X, Z)
        v = tex.sample(p.x, p.z, fu.x, fu.z, fv.x, fv.z);
        if (r.pos == 0.0 && r.slope == 0.0 && !ds.empty())
            v = distract(ds, p.x, p.z, 0.5 * (std::fabs(fu.x) + std::fabs(fv.x)),
                         0.5 * (std::fabs(fu.z) + std::fabs(fv.z)), v);
        break;
    case 2: // constant Z: (X, Y)
        v = tex.sample(p.x, p.y + r.tex_offset, fu.x, fu.y, fv.x, fv.y);
        break;
    default: // constant X: (Z, Y)
        v = tex.sample(p.z, p.y + r.tex_offset, fu.z, fu.y, fv.z, fv.y);
        break;
    }
    return v * r.shade;
}

// Pass 1: the pixel-centre ray of every pixel (exact first hit).
void centre_rows(const RowJob &job, int y0, int y1)
{
    const Rig &rig = *job.rig;
    const double fb = rig.f * rig.baseline;
    for (int y = y0; y < y1; ++y) {
        int *hr = job.hit->ptr<int>(y);
        double *ht = job.hit_t->ptr<double>(y);
        float *drow = job.disp ? job.disp->ptr<float>(y) : nullptr;
        for (int x = 0; x < rig.width; ++x) {
            const Vec3 dc = pixel_ray(rig, job.cf, job.which, x, y);
            hr[x] = job.scene->intersect(job.cf.c, dc, ht[x]);
            if (drow)
                drow[x] = hr[x] < 0 ? 0.0f : static_cast<float>(fb / ht[x]);
        }
    }
}

// Pass 2: shading.  Where the pixel and its 8 neighbours see the same
// surface, the texture is filtered once over the pixel footprint; at depth
// edges the pixel is split into ss x ss sub-samples, each ray cast and
// shaded on its own (anti-aliased occlusion boundaries).
void render_rows(const RowJob &job, int y0, int y1)
{
    const Rig &rig = *job.rig;
    const CameraFrame &cf = job.cf;
    const Scene &scene = *job.scene;
    const std::vector<Rect> &rects = scene.rects();
    const int ss = job.ss;
    const double step = 1.0 / ss;
    // Ray derivatives: dD/du = ax/f, dD/dv = ay/f, per pixel and per
    // sub-sample step.
    const Vec3 du1 = mul(cf.ax, 1.0 / rig.f), dv1 = mul(cf.ay, 1.0 / rig.f);
    const Vec3 dus = mul(du1, step), dvs = mul(dv1, step);
    const float inv = 1.0f / static_cast<float>(ss * ss);
    const auto sky = static_cast<float>(job.sky);
    const int w = rig.width, h = rig.height;
    const std::vector<Distractor> &ds = scene.params().distractors;
    for (int y = y0; y < y1; ++y) {
        float *row = job.img->ptr<float>(y);
        const int *hr = job.hit->ptr<int>(y);
        const double *ht = job.hit_t->ptr<double>(y);
        const int *ha = job.hit->ptr<int>(std::max(y - 1, 0));
        const int *hb = job.hit->ptr<int>(std::min(y + 1, h - 1));
        for (int x = 0; x < w; ++x) {
            const int rc = hr[x];
            bool uniform = true;
            if (ss > 1) {
                const int xa = std::max(x - 1, 0), xb = std::min(x + 1, w - 1);
                for (int xx = xa; xx <= xb && uniform; ++xx)
                    uniform = ha[xx] == rc && hr[xx] == rc && hb[xx] == rc;
            }
            if (uniform) {
                row[x] = rc < 0 ? sky
                                : shade_hit(*job.tex, ds, rects[static_cast<size_t>(rc)], cf.c,
                                            pixel_ray(rig, cf, job.which, x, y), ht[x], du1, dv1);
                continue;
            }
            float acc = 0.0f;
            for (int j = 0; j < ss; ++j) {
                const double v = y + (j + 0.5) * step - 0.5;
                for (int i = 0; i < ss; ++i) {
                    const double u = x + (i + 0.5) * step - 0.5;
                    const Vec3 d = pixel_ray(rig, cf, job.which, u, v);
                    double t;
                    const int r = scene.intersect(cf.c, d, t);
                    acc += r < 0 ? sky
                                 : shade_hit(*job.tex, ds, rects[static_cast<size_t>(r)], cf.c, d,
                                             t, dus, dvs);
                }
            }
            row[x] = acc * inv;
        }
    }
}

} // namespace

void render_view(const Scene &scene, const Texture &tex, const Rig &rig, const Pose &pose,
                 int which, const RenderOptions &opt, cv::Mat &img, cv::Mat *disp)
{
    img.create(rig.height, rig.width, CV_32F);
    if (disp)
        disp->create(rig.height, rig.width, CV_32F);
    cv::Mat hit(rig.height, rig.width, CV_32S), hit_t(rig.height, rig.width, CV_64F);
    RowJob job{&scene,  &tex,
               &rig,    camera_frame(rig, pose, which),
               which,   std::clamp(opt.supersample, 1, 4),
               opt.sky, &img,
               disp,    &hit,
               &hit_t};
    // Rows are independent, so threading does not change the result.
    cv::parallel_for_(cv::Range(0, rig.height),
                      [&job](const cv::Range &r) { centre_rows(job, r.start, r.end); });
    cv::parallel_for_(cv::Range(0, rig.height),
                      [&job](const cv::Range &r) { render_rows(job, r.start, r.end); });
}

float render_point(const Scene &scene, const Texture &tex, const Rig &rig, const Pose &pose,
                   int which, double u, double v, double sky)
{
    const CameraFrame cf = camera_frame(rig, pose, which);
    const Vec3 d = pixel_ray(rig, cf, which, u, v);
    double t;
    const int r = scene.intersect(cf.c, d, t);
    if (r < 0)
        return static_cast<float>(sky);
    return shade_hit(tex, scene.params().distractors, scene.rects()[static_cast<size_t>(r)], cf.c,
                     d, t, mul(cf.ax, 1.0 / rig.f), mul(cf.ay, 1.0 / rig.f));
}

void apply_blur(cv::Mat &linear, double sigma)
{
    if (sigma > 0.0)
        cv::GaussianBlur(linear, linear, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
}

// ---------------------------------------------------------------- Edge GT

EdgeGT edge_ground_truth(const Scene &scene, const Rig &rig, const Pose &pose)
{
    EdgeGT g;
    double x0, x1;
    if (!scene.edge_segment(x0, x1))
        return g;
    const double ze = scene.params().edge_z;
    const CameraFrame cf = camera_frame(rig, pose, 0);
    // Row where the edge line crosses image column u, if it is visible
    // there: the plane of all rays through column u is intersected with the
    // edge line P(X) = (X, 0, ze), and the ray to that point must not hit
    // anything nearer.
    auto at_column = [&](double u, double &row) {
        const Vec3 da = pixel_ray(rig, cf, 0, u, 0.0);
        const Vec3 db = pixel_ray(rig, cf, 0, u, rig.height - 1.0);
        const Vec3 n = cross(da, db);
        if (std::fabs(n.x) < 1e-12)
            return false;
        const double X = cf.c.x - (n.y * (0.0 - cf.c.y) + n.z * (ze - cf.c.z)) / n.x;
        if (X < x0 || X > x1)
            return false;
        const Vec3 p{X, 0.0, ze};
        double pu, depth;
        if (!project(rig, cf, 0, p, pu, row, depth))
            return false;
        if (row < -0.5 || row > rig.height - 0.5)
            return false;
        const Vec3 d = mul(sub(p, cf.c), 1.0 / depth);
        double t;
        const int ri = scene.intersect(cf.c, d, t);
        return !(ri >= 0 && t < depth * (1.0 - 1e-6));
    };
    for (int u = 0; u < rig.width; ++u) {
        double pv;
        if (!at_column(u, pv))
            continue;
        if (g.cols_visible == 0) {
            g.u_min = g.u_max = u;
            g.v_min = g.v_max = pv;
            g.v_at_u_min = pv;
        }
        g.v_at_u_max = pv;
        g.u_min = std::min(g.u_min, static_cast<double>(u));
        g.u_max = std::max(g.u_max, static_cast<double>(u));
        g.v_min = std::min(g.v_min, pv);
        g.v_max = std::max(g.v_max, pv);
        ++g.cols_visible;
    }
    g.visible = g.cols_visible > 0;
    if (g.visible && rig.cx >= -0.5 && rig.cx <= rig.width - 0.5)
        g.has_row_at_cx = at_column(rig.cx, g.row_at_cx);
    return g;
}

// ---------------------------------------------------------------- Sensor

void apply_sensor(const cv::Mat &linear, int which, const SensorOptions &s, uint64_t seed,
                  cv::Mat &out8)
{
    out8.create(linear.rows, linear.cols, CV_8U);
    Rng rng(seed ^ (which == 1 ? 0xA5A5A5A5DEADBEEFull : 0x5A5A5A5A0BADF00Dull));
    const double gain = s.brightness * (which == 1 ? s.gain_right : 1.0);
    const double off = which == 1 ? s.offset_right : 0.0;
    for (int y = 0; y < linear.rows; ++y) {
        const float *in = linear.ptr<float>(y);
        uint8_t *o = out8.ptr<uint8_t>(y);
        for (int x = 0; x < linear.cols; ++x) {
            double v = gain * in[x] + off;
            if (s.noise_sigma > 0.0)
                v += s.noise_sigma * rng.gauss();
            o[x] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
        }
    }
}

} // namespace synth
