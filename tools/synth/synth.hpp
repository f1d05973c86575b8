// negobs_synth renderer: exact ray casting of rectified stereo pairs over
// piecewise-planar pedestrian scenes (curb, stairs, hole, up-step, wall,
// ramp, flat ground).  Host tool only; see docs/SYNTH.md for the geometry.
//
// World frame (metres): X right, Y up, Z forward (the walking direction at
// yaw 0).  The near ground is the plane Y = 0.  Camera frame: x right,
// y down (image rows), z along the optical axis.  The right camera sits at
// C_left + B * x_axis, so a point at depth z (along the optical axis) seen
// at column u in the left image is at column u - f*B/z in the right image.
#ifndef NEGOBS_SYNTH_HPP
#define NEGOBS_SYNTH_HPP

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace synth {

struct Vec3 {
    double x = 0.0, y = 0.0, z = 0.0;
};

// Pinhole rig.  All angles in degrees, lengths in metres.
struct Rig {
    int width = 320;
    int height = 240;
    double f = 250.0;  // focal length, px (square pixels)
    double cx = 159.5; // principal point, px (pixel centres are integers)
    double cy = 119.5;
    double baseline = 0.12;       // m, right camera to the right of the left one
    double right_row_shift = 0.0; // px, right image content moved down by this
};

// Camera pose for one frame.
struct Pose {
    double x = 0.0;      // m, world position of the left camera centre
    double y = 1.2;      // m, height above the near ground (Y = 0)
    double z = 0.0;      // m
    double pitch = 20.0; // deg, down positive
    double roll = 0.0;   // deg, positive = right side of the camera down
    double yaw = 0.0;    // deg, positive = heading turned to the right (+X)
};

enum class Hazard { Curb, Stairs, Hole, Upstep, Wall, Flat, Ramp };

const char *hazard_name(Hazard h);
bool hazard_from_name(const std::string &s, Hazard &out);

// Flat-ground distractor painted on the near ground (Y = 0): intensity
// only, no geometry.  Must never be alarmed.
struct Distractor {
    enum Kind { Stripe, Shadow, Patch, Manhole } kind = Stripe;
    double x0 = 0, x1 = 0, z0 = 0, z1 = 0; // m; manhole: centre and radius in x0, z0, x1
    double value = 1.0;                    // Stripe: paint grey level; others: brightness factor
};
const char *distractor_name(Distractor::Kind k);
// N random distractors between z_near and z_far, deterministic from seed.
std::vector<Distractor> random_distractors(int n, double z_near, double z_far, uint64_t seed);

struct SceneParams {
    Hazard hazard = Hazard::Curb;
    double edge_z = 4.0;      // m, world Z of the hazard's near edge
    double drop = 0.15;       // m, curb/hole depth, up-step height
    int steps = 3;            // stairs
    double rise = 0.17;       // m, stairs riser height
    double run = 0.30;        // m, stairs tread depth
    double hole_width = 1.0;  // m, along X
    double hole_length = 0.8; // m, along Z
    double hole_offset = 0.0; // m, lateral centre of the hole
    double wall_height = 2.5; // m
    // Ramp (a curb cut, a sloped path): beyond edge_z the ground falls by
    // ramp_grade metres per metre of Z (negative: rises) over ramp_length
    // metres of Z, then continues level at -ramp_grade * ramp_length.
    double ramp_grade = 1.0 / 12.0;
    double ramp_length = 1.8; // m along Z; infinity: a slope that never ends
    double lower_shade = 0.9; // brightness factor of surfaces below Y = 0
    std::vector<Distractor> distractors;
};

// Axis-aligned planar rectangle (bounds may be +-infinity).
struct Rect {
    int axis = 1; // 0: X = pos, 1: Y = pos, 2: Z = pos
    double pos = 0.0;
    // Horizontal rects only (axis 1): the plane Y = pos + slope * (Z -
    // slope_z), i.e. a surface tilted about the X axis (a ramp). Bounds
    // stay on X and Z.
    double slope = 0.0;
    double slope_z = 0.0;
    double lo[3] = {0, 0, 0}; // bounds on the two other axes (index = axis)
    double hi[3] = {0, 0, 0};
    float shade = 1.0f;
    double tex_offset = 0.0; // decorrelates faces that share texture axes
};

class Scene {
public:
    explicit Scene(const SceneParams &p);
    const SceneParams &params() const { return p_; }
    const std::vector<Rect> &rects() const { return rects_; }
    // Nearest hit of the ray C + t*D, t > tmin.  Returns the rect index or -1.
    int intersect(const Vec3 &c, const Vec3 &d, double &t) const;
    // Edge line of the hazard (the near rim at ground level, Y = 0):
    // X range [x0, x1] at Z = edge_z.  Returns false for flat ground.
    bool edge_segment(double &x0, double &x1) const;
    // World Y of the walking surface under (x, z): what a walker's feet
    // follow (0 on the near ground; the ramp's surface on a ramp).
    double ground_y(double z) const;

private:
    SceneParams p_;
    std::vector<Rect> rects_;
};

// Mip-mapped, periodic grey texture defined in world units.
class Texture {
public:
    // Procedural asphalt-like texture from a seed ("asphalt" or "paving").
    bool make_procedural(uint64_t seed, const std::string &kind, std::string &err);
    // Photo tiled on the surfaces (mirrored, so the tiling is seamless).
    bool load_photo(const std::string &path, double mm_per_px, std::string &err);
    // Filtered lookup: (s, t) in metres, footprint vectors (ds/du, dt/du),
    // (ds/dv, dt/dv) in metres per sample.
    float sample(double s, double t, double a_s, double a_t, double b_s, double b_t) const;

private:
    void build_mips(std::vector<float> base, int w, int h);
    float bilinear(int level, float x, float y) const;
    struct Level {
        int w = 0, h = 0;
        std::vector<float> px;
    };
    std::vector<Level> levels_;
    double texel_s_ = 0.004; // metres per level-0 texel along s
    double texel_t_ = 0.004;
};

struct RenderOptions {
    int supersample = 2; // NxN samples per pixel
    double sky = 205.0;  // grey level where the ray hits nothing
};

struct Frame {
    cv::Mat left, right; // CV_32F, linear grey levels before sensor effects
    cv::Mat disparity;   // CV_32F, left GT disparity (0 = no surface)
};

// Renders one camera; `which` 0 = left, 1 = right.  `disp` (optional)
// receives the pixel-centre ground-truth disparity of that camera.
void render_view(const Scene &scene, const Texture &tex, const Rig &rig, const Pose &pose,
                 int which, const RenderOptions &opt, cv::Mat &img, cv::Mat *disp);

// Shades one pixel-sized sample centred at (u, v) of camera `which`, the
// way render_view shades pixels away from depth edges (test helper).
float render_point(const Scene &scene, const Texture &tex, const Rig &rig, const Pose &pose,
                   int which, double u, double v, double sky);

// Camera geometry helpers shared by the renderer, the ground truth and tests.
struct CameraFrame {
    Vec3 c;          // centre
    Vec3 ax, ay, az; // unit axes in world
};
CameraFrame camera_frame(const Rig &rig, const Pose &pose, int which);
// Ray direction (unnormalised, z component 1 in the camera frame) for a
// pixel position of camera `which`.
Vec3 pixel_ray(const Rig &rig, const CameraFrame &cf, int which, double u, double v);
// Projects a world point; returns false behind the camera.
bool project(const Rig &rig, const CameraFrame &cf, int which, const Vec3 &p, double &u, double &v,
             double &depth);

// Image-space ground truth of the hazard edge in the left image.
struct EdgeGT {
    bool visible = false;
    int cols_visible = 0;
    double u_min = 0, u_max = 0, v_min = 0, v_max = 0;
    double v_at_u_min = 0, v_at_u_max = 0; // ends of the visible edge line
    bool has_row_at_cx = false;
    double row_at_cx = 0;
};
EdgeGT edge_ground_truth(const Scene &scene, const Rig &rig, const Pose &pose);

// Sensor model applied after rendering.
struct SensorOptions {
    double noise_sigma = 0.0; // grey levels, independent per camera
    double gain_right = 1.0;  // right = gain * right + offset
    double offset_right = 0.0;
    double brightness = 1.0; // both cameras
    double blur = 0.0;       // Gaussian optics PSF sigma, px (0 = none)
};
// Lens blur (Gaussian PSF, reflective border) on a linear image, in place.
void apply_blur(cv::Mat &linear, double sigma);
// Converts to 8-bit with the sensor effects; deterministic from `seed`.
// (apply_blur is not applied here; call it first.)
void apply_sensor(const cv::Mat &linear, int which, const SensorOptions &s, uint64_t seed,
                  cv::Mat &out8);

// Deterministic, platform-independent random numbers (splitmix64).
struct Rng {
    uint64_t s;
    explicit Rng(uint64_t seed) : s(seed) {}
    uint64_t next();
    double uniform(); // [0, 1)
    double gauss();
};

} // namespace synth

#endif
