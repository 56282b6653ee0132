// Metrics: functions that add named columns (harness/metrics/columns.cpp) to a row.
//
// Per-output metrics see one backend's output on the view's samples beside the truth
// (MetricInput) and run, in registry order, on every row that did not fail:
//   error_stats.cpp (err_*, frac_*, nonfinite, excluded, samples_outside, err_px_*),
//   fetches.cpp (fetches_mean/max),
//   timing.cpp (time*, the backends' counters), shadows.cpp (shadow_err, shadow_soft_mae).
// Metrics across outputs or views take what they compare: agreement.h (two outputs),
// sweep.h (two views), reference.h (the view's references).
//
// A new per-output metric: one file harness/metrics/NAME.cpp defining
// `const Metric& NAME_metric()` (its add function and the columns it fills), and one line X(NAME)
// in PXH_OUTPUT_METRICS (metric.cpp) - or, outside the harness (a test), a MetricRegistration.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/metrics/row.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

// One backend's output on the view's samples, and the truth it is scored against.
// On a curved base (docs/conventions.md section 12), per sample: whether the eye ray meets the
// base and whether it meets the displaced surface (the truth covers it).
struct Coverage {
    std::vector<uint8_t> base_hit, truth_hit;
};

struct MetricInput {
    const MethodOutput& out;    // uv, fetches, timing, shadow factors (harness/backends/backend.h)
    const GroundTruth& gt;      // the reference's hit per sample (and true shadow state, if lit)
    int width = 0, height = 0;  // texels (errors are in texels)
    const std::vector<uint8_t>* exclude = nullptr;  // samples left out of the error statistics
    // The view's rays (footprints for the pixel error, the inside mask: outside samples are
    // left out of every statistic and counted in samples_outside); nullptr: every sample
    // inside, no footprints (no pixel error).
    const View* view = nullptr;
    // A curved base's coverage (nullptr on the plane): the errors are over the samples the
    // method and the truth both show.
    const Coverage* cover = nullptr;
    bool inside(size_t k) const { return !view || view->is_inside(k); }
    bool truth_shows(size_t k) const { return !cover || cover->truth_hit[k] != 0; }
};

using MetricFn = std::function<void(const MetricInput&, ResultRow&)>;
struct Metric {
    std::string name;
    MetricFn add;
    // The columns it fills, registered with it: they stand in results.csv after the metric
    // columns of the table (harness/metrics/columns.cpp), before the method resources'
    // precompute_ms, in metric order. Empty for the metrics whose columns the table lists
    // (error_stats, fetches, timing: results.csv's order from before metrics declared theirs).
    std::vector<ColumnSpec> columns = {};
};

// The built-in per-output metrics' columns, in metric order (what columns.cpp places).
std::vector<ColumnSpec> output_metric_columns();

// Every per-output metric, in order: the built-in ones, then the registered ones.
std::vector<const Metric*> output_metrics();

// Applies every per-output metric to the row.
void apply_output_metrics(const MetricInput& in, ResultRow& row);

// Registers a per-output metric and its columns for as long as it lives (tests; a metric
// linked into another binary). Its columns go before status and error.
class MetricRegistration {
  public:
    MetricRegistration(Metric metric, std::vector<ColumnSpec> columns);
    ~MetricRegistration();
    MetricRegistration(const MetricRegistration&) = delete;
    MetricRegistration& operator=(const MetricRegistration&) = delete;

  private:
    std::string name_;
    std::vector<std::unique_ptr<ColumnRegistration>> columns_;
};

}  // namespace pxh
