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
// that for its whole way could slip through). The gt_agree_* columns compare it with the same
// walk at half the step, and gt_residual_max is max |g| at the hits (tiles).
//
// On the plane base this reproduces section 4's exact hits up to those two (tests/truth/
// curved_truth_test.cpp); the runner uses the exact tracers there.
#pragma once
#include <cstdint>
#include <vector>

#include "harness/scene/base_surface.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/view.h"

namespace pxh {

struct CurvedHits {
    std::vector<Vec2d> uv;     // unwrapped (u, v) of the hit; NaN where the ray misses X
    std::vector<double> z;     // s (h(uv) - b) there; NaN on a miss
    std::vector<Vec3d> point;  // the hit in space; NaN on a miss
    std::vector<uint8_t> hit;  // 1 where the ray meets X
    double residual_max = 0;   // max |g| at the hits (tiles)
    double steps_mean = 0;     // walk steps per ray (cost)
};

class CurvedTracer {
  public:
    CurvedTracer(const HeightField& hf, double scale, double bias, const BaseSurface& base,
                 double step_texels = 0.25);
    // Every ray (in parallel; the result does not depend on the thread count).
    CurvedHits trace(const std::vector<WorldRay>& rays) const;
    double step_texels() const { return step_; }

  private:
    struct One {
        bool hit = false;
        double t = 0, residual = 0;
        int steps = 0;
    };
    One trace_one(const WorldRay& r) const;
    double g(Vec3d p) const;

    const HeightField& hf_;
    double s_, b_;
    const BaseSurface& base_;
    double step_;
    double slope_;  // s times an upper bound of |grad h| (per tile)
};

}  // namespace pxh
