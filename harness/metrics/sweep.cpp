#include "harness/metrics/sweep.h"

#include <cmath>

#include "harness/metrics/column_groups.h"
#include "harness/metrics/metrics.h"

namespace pxh {

namespace {

// The pair's sliding and shimmering over `step` into the row's columns of these names.
void add_pair(const std::vector<Vec2d>& a, const std::vector<Vec2d>& b, double step, ResultRow& row,
              const char* sliding, const char* shimmering, const char* step_col) {
    if (a.empty() || b.empty()) return;
    const SweepMetrics sm =
        sweep_metrics(a, b, step, int(row.num("width")), int(row.num("height")));
    row.set(sliding, sm.sliding);
    row.set(shimmering, sm.shimmering);
    row.set(step_col, step);
}

}  // namespace

void add_sweep(const std::vector<Vec2d>& lo, const std::vector<Vec2d>& hi, double dt_deg,
               ResultRow& row) {
    add_pair(lo, hi, dt_deg, row, "sliding", "shimmering", "sweep_dt_deg");
}

void add_distance_sweep(const std::vector<Vec2d>& near, const std::vector<Vec2d>& far, double dd,
                        ResultRow& row) {
    add_pair(near, far, dd, row, "sliding_dist", "shimmering_dist", "sweep_dd");
}

std::vector<DistanceStep> distance_steps(const std::vector<CameraSetting>& settings,
                                         const std::string& pair_key) {
    std::vector<DistanceStep> steps(settings.size());
    if (pair_key.empty()) return steps;  // a camera whose sweep pairs nothing (orthographic)
    const auto others_equal = [&](const CameraSetting& a, const CameraSetting& b) {
        if (a.values.size() != b.values.size()) return false;
        for (size_t k = 0; k < a.values.size(); ++k)
            if (a.values[k].first != b.values[k].first ||
                (a.values[k].first != pair_key && !(a.values[k].second == b.values[k].second)))
                return false;
        return true;
    };
    for (size_t c = 0; c < settings.size(); ++c) {
        const double d = settings[c].get(pair_key);
        if (!std::isfinite(d)) continue;
        for (size_t n = c + 1; n < settings.size(); ++n)
            if (others_equal(settings[c], settings[n])) {
                const double dd = settings[n].get(pair_key) - d;
                if (dd > 0) steps[c] = {n, dd};
                break;
            }
    }
    return steps;
}

// Sliding and shimmering: the error's change between neighbouring views.
// Declared here, by the code that fills them; harness/metrics/columns.cpp places them in
// results.csv's order.
std::vector<ColumnSpec> sweep_columns() {
    using namespace column_decl;
    return {
        ColumnSpec{"sliding", kNum, kMeasured, "|mean change of e| / dt (texels per degree)"}
            .in("sliding", "texels/degree")
            .lead(),
        ColumnSpec{"shimmering", kNum, kMeasured,
                   "mean |change of e - mean change| / dt (texels/degree)"}
            .in("sliding", "texels/degree")
            .lead(),
        {"sweep_dt_deg", kNum, kMeasured, "the dt the two above were measured over (degrees)"},
        ColumnSpec{"sliding_dist", kNum, kMeasured,
                   "perspective: |mean change of e| / dd to the next distance (texels per tile)"}
            .in("sliding", "texels/tile")
            .lead(),
        ColumnSpec{"shimmering_dist", kNum, kMeasured,
                   "perspective: mean |change of e - mean change| / dd (texels per tile)"}
            .in("sliding", "texels/tile")
            .lead(),
        {"sweep_dd", kNum, kMeasured,
         "the distance step dd the two above were measured over (tiles)"},
    };
}

}  // namespace pxh
