// Cg programming wikibook, "Projection of Bumpy Surfaces": offset clamped per component to
// +-MaxTexCoordOffset: P + clamp(z(P) V.xy / V.z, -m, +m).
#include <algorithm>

#include "methods/method.h"

namespace pxh {

struct ParallaxClamped {
    struct Config {
        double max_offset;
        bool from_scale;
    };
    static MethodInfo describe() {
        return {"parallax_clamped",
                "Wikibooks contributors: Cg Programming/Unity/Projection of Bumpy Surfaces "
                "(_MaxTexCoordOffset), "
                "https://en.wikibooks.org/wiki/Cg_Programming/Unity/Projection_of_Bumpy_Surfaces",
                "uv = P + clamp(z(P) * V.xy / V.z, -m, +m) per component (one fetch)",
                {ParamSpec::real("max_offset", std::nullopt, 0, 1e6,
                                 "m in uv units; \"scale\" (the default): the scene's scale s")
                     .or_names({"scale"})
                     .defaults_to("scale")},
                false,
                30};
    }
    static Config configure(const ParamValues& p, const std::string&) {
        const bool from_scale = p.is_name("max_offset", "scale");
        return {from_scale ? 0.0 : p.get("max_offset"), from_scale};
    }
    static GlUniforms gl_uniforms(const Config& c) {
        return {GlUniform::boolean("p_max_offset_is_scale", c.from_scale),
                GlUniform::real("p_max_offset", c.max_offset)};
    }
    static int max_fetches(const Config&, const Scene<double>&) { return 1; }
    template <typename T>
    static Vec2<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const T m = c.from_scale ? sc.scale : T(c.max_offset);
        const Vec2<T> off = sc.V.xy() * (hs.z(P) / sc.V.z);
        return P + Vec2<T>(std::clamp(off.x, -m, m), std::clamp(off.y, -m, m));
    }
};
PXH_REGISTER_METHOD(ParallaxClamped);

}  // namespace pxh
