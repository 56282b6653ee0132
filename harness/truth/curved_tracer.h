// The truth on a curved base (docs/conventions.md section 12): the first hit of each eye ray
// with the displaced surface X = B + s (h - b) N, h the bilinear height of section 1. In the
// base's own coordinates (BaseSurface::coords) X is where a point's height above the base equals
// s (h(u, v) - b), so along a ray the surface is crossed where
//   g(t) = height(o + t d) - s (h(uv(o + t d)) - b)
// changes sign from above (> 0) to at or below (<= 0). The tracer walks the ray through the
// shell between the offset bases at s (1 - b) (entered from outside) and -s b (where g <= 0
// holds for sure) and bisects the first step that ends at or below the surface to the last bit
// of t. Each step is at most g / L long, L = 1 + s G 2 S an upper bound of |g'| (G bounds the
// bilinear |grad h|, S the speed of (u, v) per unit of distance: BaseSurface::uv_speed), so no
// crossing is stepped over, and at most `step_texels` texels of (u, v) long (a bracket for the
// bisection); a step never shrinks below 10^-9 of that (a ray grazing the surface closer than
// that for its whole way could slip through). The gt_agree_* columns compare the truth (the
// pyramid tracer, same rule) with the same walk at half the step on the rays truth_check picks
// (one in 16 by default), and gt_residual_max is max |g| at the hits (tiles).
//
// On the plane base this reproduces section 4's exact hits up to those two (tests/truth/
// curved_truth_test.cpp); the runner uses the exact tracers there.
#pragma once
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/scene/base_surface.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/view.h"

