// The exact tracer's maximum mipmap (construction) and its Tracer interface.
#include "harness/truth/exact_tracer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>

#include "harness/truth/cell_solver.h"
#include "harness/truth/travel_limit.h"

namespace pxh {

namespace {

// The next level of a maximum mipmap: each block the maximum of the (up to) 2 x 2 blocks of
// `prev` (pw x ph) it covers.
HugePageVector<float> coarser_level(const HugePageVector<float>& prev, int pw, int ph, int w,
                                    int h) {
    HugePageVector<float> next(size_t(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            float m = prev[size_t(2 * j) * pw + 2 * i];
            if (2 * i + 1 < pw) m = std::max(m, prev[size_t(2 * j) * pw + 2 * i + 1]);
            if (2 * j + 1 < ph) {
                m = std::max(m, prev[size_t(2 * j + 1) * pw + 2 * i]);
                if (2 * i + 1 < pw) m = std::max(m, prev[size_t(2 * j + 1) * pw + 2 * i + 1]);
            }
            next[size_t(j) * w + i] = m;
        }
    return next;
}

// A w x h row-major level, column-major.
HugePageVector<float> transposed(const HugePageVector<float>& level, int w, int h) {
    HugePageVector<float> t(level.size());
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) t[size_t(i) * h + j] = level[size_t(j) * w + i];
    return t;
}

}  // namespace

ExactTracer::ExactTracer(const HeightField& hf, double scale, double bias)
    : hf_(hf), s_(scale), b_(bias) {
    throw_if_problem(scale_problem(scale));
    const int W = hf.width, H = hf.height;
    // (W + 1) x (H + 1): the first column and row repeated after the last, so a cell's four
    // corners are at offsets 0, 1, W + 1 and W + 2 from its first, wherever the cell lies.
    texels_.resize(texel_stride() * size_t(H + 1));
    for (int j = 0; j <= H; ++j)
        for (int i = 0; i <= W; ++i) texels_[size_t(j) * texel_stride() + i] = hf.wrapped(i, j);
    column_pairs_.resize(2 * hf.texels.size());
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            column_pairs_[2 * (size_t(j) * W + i)] = hf.at(i, j);
            column_pairs_[2 * (size_t(j) * W + i) + 1] = hf.wrapped(i, j + 1);
        }
    build_levels();
}

void ExactTracer::build_levels() {
    const HeightField& hf = hf_;
    const int W = hf.width, H = hf.height;
    HugePageVector<float> cells(hf.texels.size());
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i)
            cells[size_t(j) * W + i] = std::max({hf.wrapped(i, j), hf.wrapped(i + 1, j),
                                                 hf.wrapped(i, j + 1), hf.wrapped(i + 1, j + 1)});
    level_max_.push_back(std::move(cells));
    level_w_.push_back(W);
    level_h_.push_back(H);
    while (level_w_.back() > 1 || level_h_.back() > 1) {
        const int pw = level_w_.back(), ph = level_h_.back();
        const int w = (pw + 1) / 2, h = (ph + 1) / 2;
        level_max_.push_back(coarser_level(level_max_.back(), pw, ph, w, h));
        level_w_.push_back(w);
        level_h_.push_back(h);
    }
    for (size_t l = 0; l < std::min<size_t>(kBandLevels, level_max_.size()); ++l)
        level_max_t_.push_back(transposed(level_max_[l], level_w_[l], level_h_[l]));
    for (const auto& level : level_max_) level_ptr_.push_back(level.data());
    top_level_ = int(level_ptr_.size()) - 1;
    // The square walk's levels (its tables are built on the first per-ray trace: prepare_rays),
    // for any vector path the CPU has (set_path may choose one the environment left out).
    path_ = default_path();
    if (cpu_best_path() != RayPath::scalar)
        while (square_levels_ < kSquareLevels &&
               (2 << square_levels_) <= std::min(hf.width, hf.height))
            ++square_levels_;
    // The vector paths index the texels and the tables in 32-bit integers.
    if (3 * texel_stride() * size_t(H + 1) >= (size_t(1) << 31)) square_levels_ = 0;
}

const char* ExactTracer::path_name(RayPath p) {
    switch (p) {
        case RayPath::avx512:
            return "avx512";
        case RayPath::avx2:
            return "avx2";
        default:
            return "scalar";
    }
}

ExactTracer::RayPath ExactTracer::default_path() {
    const char* env = std::getenv("PXH_TRACER_PATH");
    if (!env || !*env) return cpu_best_path();
    const std::string want = env;
    for (RayPath p : {RayPath::scalar, RayPath::avx2, RayPath::avx512})
        if (want == path_name(p)) return std::min(p, cpu_best_path());
    throw std::invalid_argument("PXH_TRACER_PATH='" + want +
                                "': not a per-ray path (scalar, avx2 or avx512)");
}

void ExactTracer::prepare_rays() const {
    if (simd_path()) std::call_once(squares_built_, [this] { build_squares(); });
}

void ExactTracer::trace(const View& view, Hits& out) const {
    throw_if_problem(view_travel_problem(s_, view));  // every ray, before any work
    throw_if_problem(view_reach_problem(view, hf_.width, hf_.height));
    if (view.orthographic_grid() && !grid_takes_rays(view.V[0]))
        trace_grid(view.grid, view.V[0], out);
    else trace_rays(view, out);
}

bool ExactTracer::grid_takes_rays(Vec3d V) const {
    const double tan_max = std::tan(kGridRaysMaxThetaDeg * M_PI / 180);
    return simd_path() && std::hypot(V.x, V.y) <= tan_max * V.z;
}

std::unique_ptr<Tracer> make_exact_tracer(const HeightField& hf, double scale, double bias) {
    return std::make_unique<ExactTracer>(hf, scale, bias);
}

}  // namespace pxh
