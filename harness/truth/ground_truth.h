// The truth stage: a view -> its ground truth (the first hits of its eye rays, and with a light
// the true hard shadow state of every visible point). The exact tracer (exact_tracer.h) is the
// reference; Embree (embree_truth.h) a second, independent one behind the same Tracer interface.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/view.h"
#include "harness/truth/exact_tracer.h"
#include "harness/truth/tracer.h"
#include "harness/truth/travel_limit.h"

namespace pxh {

struct GroundTruth {
    std::vector<Vec2d> uv;  // per sample, unwrapped
    std::vector<double> z;
    std::vector<uint8_t> lit;  // per sample, when a light was given: true hard shadow state
    // A curved base's (empty on the plane): per sample depth(X_t) = (X_t - B_P) . f, the true
    // hit's depth from the base hit along the camera's depth axis (NaN where the ray misses X);
    // and per sample the depth of the ray's crossing of the shell at height z, for cut planes.
    std::vector<double> depth;
    std::function<double(size_t, double)> shell_depth;
    double cells_mean = 0;
};

// Every ray of the view through `tracer` (in parallel; the result does not depend on threads).
// With a light L, also the true shadow state of every visible point (the tracer must have a
// shadow query and report heights). Throws std::invalid_argument for a light or a view beyond
// the travel limit, before any tracing.
GroundTruth trace_ground_truth(const Tracer& tracer, const View& view, const Vec3d* L = nullptr);
// The N x N grid's rays parallel to V (orthographic_view(V, n)).
GroundTruth trace_ground_truth(const HeightField& hf, double scale, double bias, Vec3d V, int n,
                               const Vec3d* L = nullptr);
// The same with a tracer built once for the field (and s, b), shared by its views.
GroundTruth trace_ground_truth(const ExactTracer& tracer, Vec3d V, int n, const Vec3d* L = nullptr);

}  // namespace pxh