namespace pxh {

// The precision bound on a curved base's radius (docs/conventions.md section 9, "Bounds"). The
// base's points, coordinates and shell hits are computed about its centre R tiles from the
// look-at point (B = (0.5, *, -R) + R n; coords from p.z + R; the shells' quadratic holds
// |o - centre|^2 ~ R^2), so every position the walk and the methods' inputs see carries a
// rounding error of a few ulp of R: eps R tiles, eps = 2^-52. A height error d moves a hit by
// d tan(theta) along the surface, and a measured pixel meets the base at most 89 degrees off its
// normal (section 9's outside rule: tan 89 deg = 57.3 < 2^6). Keeping that under 2^-16 of a
// texel of a W x H field (the resolution the exact tracer keeps at its reach, kMaxSampleCells)
// needs eps R 2^6 max(W, H) <= 2^-16, i.e.
//   R max(W, H) <= 2^30 cells (kMaxBaseRadiusCells),
// R <= 3.4e7 tiles on a 32 x 32 field, 65536 on a 16384 x 16384 one. At the bound the base sags
// max(W, H) / (2 R) <= 2^-31 max(W, H)^2 texels over a tile from its tangent plane. Measured on
// fbm 32 x 32, s 0.05 (errors against the plane's): within 1e-4 at R = 1e7, +35% at 1e11, 70 x at
// 1e13, wrong by whole texels at 1e15 (all with status ok before this bound). The only base
// parameter is the radius; its lower bound is R > s b (the relief's bottom shell).
inline constexpr double kMaxBaseRadiusCells = 1073741824.0;  // 2^30
// "" when a curved base of radius R over a W x H field lies within kMaxBaseRadiusCells, else a
// one-line reason naming the radius, the field, the bound in tiles and what to do.
std::string base_radius_problem(const std::string& base, double radius, int width, int height);

// The curved walk's work, bounded before a run and during it (docs/guide/heightfields.md,
// "Curved bases"): a view's truth walks each ray through the relief's shell in steps of at most
// `step_texels` texels (and shorter near the surface), plus the check walk at half the step on
// timed views. curved_walk_estimate is the steps the longest allowed steps take through each
// ray's whole chord in the shell (from entering it to meeting its bottom or leaving it), summed
// over the view's rays (a strided sample of at most 4096 of them, scaled up): `walk_steps` for
// one walk at `step_texels`, `steps` = walks x walk_steps for the view's work (3: the walk and
// the check walk at half the step; pxh bench: its warm-up and repeats). A view over
// kMaxCurvedWalkSteps is refused before any work (an experiment when it is read, at the field's
// entry; pxh bench at --theta). The walks count their steps the same way (every step of every
// ray, both walks of a view together) and stop a view at the same limit, since near the surface
// they step shorter than the estimate assumes: the run is then refused at the field's entry with
// the count. So no view takes more than kMaxCurvedWalkSteps steps (plus at most 4096 a thread).
// Measured: 40 to 90 ns a step on this project's 2 shared cores (idle to loaded), so 2^28 steps
// are 10 to 25 s of one core, half that on 2 (the rays of a view are walked in parallel, even 4
// of them). Lower theta, the scale, the field's size or the samples to lower a view's estimate.
inline constexpr double kMaxCurvedWalkSteps = 268435456.0;  // 2^28
// The curved truth's check walk (the gt_agree_* columns) by default walks one ray in 16 of a
// timed view (truth_check = "subset"; harness/run/truth_stage.cpp): the pyramid is the truth, and
// the walk at half the step costs about 50 times the pyramid on every ray.
inline constexpr const char* kCurvedTruthCheck = "subset";
// The rays of an n-ray view that a truth's cross-check traces under truth_check `mode`: "all",
// every one; "subset", one in 16: the samples (i, j) with i % 4 == j % 4 == 2 of the N x N view
// (n = N^2; (1, 1) under 3 x 3; a view of another shape: k % 16 == 8); "none", none.
std::vector<size_t> truth_check_rays(size_t n, const std::string& mode);
// The walks the estimate of an n-ray view counts under truth_check `mode` ("": the default,
// kCurvedTruthCheck): the truth (a walk's steps bound the pyramid's) plus the check walk at half
// the step (two walks' steps) on the share of the rays it walks: 3 for "all", 1 + 2 / 16 for
// "subset" on a 4N x 4N view (more on a small one), 1 for "none".
double curved_walks(const std::string& mode, size_t rays);
struct CurvedWalkEstimate {
    double steps = 0;       // the view's estimated walk steps (all its walks)
    double walk_steps = 0;  // one walk's at step_texels
    double walks = 3;       // steps / walk_steps
    double chord_max = 0;   // the longest chord through the shell (tiles)
    size_t rays = 0;        // the view's rays
};
CurvedWalkEstimate curved_walk_estimate(const BaseSurface& base, double scale, double bias,
                                        int width, int height, const Camera& camera, size_t rays,
                                        double step_texels = 0.25, double walks = 3);
// "" when the estimate is within kMaxCurvedWalkSteps, else the one-line reason: the estimate,
// the limit and the knobs that lower it (`walks_said` says what the walks are).
std::string curved_walk_problem(
    const CurvedWalkEstimate& e,
    const std::string& walks_said = "and the check walk at half the step: 3 walks",
    const std::string& knobs = "lower theta, the scale, the field's size or samples");

// Thrown by CurvedTracer::trace when a view's walk exceeds its step budget: the steps it had
// taken when it stopped (over the budget by at most 4096 a thread) and the budget.
struct CurvedWalkTooLong : std::runtime_error {
    CurvedWalkTooLong(const std::string& what, double steps_taken, double budget_steps)
        : std::runtime_error(what), steps(steps_taken), budget(budget_steps) {}
    double steps, budget;
};

struct CurvedHits {
    std::vector<Vec2d> uv;     // unwrapped (u, v) of the hit; NaN where the ray misses X
    std::vector<double> z;     // s (h(uv) - b) there; NaN on a miss
    std::vector<Vec3d> point;  // the hit in space; NaN on a miss
    std::vector<uint8_t> hit;  // 1 where the ray meets X
    double residual_max = 0;   // max |g| at the hits (tiles)
    double steps_mean = 0;     // walk steps per ray (cost; the pyramid's: node visits and
                               // evaluations of g)
    double steps = 0;          // steps of all the rays (counted against the budget)
};

class CurvedPyramid;  // harness/truth/curved_pyramid.h

// How CurvedTracer finds the first hit: `walk`, the walk above (the test oracle and the check
// walk of the agreement columns), or `pyramid`, the same first-hit rule over a min/max pyramid
// of the field with certified steps in the cells (harness/truth/curved_pyramid.h; the runner's
// curved truth, make_curved_truth). A base the pyramid has no closed form for takes the walk.
enum class CurvedMethod { walk, pyramid };

class CurvedTracer {
  public:
    CurvedTracer(const HeightField& hf, double scale, double bias, const BaseSurface& base,
                 double step_texels = 0.25, CurvedMethod method = CurvedMethod::walk);
    ~CurvedTracer();
    CurvedTracer(const CurvedTracer&) = delete;
    CurvedTracer& operator=(const CurvedTracer&) = delete;
    // Every ray (in parallel, even a handful of rays; the result does not depend on the thread
    // count). Throws CurvedWalkTooLong (naming the steps taken and the budget) once the rays'
    // steps together exceed max_steps (a view's second walk gets what its first left).
    CurvedHits trace(const std::vector<WorldRay>& rays,
                     double max_steps = kMaxCurvedWalkSteps) const;
    double step_texels() const { return step_; }
    CurvedMethod method() const { return pyramid_ ? CurvedMethod::pyramid : CurvedMethod::walk; }
    // "walk" or "pyramid"
    std::string method_name() const;
    // The pyramid (nullptr for the walk): the tests break it on purpose.
    CurvedPyramid* pyramid_for_test() { return pyramid_.get(); }

  private:
    struct One {
        bool hit = false;
        double t = 0, residual = 0;
        long long steps = 0;
        Vec2d uv{NAN, NAN};  // the hit's coordinates where the tracer kept them (the pyramid)
    };
    struct Budget;
    One trace_one(const WorldRay& r, Budget& budget) const;
    double g(Vec3d p) const;

    const HeightField& hf_;
    double s_, b_;
    const BaseSurface& base_;
    double step_;
    double slope_;  // s times an upper bound of |grad h| (per tile)
    std::unique_ptr<CurvedPyramid> pyramid_;
};

// The curved truth of experiments (the runner's): the pyramid tracer on the cylinder and the
// sphere (harness/truth/registry.cpp).
std::unique_ptr<CurvedTracer> make_curved_truth(const HeightField& hf, double scale, double bias,
                                                const BaseSurface& base);

}  // namespace pxh
