// Dummer 2006, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection Algorithm": cone
// steps over a cone-ratio map, at most `steps` of them. The step loop follows the adaptation
// in Ban, Valasek, Balint, Vad, "Robust Cone Step Mapping", EGSR 2024, doi:10.2312/sr.20241146,
// github.com/Bundas102/robust-cone-map commit 2dbc39b, FindIntersection.slang
// (findIntersection_coneStepMapping): step = max(minimum step, cone step), with their
// conservative minimum step (to the border of the current bilinear cell) as `min_step = cell`
// and their 3 x 3 minimum post-process of the map as `map = dummer_min`. `map = bilinear`:
// pxh's cones, free of the bilinear surface (methods/cone/cone.md). `refine`: the same
// repository's Refinement.slang (refineIntersection_linearApprox, _binarySearch; REFINE_FUN
// 1, 2; refine_steps default 5 from Parallax.h's refineStepNum) on [depth before the last step,
// depth after it], run whether or not the loop ended below the surface, as theirs is.
#include <algorithm>
#include <array>
#include <cmath>

#include "methods/cone/cone_map.h"
#include "methods/method.h"

namespace pxh {
namespace {

// (h, Dummer's ratio, Ban et al.'s 3 x 3 minimum of it, pxh's bilinear ratio) per texel.
ResourceImage build_cone_map(const HeightField& hf, double, double) {
    const std::vector<float> d = cone_maps::dummer(hf);
    const std::vector<float> dm = cone_maps::min3x3(d, hf.width, hf.height);
    const std::vector<float> bl = cone_maps::bilinear(hf);
    ResourceLevel lv;
    lv.width = hf.width;
    lv.height = hf.height;
    lv.texels.resize(hf.texels.size() * 4);
    for (size_t k = 0; k < hf.texels.size(); ++k) {
        lv.texels[4 * k] = hf.texels[k];
        lv.texels[4 * k + 1] = d[k];
        lv.texels[4 * k + 2] = dm[k];
        lv.texels[4 * k + 3] = bl[k];
    }
    return {{std::move(lv)}};
}

int index_of(const std::string& name, std::initializer_list<const char*> names) {
    int i = 0;
    for (const char* n : names) {
        if (name == n) return i;
        ++i;
    }
    return 0;
}

}  // namespace

struct Cone {
    static constexpr double kConverged = 0x1p-20;  // of the slab's depth (units of h)
    struct Config {
        int steps;
        int map;       // 0 dummer, 1 dummer_min, 2 bilinear: channel 1 + map of r_cone
        int min_step;  // 0 texel, 1 cell, 2 none
        int refine;    // 0 none, 1 linear, 2 binary
        int refine_steps;
    };
    static MethodInfo describe() {
        MethodInfo m{
            "cone",
            "Dummer: Cone Step Mapping: An Iterative Ray-Heightfield Intersection Algorithm, 2006; "
            "min_step = cell, map = dummer_min: Ban, Valasek, Balint, Vad: Robust Cone Step "
            "Mapping, EGSR 2024, doi:10.2312/sr.20241146",
            "cone steps t += max(w, c (1 - t - h) / (s |V.xy / V.z| + c)) over a cone-ratio map "
            "while above the surface, then optionally Ban et al.'s refinement on the last step "
            "(at most steps + 1 fetches, + 2 linear, + refine_steps binary)",
            {ParamSpec::integer("steps", 32, 1, 1024, "the iteration cap (fixed count)")
                 .to_uniform("p_steps"),
             ParamSpec::choice("map", {"dummer", "dummer_min", "bilinear"}, "dummer",
                               "dummer: cones through texel centres (Dummer 2006); dummer_min: "
                               "their 3 x 3 minimum (Ban et al. 2024); bilinear: pxh's cones "
                               "free of the bilinear surface")
                 .to_uniform("p_map"),
             ParamSpec::choice("min_step", {"texel", "cell", "none"}, "texel",
                               "texel: at least 1/W along the normalised ray (Dummer, as Ban et "
                               "al. adapt it); cell: to the border of the current bilinear cell "
                               "(Ban et al. 2024); none: the cone step alone")
                 .to_uniform("p_min_step"),
             ParamSpec::choice("refine", {"none", "linear", "binary"}, "none",
                               "after the loop, on the last step's depths [t0, t1] (Ban et al. "
                               "2024, Refinement.slang): none; linear: the ray meets the chord "
                               "through the heights at t0 and t1 (2 fetches); binary: "
                               "refine_steps bisections from the midpoint")
                 .to_uniform("p_refine"),
             ParamSpec::integer("refine_steps", 5, 0, 64,
                                "bisections of refine = binary (Ban et al.'s default 5)")
                 .to_uniform("p_refine_steps")},
            false,
            220};
        m.resources = {{"r_cone", TexelFormat::RGBA32F, TexFilter::Linear, TexWrap::Repeat, false,
                        build_cone_map,
                        "(h, Dummer's ratio, its 3 x 3 minimum, pxh's bilinear ratio), ratios in "
                        "uv per unit of h"}};
        return m;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("steps"),
                index_of(p.get_name("map"), {"dummer", "dummer_min", "bilinear"}),
                index_of(p.get_name("min_step"), {"texel", "cell", "none"}),
                index_of(p.get_name("refine"), {"none", "linear", "binary"}),
                p.get_int("refine_steps")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) {
        return c.steps + 1 + (c.refine == 1 ? 2 : (c.refine == 2 ? c.refine_steps : 0));
    }

