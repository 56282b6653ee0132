#include "harness/scene/perspective_camera.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/limits.h"
#include "harness/core/param_dict.h"

namespace pxh {

namespace {

constexpr double kDeg = M_PI / 180.0;

std::string number(double v) {
    std::ostringstream os;
    os.precision(10);
    os << v;
    return os.str();
}

}  // namespace

double outside_cos() {
    static const double c = std::cos(89.0 * kDeg);
    return c;
}

std::string perspective_problem(const PerspectiveParams& p) {
    if (!(p.theta_deg >= 0 && p.theta_deg < 90))
        return "theta_deg = " + number(p.theta_deg) + " is not in [0, 90)";
    if (!std::isfinite(p.phi_deg)) return "phi_deg = " + number(p.phi_deg) + " is not finite";
    if (!(p.distance > 0 && std::isfinite(p.distance)))
        return "distance = " + number(p.distance) + " is not a positive number of tiles";
    if (!(p.fov_deg > 0 && p.fov_deg < 180))
        return "fov_deg = " + number(p.fov_deg) + " is not in (0, 180)";
    if (p.samples < 1) return "samples = " + std::to_string(p.samples) + " is not at least 1";
    if (p.resolution > 0 && p.samples > p.resolution)
        return "samples = " + std::to_string(p.samples) + " exceeds the image's resolution " +
               std::to_string(p.resolution) + " (samples picks N x N of its pixels)";
    if (p.resolution < 0)
        return "resolution = " + std::to_string(p.resolution) + " is not at least 1";
    return "";
}

int subset_pixel(int a, int n, int r) {
    // Exact in integers: floor((2a + 1) r / (2n)).
    return int(((2 * int64_t(a) + 1) * int64_t(r)) / (2 * int64_t(n)));
}

std::string eye_slab_problem(const PerspectiveParams& p, double scale, double bias) {
    const double eye_z = p.distance * view_vector(p.theta_deg, 0).z, top = scale * (1 - bias);
    if (eye_z > top) return "";
    return "the eye is not above the slab: distance " + number(p.distance) + " at theta " +
           number(p.theta_deg) + " puts it at height " + number(eye_z) +
           ", at or below the top of the relief s (1 - b) = " + number(top);
}

void check_eye_above_slab(const PerspectiveParams& p, double scale, double bias,
                          const std::string& where) {
    const std::string problem = eye_slab_problem(p, scale, bias);
    if (!problem.empty()) throw InputError(where, problem);
}

PerspectiveCamera::PerspectiveCamera(const PerspectiveParams& p) : p_(p) {
    const std::string problem = perspective_problem(p);
    if (!problem.empty()) throw InputError("camera", "perspective: " + problem);
    // The angles as view_vector converts them, so V0 is the orthographic camera's V exactly.
    const double t = p.theta_deg * M_PI / 180.0, ph = p.phi_deg * M_PI / 180.0;
    const double st = std::sin(t), ct = std::cos(t), sp = std::sin(ph), cp = std::cos(ph);
    V0_ = view_vector(p.theta_deg, p.phi_deg);
    E_ = {0.5 + p.distance * V0_.x, 0.5 + p.distance * V0_.y, p.distance * V0_.z};
    f_ = {-V0_.x, -V0_.y, -V0_.z};
    r_ = {-sp, cp, 0.0};
    w_ = {-ct * cp, -ct * sp, st};
    a_ = std::tan(0.5 * p.fov_deg * kDeg);
}

int PerspectiveCamera::pixel_of(int a) const {
    return subset_pixel(a, p_.samples, p_.image_size());
}

PerspectivePixel PerspectiveCamera::pixel(double i, double j) const {
    const double n = p_.image_size();
    const double x = 2 * (i + 0.5) / n - 1, y = 2 * (j + 0.5) / n - 1;
    const double ax = a_ * x, ay = a_ * y;
    PerspectivePixel px;
    px.d = {f_.x + ax * r_.x + ay * w_.x, f_.y + ax * r_.y + ay * w_.y,
            f_.z + ax * r_.z + ay * w_.z};
    const double len = std::sqrt(px.d.x * px.d.x + px.d.y * px.d.y + px.d.z * px.d.z);
    px.V = {-px.d.x / len, -px.d.y / len, -px.d.z / len};
    px.inside = px.V.z > outside_cos();
    if (px.d.z < 0) {
        const double k = E_.z / px.d.z;
        px.P = {E_.x - k * px.d.x, E_.y - k * px.d.y};
    } else {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        px.P = {nan, nan};  // the ray never meets the plane
    }
    return px;
}

Footprint PerspectiveCamera::footprint(double i, double j) const {
    const Vec3d d = pixel(i, j).d;
    const double k = -E_.z * (2 * a_ / p_.image_size()) / (d.z * d.z);
    const auto column = [&](Vec3d e) -> Vec2d {
        return {k * (e.x * d.z - d.x * e.z), k * (e.y * d.z - d.y * e.z)};
    };
    return {column(r_), column(w_)};
}

View PerspectiveCamera::view() const {
    const int n = p_.samples;
    View v;
    v.P.resize(size_t(n) * n);
    v.V.resize(size_t(n) * n);
    v.J.resize(size_t(n) * n);
    v.inside.resize(size_t(n) * n);
    v.parallel = false;
    v.grid = 0;
    v.forward = f_;
    // The look-at pixel's footprint (the image centre), what an outside sample carries.
    const double c = 0.5 * (p_.image_size() - 1);
    const Footprint centre = footprint(c, c);
    for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
            const int i = pixel_of(a), j = pixel_of(b);
            const PerspectivePixel px = pixel(i, j);
            const size_t k = size_t(b) * n + a;
            v.P[k] = px.inside ? px.P : Vec2d{0.5, 0.5};
            v.V[k] = px.inside ? px.V : V0_;
            v.J[k] = px.inside ? footprint(i, j) : centre;
            v.inside[k] = px.inside ? 1 : 0;
        }
    return v;
}

