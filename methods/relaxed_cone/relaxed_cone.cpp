// Policarpo and Oliveira 2007, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18:
// a fixed number of relaxed cone steps, then a binary search on [0, the depth reached]
// (the chapter's ray_intersect_rcsm; its listing read through public transcriptions, e.g. the
// ray_intersect_relaxedcone function in many engines' shaders). The relaxed cones: the book's
// generation (`cones = book`) or the corrected one of Ban, Valasek, Balint, Vad, "Robust Cone
// Step Mapping", EGSR 2024, doi:10.2312/sr.20241146 (`ban`; `ban_min` adds their 3 x 3 minimum
// post-process); methods/cone/cone_map.h, methods/relaxed_cone/relaxed_cone.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "harness/core/error.h"
#include "methods/cone/cone_map.h"
#include "methods/method.h"

namespace pxh {
namespace {

// (h, the book's relaxed ratio, Ban et al.'s, its 3 x 3 minimum) per texel.
ResourceImage build_relaxed_map(const HeightField& hf, double, double) {
    const size_t n = size_t(hf.width) * size_t(hf.height);
    if (n > cone_maps::kRelaxedTexelLimit)
        throw InputError("height field '" + hf.name + "'",
                         std::to_string(hf.width) + " x " + std::to_string(hf.height) +
                             " texels: relaxed_cone builds its maps (the book's relaxed cones) "
                             "for at most 65536 texels (256 x 256); see "
                             "methods/relaxed_cone/relaxed_cone.md");
    const std::vector<float> book = cone_maps::relaxed_book(hf);
    const std::vector<float> ban = cone_maps::relaxed_ban(hf);
    const std::vector<float> ban_min = cone_maps::min3x3(ban, hf.width, hf.height);
    ResourceLevel lv;
    lv.width = hf.width;
    lv.height = hf.height;
    lv.texels.resize(n * 4);
    for (size_t k = 0; k < n; ++k) {
        lv.texels[4 * k] = hf.texels[k];
        lv.texels[4 * k + 1] = book[k];
        lv.texels[4 * k + 2] = ban[k];
        lv.texels[4 * k + 3] = ban_min[k];
    }
    return {{std::move(lv)}};
}

}  // namespace

struct RelaxedCone {
    struct Config {
        int cone_steps, binary_steps;
        int cones;  // 0 book, 1 ban, 2 ban_min: channel 1 + cones of r_relaxed
    };
    static MethodInfo describe() {
        MethodInfo m{
            "relaxed_cone",
            "Policarpo, Oliveira: Relaxed Cone Stepping for Relief Mapping, GPU Gems 3 ch. 18, "
            "Addison-Wesley 2007, pp. 409-428; cones = ban, ban_min: Ban, Valasek, Balint, Vad: "
            "Robust Cone Step Mapping, EGSR 2024, doi:10.2312/sr.20241146",
            "cone_steps relaxed cone steps, then binary_steps bisections of [0, the depth "
            "reached] (cone_steps + binary_steps fetches)",
            {ParamSpec::integer("cone_steps", 15, 1, 1024, "relaxed cone steps (fixed count)")
                 .to_uniform("p_cone_steps"),
             ParamSpec::integer("binary_steps", 6, 0, 64, "binary search steps (fixed count)")
                 .to_uniform("p_binary_steps"),
             ParamSpec::choice("cones", {"book", "ban", "ban_min"}, "book",
                               "book: the chapter's relaxed-cone generation; ban: Ban et al. "
                               "2024's corrected relaxed cones; ban_min: with their 3 x 3 "
                               "minimum post-process")
                 .to_uniform("p_cones")},
            false,
            230};
        m.resources = {{"r_relaxed", TexelFormat::RGBA32F, TexFilter::Linear, TexWrap::Repeat,
                        false, build_relaxed_map,
                        "(h, the book's relaxed ratio, Ban et al.'s, its 3 x 3 minimum), ratios "
                        "in uv per unit of h"}};
        return m;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        const std::string& c = p.get_name("cones");
        return {p.get_int("cone_steps"), p.get_int("binary_steps"),
                c == "book" ? 0 : (c == "ban" ? 1 : 2)};
    }
    static int max_fetches(const Config& c, const Scene<double>&) {
        return c.cone_steps + c.binary_steps;
    }
    // Depth t in units of h below the slab top: the ray is at uv0 + m t, height 1 - t.
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>&,
                             ResourceSamplers<T>& res, Vec2<T> P) {
        const Vec2<T> D = sc.V.xy() * (T(1) / sc.V.z);
        const Vec2<T> uv0 = P + D * sc.z_top();
        const Vec2<T> m = D * (-sc.scale);
        const T dist = std::sqrt(m.x * m.x + m.y * m.y);  // the book's length(v.xy), v.z = 1
        T t = T(0);
        for (int i = 0; i < c.cone_steps; ++i) {
            const std::array<T, 4> tex = res[0].fetch(uv0 + m * t, 0);
            const T gap = std::clamp(T(1) - t - tex[0], T(0), T(1));  // saturate(depth - p.z)
            const T ratio = tex[size_t(1 + c.cones)];
            t = t + ratio * gap / (dist + ratio);
        }
        T range = t * T(0.5);
        T tb = range;
        for (int i = 0; i < c.binary_steps; ++i) {
            const std::array<T, 4> tex = res[0].fetch(uv0 + m * tb, 0);
            range = range * T(0.5);
            if (tb < T(1) - tex[0]) tb = tb + range;  // above the surface: forward
            else tb = tb - range;
        }
        return {uv0 + m * tb, sc.z_top() - sc.scale * tb};
    }
};
PXH_REGISTER_METHOD(RelaxedCone);

}  // namespace pxh
