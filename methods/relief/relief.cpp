// Policarpo, Oliveira & Comba 2005, "Real-Time Relief Mapping on Arbitrary Polygonal
// Surfaces"; tutorial "Relief Parallax Mapping": layer search, then n_binary bisection steps
// on [k-1, k]; returns the midpoint of the final interval (the tutorial's last move).
#include "methods/layered.h"

namespace pxh {

struct Relief {
    struct Config {
        LayerConfig layers;
        int binary_steps;
    };
    static MethodInfo describe() {
        auto params = layer_params();
        params.push_back(ParamSpec::integer("binary_steps", 5, 0, 64, "n_binary bisection steps")
                             .to_uniform("p_binary_steps"));
        return {"relief",
                "Policarpo, Oliveira, Comba: Real-Time Relief Mapping on Arbitrary Polygonal "
                "Surfaces, I3D 2005, pp. 155-162, doi:10.1145/1053427.1053453; LearnOpenGL "
                "Parallax Mapping (Habr translation, relief section)",
                "bisection on [k-1, k] after the layer search (k + 1 + n_binary fetches)",
                params,
                false,
                80};
    }
    static Config configure(const ParamValues& p, const std::string& where) {
        return {layer_config(p, where), p.get_int("binary_steps")};
    }
    static void complete_params(ParamValues& p) { complete_layer_params(p); }
    static GlUniforms gl_uniforms(const Config& c) { return layer_uniforms(c.layers); }
    static int max_fetches(const Config& c, const Scene<double>& sc) {
        return max_layer_index(c.layers, sc) + 1 + c.binary_steps;
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const LayerSearch<T> r = layer_search(c.layers, sc, hs, P);
        if (r.k == 0) return {r.uv0, r.z0};
        T lo = T(r.k - 1), hi = T(r.k);
        for (int i = 0; i < c.binary_steps; ++i) {
            const T mid = (lo + hi) * T(0.5);
            const T g = r.z_at(mid) - hs.z(r.uv_at(mid));
            if (g > T(0)) lo = mid;
            else hi = mid;
        }
        const T x = (lo + hi) * T(0.5);  // the bisection's answer: the ray's point there
        return {r.uv_at(x), r.z_at(x)};
    }
};
PXH_REGISTER_METHOD(Relief);

}  // namespace pxh
