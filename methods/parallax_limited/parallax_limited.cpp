// Welsh 2004, "Parallax Mapping with Offset Limiting", sec. 4.3: P + z(P) V.xy.
#include "methods/method.h"

namespace pxh {

struct ParallaxLimited {
    struct Config {};
    static MethodInfo describe() {
        return {"parallax_limited",
                "Welsh: Parallax Mapping with Offset Limiting: A Per-Pixel Approximation of Uneven "
                "Surfaces, Infiscape Corp. tech. report rev. 0.3, 2004, sec. 4.3",
                "uv = P + z(P) * V.xy (one fetch; offset never longer than |z|)",
                {},
                false,
                20};
    }
    static Config configure(const ParamValues&, const std::string&) { return {}; }
    static int max_fetches(const Config&, const Scene<double>&) { return 1; }
    template <typename T>
    static Vec2<T> eval(const Config&, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        return P + sc.V.xy() * hs.z(P);
    }
};
PXH_REGISTER_METHOD(ParallaxLimited);

}  // namespace pxh
