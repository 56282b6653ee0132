// The view stage: the eye rays (P_k, V_k) of one view, as a camera makes them. Ray k crosses
// the reference plane z = 0 at texture coordinate P_k (in tiles) and points toward the eye
// along V_k (unit, V_k.z > 0; docs/conventions.md sections 2, 3).
//
// Adding a camera: one file harness/scene/NAME_camera.cpp defining a Camera subclass, a reader
// of the camera's own keys of [views] (through the ParamDict it is given: typed getters with
// defaults, errors at the key's FILE:LINE) that returns its settings, and a factory, plus one
// line in camera_registry() (harness/scene/view.cpp). A key of [views] that neither the view
// sweep nor the camera reads is an error at its FILE:LINE.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/footprint.h"

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
    // The pixels' footprints: one per sample, or exactly one shared by every sample.
    std::vector<Footprint> J;
    // 1 for a sample inside the view, 0 for one outside (section 10: its ray is at or beyond
    // the horizon; it carries a ray every stage can process, and its results are left out of
    // every statistic and counted); empty: every sample is inside.
    std::vector<uint8_t> inside;
    // The view depth's axis f (docs/conventions.md section 11: view depth z_eye(X) = (X - E) . f):
    // the perspective camera's forward vector; zero: -V (parallel rays, where the depth of a
    // point is its distance along the rays).
    Vec3d forward{0, 0, 0};
    // A curved base's view (harness/scene/curved_view.h): per sample the depth axis in that
    // sample's tangent frame (f . T, f . Bt, f . N), so that depth(X_w) = (X_w - P) . f holds in
    // the frame the method answers in; empty: depth_axis() for every sample.
    std::vector<Vec3d> axes;

    size_t size() const { return P.size(); }
    Vec3d depth_axis() const {
        if (forward.x != 0 || forward.y != 0 || forward.z != 0) return forward;
        const Vec3d v = V.empty() ? Vec3d{0, 0, 1} : V[0];
        return {-v.x, -v.y, -v.z};
    }
    Vec3d depth_axis(size_t k) const { return axes.empty() ? depth_axis() : axes[k]; }
    Vec3d dir(size_t k) const { return V[parallel ? 0 : k]; }
    // Whether sample k's ray is exactly (bit for bit) the ray through `at` along `d`.
    bool has_ray(size_t k, Vec2d at, Vec3d d) const {
        const Vec2d p = P[k];
        const Vec3d v = dir(k);
        return p.x == at.x && p.y == at.y && v.x == d.x && v.y == d.y && v.z == d.z;
    }
    const Footprint& footprint(size_t k) const { return J[J.size() == 1 ? 0 : k]; }
    bool is_inside(size_t k) const { return inside.empty() || inside[k] != 0; }
    size_t outside_count() const;
    // Parallel rays through the N x N sample grid: the exact tracer's band fast path.
    bool orthographic_grid() const { return parallel && grid > 0; }
};

// The N x N orthographic grid of section 3: dP/di = (1/N, 0), dP/dj = (0, 1/N).
Footprint orthographic_footprint(int n);

// Every sample's ray parallel to V through sample_grid(n), one footprint for all.
View orthographic_view(Vec3d V, int n);

// "" for a well-formed view, else a one-line reason: V's size does not match P (one entry
// when parallel, one per sample otherwise), `grid` does not match P's size, J is neither one
// nor one per sample, or `inside` is neither empty nor one per sample.
std::string view_problem(const View& view);

// What a camera is made from besides its own keys: the view's angles (the view sweep's
// theta_deg, phi_deg) and samples per side.
struct CameraSpec {
    double theta_deg = 0, phi_deg = 0;
    int samples = 0;
};

// One setting of a camera's own keys: the value of each of its keys for one view, in the
// camera's order (the perspective camera: distance, fov_deg; the orthographic camera: none).
// Each is also the row column of that name. A camera's keys may be lists (or ranges): its
// settings are then their product, and the run sweeps them like the views' angles.
struct CameraSetting {
    std::vector<std::pair<std::string, double>> values;
    double get(const std::string& key) const;  // NaN when the camera has no such key
    std::string label() const;                 // "distance=1.5 fov_deg=45"; "" for none
};

// A ray in space: origin and unit direction (into the scene).
struct WorldRay {
    Vec3d o, d;
};

