// The GLSL render of one method setting against its CPU float reference on the N x N grid:
// how many samples land more than 1e-3 texel apart, and how many differ in fetch count. `res`:
// the method's precomputed textures (ResourceCache::get), for methods that declare any.
#pragma once
#include <cmath>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/metrics/metrics.h"

namespace pxh::test {

struct GlslCpuDiff {
    size_t samples = 0, far = 0, fetch_off = 0;
};

inline GlslCpuDiff glsl_vs_cpu(GlslBackend& gl, const MethodSpec& spec, const Scene<double>& sc,
                               const HeightField& hf, int N, const MethodResources* res = nullptr) {
    const auto P = sample_grid(N);
    const MethodOutput gpu = gl.run(spec, sc, hf, N, "r32f", nullptr, 0, res);
    const MethodOutput cpu = run_cpu(spec, "float", sc, hf, P, 0, res);
    GlslCpuDiff d;
    d.samples = P.size();
    for (size_t k = 0; k < P.size(); ++k) {
        const Vec2d e = texel_error(gpu.uv[k], cpu.uv[k], hf.width, hf.height);
        d.far += !(std::hypot(e.x, e.y) <= 1e-3);
        d.fetch_off += gpu.fetches[k] != cpu.fetches[k];
    }
    return d;
}

}  // namespace pxh::test
