#include "harness/metrics/score.h"

#include <cmath>
#include <limits>

#include "harness/core/params.h"
#include "harness/metrics/measured.h"

namespace pxh {

ResultRow score(const MethodOutput& out, const GroundTruth& gt, int width, int height,
                const std::vector<uint8_t>* exclude, const View* view, const Coverage* cover) {
    ResultRow row;
    MetricInput in{out, gt, width, height, exclude, view};
    in.cover = cover;
    apply_output_metrics(in, row);
    row.set_text("shader", out.shader);
    row.set_text("shader_sha256", out.shader_sha256);
    return row;
}

HoleMask hole_mask(const HeightField& hf, const GroundTruth& gt) {
    HoleMask m;
    if (hf.filled.empty()) return m;
    m.on_filled.resize(gt.uv.size());
    size_t count = 0;
    for (size_t k = 0; k < gt.uv.size(); ++k) {
        if (!std::isfinite(gt.uv[k].x) || !std::isfinite(gt.uv[k].y)) continue;  // no true hit
        const double x = gt.uv[k].x * hf.width - 0.5, y = gt.uv[k].y * hf.height - 0.5;
        const int64_t i = int64_t(std::floor(x)), j = int64_t(std::floor(y));
        bool f = false;
        for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di)
                f = f || hf.filled[size_t(wrap_index(j + dj, hf.height)) * hf.width +
                                   size_t(wrap_index(i + di, hf.width))];
        m.on_filled[k] = f;
        count += f;
    }
    m.frac = double(count) / double(gt.uv.size());
    return m;
}

namespace {

// The spacing of floats at |u| (the gap to the next float up), in double.
double float_gap(double u) {
    const float f = float(std::abs(u));
    return double(std::nextafter(f, std::numeric_limits<float>::infinity())) - double(f);
}

// Float rows whose uv float spaces this coarsely (texels) or more at some inside sample say so:
// from there on their error grows with the eye's distance whatever the method (a perspective
// eye far out puts the samples far from the origin; double rows stay exact).
constexpr double kFloatSpacingNote = 1.0 / 16;

std::string float_spacing_note(const FloatSpacing& s) {
    return "float spaces uv " + format_number(s.texels) +
           " texels apart at inside samples (e.g. uv " + format_number(s.at.x) + ", " +
           format_number(s.at.y) +
           "): float rounding alone costs up to half that; the double rows are exact there";
}

}  // namespace

FloatSpacing float_spacing(const View& view, int width, int height) {
    FloatSpacing s;
    for (size_t k = 0; k < view.size(); ++k) {
        if (!view.is_inside(k)) continue;
        const Vec2d P = view.P[k];
        const double gap = std::max(float_gap(P.x) * width, float_gap(P.y) * height);
        if (gap > s.texels) {
            s.texels = gap;
            s.at = P;
        }
    }
    return s;
}

std::string row_failure(const ResultRow& row, const MethodOutput& out, bool covered, int bound,
                        const MethodInfo& method) {
    // Nothing measured: a failure with its reason, never an ok row of empty cells.
    if (std::string why = nothing_measured(row, out, covered); !why.empty()) return why;
    // The declared bound is enforced: a row over it fails, naming both numbers.
    if (bound >= 0 && row.num("fetches_max") > bound)
        return "fetches_max = " + format_number(row.num("fetches_max")) +
               " exceeds the declared bound fetches_bound = " + std::to_string(bound) +
               (method.plugin_shader.empty() ? " (the method's max_fetches)"
                                             : " (the entry's max_fetches)");
    return "";
}

std::string row_notes(const MethodOutput& o, const MethodInfo& method, const Variant& v,
                      const FloatSpacing& spacing) {
    std::string notes;
    if (o.samples_discarded > 0)
        notes = "note: " + std::to_string(o.samples_discarded) + " of " +
                std::to_string(o.uv.size()) +
                (method.discard_test.empty() ? " samples discarded or unwritten by the shader"
                                             : " samples discarded by " + method.name +
                                                   "'s own test (" + method.discard_test + ")") +
                " (no uv: counted in samples_discarded, not in nonfinite; left out of the "
                "errors and of fetches_mean)";
    if (v.precision == "float" && spacing.texels >= kFloatSpacingNote)
        notes += (notes.empty() ? "note: " : "; ") + float_spacing_note(spacing);
    return notes;
}

}  // namespace pxh
