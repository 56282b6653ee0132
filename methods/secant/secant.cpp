// Risser, Shah, Pattanaik: "Faster Relief Mapping Using the Secant Method", journal of graphics
// tools 12(3), 2007, pp. 17-24 (its predecessor: Risser, Shah, Pattanaik, "Interval Mapping",
// Univ. of Central Florida, 2005). The paper's text and its source code (secant.txt on the JGT
// page) could not be read here; the method is built from the abstract (an interval whose bounds
// come from a linear search and are refined by ray/segment intersection each iteration) and is
// documented in methods/secant/secant.md: pom's linear search (methods/layered.h), then
// false-position steps on the bracket [k-1, k]: x = x_a + (x_b - x_a) g_a / (g_a - g_b); the first
// `iterations - 1` points are probed (1 fetch each) and replace the bracket end of their sign,
// the last one is returned (iterations = 1 is pom's interpolation).
#include <algorithm>

#include "methods/layered.h"

namespace pxh {

// The false-position point of the bracket (x_a, g_a > 0), (x_b, g_b <= 0): where the ray meets
// the segment joining the surface points at both ends. x_b when the denominator is not positive
// (rounding, NaN).
template <typename T>
T secant_point(T xa, T ga, T xb, T gb) {
    const T d = ga - gb;
    if (!(d > T(0))) return xb;
    const T w = std::clamp(ga / d, T(0), T(1));
    return xa + (xb - xa) * w;
}

struct Secant {
    struct Config {
        LayerConfig layers;
        int iterations;
    };
    static MethodInfo describe() {
        auto params = layer_params();
        params.push_back(
            ParamSpec::integer("iterations", 5, 1, 64,
                               "secant points; all but the last are probed (1 fetch each)")
                .to_uniform("p_iterations"));
        return {"secant",
                "Risser, Shah, Pattanaik: Faster Relief Mapping Using the Secant Method, journal "
                "of graphics tools 12(3), 2007, pp. 17-24; Risser, Shah, Pattanaik: Interval "
                "Mapping, Univ. of Central Florida, 2005",
                "layer search, then false-position steps on [k-1, k] (k + iterations fetches)",
                params,
                true,
                84};
    }
    static Config configure(const ParamValues& p, const std::string& where) {
        return {layer_config(p, where), p.get_int("iterations")};
    }
    static void complete_params(ParamValues& p) { complete_layer_params(p); }
    static GlUniforms gl_uniforms(const Config& c) { return layer_uniforms(c.layers); }
    static int max_fetches(const Config& c, const Scene<double>& sc) {
        return max_layer_index(c.layers, sc) + 1 + (c.iterations - 1);
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const LayerSearch<T> r = layer_search(c.layers, sc, hs, P);
        if (r.k == 0 || !r.crossed) return {r.uv_at(T(r.k)), r.z_at(T(r.k))};
        T xa = T(r.k - 1), ga = r.g_prev, xb = T(r.k), gb = r.g_k;
        for (int i = 1; i < c.iterations; ++i) {
            const T x = secant_point(xa, ga, xb, gb);
            const T g = r.z_at(x) - hs.z(r.uv_at(x));
            if (g > T(0)) {
                xa = x;
                ga = g;
            } else {
                xb = x;
                gb = g;
            }
        }
        const T x = secant_point(xa, ga, xb, gb);  // the secant's answer: the ray's point there
        return {r.uv_at(x), r.z_at(x)};
    }
};
PXH_REGISTER_METHOD(Secant);

}  // namespace pxh
