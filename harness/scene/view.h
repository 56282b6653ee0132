// The view stage: the eye rays (P_k, V_k) of one view, as a camera makes them. Ray k crosses
// the reference plane z = 0 at texture coordinate P_k (in tiles) and points toward the eye
// along V_k (unit, V_k.z > 0; docs/conventions.md sections 2, 3).
//
// Adding a camera: one file harness/scene/NAME_camera.cpp defining a Camera subclass and a
// factory that reads the camera's own keys of [views] through the ParamDict it is given
// (typed getters with defaults, errors at the key's FILE:LINE), plus one line in
// camera_registry() (harness/scene/view.cpp). A key of [views] that neither the view sweep
// nor the camera reads is an error at its FILE:LINE.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "harness/core/vec.h"

namespace pxh {

class ParamDict;

// Sample points of an N x N grid over one tile: ((i + 0.5) / N, (j + 0.5) / N), row-major.
std::vector<Vec2d> sample_grid(int n);

// Unit vector toward the eye for polar angle theta and azimuth phi (degrees).
Vec3d view_vector(double theta_deg, double phi_deg);

// The rays of one view, plus what the tracers' fast paths may assume about them.
struct View {
    std::vector<Vec2d> P;   // per sample
    std::vector<Vec3d> V;   // per sample, or exactly one when `parallel`
    bool parallel = false;  // every ray has direction V[0] (an orthographic camera)
    int grid = 0;           // > 0: P is sample_grid(grid), N x N row-major

    size_t size() const { return P.size(); }
    Vec3d dir(size_t k) const { return V[parallel ? 0 : k]; }
    // Parallel rays through the N x N sample grid: the exact tracer's band fast path.
    bool orthographic_grid() const { return parallel && grid > 0; }
};

// Every sample's ray parallel to V through sample_grid(n).
View orthographic_view(Vec3d V, int n);

// "" for a well-formed view, else a one-line reason: V's size does not match P (one entry
// when parallel, one per sample otherwise), or `grid` does not match P's size.
std::string view_problem(const View& view);

// What a camera is made from besides its own keys: the view's angles (the view sweep's
// theta_deg, phi_deg) and samples per side.
struct CameraSpec {
    double theta_deg = 0, phi_deg = 0;
    int samples = 0;
};

class Camera {
  public:
    virtual ~Camera() = default;
    virtual std::string name() const = 0;
    virtual View view() const = 0;
    // Camera NAME for one view, reading its own keys from `params` ([views]; the orthographic
    // camera reads none); `loc` (FILE:LINE of [views]) names the view in its errors. Cheap:
    // the parser makes one to read the keys (view() makes the rays), the runner one per view. An
    // unknown NAME is InputError(loc, "unknown camera 'x' (known: orthographic)").
    static std::unique_ptr<Camera> create(const std::string& name, const ParamDict& params,
                                          const CameraSpec& spec, const std::string& loc);
};

// One direction view_vector(theta, phi) for every ray, through the N x N sample grid.
class OrthographicCamera final : public Camera {
  public:
    OrthographicCamera(double theta_deg, double phi_deg, int n);
    std::string name() const override { return "orthographic"; }
    View view() const override { return orthographic_view(V_, n_); }
    Vec3d direction() const { return V_; }

  private:
    Vec3d V_;
    int n_;
};

// The registry (camera_registry() in harness/scene/view.cpp): one line per camera.
struct CameraEntry {
    const char* name;
    std::unique_ptr<Camera> (*make)(const ParamDict& params, const CameraSpec& spec,
                                    const std::string& loc);
};
const std::vector<CameraEntry>& camera_registry();
std::vector<std::string> camera_names();  // in registry order
// Camera::create with no keys of its own (every key at its default), loc "camera".
std::unique_ptr<Camera> make_camera(const std::string& name, const CameraSpec& spec);

}  // namespace pxh
