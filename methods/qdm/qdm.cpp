// Drobot: "Quadtree Displacement Mapping with Height Blending", GPU Pro (ed. W. Engel), A K
// Peters 2010, pp. 117-148. The chapter itself could not be read here; the algorithm is taken
// from the GLSL transcription of its listing in FlightGear's terrain shaders, function QDM()
// ("Adapted from the paper and sources by M. Drobot in GPU Pro", Frederic Bouvier, GPL v2):
// repository FGDATA/fgdata, Shaders/urban.frag, commit 0508a7a0b3b328aeddf1f11d0cdeb0cac19b5e7e
// (read for the algorithm and its constants only; the code here is written anew). A min-depth
// (= max-height) quadtree traversed top-down from the coarsest level: a node whose top lies below
// the ray moves the ray down to it, or to the node's border plus a small nudge if the ray leaves
// the node first (and then stays at that level); otherwise descend. At level 0 the source refines
// with its "manual bilinear filtering": two bilinear height fetches one texel before and after
// along the ray, the result interpolated by their distances to the surface.
#include "methods/qdm/qdm.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "methods/method.h"

namespace pxh {

namespace {

// The max over texels i in [floor(k n / m), ceil((k + 1) n / m)) of `row` (n values), for each
// of the m nodes k: every texel whose nearest-filter footprint meets node k's uv span.
void max_over_spans(const float* row, int n, size_t stride, int m, float* out, size_t out_stride) {
    for (int k = 0; k < m; ++k) {
        const int lo = int((int64_t(k) * n) / m);
        const int hi = int((int64_t(k + 1) * n + m - 1) / m);
        float v = row[size_t(lo) * stride];
        for (int i = lo + 1; i < hi; ++i) v = std::max(v, row[size_t(i) * stride]);
        out[size_t(k) * out_stride] = v;
    }
}

// Level 0: the heights; level L (max(1, W >> L) x max(1, H >> L)): the max over the texels whose
// footprint meets the node's uv span. For power-of-two sizes this is the 2^L x 2^L block max
// (the source's pyramid); for other sizes a node takes every texel it overlaps, so the pyramid
// stays conservative for node ids floor(uv * nodes).
ResourceImage build_qdm(const HeightField& hf, double, double) {
    const int W = hf.width, H = hf.height;
    ResourceImage img;
    img.levels.push_back({W, H, hf.texels});
    for (int L = 1; W >> (L - 1) > 1 || H >> (L - 1) > 1; ++L) {
        const int w = std::max(1, W >> L), h = std::max(1, H >> L);
        std::vector<float> rows(size_t(w) * size_t(H));
        tbb::parallel_for(0, H, [&](int j) {
            max_over_spans(hf.texels.data() + size_t(j) * size_t(W), W, 1, w,
                           rows.data() + size_t(j) * size_t(w), 1);
        });
        ResourceLevel lv{w, h, std::vector<float>(size_t(w) * size_t(h))};
        tbb::parallel_for(0, w, [&](int i) {
            max_over_spans(rows.data() + size_t(i), H, size_t(w), h, lv.texels.data() + size_t(i),
                           size_t(w));
        });
        img.levels.push_back(std::move(lv));
    }
    return img;
}

}  // namespace

struct Qdm {
    struct Config {
        int max_iterations;
        bool refine;
    };
    static MethodInfo describe() {
        MethodInfo m{
            "qdm",
            "Drobot: Quadtree Displacement Mapping with Height Blending, GPU Pro, A K Peters 2010, "
            "pp. 117-148 (via FlightGear fgdata Shaders/urban.frag QDM(), commit 0508a7a)",
            "top-down max-height quadtree traversal + the source's two-fetch refinement "
            "(iterations + 2 fetches)",
            {ParamSpec::integer("max_iterations", 64, 1, 1e6,
                                "traversal iterations (one pyramid fetch each); 64 as the "
                                "FlightGear transcription's gIterationCap")
                 .to_uniform("p_max_iterations"),
             ParamSpec::boolean("refine", true,
                                "the source's refinement at level 0 (two bilinear height fetches "
                                "one texel before and after); false: the box hit")
                 .to_uniform("p_refine")},
            true,
            210};
        m.resources = {{"r_qdm", TexelFormat::R32F, TexFilter::Nearest, TexWrap::Repeat, false,
                        build_qdm,
                        "max-height (min-depth) quadtree: level 0 the heights, level L the max "
                        "over each node's texels"}};
        return m;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("max_iterations"), p.get_bool("refine")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) {
        return c.max_iterations + (c.refine ? 2 : 0);
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs,
                             ResourceSamplers<T>& res, Vec2<T> P) {
        return qdm::trace<T>(sc, hs, res[0], P, c.max_iterations, c.refine, nullptr);
    }
};
PXH_REGISTER_METHOD(Qdm);

}  // namespace pxh
