// Agreement between two outputs on the same samples: GLSL vs the CPU float reference
// (cpu_diff_max, cpu_diff_p999, decision_mismatch) and CPU float vs double (double_diff_*);
// and between two references (tracers) on the same rays: per sample the distance between
// their hits in texels (|texel_error(a, b)|, wrapped), summarized by error_stats (the
// gt_agree_* columns read p50, p99, max and frac_gt_0_5). Any pair of references.
#pragma once
#include <cmath>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/core/vec.h"
#include "harness/metrics/metrics.h"
#include "harness/metrics/row.h"

namespace pxh {

// max and p99.9 |uv_a - uv_b| in texels (a non-finite difference counts as infinite), and the
// number of samples whose fetch count (the layer/step decision) differs. `inside` (when
// given and not empty): only the samples it marks 1 are compared (a view's outside pixels are
// left out, as from every statistic).
struct OutputDiff {
    double max = NAN, p999 = NAN, mean = NAN, p95 = NAN;
    long long decision_mismatch = 0;
    long long skipped = 0;  // samples neither side answered (no uv on both): not compared
    // The sample (index k = j N + i, as uv_a is) with the largest difference (the first of
    // equal ones), -1 when none was compared; and the first samples that differ by more than
    // kDiffShown texel or in fetch count, at most kFirstDiffs, in sample order.
    long long worst = -1;
    std::vector<size_t> first;
    // Those samples in words: "k: uv_a | uv_b fetches a | b" (no comma) each, "; " between them.
    std::string first_text;
};
inline constexpr double kDiffShown = 1e-3;
inline constexpr size_t kFirstDiffs = 8;
OutputDiff compare_uv(const std::vector<Vec2d>& uv_a, const std::vector<int>& fetches_a,
                      const std::vector<Vec2d>& uv_b, const std::vector<int>& fetches_b, int width,
                      int height, const std::vector<uint8_t>* inside = nullptr);

OutputDiff compare_outputs(const MethodOutput& a, const MethodOutput& b, int width, int height,
                           const std::vector<uint8_t>* inside = nullptr);

// cpu_diff_max, cpu_diff_p999, decision_mismatch from (GLSL, CPU float).
void add_backend_agreement(const OutputDiff& glsl_vs_cpu_float, ResultRow& row);
// p99.9 |a - b| of two written depths (MethodOutput::depth, tiles) over the samples with a
// depth in either (one without: infinite); NaN when either has none.
double depth_diff_p999(const std::vector<double>& a, const std::vector<double>& b,
                       const std::vector<uint8_t>* inside = nullptr);
// The same from the two outputs (GLSL vs CPU float on the same samples), and
// depth_cpu_diff_p999.
void add_agreement(ResultRow& row, const MethodOutput& glsl, const MethodOutput& cpu_float,
                   int width, int height, const std::vector<uint8_t>* inside = nullptr);
// double_diff_max, double_diff_p999 from (CPU float, CPU double).
void add_precision_agreement(const OutputDiff& float_vs_double, ResultRow& row);

// a and b: the two references' hits (unwrapped uv), per sample, of equal size.
ErrorStats reference_agreement(const std::vector<Vec2d>& a, const std::vector<Vec2d>& b, int width,
                               int height);

}  // namespace pxh