WorldRay PerspectiveCamera::world_ray(size_t k, double di, double dj, double) const {
    const size_t n = size_t(p_.samples);
    const PerspectivePixel px = pixel(pixel_of(int(k % n)) + di, pixel_of(int(k / n)) + dj);
    return {E_, {-px.V.x, -px.V.y, -px.V.z}};
}

std::vector<uint8_t> PerspectiveCamera::inside() const {
    const int n = p_.samples;
    std::vector<uint8_t> in(size_t(n) * n);
    for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a)
            in[size_t(b) * n + a] = pixel(pixel_of(a), pixel_of(b)).inside ? 1 : 0;
    return in;
}

size_t PerspectiveCamera::outside_count() const {
    size_t c = 0;
    for (uint8_t in : inside()) c += in ? 0 : 1;
    return c;
}

std::vector<Footprint> PerspectiveCamera::footprints() const {
    const int n = p_.samples;
    std::vector<Footprint> J(size_t(n) * n);
    for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) J[size_t(b) * n + a] = footprint(pixel_of(a), pixel_of(b));
    return J;
}

std::vector<CameraSetting> read_perspective_settings(const ParamDict& params,
                                                     const std::string& loc, int samples) {
    if (!params.has("distance"))
        throw InputError(loc,
                         "camera 'perspective' needs distance (the eye's distance from the "
                         "look-at point, in tiles: a value, a list or { from, to, step })");
    const std::vector<double> distances = params.angles("distance", {});
    for (double d : distances)
        if (!(d > 0 && std::isfinite(d)))
            throw InputError(params.where("distance"),
                             "distance = " + number(d) + " is not a positive number of tiles");
    const std::vector<double> fovs = params.numbers("fov_deg", {45.0});
    for (double f : fovs)
        if (!(f > 0 && f < 180))
            throw InputError(params.where("fov_deg"),
                             "fov_deg = " + number(f) +
                                 " is impossible: the full field of view lies in (0, 180)");
    // The image's pixels per side: integers in [1, kMaxSamples], default the file's samples.
    std::vector<double> resolutions{double(samples)};
    if (params.has("resolution")) {
        resolutions = params.numbers("resolution", {});
        for (double r : resolutions)
            if (!(r >= 1 && r <= kMaxSamples && r == std::floor(r)))
                throw InputError(params.where("resolution"),
                                 "resolution = " + number(r) +
                                     " is not a whole number of pixels per side in [1, " +
                                     std::to_string(kMaxSamples) + "]");
    }
    std::vector<CameraSetting> out;
    for (double d : distances)
        for (double f : fovs)
            for (double r : resolutions)
                out.push_back({{{"distance", d}, {"fov_deg", f}, {"resolution", r}}});
    return out;
}

