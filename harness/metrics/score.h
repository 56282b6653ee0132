// Scoring one backend's output on one view: its row's statistics (every per-output metric),
// the rules that fail a row or note something beside its numbers, and the per-view facts those
// rules read (float's spacing at the samples, the true hits on filled holes).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/row.h"
#include "harness/scene/heightfield.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

// Scores one method output against the truth: every per-output metric
// (harness/metrics/metric.h) and its shader column; samples flagged in `exclude` (when given)
// are left out of the error statistics and counted in `excluded`.
// `view` (when given): its outside samples are left out and counted, its footprints give the
// pixel error.
// `cover` (a curved base's): the errors are over the samples both show, and the coverage
// columns are filled.
ResultRow score(const MethodOutput& out, const GroundTruth& gt, int width, int height,
                const std::vector<uint8_t>* exclude = nullptr, const View* view = nullptr,
                const Coverage* cover = nullptr);

// Measured fields: which true hits depend on a filled hole (any of the 4 texels the bilinear
// surface there interpolates).
struct HoleMask {
    std::vector<uint8_t> on_filled;  // empty for fields without holes
    double frac = NAN;
};
HoleMask hole_mask(const HeightField& hf, const GroundTruth& gt);

// The coarsest spacing of float values at the inside samples' uv (texels, the larger of u and
// v): a float row cannot place its uv closer than half of it to the truth; and the first inside
// sample where it is coarsest (its P).
struct FloatSpacing {
    double texels = 0;
    Vec2d at{0, 0};
};
FloatSpacing float_spacing(const View& view, int width, int height);

// Why a scored row fails ("" when it does not): nothing measured (nothing_measured), or
// fetches_max over the method's declared bound (`bound` >= 0), naming both numbers.
std::string row_failure(const ResultRow& row, const MethodOutput& out, bool covered, int bound,
                        const MethodInfo& method);

// What an ok row says beside its numbers ("" when nothing): samples the shader discarded
// (samples_discarded), and float's spacing at far samples (float rows).
std::string row_notes(const MethodOutput& out, const MethodInfo& method, const Variant& variant,
                      const FloatSpacing& spacing);

}  // namespace pxh
