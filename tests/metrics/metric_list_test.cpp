// The per-output metrics come from one list (PXH_OUTPUT_METRICS in harness/metrics/metric.cpp);
// a metric that declares its columns (Metric::columns) gets them registered with it, in
// results.csv after the table's metric columns and before the method resources' columns.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "harness/metrics/columns.h"
#include "harness/metrics/metric.h"

namespace pxh {
namespace {

std::vector<std::string> column_names() {
    std::vector<std::string> out;
    for (const ColumnSpec* c : result_column_specs()) out.push_back(c->name);
    return out;
}

TEST(MetricList, TheMetricsRunInTheListsOrder) {
    std::vector<std::string> names;
    for (const Metric* m : output_metrics()) names.push_back(m->name);
    EXPECT_EQ(names, (std::vector<std::string>{"error_stats", "fetches", "timing", "shadows"}));
}

TEST(MetricList, DeclaredColumnsStandBeforeTheResourceColumnsInMetricOrder) {
    std::vector<std::string> declared;
    for (const Metric* m : output_metrics())
        for (const ColumnSpec& c : m->columns) declared.push_back(c.name);
    ASSERT_EQ(declared, (std::vector<std::string>{"shadow_err", "shadow_soft_mae"}));
    EXPECT_EQ(output_metric_columns().size(), declared.size());
    const std::vector<std::string> cols = column_names();
    const auto at = std::find(cols.begin(), cols.end(), "precompute_ms");
    ASSERT_NE(at, cols.end());
    ASSERT_GE(size_t(at - cols.begin()), declared.size());
    EXPECT_EQ(std::vector<std::string>(at - std::ptrdiff_t(declared.size()), at), declared);
    for (const std::string& n : declared) {
        const ColumnSpec* c = find_column(n);
        ASSERT_NE(c, nullptr) << n;
        EXPECT_EQ(c->role, ColumnRole::measured) << n;
        EXPECT_EQ(std::count(cols.begin(), cols.end(), n), 1) << n;
    }
}

}  // namespace
}  // namespace pxh
