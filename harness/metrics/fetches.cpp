// fetches_mean, fetches_max: filtered lookups (height map or a precomputed map) per sample
// over the view's inside samples (fetches_bound, the method's declared bound, is a key the
// run sets on every row).
#include <algorithm>
#include <cmath>

#include "harness/metrics/metric.h"

namespace pxh {

namespace {

void add_fetches(const MetricInput& in, ResultRow& row) {
    size_t n = 0;  // inside samples
    double sum = 0;
    int most = 0;
    for (size_t k = 0; k < in.out.fetches.size(); ++k) {
        if (!in.inside(k)) continue;
        // a discarded sample's fetches are not known on the GL side: not counted on either
        if (in.out.discarded.size() == in.out.fetches.size() && in.out.discarded[k]) continue;
        const int f = in.out.fetches[k];
        ++n;
        sum += f;
        most = std::max(most, f);
    }
    row.set("fetches_mean", n ? sum / double(n) : NAN);
    row.set("fetches_max", n ? double(most) : NAN);
}

}  // namespace

// Its columns are in the table of harness/metrics/columns.cpp.
const Metric& fetches_metric() {
    static const Metric m{"fetches", add_fetches};
    return m;
}

}  // namespace pxh
