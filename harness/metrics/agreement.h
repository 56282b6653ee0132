// Agreement between two references (tracers) on the same rays: per sample the distance
// between their hits in texels (|texel_error(a, b)|, wrapped), summarized by error_stats
// (the gt_agree_* columns read p50, p99, max and frac_gt_0_5). Any pair of references.
#pragma once
#include <vector>

#include "harness/core/vec.h"
#include "harness/metrics/metrics.h"

namespace pxh {

// a and b: the two references' hits (unwrapped uv), per sample, of equal size.
ErrorStats reference_agreement(const std::vector<Vec2d>& a, const std::vector<Vec2d>& b, int width,
                               int height);

}  // namespace pxh
