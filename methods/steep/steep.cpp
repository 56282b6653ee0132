// McGuire & McGuire 2005, "Steep Parallax Mapping"; tutorial "Steep Parallax Mapping":
// the first layer at or below the surface, uv_k.
#include "methods/layered.h"

namespace pxh {

struct Steep {
    using Config = LayerConfig;
    static MethodInfo describe() {
        return {"steep", "McGuire 2005; tutorial 'Steep Parallax Mapping'",
                "uv_k of the first layer at or below the surface (k + 1 fetches)",
                layer_params(), false, 60};
    }
    static Config configure(const ParamValues& p, const std::string& where) {
        return layer_config(p, where);
    }
    static GlUniforms gl_uniforms(const Config& c) { return layer_uniforms(c); }
    static int max_fetches(const Config& c, const Scene<double>& sc) {
        return max_layer_index(c, sc) + 1;
    }
    template <typename T>
    static Vec2<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const LayerSearch<T> r = layer_search(c, sc, hs, P);
        return r.uv_at(T(r.k));
    }
};
PXH_REGISTER_METHOD(Steep);

}  // namespace pxh
