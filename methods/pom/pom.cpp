// Tatarchuk 2006, "Parallax Occlusion Mapping"; tutorial "Parallax Occlusion Mapping":
// linear interpolation between the layers around the crossing, w = g_k / (g_k - g_{k-1}).
#include <algorithm>

#include "methods/layered.h"

namespace pxh {

struct Pom : LayeredMethod {
    static MethodInfo describe() {
        return {
            "pom",
            "Tatarchuk: Dynamic Parallax Occlusion Mapping with Approximate Soft Shadows, I3D "
            "2006, pp. 63-69, doi:10.1145/1111411.1111423; de Vries: Parallax Mapping, LearnOpenGL",
            "w uv_{k-1} + (1 - w) uv_k, w = g_k / (g_k - g_{k-1}) (k + 1 fetches)",
            layer_params(),
            true,
            70};
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const LayerSearch<T> r = layer_search(c, sc, hs, P);
        const MethodHit<T> at_k{r.uv_at(T(r.k)), r.z_at(T(r.k))};
        // k = 0, or stopped by the bound without crossing: no bracket to interpolate in.
        if (r.k == 0 || !r.crossed) return at_k;
        const T denom = r.g_k - r.g_prev;  // < 0 since g_{k-1} > 0 >= g_k
        if (!(denom < T(0))) return at_k;
        const T w = std::clamp(r.g_k / denom, T(0), T(1));
        // z_m = w z_{k-1} + (1 - w) z_k: the ray's height at the interpolated point
        return {r.uv_at(T(r.k - 1)) * w + at_k.uv * (T(1) - w),
                r.z_at(T(r.k - 1)) * w + at_k.z * (T(1) - w)};
    }
};
PXH_REGISTER_METHOD(Pom);

}  // namespace pxh
