// Contact refinement parallax mapping: Riccardi, "A new approach for parallax mapping:
// presenting the Contact Refinement Parallax Mapping technique", ArtStation blog, 2018
// (https://andreariccardi.artstation.com/blog/3VPo/...), reference shader a-riccardi/shader-toy
// ShaderToy/Assets/Shaders/ParallaxOcclusionMapping.cginc @
// 795f587896e3d02cd2a164e3a66d4406f4619420 (get_parallax_offset_uv with _PTHQ_CONTACT_REFINEMENT:
// "rolling back to the previous step along the ray, it uses another loop with the same step
// numbers" over 1/layerN of a step, then optionally the linear interpolation of
// _PTHQ_OCCLUSION_MAPPING); also O3DE Atom ParallaxMapping.azsli (Contact). Here: pom's layer
// search (methods/layered.h) finds k, then a second search from layer k-1 in sub-layers of 1/n of a
// layer (the layers of pom with n^2 layers inside [k-1, k]) stops at the first sub-layer at or
// below the surface; `lerp` (default) interpolates between it and the sub-layer before, as pom does
// (methods/contact/contact.md).
#include <algorithm>
#include <cmath>

#include "methods/layered.h"

namespace pxh {

struct Contact {
    struct Config {
        LayerConfig layers;
        bool lerp;
    };
    static MethodInfo describe() {
        auto params = layer_params();
        params.push_back(ParamSpec::boolean("lerp", true,
                                            "interpolate between the last sub-layer above and "
                                            "the first at or below the surface (pom's weight)")
                             .to_uniform("p_lerp"));
        return {"contact",
                "Riccardi: A new approach for parallax mapping: presenting the Contact Refinement "
                "Parallax Mapping technique, ArtStation blog, 2018; reference shader "
                "github.com/a-riccardi/shader-toy ParallaxOcclusionMapping.cginc @ 795f587",
                "layer search, then sub-layers of 1/n from layer k-1 (at most 2 ceil(n) fetches)",
                params,
                true,
                86};
    }
    static Config configure(const ParamValues& p, const std::string& where) {
        return {layer_config(p, where), p.get_bool("lerp")};
    }
    static void complete_params(ParamValues& p) { complete_layer_params(p); }
    static GlUniforms gl_uniforms(const Config& c) { return layer_uniforms(c.layers); }
    // k + 1 for the search, at most ceil(n) - 1 sub-layers (layer k itself is known).
    static int max_fetches(const Config& c, const Scene<double>& sc) {
        const int kmax = max_layer_index(c.layers, sc);
        return kmax + 1 + std::max(kmax - 1, 0);
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const LayerSearch<T> r = layer_search(c.layers, sc, hs, P);
        if (r.k == 0 || !r.crossed) return {r.uv_at(T(r.k)), r.z_at(T(r.k))};
        const T base = T(r.k - 1), sub = T(1) / r.n;
        const int jmax = int(std::ceil(r.n)) - 1;
        T xa = base, ga = r.g_prev, xb = T(r.k), gb = r.g_k;
        for (int j = 1; j <= jmax; ++j) {
            const T x = base + sub * T(j);
            const T g = r.z_at(x) - hs.z(r.uv_at(x));
            if (!(g > T(0))) {
                xb = x;
                gb = g;
                break;
            }
            xa = x;
            ga = g;
        }
        if (!c.lerp) return {r.uv_at(xb), r.z_at(xb)};
        const T denom = gb - ga;  // < 0 since ga > 0 >= gb
        if (!(denom < T(0))) return {r.uv_at(xb), r.z_at(xb)};
        const T w = std::clamp(gb / denom, T(0), T(1));
        return {r.uv_at(xa) * w + r.uv_at(xb) * (T(1) - w),
                r.z_at(xa) * w + r.z_at(xb) * (T(1) - w)};
    }
};
PXH_REGISTER_METHOD(Contact);

}  // namespace pxh
