#include "harness/scene/footprint.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pxh {

double footprint_scale(const Footprint& J, int width, int height) {
    const double W = width, H = height;
    const double ix = W * J.dPdi.x, iy = H * J.dPdi.y, jx = W * J.dPdj.x, jy = H * J.dPdj.y;
    return std::max(std::sqrt(ix * ix + iy * iy), std::sqrt(jx * jx + jy * jy));
}

double footprint_lod(const Footprint& J, int width, int height) {
    return std::log2(footprint_scale(J, width, height));
}

std::vector<double> sample_lods(const std::vector<Footprint>& J, int width, int height) {
    std::vector<double> lod(J.size());
    for (size_t k = 0; k < J.size(); ++k) lod[k] = footprint_lod(J[k], width, height);
    return lod;
}

double pixel_error(const Footprint& J, Vec2d e) {
    // J = [[a, c], [b, d]] with columns dP/di = (a, b), dP/dj = (c, d): solve J (di, dj) = e.
    const double a = J.dPdi.x, b = J.dPdi.y, c = J.dPdj.x, d = J.dPdj.y;
    const double det = a * d - b * c;
    if (!(det != 0) || !std::isfinite(det)) return std::numeric_limits<double>::quiet_NaN();
    const double di = (d * e.x - c * e.y) / det, dj = (a * e.y - b * e.x) / det;
    return std::sqrt(di * di + dj * dj);
}

}  // namespace pxh
