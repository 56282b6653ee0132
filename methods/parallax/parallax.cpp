// Kaneko et al. 2001 (ICAT); Welsh 2004, 4.1; tutorial "Parallax Mapping": P + z(P) V.xy / V.z.
#include "methods/method.h"

namespace pxh {

struct Parallax {
    struct Config {};
    static MethodInfo describe() {
        return {"parallax",
                "Kaneko, Takahei, Inami, Kawakami, Yanagida, Maeda, Tachi: Detailed Shape "
                "Representation with Parallax Mapping, ICAT 2001, pp. 205-208; Welsh: Parallax "
                "Mapping with Offset Limiting, Infiscape Corp. tech. report, 2004, sec. 4.1",
                "uv = P + z(P) * V.xy / V.z (one fetch)",
                {},
                true,
                10};
    }
    static Config configure(const ParamValues&, const std::string&) { return {}; }
    static int max_fetches(const Config&, const Scene<double>&) { return 1; }
    template <typename T>
    static Vec2<T> eval(const Config&, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        return P + sc.V.xy() * (hs.z(P) / sc.V.z);
    }
};
PXH_REGISTER_METHOD(Parallax);

}  // namespace pxh
