// Self-shadowing from the tutorial ("Relief Parallax Mapping", translator's bonus): a layered
// march from the shaded point toward the light L, up to the top of the relief.
//   n = mix(n_max, n_min, |L.z|) layers between the shaded point's height z_0 and z_top;
//   point i: uv_i = uv + i dz L.xy / L.z, z_i = z_0 + i dz, dz = (z_top - z_0) / n, i >= 1.
//   hard: 0 if any point lies below the surface (z_i < z(uv_i)), else 1.
//   soft: 1 - max_i (z(uv_i) - z_i) / s * (1 - i / n) over the points below; 1 if none.
// The light factor is 1 for lit, 0 for shadowed; L.z <= 0 gives 0.
#pragma once
#include <algorithm>
#include <cmath>

#include "methods/method.h"

namespace pxh {

struct ShadowConfig {
    double n_min = 8, n_max = 32;
};

template <typename T>
struct ShadowFactors {
    T hard, soft;
    int fetches;
};

template <typename T>
ShadowFactors<T> shadow_factors(const ShadowConfig& c, const Scene<T>& sc, Vec3<T> L,
                                HeightSampler<T>& hs, Vec2<T> uv) {
    const int before = hs.fetches;
    if (!(L.z > T(0))) return {T(0), T(0), 0};
    const T z0 = hs.z(uv);
    const T a = std::abs(L.z);
    const T n = T(c.n_max) * (T(1) - a) + T(c.n_min) * a;
    const T dz = (sc.z_top() - z0) / n;
    const Vec2<T> duv = L.xy() * (dz / L.z);
    T worst = T(0);
    bool below = false;
    const int count = int(std::ceil(n));
    for (int i = 1; i < count; ++i) {  // points strictly between z_0 and z_top
        const T zi = z0 + T(i) * dz;
        const T surf = hs.z(uv + duv * T(i));
        if (zi < surf) {
            below = true;
            worst = std::max(worst, (surf - zi) / sc.scale * (T(1) - T(i) / n));
        }
    }
    return {below ? T(0) : T(1), below ? T(1) - worst : T(1), hs.fetches - before};
}

}  // namespace pxh