    // Ban et al.'s refinements on [t0, t1] (depths; the height is r_cone's r channel, the one
    // the loop tests). linear: where the ray meets the chord through (t0, h(t0)), (t1, h(t1)),
    // clamped to [t0, t1]; a parallel chord (zero denominator) gives what their clamp gives to
    // +-inf or NaN under D3D min/max: t1 if the ray is above at t0, else t0.
    template <typename T>
    static T refine_linear(ResourceSamplers<T>& res, Vec2<T> uv0, Vec2<T> m, T t0, T t1) {
        const T h0 = res[0].fetch(uv0 + m * t0, 0)[0];
        const T h1 = res[0].fetch(uv0 + m * t1, 0)[0];
        const T dt = t1 - t0;
        const T num = dt + t0 * h1 - t1 * h0;
        const T den = dt + h1 - h0;
        const T t = den != T(0) ? num / den : (num > T(0) ? t1 : t0);
        return std::min(std::max(t, t0), t1);
    }
    // binary: `steps` bisections from the midpoint (one fetch each); the final midpoint.
    template <typename T>
    static T refine_binary(ResourceSamplers<T>& res, Vec2<T> uv0, Vec2<T> m, T t0, T t1,
                           int steps) {
        T th = T(0.5) * (t0 + t1);
        for (int i = 0; i < steps; ++i) {
            const T fh = res[0].fetch(uv0 + m * th, 0)[0];
            if (fh > T(1) - th) t1 = th;
            else t0 = th;
            th = T(0.5) * (t0 + t1);
        }
        return th;
    }

    // Depth (in units of h) from p along m (uv per unit depth) to the next border of the
    // bilinear cell p lies in; false when m = 0 (a vertical ray crosses no border).
    template <typename T>
    static bool to_cell_border(Vec2<T> p, Vec2<T> m, const Scene<T>& sc, T& d) {
        bool any = false;
        if (m.x != T(0)) {
            const T i0 = std::floor(p.x * T(sc.width) - T(0.5));
            const T wall = (i0 + (m.x > T(0) ? T(1.5) : T(0.5))) / T(sc.width);
            d = (wall - p.x) / m.x;
            any = true;
        }
        if (m.y != T(0)) {
            const T j0 = std::floor(p.y * T(sc.height) - T(0.5));
            const T wall = (j0 + (m.y > T(0) ? T(1.5) : T(0.5))) / T(sc.height);
            const T dy = (wall - p.y) / m.y;
            d = any ? std::min(d, dy) : dy;
            any = true;
        }
        return any;
    }

    // The ray at depth t (units of h below the slab top) is at uv0 + m t, height 1 - t.
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>&,
                             ResourceSamplers<T>& res, Vec2<T> P) {
        const Vec2<T> D = sc.V.xy() * (T(1) / sc.V.z);
        const Vec2<T> uv0 = P + D * sc.z_top();
        const Vec2<T> m = D * (-sc.scale);
        const T dist = std::sqrt(m.x * m.x + m.y * m.y);     // uv per unit depth: s |V.xy / V.z|
        const T dsz = T(1) / std::sqrt(T(1) + dist * dist);  // depth per unit of ray length
        T t = T(0), t_last = T(0);
        Vec2<T> q = uv0;
        std::array<T, 4> tex = res[0].fetch(q, 0);
        // Until the ray is less than kConverged above the surface (Ban et al.: until it is not
        // above it; the margin keeps both twins' decisions equal where a step lands on it).
        for (int k = 0; k < c.steps && T(1) - t - tex[0] > T(kConverged); ++k) {
            t_last = t;
            const T ratio = tex[size_t(1 + c.map)];
            const T cone = ratio * (T(1) - t - tex[0]) / (dist + ratio);
            T w = T(0);
            if (c.min_step == 0) {
                w = dsz / T(sc.width);
            } else if (c.min_step == 1) {
                T b = T(0);
                if (to_cell_border(q, m, sc, b)) w = b + T(1e-5) * dsz;
            }
            t = t + std::max(w, cone);
            q = uv0 + m * t;
            tex = res[0].fetch(q, 0);
        }
        if (c.refine == 1) t = refine_linear(res, uv0, m, t_last, t);
        else if (c.refine == 2) t = refine_binary(res, uv0, m, t_last, t, c.refine_steps);
        else return {q, sc.z_top() - sc.scale * t};
        return {uv0 + m * t, sc.z_top() - sc.scale * t};
    }
};
PXH_REGISTER_METHOD(Cone);

}  // namespace pxh
