// fetches_mean, fetches_max: filtered lookups (height map or a precomputed map) per sample
// (fetches_bound, the method's declared bound, is a key the run sets on every row).
#include <algorithm>
#include <cmath>

#include "harness/metrics/metric.h"

namespace pxh {

void add_fetches(const MetricInput& in, ResultRow& row) {
    const size_t n = in.out.uv.size();
    double sum = 0;
    int most = 0;
    for (int f : in.out.fetches) {
        sum += f;
        most = std::max(most, f);
    }
    row.set("fetches_mean", n ? sum / double(n) : NAN);
    row.set("fetches_max", n ? double(most) : NAN);
}

}  // namespace pxh