class Camera {
  public:
    virtual ~Camera() = default;
    virtual std::string name() const = 0;
    virtual View view() const = 0;
    // The ray of sample k (in view()'s order) moved (di, dj) pixels from its pixel's centre
    // along the image's columns and rows, for a scene whose every point lies at or below
    // z = top: its origin is the eye (a pinhole) or a point above z = top. The curved bases
    // (harness/scene/curved_view.h) intersect these rays themselves, also where view() calls a
    // sample outside (the polygon's horizon is not theirs).
    virtual WorldRay world_ray(size_t k, double di, double dj, double top) const = 0;
    // The settings camera NAME reads from its own keys in `params` ([views]; the orthographic
    // camera reads none and has one empty setting), in sweep order; `loc` (FILE:LINE of
    // [views]) names the view in its errors; `samples` is the experiment file's (a camera's
    // defaults may follow it: the perspective camera's resolution). An unknown NAME is
    // InputError(loc, "unknown camera 'x' (known: orthographic, perspective)").
    static std::vector<CameraSetting> settings(const std::string& name, const ParamDict& params,
                                               const std::string& loc, int samples);
    // Camera NAME for one view at one of its settings. Cheap: the runner makes one per view.
    static std::unique_ptr<Camera> create(const std::string& name, const CameraSetting& setting,
                                          const CameraSpec& spec);
};

// One direction view_vector(theta, phi) for every ray, through the N x N sample grid.
class OrthographicCamera final : public Camera {
  public:
    OrthographicCamera(double theta_deg, double phi_deg, int n);
    std::string name() const override { return "orthographic"; }
    View view() const override { return orthographic_view(V_, n_); }
    // Parallel to -V through the grid point of sample k moved (di, dj) / N, starting above top.
    WorldRay world_ray(size_t k, double di, double dj, double top) const override;
    Vec3d direction() const { return V_; }

  private:
    Vec3d V_;
    int n_;
};

// One of a camera's own keys as the results show it: a key column of that name (a number per
// row; empty on other cameras' rows), what it means, and the tag that marks its value in the
// names of the view's files ("d": "_d1.5"). results.csv, pxh check's filters, pxh compare's row
// keys and the file names take a camera's keys from here (harness/metrics/columns.cpp).
struct CameraKey {
    std::string name, meaning, tag;
    // Results written before the key existed: the column whose cell stands for it ("samples" for
    // the perspective camera's resolution); "" when none.
    std::string default_column = {};
    // Whether the run's sweep pairs along this key (docs/conventions.md section 5.3): a setting
    // and the next one that differs only in it, at a larger value, pair pixel by pixel
    // (sliding_dist, shimmering_dist: the perspective camera's distance). At most one key.
    bool sweep_pairs = false;
    // Its unit, where it has one ("tiles", "degrees"): figures label their axes with it.
    std::string unit = {};
};

// The registry (camera_registry() in harness/scene/view.cpp): one line per camera.
struct CameraEntry {
    const char* name;
    std::vector<CameraSetting> (*read)(const ParamDict& params, const std::string& loc,
                                       int samples);
    std::unique_ptr<Camera> (*make)(const CameraSetting& setting, const CameraSpec& spec);
    // "" when the camera at this setting and view can look at a surface of scale s and bias b,
    // else why not (the perspective camera: its eye must lie above the slab); nullptr: always.
    std::string (*scene_problem)(const CameraSetting& setting, const CameraSpec& spec, double scale,
                                 double bias) = nullptr;
    // Whether its rays are parallel (the orthographic camera): otherwise a view's pixels look up
    // to 89 degrees from the normal whatever theta, and the truth's travel limit is checked there.
    bool parallel = false;
    // Its own keys, in the order of its settings' values (the perspective camera: distance,
    // fov_deg, resolution); none for the orthographic camera.
    std::vector<CameraKey> keys = {};
    // "" when the camera at this setting can measure `samples` per side, else why not (the
    // perspective camera: samples picks N x N pixels of its image, so N <= resolution; and
    // with `neighbours`, when something takes differences between neighbouring samples as
    // between neighbouring pixels (lod implicit), N = resolution); nullptr: any.
    std::string (*samples_problem)(const CameraSetting& setting, int samples,
                                   bool neighbours) = nullptr;
    // How far (tiles) from the look-at point its inside samples reach at this setting and view
    // (the same at every phi): the exact tracer must resolve a hit that far out (the perspective
    // camera: its farthest inside pixel); nullptr: within the tile (the orthographic grid).
    double (*reach)(const CameraSetting& setting, const CameraSpec& spec) = nullptr;
    // The key its sweep pairs along (CameraKey::sweep_pairs), "" when none.
    std::string pair_key() const;
};
const CameraEntry& camera_entry(const std::string& name, const std::string& loc);
const std::vector<CameraEntry>& camera_registry();
std::vector<std::string> camera_names();  // in registry order
// Camera NAME with no keys of its own (every key at its default; its first setting).
std::unique_ptr<Camera> make_camera(const std::string& name, const CameraSpec& spec);

}  // namespace pxh
