// Iterative parallax mapping with slope information: Premecz, "Iterative Parallax Mapping with
// Slope Information", CESCG 2006 (Budapest University of Technology). Only the paper's title
// page and abstract could be read here; the iteration is the one implementations of the paper
// ship, e.g. horde3d/Horde3D Horde3D/Binaries/Content/shaders/model.shader
// @ 3957610651c5c0e91449db016c6cf54212eb6502 ("Iterative parallax mapping":
// newCoords += (height - newCoords.p) * nmap.z * eye, 4 iterations, eye the unit tangent-space
// view vector, nmap.z the z of the unit normal from the normal map). In pxh's terms
// (methods/iterative/iterative.md): a point q = (uv, zeta) starts at (P, 0) and moves along V:
//   q <- q + (z(uv) - zeta) N_z(uv) V,   N_z = 1 / sqrt(1 + s^2 |grad h|^2)
// k = `iterations` times (slope = false: N_z = 1); returns uv. The normal map is a resource:
// r_grad = (dh/du, dh/dv) per texel by central differences (wrapping), sampled bilinearly.
#include <tbb/parallel_for.h>

#include <cmath>

#include "methods/method.h"
#include "methods/resource.h"

namespace pxh {

namespace {

// (dh/du, dh/dv, 0, 0) at texel (i, j): central differences of the wrapped field, in uv units.
ResourceImage build_gradient(const HeightField& hf, double, double) {
    const int W = hf.width, H = hf.height;
    ResourceLevel lv;
    lv.width = W;
    lv.height = H;
    lv.texels.resize(size_t(W) * size_t(H) * 4);
    // Rows in parallel: each texel is written by one task from the field alone.
    tbb::parallel_for(0, H, [&](int j) {
        const int jp = (j + 1) % H, jm = (j + H - 1) % H;
        for (int i = 0; i < W; ++i) {
            const int ip = (i + 1) % W, im = (i + W - 1) % W;
            float* t = lv.texels.data() + (size_t(j) * size_t(W) + size_t(i)) * 4;
            t[0] = float((double(hf.at(ip, j)) - double(hf.at(im, j))) * 0.5 * W);
            t[1] = float((double(hf.at(i, jp)) - double(hf.at(i, jm))) * 0.5 * H);
            t[2] = 0;
            t[3] = 0;
        }
    });
    return {{std::move(lv)}};
}

}  // namespace

struct Iterative {
    struct Config {
        int iterations;
        bool slope;
    };
    enum { kGrad = 0 };
    static MethodInfo describe() {
        MethodInfo m{
            "iterative",
            "Premecz: Iterative Parallax Mapping with Slope Information, CESCG 2006; iteration "
            "as in horde3d/Horde3D Horde3D/Binaries/Content/shaders/model.shader @ 3957610",
            "k steps q += (z(uv) - zeta) N_z V from (P, 0) (k or 2k fetches)",
            {ParamSpec::integer("iterations", 4, 1, 64, "k: fixed-point steps")
                 .to_uniform("p_iterations"),
             ParamSpec::boolean("slope", true,
                                "scale each step by N_z of the surface normal (the paper's "
                                "slope information); false: N_z = 1")
                 .to_uniform("p_slope")},
            false,
            45};
        m.resources = {{"r_grad", TexelFormat::RGBA32F, TexFilter::Linear, TexWrap::Repeat, false,
                        build_gradient,
                        "(dh/du, dh/dv, 0, 0): central differences per texel, uv units"}};
        return m;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("iterations"), p.get_bool("slope")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) {
        return c.iterations * (c.slope ? 2 : 1);
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs,
                             ResourceSamplers<T>& res, Vec2<T> P) {
        Vec2<T> uv = P;
        T zeta = T(0);
        for (int i = 0; i < c.iterations; ++i) {
            const T z = hs.z(uv);
            T nz = T(1);
            if (c.slope) {
                const auto g = res[kGrad].fetch(uv, 0);
                const T gx = sc.scale * g[0], gy = sc.scale * g[1];
                nz = T(1) / std::sqrt(T(1) + gx * gx + gy * gy);
            }
            const T d = (z - zeta) * nz;
            uv = uv + sc.V.xy() * d;
            zeta = zeta + sc.V.z * d;
        }
        return {uv, zeta};  // uv - P = V.xy t, zeta = V.z t: the eye ray's point
    }
};
PXH_REGISTER_METHOD(Iterative);

}  // namespace pxh
