#include "harness/metrics/metric.h"

#include <algorithm>
#include <list>

namespace pxh {
namespace {

// THE list of per-output metrics: one line each.
const std::vector<Metric>& builtin_metrics() {
    static const std::vector<Metric> m = {
        {"error_stats", add_error_stats},
        {"fetches", add_fetches},
        {"timing", add_timing},
        {"shadows", add_shadow_errors},
    };
    return m;
}

std::list<Metric>& registered() {
    static std::list<Metric> m;
    return m;
}

}  // namespace

std::vector<const Metric*> output_metrics() {
    std::vector<const Metric*> out;
    for (const auto& m : builtin_metrics()) out.push_back(&m);
    for (const auto& m : registered()) out.push_back(&m);
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
