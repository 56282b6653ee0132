// Zhao, Wu, Gao 2012, "Realistic and Detail Rendering of Village Virtual Scene Based on Pixel
// Offset", sec. 3.2: half the classic offset, P + 0.5 z(P) V.xy / V.z.
#include "methods/method.h"

namespace pxh {

struct ParallaxHalved {
    struct Config {};
    static MethodInfo describe() {
        return {
            "parallax_halved",
            "Zhao, Wu, Gao: Realistic and Detail Rendering of Village Virtual Scene Based on Pixel "
            "Offset, Appl. Math. Inf. Sci. 6(3S), pp. 769-775, 2012, sec. 3.2 (halved offset)",
            "uv = P + 0.5 * z(P) * V.xy / V.z (one fetch)",
            {},
            false,
            40};
    }
    static Config configure(const ParamValues&, const std::string&) { return {}; }
    static int max_fetches(const Config&, const Scene<double>&) { return 1; }
    template <typename T>
    static Vec2<T> eval(const Config&, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        return P + sc.V.xy() * (T(0.5) * hs.z(P) / sc.V.z);
    }
};
PXH_REGISTER_METHOD(ParallaxHalved);

}  // namespace pxh
