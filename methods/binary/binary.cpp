// Binary search over the whole slab, without a linear search: the search that Policarpo,
// Oliveira, Comba ("Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005,
// pp. 155-162, doi:10.1145/1053427.1053453) run after the linear search, here run
// alone on [z_top, z_bot], to show where it fails: with more than one crossing on the ray it
// can converge to any of them (the paper's reason for the linear search first).
//   x in [0, 1] along the ray from z_top (x = 0) to z_bot (x = 1): uv(x) = uv_0 + x duv,
//   uv_0 = P + V.xy / V.z z_top, duv = -V.xy / V.z s, zeta(x) = z_top - x s,
//   g(x) = zeta(x) - z(uv(x)); `iterations` times: mid = (lo + hi) / 2, g(mid) > 0: lo = mid,
//   otherwise hi = mid; returns uv((lo + hi) / 2) (relief's last move). methods/binary/binary.md.
#include "methods/method.h"

namespace pxh {

struct Binary {
    struct Config {
        int iterations;
    };
    static MethodInfo describe() {
        return {"binary",
                "Policarpo, Oliveira, Comba: Real-Time Relief Mapping on Arbitrary Polygonal "
                "Surfaces, I3D 2005, pp. 155-162, doi:10.1145/1053427.1053453 (its binary "
                "search, here without the linear search)",
                "bisection of the ray over the whole slab (iterations fetches)",
                {ParamSpec::integer("iterations", 10, 1, 64, "bisection steps (1 fetch each)")
                     .to_uniform("p_iterations")},
                false,
                88};
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("iterations")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) { return c.iterations; }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const Vec2<T> dir = sc.V.xy() * (T(1) / sc.V.z);
        const T z0 = sc.z_top();
        const Vec2<T> uv0 = P + dir * z0;
        const Vec2<T> duv = dir * (-sc.scale);
        T lo = T(0), hi = T(1);
        for (int i = 0; i < c.iterations; ++i) {
            const T mid = (lo + hi) * T(0.5);
            const T g = (z0 - sc.scale * mid) - hs.z(uv0 + duv * mid);
            if (g > T(0)) lo = mid;
            else hi = mid;
        }
        const T t = (lo + hi) * T(0.5);
        return {uv0 + duv * t, z0 - sc.scale * t};
    }
};
PXH_REGISTER_METHOD(Binary);

}  // namespace pxh
