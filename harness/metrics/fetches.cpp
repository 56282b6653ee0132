// fetches_mean, fetches_max: filtered lookups (height map or a precomputed map) per sample
// over the view's inside samples (fetches_bound, the method's declared bound, is a key the
// run sets on every row).
#include <algorithm>
#include <cmath>

#include "harness/metrics/column_groups.h"
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

// The height fetches this file counts, and the method's declared bound.
// Declared here, by the code that fills them; harness/metrics/columns.cpp places them in
// results.csv's order.
std::vector<ColumnSpec> fetches_columns() {
    using namespace column_decl;
    return {
        ColumnSpec{"fetches_mean", kNum, kMeasured,
                   "filtered lookups (height map or precomputed map) per sample, mean"}
            .in("fetches", "fetches/sample")
            .lead(),
        ColumnSpec{"fetches_max", kNum, kMeasured,
                   "filtered lookups (height map or precomputed map) per sample, max"}
            .in("fetches", "fetches/sample"),
        {"fetches_bound", kInt, kKey, "the method's declared fetch bound for this view"},
    };
}

}  // namespace pxh
