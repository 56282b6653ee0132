// Coverage on a curved base (docs/conventions.md section 12): over the pixels where the base or
// the displaced surface is hit, cover_extra_frac (the method shows surface, the truth none: the
// background behind a silhouette) and cover_missing_frac (the truth shows surface, the method
// none: its ray missed the base, or it discarded). samples_outside becomes the pixels neither
// shows plus those whose base hit is too grazing to measure (V_ts.z <= cos 89 degrees, the
// plane's outside rule). Empty on the plane base, where
// both always cover the inside pixels.
#include <cmath>

#include "harness/metrics/metric.h"
#include "harness/metrics/metrics.h"

namespace pxh {

namespace {

void add_coverage(const MetricInput& in, ResultRow& row) {
    if (!in.cover) return;
    const Coverage& c = *in.cover;
    const size_t n = in.out.uv.size();
    if (c.base_hit.size() != n || c.truth_hit.size() != n) return;
    double extra = 0, missing = 0, either = 0;
    for (size_t k = 0; k < n; ++k) {
        const Vec2d uv = in.out.uv[k];
        const bool shows = in.inside(k) && std::isfinite(uv.x) && std::isfinite(uv.y);
        const bool truth = c.truth_hit[k] != 0;
        if (!c.base_hit[k] && !truth) continue;
        // the base met too grazing to measure (V_ts.z <= cos 89 degrees): outside, as on the
        // plane, whatever the truth shows there
        if (c.base_hit[k] && !in.inside(k)) continue;
        ++either;
        extra += shows && !truth;
        missing += truth && !shows;
    }
    row.set("samples_outside", double(n) - either);
    if (either == 0) return;
    row.set("cover_extra_frac", extra / either);
    row.set("cover_missing_frac", missing / either);
}

constexpr ColumnType kNum = ColumnType::number;
constexpr ColumnRole kMeasured = ColumnRole::measured;

}  // namespace

const Metric& coverage_metric() {
    static const Metric m{
        "coverage",
        add_coverage,
        {ColumnSpec{
             "cover_extra_frac", kNum, kMeasured,
             "curved bases: fraction of the covered pixels where the method shows surface and the "
             "truth none"}
             .in("coverage", "fraction")
             .lead(),
         ColumnSpec{
             "cover_missing_frac", kNum, kMeasured,
             "curved bases: fraction of the covered pixels where the truth shows surface and the "
             "method none"}
             .in("coverage", "fraction")
             .lead()}};
    return m;
}

}  // namespace pxh
