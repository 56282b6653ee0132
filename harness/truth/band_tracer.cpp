// Every ray of an orthographic view on the sample grid at once: the band tracer (trace_grid).
#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "harness/truth/band_tracer.h"

namespace pxh {

namespace {

// Traces the rays of one band, given in order of p0 (ties in order of k), kAhead rays ahead:
// a ray's first candidate is found (and its texels requested) kAhead rays before it walks, so
// that the memory system answers while the rays before it walk. Each ray is started in place,
// in a ring of kAhead + 1 (copying a start cost 3-8%; 2 and 4 rays ahead measured alike).
class BandRun {
  public:
    using Start = ViewTracer::Start;
    static constexpr int kAhead = 1, kSlots = kAhead + 1;
    BandRun(const ViewTracer& vt, ViewTracer::Band& band, Hits& out)
        : vt_(vt), band_(band), out_(out) {}
    void begin(double eta_lo, double w) {
        band_.eta_lo = eta_lo;
        band_.w = w;
        band_.chunks = 0;
        band_.used = 0;
        held_ = 0;
        head_ = 0;
    }
    void add(Vec2d P, size_t k) {
        if (held_ == 0) {
            // Run 0 starts at the earliest first column (the first ray's), in whole runs.
            band_.base = vt_.scan(vt_.ray(P)).c_first & ~((int64_t(1) << vt_.level()) - 1);
            lb_ = band_.base;
        }
        // Started in place (the slot after the held ones), then the oldest walks.
        const int at = (head_ + held_) % kSlots;
        vt_.start(band_, P, lb_, cur_[at]);
        vt_.prefetch(band_, cur_[at]);
        k_[at] = k;
        if (held_ == kAhead) {
            out_.set(k_[head_], vt_.trace(band_, cur_[head_]));
            head_ = (head_ + 1) % kSlots;
        } else {
            ++held_;
        }
    }
    void end() {
        for (; held_ > 0; --held_, head_ = (head_ + 1) % kSlots)
            out_.set(k_[head_], vt_.trace(band_, cur_[head_]));
        head_ = 0;
    }

  private:
    const ViewTracer& vt_;
    ViewTracer::Band& band_;
    Hits& out_;
    int held_ = 0, head_ = 0;  // rays started and not walked yet: cur_[head_], ... (a ring)
    Start cur_[kSlots]{};
    size_t k_[kSlots]{};
    int64_t lb_ = 0;
};

// The same with the vector walks (band_walk::walk_avx2, walk_avx512): the band's rays are all
// started first, in the same order (the same first candidates), then walked lanes at a time.
class VectorBandRun {
  public:
    using Walk = void (*)(const ViewTracer&, ViewTracer::Band&, const ViewTracer::Start*,
                          const size_t*, size_t, Hits&);
    // The starts and places live in each thread's own buffers, kept from band to band (fresh
    // ones per band cost page faults: bands are tasks of their own).
    VectorBandRun(const ViewTracer& vt, ViewTracer::Band& band, Hits& out, Walk walk)
        : vt_(vt), band_(band), out_(out), walk_(walk), st_(buffers().st), k_(buffers().k) {}
    void begin(double eta_lo, double w) {
        band_.eta_lo = eta_lo;
        band_.w = w;
        band_.chunks = 0;
        band_.used = 0;
        n_ = 0;
    }
    void add(Vec2d P, size_t k) {
        if (n_ == 0) {
            band_.base = vt_.scan(vt_.ray(P)).c_first & ~((int64_t(1) << vt_.level()) - 1);
            lb_ = band_.base;
        }
        if (n_ == st_.size()) {
            st_.resize(2 * n_ + 64);
            k_.resize(2 * n_ + 64);
        }
        vt_.start(band_, P, lb_, st_[n_]);
        vt_.prefetch(band_, st_[n_]);
        k_[n_++] = k;
    }
    void end() {
        walk_(vt_, band_, st_.data(), k_.data(), n_, out_);
        n_ = 0;
    }

