// Tevs, Ihrke, Seidel: "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field
// Rendering", I3D 2008, pp. 183-190, doi:10.1145/1342250.1342279 (read: the abstract, the
// project page http://tevs.eu/project_i3d08.html and the paper's first page; its traversal's
// details could not be read here: see methods/maxmip/maxmip.md). A max
// pyramid over the bilinear cells' corners, the eye ray traversed through it top-down (a block
// whose highest corner lies below the ray's lowest point in it is stepped over, otherwise the ray
// is advanced to the block's maximum and the block refined), the exact ray / bilinear-patch
// quadratic at the leaf: docs/conventions.md section 4, the same cell solve as the exact tracer
// (harness/truth/cell_solver.h), written here as a method over one texture.
#include "methods/maxmip/maxmip.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "methods/method.h"

namespace pxh {

namespace {

// Level 0: per cell (i, j) its four corners (h(i, j), h(i + 1, j), h(i, j + 1), h(i + 1, j + 1)),
// wrapped; level k + 1: the max of the 2 x 2 (and, at an odd size's last row/column, 3) texels of
// level k it covers, in all four channels (the GL mip chain of reduce_pyramid).
ResourceImage build_maxmip(const HeightField& hf, double, double) {
    const int W = hf.width, H = hf.height;
    ResourceImage img;
    ResourceLevel base{W, H, std::vector<float>(size_t(W) * size_t(H) * 4)};
    // Rows in parallel; each texel written by one task from the field alone.
    tbb::parallel_for(0, H, [&](int j) {
        const int j1 = j + 1 == H ? 0 : j + 1;
        for (int i = 0; i < W; ++i) {
            const int i1 = i + 1 == W ? 0 : i + 1;
            float* t = base.texels.data() + (size_t(j) * size_t(W) + size_t(i)) * 4;
            t[0] = hf.at(i, j);
            t[1] = hf.at(i1, j);
            t[2] = hf.at(i, j1);
            t[3] = hf.at(i1, j1);
        }
    });
    img.levels.push_back(std::move(base));
    while (img.levels.back().width > 1 || img.levels.back().height > 1) {
        const ResourceLevel& src = img.levels.back();
        ResourceLevel dst{std::max(1, src.width / 2), std::max(1, src.height / 2), {}};
        dst.texels.resize(size_t(dst.width) * size_t(dst.height) * 4);
        tbb::parallel_for(0, dst.height, [&](int j) {
            const int j0 = 2 * j, j1 = j + 1 == dst.height ? src.height - 1 : 2 * j + 1;
            for (int i = 0; i < dst.width; ++i) {
                const int i0 = 2 * i, i1 = i + 1 == dst.width ? src.width - 1 : 2 * i + 1;
                float m = 0;
                for (int jj = j0; jj <= j1; ++jj)
                    for (int ii = i0; ii <= i1; ++ii)
                        for (int c = 0; c < 4; ++c)
                            m = std::max(
                                m, src.texels[(size_t(jj) * size_t(src.width) + size_t(ii)) * 4 +
                                              size_t(c)]);
                float* t = dst.texels.data() + (size_t(j) * size_t(dst.width) + size_t(i)) * 4;
                t[0] = t[1] = t[2] = t[3] = m;
            }
        });
        img.levels.push_back(std::move(dst));
    }
    return img;
}

}  // namespace

struct MaxMip {
    struct Config {
        int max_iterations;
    };
    static MethodInfo describe() {
        MethodInfo m{
            "maxmip",
            "Tevs, Ihrke, Seidel: Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height "
            "Field Rendering, I3D 2008, pp. 183-190, doi:10.1145/1342250.1342279",
            "max-pyramid traversal, exact ray / bilinear-patch hit at the leaf (1 fetch per "
            "iteration)",
            {ParamSpec::integer("max_iterations", 4096, 1, 1e6,
                                "traversal iterations (one fetch each); when reached, the ray "
                                "point where the traversal stood is returned")
                 .to_uniform("p_max_iterations")},
            true,
            200};
        m.resources = {{"r_maxmip", TexelFormat::RGBA32F, TexFilter::Nearest, TexWrap::Repeat,
                        false, build_maxmip,
                        "level 0: each bilinear cell's four corner heights; level k: the max of "
                        "the cells under a 2^k block (all channels)"}};
        return m;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("max_iterations")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) { return c.max_iterations; }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>&,
                             ResourceSamplers<T>& res, Vec2<T> P) {
        return maxmip::traverse<T>(sc, res[0], P, c.max_iterations, nullptr);
    }
};
PXH_REGISTER_METHOD(MaxMip);

}  // namespace pxh
