#include "harness/metrics/metric.h"

#include <algorithm>
#include <list>

namespace pxh {

// THE list of per-output metrics, in the order they run: one line X(NAME) each, for the file
// harness/metrics/NAME.cpp defining `const Metric& NAME_metric()`.
#define PXH_OUTPUT_METRICS(X) \
    X(error_stats)            \
    X(fetches)                \
    X(timing)                 \
    X(shadows)                \
    X(depth)                  \
    X(coverage)

#define PXH_DECLARE_METRIC(NAME) const Metric& NAME##_metric();
PXH_OUTPUT_METRICS(PXH_DECLARE_METRIC)
#undef PXH_DECLARE_METRIC

namespace {

const std::vector<const Metric*>& builtin_metrics() {
#define PXH_LIST_METRIC(NAME) &NAME##_metric(),
    static const std::vector<const Metric*> m = {PXH_OUTPUT_METRICS(PXH_LIST_METRIC)};
#undef PXH_LIST_METRIC
    return m;
}

std::list<Metric>& registered() {
    static std::list<Metric> m;
    return m;
}

}  // namespace

std::vector<const Metric*> output_metrics() {
    std::vector<const Metric*> out;
    for (const Metric* m : builtin_metrics()) out.push_back(m);
    for (const auto& m : registered()) out.push_back(&m);
    return out;
}

std::vector<ColumnSpec> output_metric_columns() {
    std::vector<ColumnSpec> out;
    for (const Metric* m : builtin_metrics())
        out.insert(out.end(), m->columns.begin(), m->columns.end());
    return out;
}

void apply_output_metrics(const MetricInput& in, ResultRow& row) {
    for (const Metric* m : output_metrics()) m->add(in, row);
}

MetricRegistration::MetricRegistration(Metric metric, std::vector<ColumnSpec> columns)
    : name_(metric.name) {
    for (auto& c : columns) columns_.push_back(std::make_unique<ColumnRegistration>(std::move(c)));
    registered().push_back(std::move(metric));
}

MetricRegistration::~MetricRegistration() {
    auto& r = registered();
    r.remove_if([&](const Metric& m) { return m.name == name_; });
}

}  // namespace pxh
