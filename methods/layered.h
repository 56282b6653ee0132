// The layered search shared by steep, pom and relief (docs/conventions.md section 6.3).
//   n fixed or n = mix(n_max, n_min, |V.z|); dz = s / n; duv = -V.xy / V.z * dz;
//   uv_0 = P + V.xy / V.z * z_top; uv_k = uv_0 + k duv; z_k = z_top - k dz; g_k = z_k - z(uv_k);
//   k = first index with g_k <= 0, and at most ceil(n).
#pragma once
#include <algorithm>
#include <cmath>

#include "harness/core/error.h"
#include "methods/method.h"

namespace pxh {

// Two modes: fixed n (layers = a number) or view-adaptive (layers = "adaptive", or
// layers_min / layers_max given). In `params` (complete_layer_params fills the defaults):
// fixed n is "layers=32;layers_min=off;layers_max=off", view-adaptive "layers=adaptive;
// layers_min=8;layers_max=32" (the values in use, never both modes at once). The names are
// accepted as input too, so a `params` value read back means the same setting.
inline std::vector<ParamSpec> layer_params() {
    return {
        ParamSpec::real("layers", std::nullopt, 1, 4096,
                        "fixed layer count n (default 32 when neither layers_min nor layers_max "
                        "is given); \"adaptive\": view-adaptive")
            .or_names({"adaptive"})
            .unset_as("adaptive"),
        ParamSpec::real("layers_min", std::nullopt, 1, 4096,
                        "view-adaptive: n = mix(layers_max, layers_min, |V.z|) (default 8); "
                        "\"off\": fixed n")
            .or_names({"off"})
            .unset_as("off"),
        ParamSpec::real("layers_max", std::nullopt, 1, 4096,
                        "view-adaptive upper count (default 32); \"off\": fixed n")
            .or_names({"off"})
            .unset_as("off"),
    };
}

struct LayerConfig {
    bool adaptive = false;
    double n = 32, n_min = 8, n_max = 32;
};

inline LayerConfig layer_config(const ParamValues& p, const std::string& where) {
    LayerConfig c;
    const bool says_fixed =
        p.is_number("layers") || p.is_name("layers_min", "off") || p.is_name("layers_max", "off");
    c.adaptive =
        p.is_name("layers", "adaptive") || p.is_number("layers_min") || p.is_number("layers_max");
    if (c.adaptive && says_fixed)
        throw InputError(where,
                         "give either 'layers' (fixed) or 'layers_min'/'layers_max' "
                         "(view-adaptive), not both");
    c.n = p.is_number("layers") ? p.get("layers") : 32;
    c.n_min = p.is_number("layers_min") ? p.get("layers_min") : 8;
    c.n_max = p.is_number("layers_max") ? p.get("layers_max") : 32;
    if (c.adaptive && c.n_min > c.n_max)
        throw InputError(where, "layers_min must not exceed layers_max");
    return c;
}

// The resolved set: the mode and the defaults the search uses written in (fixed: layers = 32,
// layers_min = layers_max = "off"; adaptive: layers = "adaptive", layers_min = 8,
// layers_max = 32), so `params` says exactly what ran. Call after layer_config accepted the
// given values.
inline void complete_layer_params(ParamValues& p) {
    const LayerConfig c = layer_config(p, "");
    if (c.adaptive) {
        p.set("layers", "adaptive");
        p.set("layers_min", c.n_min);
        p.set("layers_max", c.n_max);
    } else {
        p.set("layers", c.n);
        p.set("layers_min", "off");
        p.set("layers_max", "off");
    }
}

// Layer count n for this view, kept as a real number (the tutorial's mix()).
template <typename T>
T layer_count(const LayerConfig& c, const Scene<T>& sc) {
    if (!c.adaptive) return T(c.n);
    const T a = std::abs(sc.V.z);
    return T(c.n_max) * (T(1) - a) + T(c.n_min) * a;
}

// The uniforms of common.glsl's pxh_layer_search.
inline GlUniforms layer_uniforms(const LayerConfig& c) {
    return {GlUniform::boolean("p_layers_adaptive", c.adaptive), GlUniform::real("p_layers", c.n),
            GlUniform::real("p_layers_min", c.n_min), GlUniform::real("p_layers_max", c.n_max)};
}

// Bound on the layer index: ceil(n) (layers 0..ceil(n), so ceil(n) + 1 fetches).
inline int max_layer_index(const LayerConfig& c, const Scene<double>& sc) {
    // Evaluate in float and double and take the larger ceil, so the bound holds for both.
    const double nd = layer_count(c, sc);
    const float nf = layer_count(c, scene_cast<float>(sc));
    return int(std::max(std::ceil(nd), double(std::ceil(nf))));
}

// What steep and pom share: the layer parameters, their checks, bound and GLSL uniforms.
struct LayeredMethod {
    using Config = LayerConfig;
    static Config configure(const ParamValues& p, const std::string& where) {
        return layer_config(p, where);
    }
    static int max_fetches(const Config& c, const Scene<double>& sc) {
        return max_layer_index(c, sc) + 1;
    }
    static GlUniforms gl_uniforms(const Config& c) { return layer_uniforms(c); }
    static void complete_params(ParamValues& p) { complete_layer_params(p); }
    // Every layered search returns a point of the eye ray (a layer, or between two).
    static HitHeight hit_height(const Config&) { return HitHeight::ray; }
};

template <typename T>
struct LayerSearch {
    T n;  // layer count
    Vec2<T> uv0, duv;
    T z0, dz;
    int k;          // the stopping layer
    T g_prev, g_k;  // g at k-1 (valid for k >= 1) and at k
    bool crossed;   // g_k <= 0 (false only when stopped by the ceil(n) bound)
    Vec2<T> uv_at(T layer) const { return uv0 + duv * layer; }
    T z_at(T layer) const { return z0 - dz * layer; }
};

template <typename T>
LayerSearch<T> layer_search(const LayerConfig& c, const Scene<T>& sc, HeightSampler<T>& hs,
                            Vec2<T> P) {
    LayerSearch<T> r;
    r.n = layer_count(c, sc);
    const Vec2<T> dir = sc.V.xy() * (T(1) / sc.V.z);  // V.xy / V.z
    r.dz = sc.scale / r.n;
    r.duv = dir * (-r.dz);
    r.z0 = sc.z_top();
    r.uv0 = P + dir * r.z0;
    const int kmax = int(std::ceil(r.n));
    r.g_prev = T(0);
    r.g_k = r.z0 - hs.z(r.uv0);
    r.k = 0;
    while (r.g_k > T(0) && r.k < kmax) {
        ++r.k;
        r.g_prev = r.g_k;
        r.g_k = r.z_at(T(r.k)) - hs.z(r.uv_at(T(r.k)));
    }
    r.crossed = !(r.g_k > T(0));
    return r;
}

}  // namespace pxh
