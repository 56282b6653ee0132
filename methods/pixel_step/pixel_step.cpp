// Zhao, Wu, Gao 2012, "Realistic and Detail Rendering of Village Virtual Scene Based on Pixel
// Offset", sec. 3.2.2 ("pixel offset translation"), generalised to any bias by starting where the
// ray leaves the slab at the bottom: q_k = q_0 + k/W * V.xy/|V.xy|, z_k = z_bot + k/W * V.z/|V.xy|;
// stop at the first z_k >= z(q_k).
#include <algorithm>
#include <cmath>

#include "methods/method.h"

namespace pxh {

struct PixelStep {
    struct Config {
        int max_steps;
    };
    static MethodInfo describe() {
        return {"pixel_step",
                "Zhao, Wu, Gao: Realistic and Detail Rendering of Village Virtual Scene Based on "
                "Pixel Offset, Appl. Math. Inf. Sci. 6(3S), pp. 769-775, 2012, sec. 3.2.2 (pixel "
                "offset translation)",
                "march one texel at a time from the slab bottom toward the eye (k + 1 fetches)",
                {ParamSpec::integer("max_steps", 16384, 1, 1e8,
                                    "loop bound; the march needs ceil(s W tan(theta)) steps to "
                                    "leave the slab")
                     .to_uniform("p_max_steps")},
                false,
                50};
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("max_steps")};
    }
    // Steps needed to rise through the slab: s W tan(theta), plus one for rounding.
    static int max_fetches(const Config& c, const Scene<double>& sc) {
        const double vxy = std::hypot(sc.V.x, sc.V.y);
        if (vxy == 0) return 0;
        const double need = std::ceil(sc.scale * sc.width * vxy / sc.V.z) + 1;
        return int(std::min<double>(need, c.max_steps)) + 1;
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const T vxy = std::sqrt(sc.V.x * sc.V.x + sc.V.y * sc.V.y);
        if (vxy == T(0)) return {P};  // no step to take: the surface at P (not fetched)
        const T texel = T(1) / T(sc.width);
        const Vec2<T> q0 = P + sc.V.xy() * (sc.z_bot() / sc.V.z);
        const Vec2<T> step = sc.V.xy() * (texel / vxy);
        const T rise = texel * sc.V.z / vxy;
        const T zb = sc.z_bot();
        const int kmax = max_fetches(c, scene_cast_back(sc)) - 1;
        int k = 0;
        Vec2<T> q = q0;
        while (zb + T(k) * rise < hs.z(q) && k < kmax) {
            ++k;
            q = q0 + step * T(k);
        }
        return {q, zb + T(k) * rise};  // the ray's height at q
    }
    template <typename T>
    static Scene<double> scene_cast_back(const Scene<T>& s) {
        return {double(s.scale), double(s.bias), Vec3d(s.V), s.width, s.height};
    }
};
PXH_REGISTER_METHOD(PixelStep);

}  // namespace pxh
