// A test-only method (registered in pxh_tests, not in pxh) that reads precomputed textures in
// its C++ twin and its shader: a one-step offset to the level of the local maximum,
//   max:  uv = P + V.xy / V.z * s (M_L(P) - b)              (1 fetch of r_maxmip)
//   mid:  uv = P + V.xy / V.z * s ((M_L(P) + h(P)) / 2 - b) (1 of r_maxmip, 1 of the height)
//   zmap: uv = P + V.xy / V.z * Z(P).r                      (1 of r_zmap)
// M_0(i, j) = max of the heights at texels (i, j), (i+1, j), (i, j+1), (i+1, j+1) (wrapped): the
// corners of the bilinear cell whose lower-left texel centre is (i, j); M_L is level L of the
// max pyramid over it (nearest, repeat). Z = (s (h - b), h, 0, 1) per texel, linear, clamp, built
// per (s, b). On a flat field every mode returns the true point.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "harness/backends/shaders.h"  // EmbeddedShader (the test binary embeds this shader)
#include "methods/method.h"
#include "methods/resource.h"

namespace pxh {

const std::vector<EmbeddedShader>& test_embedded_shaders();  // generated for pxh_tests

namespace {

ResourceImage build_maxmip(const HeightField& hf, double, double) {
    ResourceLevel base;
    base.width = hf.width;
    base.height = hf.height;
    base.texels.resize(size_t(hf.width) * size_t(hf.height));
    // Rows in parallel: each texel is written by one task from the field alone, so the bytes
    // do not depend on the thread count.
    tbb::parallel_for(0, hf.height, [&](int j) {
        const int j1 = (j + 1) % hf.height;
        for (int i = 0; i < hf.width; ++i) {
            const int i1 = (i + 1) % hf.width;
            base.texels[size_t(j) * size_t(hf.width) + size_t(i)] =
                std::max({hf.at(i, j), hf.at(i1, j), hf.at(i, j1), hf.at(i1, j1)});
        }
    });
    return reduce_pyramid(std::move(base), [](float a, float b) { return std::max(a, b); });
}

ResourceImage build_zmap(const HeightField& hf, double s, double b) {
    ResourceLevel lv;
    lv.width = hf.width;
    lv.height = hf.height;
    lv.texels.resize(size_t(hf.width) * size_t(hf.height) * 4);
    for (size_t k = 0; k < hf.texels.size(); ++k) {
        const float h = hf.texels[k];
        lv.texels[4 * k] = float(s * (double(h) - b));
        lv.texels[4 * k + 1] = h;
        lv.texels[4 * k + 2] = 0;
        lv.texels[4 * k + 3] = 1;
    }
    return {{std::move(lv)}};
}

}  // namespace

struct TestMaxLevel {
    struct Config {
        int level;
        int mode;  // 0 max, 1 mid, 2 zmap
    };
    enum { kMaxMip = 0, kZMap = 1 };
    static MethodInfo describe() {
        MethodInfo m{"test_maxlevel",
                     "pxh test-only method (tests/methods/test_maxlevel)",
                     "uv = P + V.xy / V.z * z of the local maximum, from precomputed textures",
                     {ParamSpec::integer("level", 0, 0, 16, "level of the max pyramid")
                          .to_uniform("p_level"),
                      ParamSpec::choice("mode", {"max", "mid", "zmap"}, "max",
                                        "max: M_L; mid: (M_L + h) / 2; zmap: Z(P).r")
                          .to_uniform("p_mode")},
                     true,
                     1000};
        m.resources = {
            {"r_maxmip", TexelFormat::R32F, TexFilter::Nearest, TexWrap::Repeat, false,
             build_maxmip, "max of each bilinear cell's four corners, then a max pyramid"},
            {"r_zmap", TexelFormat::RGBA32F, TexFilter::Linear, TexWrap::Clamp, true, build_zmap,
             "(s (h - b), h, 0, 1) per texel"}};
        m.shader_path = "tests/methods/test_maxlevel/test_maxlevel.frag.glsl";
        for (const auto& s : test_embedded_shaders())
            if (m.shader_path == s.path) m.shader_text = s.source;
        return m;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        const std::string& mode = p.get_name("mode");
        return {p.get_int("level"), mode == "max" ? 0 : (mode == "mid" ? 1 : 2)};
    }
    static int max_fetches(const Config& c, const Scene<double>&) { return c.mode == 1 ? 2 : 1; }
    template <typename T>
    static Vec2<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs,
                        ResourceSamplers<T>& res, Vec2<T> P) {
        const Vec2<T> dir = sc.V.xy() * (T(1) / sc.V.z);
        T z;
        if (c.mode == 2) {
            z = res[kZMap].fetch_r(P, c.level);
        } else {
            T m = res[kMaxMip].fetch_r(P, c.level);
            if (c.mode == 1) m = (m + hs.height(P)) * T(0.5);
            z = sc.scale * (m - sc.bias);
        }
        return P + dir * z;
    }
};
PXH_REGISTER_METHOD(TestMaxLevel);

}  // namespace pxh
