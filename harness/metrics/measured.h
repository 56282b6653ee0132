// Whether a scored row measured anything: a row whose every error column would be empty is a
// failure with its reason, never an ok row of empty cells (docs/guide/running.md).
#pragma once
#include <string>

#include "harness/backends/backend.h"
#include "harness/metrics/row.h"

namespace pxh {

// "" when `row` (scored from `out`) measured something, else the one-line reason: every sample
// outside the view; on a curved base (`curved`) no pixel covered by both the method and the
// truth; every inside sample without a uv (non-finite, or discarded).
std::string nothing_measured(const ResultRow& row, const MethodOutput& out, bool curved);

}  // namespace pxh
