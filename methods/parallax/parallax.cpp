// Kaneko et al. 2001 (ICAT); Welsh 2004, 4.1; tutorial "Parallax Mapping": P + z(P) V.xy / V.z.
#include "methods/method.h"

namespace pxh {

struct Parallax {
    struct Config {};
    static MethodInfo describe() {
        return {"parallax", "Kaneko et al. 2001; Welsh 2004 sec. 4.1",
                "uv = P + z(P) * V.xy / V.z (one fetch)", {}, true, 10};
    }
    static Config configure(const ParamValues&, const std::string&) { return {}; }
    static GlUniforms gl_uniforms(const Config&) { return {}; }
    static int max_fetches(const Config&, const Scene<double>&) { return 1; }
    template <typename T>
    static Vec2<T> eval(const Config&, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        return P + sc.V.xy() * (hs.z(P) / sc.V.z);
    }
};
PXH_REGISTER_METHOD(Parallax);

}  // namespace pxh
