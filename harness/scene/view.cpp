#include "harness/scene/view.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/param_dict.h"
#include "harness/core/registry.h"
#include "harness/scene/perspective_camera.h"

namespace pxh {

std::vector<Vec2d> sample_grid(int n) {
    std::vector<Vec2d> p(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) p[size_t(j) * n + i] = {(i + 0.5) / n, (j + 0.5) / n};
    return p;
}

Vec3d view_vector(double theta_deg, double phi_deg) {
    const double t = theta_deg * M_PI / 180.0, p = phi_deg * M_PI / 180.0;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

Footprint orthographic_footprint(int n) { return {{1.0 / n, 0.0}, {0.0, 1.0 / n}}; }

View orthographic_view(Vec3d V, int n) {
    View v;
    if (n > 0) v.P = sample_grid(n);
    v.V = {V};
    v.parallel = true;
    v.grid = std::max(n, 0);
    if (n > 0) v.J = {orthographic_footprint(n)};
    return v;
}

WorldRay OrthographicCamera::world_ray(size_t k, double di, double dj, double top) const {
    const size_t n = size_t(std::max(n_, 1));
    const double x = (double(k % n) + 0.5 + di) / double(n),
                 y = (double(k / n) + 0.5 + dj) / double(n);
    const double L = (std::max(top, 0.0) + 1) / V_.z;  // theta < 90: V.z > 0
    return {{x + L * V_.x, y + L * V_.y, L * V_.z}, {-V_.x, -V_.y, -V_.z}};
}

size_t View::outside_count() const {
    size_t c = 0;
    for (uint8_t in : inside) c += in ? 0 : 1;
    return c;
}

double CameraSetting::get(const std::string& key) const {
    for (const auto& [k, v] : values)
        if (k == key) return v;
    return NAN;
}

std::string CameraSetting::label() const {
    std::ostringstream os;
    for (const auto& [k, v] : values) os << (os.tellp() > 0 ? " " : "") << k << "=" << v;
    return os.str();
}

std::string view_problem(const View& view) {
    const size_t want = view.parallel ? 1 : view.P.size();
    if (view.V.size() != want)
        return "a view of " + std::to_string(view.P.size()) + " samples has " +
               std::to_string(view.V.size()) + " ray directions (expected " + std::to_string(want) +
               (view.parallel ? ": parallel rays share one)" : ": one per sample)");
    if (view.grid > 0 && view.P.size() != size_t(view.grid) * size_t(view.grid))
        return "a view marked as a " + std::to_string(view.grid) + " x " +
               std::to_string(view.grid) + " sample grid has " + std::to_string(view.P.size()) +
               " samples";
    if (!(view.J.empty() || view.J.size() == 1 || view.J.size() == view.P.size()))
        return "a view of " + std::to_string(view.P.size()) + " samples has " +
               std::to_string(view.J.size()) + " footprints (expected one, or one per sample)";
    if (!(view.inside.empty() || view.inside.size() == view.P.size()))
        return "a view of " + std::to_string(view.P.size()) + " samples has an inside mask of " +
               std::to_string(view.inside.size());
    return "";
}

OrthographicCamera::OrthographicCamera(double theta_deg, double phi_deg, int n)
    : V_(view_vector(theta_deg, phi_deg)), n_(n) {}

namespace {

// Reads no keys of its own: one setting, with no values.
std::vector<CameraSetting> read_orthographic_settings(const ParamDict&, const std::string&, int) {
    return {CameraSetting{}};
}

std::unique_ptr<Camera> make_orthographic_camera(const CameraSetting&, const CameraSpec& s) {
    return std::make_unique<OrthographicCamera>(s.theta_deg, s.phi_deg, s.samples);
}

}  // namespace

const std::vector<CameraEntry>& camera_registry() {
    static const std::vector<CameraEntry> entries = {
        {"orthographic", &read_orthographic_settings, &make_orthographic_camera, nullptr, true},
        {"perspective", &read_perspective_settings, &make_perspective_camera,
         &perspective_scene_problem, false, perspective_keys(), &perspective_samples_problem,
         static_cast<double (*)(const CameraSetting&, const CameraSpec&)>(&perspective_reach)},
    };
    return entries;
}

std::vector<std::string> camera_names() { return entry_names(camera_registry()); }

std::string CameraEntry::pair_key() const {
    for (const CameraKey& k : keys)
        if (k.sweep_pairs) return k.name;
    return "";
}

const CameraEntry& camera_entry(const std::string& name, const std::string& loc) {
    return find_entry(camera_registry(), name, "camera", loc);
}

std::vector<CameraSetting> Camera::settings(const std::string& name, const ParamDict& params,
                                            const std::string& loc, int samples) {
    return find_entry(camera_registry(), name, "camera", loc).read(params, loc, samples);
}

std::unique_ptr<Camera> Camera::create(const std::string& name, const CameraSetting& setting,
                                       const CameraSpec& spec) {
    return find_entry(camera_registry(), name, "camera", "camera").make(setting, spec);
}

std::unique_ptr<Camera> make_camera(const std::string& name, const CameraSpec& spec) {
    return Camera::create(name, Camera::settings(name, ParamDict(), "camera", spec.samples).front(),
                          spec);
}

}  // namespace pxh
