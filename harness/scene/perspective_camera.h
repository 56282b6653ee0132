// The perspective camera (docs/conventions.md section 10): a pinhole at
// eye distance D (tiles) from the look-at point C = (0.5, 0.5, 0) along the view direction of
// (theta, phi), an N x N square image of full field of view F. Per pixel: the sample P where the
// pixel's ray meets the polygon z = 0, its view vector V, whether it is outside (V.z <= cos 89
// degrees), and the footprint J = [dP/di, dP/dj] in closed form (footprint.h: rho, lambda).
//
// Registered as camera "perspective": [views] distance (tiles; a value, a list or a range
// { from, to, step }, swept), fov_deg (degrees, default 45; a value or a list) and resolution
// (the image's pixels per side, default the experiment file's samples; a value or a list). The
// run's `samples` N picks N x N of the R x R image's pixels, spread evenly over it (pixel
// index floor((a + 0.5) R / N) for a = 0 .. N - 1, in each axis): every measured pixel keeps
// its ray, footprint, lambda and inside flag of the full image, so a quick run at a lower N
// measures pixels of the same image at the same levels.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/view.h"

namespace pxh {

// V.z at or below this is outside: at or beyond the horizon, or too grazing to measure.
double outside_cos();  // cos(89 degrees)

struct PerspectiveParams {
    double theta_deg = 0, phi_deg = 0;
    double distance = 0;  // D, tiles from C to the eye
    double fov_deg = 45;  // F, full field of view of the square image
    int samples = 0;      // N pixels per side measured
    int resolution = 0;   // R pixels per side of the image (0: R = N)
    int image_size() const { return resolution > 0 ? resolution : samples; }
};

// The image pixel (in one axis) of measured sample a of N across an image of R pixels:
// floor((a + 0.5) R / N), the pixel under the centre of the a-th of N equal bands (a itself
// when N = R).
int subset_pixel(int a, int n, int r);

// "" when the parameters make a camera, else a one-line reason: theta in [0, 90), phi finite,
// D > 0 finite, F in (0, 180), N >= 1, 1 <= N <= R when R is given.
std::string perspective_problem(const PerspectiveParams& p);

// "" when the eye lies above the slab of scale s and bias b (D cos theta > s (1 - b)), else the
// reason. Call with the scene's s and b before tracing a view.
std::string eye_slab_problem(const PerspectiveParams& p, double scale, double bias);

// Throws InputError(where, reason) unless the eye lies above the slab.
void check_eye_above_slab(const PerspectiveParams& p, double scale, double bias,
                          const std::string& where);

// One pixel of a perspective camera.
struct PerspectivePixel {
    Vec3d d;      // the ray direction f + a x r + a y w (not normalised)
    Vec2d P;      // where the ray meets z = 0 (meaningful when inside)
    Vec3d V;      // -d / |d|
    bool inside;  // V.z > cos(89 degrees)
};

class PerspectiveCamera final : public Camera {
  public:
    // Throws InputError("camera", perspective_problem(p)) for bad parameters.
    explicit PerspectiveCamera(const PerspectiveParams& p);
    std::string name() const override { return "perspective"; }

    // Every measured pixel's ray, sample index b N + a for image pixel (subset_pixel(a),
    // subset_pixel(b)) (row 0 at the bottom, as gl_FragCoord; with N = R sample j N + i is
    // pixel (i, j)), its footprint and the inside mask. An outside sample carries the look-at ray
    // (P = C, V = V0) and the look-at pixel's footprint so that every stage can process it; its
    // results must be left out by the mask (View::inside).
    View view() const override;
    // From the eye through image pixel (pixel_of(a) + di, pixel_of(b) + dj), k = b N + a.
    WorldRay world_ray(size_t k, double di, double dj, double top) const override;
    std::vector<uint8_t> inside() const;  // 1 per inside sample, in sample order
    // The image pixel of sample a of N along one axis (subset_pixel at this N and R).
    int pixel_of(int a) const;
    size_t outside_count() const;

    // Image pixel (i, j) of the R x R image, at continuous pixel coordinates (integers are pixel
    // centres' indices).
    PerspectivePixel pixel(double i, double j) const;
    // The closed-form footprint of pixel (i, j) (valid where the ray meets the plane, d.z < 0).
    Footprint footprint(double i, double j) const;
    std::vector<Footprint> footprints() const;  // per sample, in sample order

    const PerspectiveParams& params() const { return p_; }
    Vec3d eye() const { return E_; }
    Vec3d forward() const { return f_; }
    Vec3d right() const { return r_; }
    Vec3d up() const { return w_; }
    double half_tan() const { return a_; }  // a = tan(F / 2)

  private:
    PerspectiveParams p_;
    Vec3d V0_, E_, f_, r_, w_;
    double a_;
};

// The registry's entry points: the settings its keys give (the product of distance x fov_deg,
// distance outer), and the camera at one of them.
std::vector<CameraSetting> read_perspective_settings(const ParamDict& params,
                                                     const std::string& loc, int samples);
std::unique_ptr<Camera> make_perspective_camera(const CameraSetting& setting,
                                                const CameraSpec& spec);
// Its keys as the results show them: distance ("_d"), fov_deg ("_f"), resolution ("_r").
std::vector<CameraKey> perspective_keys();
// "" when N samples per side can be picked from the setting's image (N <= resolution).
// With `neighbours` (lod implicit: the GPU's derivatives between neighbouring fragments) N = R.
std::string perspective_samples_problem(const CameraSetting& setting, int samples, bool neighbours);
// An upper bound of |P - C| over the camera's inside pixels (tiles from the look-at point; the
// same at every phi): the farthest of the image's corner pixels when all four are inside (the
// inside region is then their convex quadrilateral), else the horizon's bound, the eye's foot
// plus E.z tan(89 degrees).
double perspective_reach(const PerspectiveParams& p);
// perspective_reach at this setting and view.
double perspective_reach(const CameraSetting& setting, const CameraSpec& spec);

// eye_slab_problem at this setting and view.
std::string perspective_scene_problem(const CameraSetting& setting, const CameraSpec& spec,
                                      double scale, double bias);

}  // namespace pxh