std::string perspective_samples_problem(const CameraSetting& setting, int samples,
                                        bool neighbours) {
    const double r = setting.get("resolution");
    if (samples > r)
        return "samples = " + std::to_string(samples) +
               " exceeds the perspective image's resolution " + number(r) +
               ": samples picks N x N of the image's R x R pixels (N <= R)";
    if (neighbours && samples != r)
        return "lod 'implicit' takes the GPU's derivatives between neighbouring fragments, which "
               "are neighbouring pixels only when samples = resolution (here " +
               std::to_string(samples) + " of " + number(r) +
               "): measure it at samples = resolution, or use lod 'grad' (the exact footprint)";
    return "";
}

std::vector<CameraKey> perspective_keys() {
    return {{"distance", "perspective: eye distance from the look-at point (tiles)", "d", "", true,
             "tiles"},
            {"fov_deg", "perspective: full field of view of the square image (degrees)", "f", "",
             false, "degrees"},
            {"resolution", "perspective: the image's pixels per side (samples picks N x N of them)",
             "r", "samples", false, "pixels"}};
}

namespace {

// The camera's parameters at one of its settings and one view.
PerspectiveParams params_of(const CameraSetting& setting, const CameraSpec& spec) {
    PerspectiveParams p;
    p.theta_deg = spec.theta_deg;
    p.phi_deg = spec.phi_deg;
    p.samples = spec.samples;
    p.distance = setting.get("distance");
    p.fov_deg = setting.get("fov_deg");
    const double r = setting.get("resolution");
    p.resolution = std::isnan(r) ? 0 : int(r);
    return p;
}

}  // namespace

std::unique_ptr<Camera> make_perspective_camera(const CameraSetting& setting,
                                                const CameraSpec& spec) {
    return std::make_unique<PerspectiveCamera>(params_of(setting, spec));
}

double perspective_reach(const PerspectiveParams& p) {
    const PerspectiveCamera cam(p);
    const Vec3d E = cam.eye();
    const double last = p.image_size() - 1;  // the image's corners bound every pixel measured
    double reach = 0;
    for (const double j : {0.0, last})
        for (const double i : {0.0, last}) {
            const PerspectivePixel px = cam.pixel(i, j);
            if (!px.inside) {  // the horizon's bound: the eye's foot, then E.z tan(89 degrees)
                const double c = outside_cos(), tan89 = std::sqrt(1 - c * c) / c;
                return std::hypot(E.x - 0.5, E.y - 0.5) + E.z * tan89;
            }
            reach = std::max(reach, std::hypot(px.P.x - 0.5, px.P.y - 0.5));
        }
    return reach;
}

double perspective_reach(const CameraSetting& setting, const CameraSpec& spec) {
    return perspective_reach(params_of(setting, spec));
}

std::string perspective_scene_problem(const CameraSetting& setting, const CameraSpec& spec,
                                      double scale, double bias) {
    return eye_slab_problem(params_of(setting, spec), scale, bias);
}

}  // namespace pxh
