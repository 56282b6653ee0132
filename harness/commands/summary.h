// The console summary `pxh run` prints after a run.
#pragma once
#include <vector>

#include "harness/results/results.h"

namespace pxh {

// Per method, parameters and backend: mean error over all rows, the worst p95, cost.
void print_summary(const std::vector<ResultRow>& rows);

}  // namespace pxh
