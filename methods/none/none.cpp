// Plain texture mapping: the sample's own coordinate, no height fetch (the baseline).
#include "methods/method.h"

namespace pxh {

struct None {
    struct Config {};
    static MethodInfo describe() {
        return {"none", "plain texture mapping (baseline)", "uv = P", {}, false, 0};
    }
    static Config configure(const ParamValues&, const std::string&) { return {}; }
    static int max_fetches(const Config&, const Scene<double>&) { return 0; }
    template <typename T>
    static Vec2<T> eval(const Config&, const Scene<T>&, HeightSampler<T>&, Vec2<T> P) {
        return P;
    }
};
PXH_REGISTER_METHOD(None);

}  // namespace pxh
