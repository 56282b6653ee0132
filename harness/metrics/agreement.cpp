#include "harness/metrics/agreement.h"

#include <cmath>
#include <stdexcept>

namespace pxh {

ErrorStats reference_agreement(const std::vector<Vec2d>& a, const std::vector<Vec2d>& b, int width,
                               int height) {
    if (a.size() != b.size()) throw std::logic_error("reference_agreement: hit counts differ");
    std::vector<double> gap(a.size());
    for (size_t k = 0; k < a.size(); ++k) {
        const Vec2d e = texel_error(a[k], b[k], width, height);
        gap[k] = std::hypot(e.x, e.y);
    }
    return error_stats(gap);
}

}  // namespace pxh