  private:
    const ViewTracer& vt_;
    ViewTracer::Band& band_;
    Hits& out_;
    Walk walk_;
    struct Buffers {
        std::vector<ViewTracer::Start> st;
        std::vector<size_t> k;
    };
    static Buffers& buffers() {
        thread_local Buffers b;
        return b;
    }
    std::vector<ViewTracer::Start>& st_;
    std::vector<size_t>& k_;
    size_t n_ = 0;
    int64_t lb_ = 0;
};

// Band width in grid units: about the rays' spacing (the side of the grid area per ray), so
// that a band holds a row of rays; narrower bands bound more tightly but cost a bound per run.
double band_width(double area, size_t rays) {
    return std::clamp(std::round(std::sqrt(area / double(std::max<size_t>(rays, 1)))), 1.0, 8.0);
}

// The mipmap level the bounds come from: blocks about half the band's width (level 0, the
// cells themselves, for bands one cell wide), small arrays that stay in cache.
int band_level(double w) { return std::max(0, int(std::lround(std::log2(w / 2)))); }

// Sample (i, j) of the N x N grid, as sample_grid places it.
Vec2d grid_sample(int n, int64_t i, int64_t j) {
    return {(double(i) + 0.5) / n, (double(j) + 0.5) / n};
}

// The grid's rays in bands, each traced in order of p0 (its start along the major axis),
// enumerated without sorting: a sample's p0 depends only on its major index a, its lateral
// offset eta = q0 - m p0 only grows with its minor index b, so band by band, for each a in
// order of p0, the band's samples are a run of b, followed from one a to the next.
class BandLayout {
  public:
    // Chooses the band width and the mipmap level vt's bounds come from.
    BandLayout(ViewTracer& vt, int n, const HeightField& hf) : vt_(vt), n_(n) {
        const bool mx = vt.major_x();
        maj_.resize(size_t(n));  // X0 or Y0 by index
        mnr_.resize(size_t(n));
        for (int64_t t = 0; t < n; ++t) {
            const auto r = vt.ray(grid_sample(n, t, t));
            maj_[size_t(t)] = mx ? r.X0 : r.Y0;
            mnr_[size_t(t)] = mx ? r.Y0 : r.X0;
        }
        // eta is monotone in a and in b: its extremes lie at the corners.
        eta_lo_ = std::numeric_limits<double>::infinity();
        double eta_hi = -eta_lo_;
        for (int64_t a : {int64_t(0), int64_t(n - 1)})
            for (int64_t b : {int64_t(0), int64_t(n - 1)})
                eta_lo_ = std::min(eta_lo_, eta(a, b)), eta_hi = std::max(eta_hi, eta(a, b));
        const double spacing = double(n - 1) / n;  // the samples' extent, in tiles
        const double area = std::max(1.0, spacing * hf.width) * std::max(1.0, spacing * hf.height);
        w_ = band_width(area, size_t(n) * size_t(n));
        vt.use_level(band_level(w_));
        inv_w_ = 1 / w_;
        bands_ = int64_t(std::floor((eta_hi - eta_lo_) * inv_w_)) + 1;
    }
    int64_t bands() const { return bands_; }

    // Traces band bd's rays into `run`.
    template <class Run>
    void trace_band(int64_t bd, Run& run) const {
        const int64_t n = n_;
        run.begin(eta_lo_ + double(bd) * w_, w_);
        int64_t b0 = -1;  // the band's first b at the current a
        for (int64_t step = 0; step < n; ++step) {
            const int64_t a = vt_.sign() > 0 ? step : n - 1 - step;  // p0 grows
            if (b0 < 0) {  // first a: search (band grows with b)
                int64_t lo = 0, hi = n;
                while (lo < hi) {
                    const int64_t mid = (lo + hi) / 2;
                    if (band(a, mid) < bd) lo = mid + 1;
                    else hi = mid;
                }
                b0 = lo;
            } else {
                while (b0 < n && band(a, b0) < bd) ++b0;
                while (b0 > 0 && band(a, b0 - 1) >= bd) --b0;
            }
            for (int64_t b = b0; b < n && band(a, b) == bd; ++b) {
                const int64_t i = vt_.major_x() ? a : b, j = vt_.major_x() ? b : a;
                run.add(grid_sample(n_, i, j), size_t(j) * size_t(n) + size_t(i));
            }
        }
        run.end();
    }

  private:
    double eta(int64_t a, int64_t b) const {
        return mnr_[size_t(b)] - vt_.slope() * (vt_.sign() * maj_[size_t(a)]);
    }
    int64_t band(int64_t a, int64_t b) const {
        return std::min(bands_ - 1, int64_t((eta(a, b) - eta_lo_) * inv_w_));
    }

    const ViewTracer& vt_;
    int n_;
    std::vector<double> maj_, mnr_;
    double eta_lo_ = 0, w_ = 1, inv_w_ = 1;
    int64_t bands_ = 0;
};

}  // namespace

void ExactTracer::trace_grid(int n, Vec3d V, Hits& out) const {
    throw_if_problem(ray_travel_problem(s_, V));  // before any band's bounds grow with the travel
    out.resize_all(size_t(n) * size_t(std::max(n, 0)));
    if (n <= 0) return;
    ViewTracer vt(*this, grid_sample(n, 0, 0), V);
    if (!vt.useful()) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, out.uv.size(), 256), [&](const auto& rg) {
            for (size_t k = rg.begin(); k < rg.end(); ++k)
                out.set(k, trace_naive(grid_sample(n, int64_t(k % n), int64_t(k / n)), V));
        });
        return;
    }
    const BandLayout layout(vt, n, hf_);
    const RayPath path = band_path();
    const VectorBandRun::Walk lanes = path == RayPath::avx512 ? band_walk::walk_avx512
                                     : path == RayPath::avx2 ? band_walk::walk_avx2
                                                             : nullptr;
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, layout.bands(), 1), [&](const auto& rg) {
        ViewTracer::Band mem;
        if (lanes) {
            VectorBandRun run(vt, mem, out, lanes);
            for (int64_t bd = rg.begin(); bd < rg.end(); ++bd) layout.trace_band(bd, run);
            return;
        }
        BandRun run(vt, mem, out);
        for (int64_t bd = rg.begin(); bd < rg.end(); ++bd) layout.trace_band(bd, run);
    });
}

void ExactTracer::trace_grid(int n, Vec3d V, std::vector<TruthHit>& out) const {
    Hits hits;
    trace_grid(n, V, hits);
    out.resize(hits.uv.size());
    for (size_t k = 0; k < out.size(); ++k) out[k] = {hits.uv[k], hits.z[k], hits.cells[k]};
}

}  // namespace pxh
