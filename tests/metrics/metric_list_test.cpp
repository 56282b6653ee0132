// The per-output metrics come from one list (PXH_OUTPUT_METRICS in harness/metrics/metric.cpp);
// a metric that declares its columns (Metric::columns) gets them registered with it, in
// results.csv after the table's metric columns and before the method resources' columns.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "harness/metrics/columns.h"
#include "harness/metrics/metric.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

// The list has each metric once, and the errors first: the others read what error_stats sets
// (a metric added later takes its place in the list; nothing here names it).
TEST(MetricList, TheMetricsRunInTheListsOrder) {
    std::vector<std::string> names;
    for (const Metric* m : output_metrics()) {
        EXPECT_FALSE(m->name.empty());
        EXPECT_EQ(std::count(names.begin(), names.end(), m->name), 0) << m->name;
        names.push_back(m->name);
    }
    ASSERT_FALSE(names.empty());
    EXPECT_EQ(names.front(), "error_stats");
    for (const char* n : {"fetches", "timing", "shadows"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
}

TEST(MetricList, DeclaredColumnsStandBeforeTheResourceColumnsInMetricOrder) {
    std::vector<std::string> declared;
    for (const Metric* m : output_metrics())
        for (const ColumnSpec& c : m->columns) declared.push_back(c.name);
    // The shadows metric's among them (a metric added later brings its own).
    for (const char* n : {"shadow_err", "shadow_soft_mae"})
        EXPECT_NE(std::find(declared.begin(), declared.end(), n), declared.end()) << n;
    EXPECT_EQ(output_metric_columns().size(), declared.size());
    const std::vector<std::string> cols = test::result_column_names();
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
