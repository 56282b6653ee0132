#include "harness/scene/heightfield.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "harness/core/error.h"

namespace pxh {

HeightField::HeightField(int w, int h, std::string n)
    : width(w), height(h), texels(size_t(w) * size_t(h), 0.0f), name(std::move(n)) {}

void HeightField::validate(const std::string& where) const {
    if (width < 1 || height < 1) throw InputError(where, "height field has zero size");
    for (size_t k = 0; k < texels.size(); ++k) {
        const float v = texels[k];
        if (!std::isfinite(v) || v < 0.0f || v > 1.0f) {
            std::ostringstream os;
            os << "texel (" << k % width << ", " << k / width << ") is " << v
               << (std::isfinite(v) ? ", outside [0,1]" : ", not finite")
               << " (heights must be finite and lie in [0,1])";
            throw InputError(where, os.str());
        }
    }
}

float HeightField::min_value() const { return *std::min_element(texels.begin(), texels.end()); }
float HeightField::max_value() const { return *std::max_element(texels.begin(), texels.end()); }

}  // namespace pxh
