#include "harness/truth/ground_truth.h"

#include <tbb/parallel_for.h>

#include <stdexcept>

namespace pxh {

GroundTruth trace_ground_truth(const Tracer& tracer, const View& view, const Vec3d* L) {
    if (L && !tracer.has_shadow_query())
        throw std::logic_error("the " + tracer.name() +
                               " tracer cannot answer the true shadow state");
    if (L && L->z > 0)
        throw_if_problem(ray_travel_problem(tracer.scale(), *L));  // before any tracing
    Hits hits;
    tracer.trace(view, hits);
    if (L && hits.z.size() != hits.uv.size())
        throw std::logic_error("the " + tracer.name() + " tracer does not report heights");
    GroundTruth gt;
    gt.uv = std::move(hits.uv);
    gt.z = std::move(hits.z);
    if (L) {
        gt.lit.resize(gt.uv.size());
        tbb::parallel_for(tbb::blocked_range<size_t>(0, gt.uv.size(), 256), [&](const auto& r) {
            for (size_t k = r.begin(); k < r.end(); ++k)
                gt.lit[k] = !tracer.occluded(gt.uv[k], gt.z[k], *L);
        });
    }
    double sum = 0;
    for (const int cells : hits.cells) sum += cells;
    gt.cells_mean = hits.cells.empty() ? 0 : sum / double(hits.cells.size());
    return gt;
}

GroundTruth trace_ground_truth(const HeightField& hf, double scale, double bias, Vec3d V, int n,
                               const Vec3d* L) {
    return trace_ground_truth(ExactTracer(hf, scale, bias), V, n, L);
}

GroundTruth trace_ground_truth(const ExactTracer& tracer, Vec3d V, int n, const Vec3d* L) {
    return trace_ground_truth(static_cast<const Tracer&>(tracer), orthographic_view(V, n), L);
}

}  // namespace pxh
