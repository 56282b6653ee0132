#include "harness/metrics/measured.h"

#include <cmath>

#include "harness/core/params.h"

namespace pxh {

std::string nothing_measured(const ResultRow& row, const MethodOutput& o, bool curved) {
    if (o.uv.empty()) return "";
    const double n = double(o.uv.size());
    // No inside sample (a perspective view at or beyond the horizon).
    if (row.num("samples_outside") >= n)
        return "every sample (" + format_number(n) +
               ") lies outside the view (V.z <= cos 89 degrees: at or beyond the horizon, "
               "samples_outside): nothing to measure; lower theta or widen fov_deg";
    if (std::isfinite(row.num("err_mean"))) return "";
    // A curved base where no pixel is covered by both the method and the truth.
    if (curved && row.num("nonfinite") == 0)
        return "no pixel is covered by both the method and the truth (cover_extra_frac " +
               format_number(row.num("cover_extra_frac")) + ", cover_missing_frac " +
               format_number(row.num("cover_missing_frac")) + ", samples_outside " +
               format_number(row.num("samples_outside")) + " of " + format_number(n) +
               "): no error to measure; a larger radius or scale, or a camera that sees more of "
               "the base";
    // Every inside sample without a uv (a parameter combination that gives no answer at this
    // view, e.g. a layer count of 0, or a shader that discards every sample).
    const double no_uv = row.num("nonfinite") + double(o.samples_discarded);
    if (no_uv > 0 && no_uv >= n - row.num("samples_outside"))
        return "every sample (" + format_number(no_uv) + ") " +
               (o.samples_discarded > 0 && row.num("nonfinite") == 0
                    ? std::string("was discarded or left unwritten by the shader "
                                  "(samples_discarded)")
                    : std::string("gave a non-finite uv: the method's parameters give no answer "
                                  "at this view"));
    return "";
}

}  // namespace pxh
