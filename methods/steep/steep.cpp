// McGuire & McGuire 2005, "Steep Parallax Mapping"; tutorial "Steep Parallax Mapping":
// the first layer at or below the surface, uv_k.
#include "methods/layered.h"

namespace pxh {

struct Steep : LayeredMethod {
    static MethodInfo describe() {
        return {"steep",
                "McGuire, McGuire: Steep Parallax Mapping, I3D 2005 poster; de Vries: Parallax "
                "Mapping, LearnOpenGL, https://learnopengl.com/Advanced-Lighting/Parallax-Mapping",
                "uv_k of the first layer at or below the surface (k + 1 fetches)",
                layer_params(),
                false,
                60};
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        const LayerSearch<T> r = layer_search(c, sc, hs, P);
        return {r.uv_at(T(r.k)), r.z_at(T(r.k))};
    }
};
PXH_REGISTER_METHOD(Steep);

}  // namespace pxh
