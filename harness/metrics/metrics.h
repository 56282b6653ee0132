// Texel error (docs/conventions.md sections 5.1-5.2): e = uv_method - uv_true wrapped to [-0.5,
// 0.5) per component, scaled by (W, H); statistics over the finite samples, non-finite ones
// counted.
#pragma once
#include <vector>

#include "harness/core/vec.h"

namespace pxh {

// Wrapped, texel-scaled error vector; NaN components if the method output is not finite.
Vec2d texel_error(Vec2d uv_method, Vec2d uv_true, int width, int height);

struct ErrorStats {
    double mean = 0, rms = 0, p50 = 0, p95 = 0, p99 = 0, max = 0;
    double frac_gt_0_5 = 0, frac_gt_1 = 0;  // fractions of the finite samples
    long long nonfinite = 0;
    long long count = 0;  // finite samples
};

// Percentile with linear interpolation between order statistics (numpy's default):
// position q (N - 1) in the sorted values. `sorted` must be ascending and non-empty.
double percentile_sorted(const std::vector<double>& sorted, double q);

// percentile_sorted(sorted v, q) for each q of `qs` (ascending, in [0, 1]), by selection rather
// than a sort (the same two order statistics, the same arithmetic: the same doubles); v is
// reordered. v must be non-empty and hold no NaN.
std::vector<double> percentiles_of(std::vector<double>& v, const std::vector<double>& qs);

// Sliding and shimmering (docs/conventions.md section 5.3) from the error vectors of two views a
// sweep step apart (dt degrees of theta, or dd tiles of eye distance): d(P) = e1(P) - e0(P)
// (wrapped to the half-open tile range, in texels); sliding = |mean_P d| / step (coherent drift,
// texels per unit of the step); shimmering = mean_P |d - mean_P d| / step (incoherent per-sample
// change, same unit). Samples non-finite in either view are left out of both.
struct SweepMetrics {
    double sliding = NAN, shimmering = NAN;
};
SweepMetrics sweep_metrics(const std::vector<Vec2d>& e0, const std::vector<Vec2d>& e1, double step,
                           int width, int height);

// Statistics of the magnitudes |e|; NaN/Inf magnitudes are counted in `nonfinite`, never used.
ErrorStats error_stats(const std::vector<double>& magnitudes);

}  // namespace pxh
