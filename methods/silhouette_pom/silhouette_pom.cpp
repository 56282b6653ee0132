// Silhouette parallax occlusion mapping, as three.js PR 33953 proposed it (SkyeShark, "TSL: Add
// silhouette parallax occlusion mapping (parallaxOcclusionUV)", closed unmerged; its file
// examples/jsm/tsl/utils/ParallaxOcclusion.js read at mrdoob/three.js bd5a73c8b9f4 and, line for
// line, at SkyeShark/threejs-silhouette-pom 4f35db0164a9, lines 205-350 and 376-426; the
// extracted loop: docs/internals/silhouette_sources.md section 1), with its curvedSilhouette
// mode and the base's analytic curvatures (the source's per-axis [k_u, k_v] form):
//   n = layers_max + (layers_min - layers_max) clamp(|V.z|, 0, 1) (real), dL = 1 / n;
//   shift = V.xy / max(|V.z|, 0.05) s, duv = shift / n;
//   bend = min(k / max(2 s, 1e-4), 6) per axis; depth below the top, in units of s:
//     D(uv) = 1 - h(uv) + bend.x (uv.x - P.x)^2 + bend.y (uv.y - P.y)^2;
//   uv = P + shift (1 - b) (the source has b = 1: it starts at P), L = 0, d = D(uv);
//   up to layers_max times: stop when L >= d, else uv -= duv, L += dL, d = D(uv);
//   then up to `chase` times (the source's 24-step "horizon chase") the same with 4 steps at once;
//   prev = uv + duv (one single step back, as the source, even after a chase step);
//   after = L - d, before = D(prev) - (L - dL), w = clamp(after / max(after + before, 1e-4), 0, 1);
//   discard when d - L > miss_tol (the source: coverage = clamp(1 - (d - L) / 0.05) < 0.5, i.e.
//   0.025: the ray ended its budget still above the bent relief); else uv + (prev - uv) w.
// The source's bounds test (a landing uv more than 0.01 outside [0, 1]) is not applied: pxh's
// texture tiles without end, as the PR's own curved demo (bounds +-1e6) has it.
#include <algorithm>
#include <cmath>
#include <limits>

#include "methods/method.h"

namespace pxh {

struct SilhouettePom {
    struct Config {
        double layers_min, layers_max;
        int chase;
        double miss_tol;
    };
    static MethodInfo describe() {
        MethodInfo info{
            "silhouette_pom",
            "three.js PR 33953 (SkyeShark 2026, closed unmerged): silhouette parallax "
            "occlusion mapping, curvedSilhouette mode, ParallaxOcclusion.js @ bd5a73c8b9f4",
            "POM against the relief bent by the base's curvature, a 4x horizon chase; "
            "discards when the ray ends above the relief",
            {ParamSpec::integer("layers_min", 16, 1, 256, "layers head-on (source: 16)")
                 .to_uniform("p_min_layers"),
             ParamSpec::integer("layers_max", 48, 1, 256,
                                "layers at grazing views, and the loop's bound (source: 48)")
                 .to_uniform("p_max_layers"),
             ParamSpec::integer("chase", 24, 0, 256, "4-layer steps after the budget (source: 24)")
                 .to_uniform("p_chase"),
             ParamSpec::real("miss_tol", 0.025, 0, 1,
                             "discard when the ray ends this far above the relief, in units "
                             "of s (source: 0.025)")
                 .to_uniform("p_miss_tol")},
            false,
            151};
        info.may_discard = true;
        info.discard_test =
            "the ray still above the bent relief by more than miss_tol after its layers and the "
            "chase: three.js PR 33953's discard";
        return info;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {double(p.get_int("layers_min")), double(p.get_int("layers_max")),
                p.get_int("chase"), p.get("miss_tol")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) {
        return 1 + int(c.layers_max) + c.chase + 1;
    }
    // Its search line: uv = P + (V.xy / vz) z, vz = max(|V.z|, 0.05) (the eye ray's where
    // |V.z| >= 0.05).
    static Vec2d hit_direction(const Config&, Vec3d V, double) {
        const double vz = std::max(std::abs(V.z), 0.05);
        return {V.x / vz, V.y / vz};
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const Vec3<T> V = sc.V;
        const T s = sc.scale;
        const T a = std::clamp(std::abs(V.z), T(0), T(1));
        const T n = T(c.layers_max) + (T(c.layers_min) - T(c.layers_max)) * a;
        const T dL = T(1) / n;
        const T vz = std::max(std::abs(V.z), T(0.05));
        const Vec2<T> shift{V.x / vz * s, V.y / vz * s};
        const Vec2<T> duv{shift.x / n, shift.y / n};
        const T two_s = std::max(T(2) * s, T(1e-4));
        const Vec2<T> bend{std::min(sc.curvature.x / two_s, T(6)),
                           std::min(sc.curvature.y / two_s, T(6))};
        auto D = [&](Vec2<T> uv) {
            const T du = uv.x - P.x, dv = uv.y - P.y;
            return T(1) - hs.height(uv) + bend.x * du * du + bend.y * dv * dv;
        };
        Vec2<T> uv{P.x + shift.x * (T(1) - sc.bias), P.y + shift.y * (T(1) - sc.bias)};
        T L = T(0), d = D(uv);
        for (int i = 0; i < int(c.layers_max) && L < d; ++i) {
            uv = uv - duv;
            L += dL;
            d = D(uv);
        }
        for (int i = 0; i < c.chase && L < d; ++i) {
            uv = uv - duv * T(4);
            L += T(4) * dL;
            d = D(uv);
        }
        const Vec2<T> prev = uv + duv;
        const T after = L - d, before = D(prev) - (L - dL);
        const T w = std::clamp(after / std::max(after + before, T(1e-4)), T(0), T(1));
        if (d - L > T(c.miss_tol)) return MethodHit<T>::none();
        // its line uv = P + (V.xy / vz) z, z = s (1 - b - layer): the answer at layer L - w dL
        return {uv + (prev - uv) * w, s * (T(1) - sc.bias - (L - w * dL))};
    }
};
PXH_REGISTER_METHOD(SilhouettePom);

}  // namespace pxh
