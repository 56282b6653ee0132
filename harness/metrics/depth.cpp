// The depth a method setting writes against the truth's (docs/conventions.md section 11):
// depth_err_mean / _p95 / _max (|depth(X_w) - depth(X_t)|), depth_bias_mean (signed: > 0 behind
// the true surface) and depth_toward_frac (written nearer the eye than the polygon), in tiles
// along the view's depth axis, over the inside samples with a finite uv and a finite truth.
#include "methods/depth.h"

#include <algorithm>
#include <cmath>

#include "harness/metrics/depth.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/metrics.h"

namespace pxh {

namespace {

// How far nearer the eye than the polygon a written depth must be to count as toward it.
constexpr double kTowardEps = 1e-9;
// A written depth within this of the cut plane's (or the sample's own float rounding, depth_tol,
// where larger) decides nothing: a tie (docs/conventions.md section 8).
constexpr double kCutTieTau = 1e-7;

void add_depth_errors(const MetricInput& in, ResultRow& row) {
    const MethodOutput& o = in.out;
    const size_t n = o.uv.size();
    if (!in.view || o.depth.size() != n || n == 0) return;
    const View& view = *in.view;
    std::vector<double> mag;
    mag.reserve(n);
    double bias = 0, toward = 0, nonfinite = 0, clamped = 0, answered = 0;
    for (size_t k = 0; k < n; ++k) {
        if (!in.inside(k) || (in.exclude && (*in.exclude)[k])) continue;
        if (!std::isfinite(o.uv[k].x) || !std::isfinite(o.uv[k].y)) continue;
        ++answered;
        // a uv with a non-finite written depth: counted, never scored; beyond what the GL depth
        // target holds (|depth| > span / 2): counted, and scored with the value written
        if (!std::isfinite(o.depth[k])) {
            ++nonfinite;
            continue;
        }
        if (o.depth_span > 0 && std::abs(o.depth[k]) > 0.5 * o.depth_span) ++clamped;
        const Vec2d t = in.gt.uv[k];
        const double zt = in.gt.z.size() == n ? in.gt.z[k] : NAN;
        if (!std::isfinite(t.x) || !std::isfinite(zt)) continue;
        const double truth = in.gt.depth.size() == n
                                 ? in.gt.depth[k]
                                 : depth_offset(view.P[k], view.depth_axis(k), t, zt);
        if (!std::isfinite(truth)) continue;
        const double e = o.depth[k] - truth;
        mag.push_back(std::abs(e));
        bias += e;
        const double eps =
            o.depth_tol.size() == n ? std::max(kTowardEps, o.depth_tol[k]) : kTowardEps;
        toward += o.depth[k] < -eps ? 1 : 0;
    }
    if (answered > 0) {
        row.set("depth_nonfinite", nonfinite);
        row.set("depth_clamped", clamped);
    }
    if (mag.empty()) return;
    const double count = double(mag.size());
    double sum = 0;
    for (double m : mag) sum += m;
    const std::vector<double> p = percentiles_of(mag, {0.95, 1.0});
    row.set("depth_err_mean", sum / count);
    row.set("depth_err_p95", p[0]);
    row.set("depth_err_max", p[1]);
    row.set("depth_bias_mean", bias / count);
    row.set("depth_toward_frac", toward / count);
}

constexpr ColumnType kNum = ColumnType::number;
constexpr ColumnRole kMeasured = ColumnRole::measured;

}  // namespace

std::vector<uint8_t> add_cut_flips(const MethodOutput& out, const GroundTruth& gt, const View& view,
                                   const std::vector<uint8_t>* exclude, double z_cut,
                                   ResultRow& row) {
    const size_t n = out.uv.size();
    if (out.depth.size() != n || gt.uv.size() != n || gt.z.size() != n || view.size() != n)
        return {};
    std::vector<uint8_t> shows(n, 0);
    double flips = 0, counted = 0, ties = 0;
    for (size_t k = 0; k < n; ++k) {
        if (!view.is_inside(k) || (exclude && (*exclude)[k])) continue;
        if (!std::isfinite(out.depth[k]) || !std::isfinite(gt.z[k])) continue;
        // a curved base: the shell at height z_cut (NaN: the ray never meets it, never shown)
        const double plane = gt.shell_depth
                                 ? gt.shell_depth(k, z_cut)
                                 : ray_depth_at_height(view.dir(k), view.depth_axis(k), z_cut);
        const double truth = gt.depth.size() == n
                                 ? gt.depth[k]
                                 : depth_offset(view.P[k], view.depth_axis(k), gt.uv[k], gt.z[k]);
        if (!std::isfinite(truth)) continue;
        const bool shown_true = plane < truth, shown = plane < out.depth[k];
        shows[k] = uint8_t((shown_true ? 1 : 0) | (shown ? 2 : 0));
        ++counted;
        const double tau =
            out.depth_tol.size() == n ? std::max(kCutTieTau, out.depth_tol[k]) : kCutTieTau;
        if (std::isfinite(plane) && std::abs(out.depth[k] - plane) <= tau) {
            ++ties;  // decided by rounding: out of cut_flip_frac
            continue;
        }
        flips += shown_true != shown ? 1 : 0;
    }
    if (counted > 0) row.set("cut_tie_frac", ties / counted);
    if (counted > ties) row.set("cut_flip_frac", flips / (counted - ties));
    return shows;
}

const Metric& depth_metric() {
    static const Metric m{
        "depth",
        add_depth_errors,
        {ColumnSpec{"depth_err_mean", kNum, kMeasured,
                    "mean |depth written - true depth| along the view's depth axis (tiles)"}
             .in("depth", "tiles")
             .lead(),
         ColumnSpec{"depth_err_p95", kNum, kMeasured,
                    "95th-percentile |depth written - true depth| (tiles)"}
             .in("depth", "tiles")
             .lead(),
         ColumnSpec{"depth_err_max", kNum, kMeasured,
                    "largest |depth written - true depth| (tiles)"}
             .in("depth", "tiles"),
         ColumnSpec{"depth_bias_mean", kNum, kMeasured,
                    "mean signed depth written - true depth (tiles; > 0: behind the true surface)"}
             .in("depth", "tiles", Better::none),
         ColumnSpec{
             "depth_toward_frac", kNum, kMeasured,
             "fraction of samples whose written depth lies nearer the eye than the polygon's"}
             .in("depth", "fraction", Better::none),
         ColumnSpec{
             "depth_nonfinite", kNum, kMeasured,
             "samples with a uv whose written depth is not finite (NaN or infinite: not scored)"}
             .in("depth", "samples"),
         ColumnSpec{
             "depth_clamped", kNum, kMeasured,
             "samples whose written depth lies beyond what the GL depth target holds (|depth| > "
             "span / 2: a depth buffer clamps it; scored with the value written)"}
             .in("depth", "samples"),
         ColumnSpec{
             "cut_flip_frac", kNum, kMeasured,
             "[views] cut: fraction of samples where the depth test against the plane shows the "
             "other of plane and surface than the truth (ties left out)"}
             .in("cut", "fraction")
             .lead(),
         ColumnSpec{
             "cut_tie_frac", kNum, kMeasured,
             "[views] cut: fraction of samples whose written depth is within rounding of the "
             "plane's (1e-7 tiles, or four float steps in float): left out of cut_flip_frac"}
             .in("cut", "fraction", Better::none)}};
    return m;
}

}  // namespace pxh
