// Curved relief mapping: Oliveira & Policarpo, "An Efficient Representation for Surface
// Details", UFRGS RP-351, 2005 (per-vertex quadric; the body of the report could not be read
// here). The loop is Policarpo's curved-relief shader as three independent ports carry it
// (docs/internals/silhouette_sources.md section 3: Skillman's HLSL, a Unity port, a GLSL
// doReliefMappingQuadric; their cores agree), re-expressed in docs/conventions.md's terms:
//   the ray leaves the base hit P along -V (lambda = distance, tiles): uv(l) = P - V.xy l; the
//   base falls away below the tangent plane by q l^2, q = (k_u V.x^2 + k_v V.y^2) / 2 (k the
//   base's normal curvatures along T, Bt: the source's quadric coefficients a = k_u / 2,
//   b = k_v / 2); the ray's height above the base is g(l) = -V.z l + q l^2 (the source's
//   "v.z t - dataz t^2" below the top); a hit is g(l) <= z(uv(l)), z = s (h - b).
//   The search starts where the ray enters the shell top z = s (1 - b) (the source: b = 1, at P)
//   and ends at lambda_end, the first of: the ray reaching the floor -s b, coming back up
//   through the top (convex bases only), or the source's cap 50. `steps` uniform steps of
//   (lambda_end - lambda_0 + 0.001) / steps (the source: N = 64, advancing while above, no early
//   exit), `binary_steps` halvings (5), then: lambda > lambda_end discards ("no intersection,
//   discard fragment": past the silhouette), else uv(lambda). The source's |q| >= 0.001 clamp is
//   left out: the stable root forms below need none (q = 0 is relief mapping with a uniform
//   step in lambda).
#include <algorithm>
#include <cmath>
#include <limits>

#include "methods/method.h"

namespace pxh {

struct CurvedRelief {
    struct Config {
        int steps, binary_steps;
    };
    static MethodInfo describe() {
        MethodInfo info{
            "curved_relief",
            "Oliveira, Policarpo: An Efficient Representation for Surface Details, UFRGS "
            "Technical Report RP-351, 2005 (curved relief mapping; the loop of Policarpo's "
            "shader as its ports carry it)",
            "linear + binary search of the ray bent by the base's quadric; discards when it "
            "leaves the relief (steps + binary_steps fetches)",
            {ParamSpec::integer("steps", 64, 1, 512, "uniform linear steps (source: 64)")
                 .to_uniform("p_steps"),
             ParamSpec::integer("binary_steps", 5, 0, 64, "halvings (source: 5)")
                 .to_uniform("p_binary_steps")},
            false,
            150};
        info.may_discard = true;
        info.discard_test =
            "its search ended past t_max, where the ray leaves the relief through its floor or "
            "back out through the top: the source's discard; on the plane only where texels lie "
            "at exactly h = 0 and the halvings end a rounding step past t_max";
        return info;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("steps"), p.get_int("binary_steps")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) {
        return c.steps + c.binary_steps;
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const Vec3<T> V = sc.V;
        const T q = T(0.5) * (sc.curvature.x * V.x * V.x + sc.curvature.y * V.y * V.y);
        const T zt = sc.z_top(), zb = sc.z_bot();  // s (1 - b), -s b
        // entering the top: q l^2 - V.z l - zt = 0, the root at or before P (l <= 0)
        const T l0 = -T(2) * zt / (V.z + std::sqrt(std::max(V.z * V.z + T(4) * q * zt, T(0))));
        T l_end = T(50);
        const T disc = V.z * V.z + T(4) * q * zb;  // reaching the floor: q l^2 - V.z l - zb = 0
        if (disc >= T(0)) l_end = std::min(l_end, -T(2) * zb / (V.z + std::sqrt(disc)));
        if (q > T(0))  // back out through the top: the larger root
            l_end = std::min(l_end, (V.z + std::sqrt(V.z * V.z + T(4) * q * zt)) / (T(2) * q));
        auto uv_at = [&](T l) { return Vec2<T>{P.x - V.x * l, P.y - V.y * l}; };
        auto above = [&](T l) { return -V.z * l + q * l * l > hs.z(uv_at(l)); };
        T size = (l_end - l0 + T(0.001)) / T(c.steps);
        T l = l0;
        for (int i = 0; i < c.steps; ++i)
            if (above(l)) l += size;
        for (int i = 0; i < c.binary_steps; ++i) {
            size *= T(0.5);
            if (above(l)) l += size;
            else l -= size;
        }
        if (l > l_end) return MethodHit<T>::none();
        // the eye ray's point at l in the tangent frame (P - V l): its height -V.z l (the
        // method's curved comparison is against the base bending away below it)
        return {uv_at(l), -V.z * l};
    }
};
PXH_REGISTER_METHOD(CurvedRelief);

}  // namespace pxh
