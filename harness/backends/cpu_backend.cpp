#include "harness/backends/cpu_backend.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>

#include "harness/backends/written_depth.h"
#include "harness/core/error.h"
#include "harness/core/param_dict.h"
#include "harness/truth/ground_truth.h"
#include "methods/shadow.h"

namespace pxh {
namespace {

template <typename T>
MethodOutput run_cpu_typed(BatchFn<T> fn, const ParamValues& params, const Scene<double>& scene,
                           const HeightField& hf, const std::vector<Vec2d>& P, int repeats,
                           const MethodResources* resources, const std::vector<Vec3d>* V,
                           const TextureLevels* levels, const std::vector<double>* lambda,
                           DepthMode depth) {
    const MethodInputs in{&hf, resources, levels, lambda ? lambda->data() : nullptr};
    // A sub-batch's inputs: lambda from its first sample on.
    const auto at = [&in](size_t first) {
        MethodInputs sub = in;
        if (sub.lambda) sub.lambda += first;
        return sub;
    };
    const Scene<T> sc = scene_cast<T>(scene);
    const size_t n = P.size();
    std::vector<Vec2<T>> pts(n), uv(n);
    // z_m only where a depth mode reads it, the engine's height only for `engine` (single-step
    // methods would sample the surface once more per sample for nothing)
    std::vector<T> z(depth != DepthMode::base ? n : 0), ze(depth == DepthMode::engine ? n : 0);
    for (size_t k = 0; k < n; ++k) pts[k] = Vec2<T>(P[k]);
    std::vector<Vec3<T>> dirs(V ? n : 0);  // per-sample directions, in the method's precision
    for (size_t k = 0; k < dirs.size(); ++k) dirs[k] = Vec3<T>((*V)[k]);
    const Vec3<T>* D = V ? dirs.data() : nullptr;
    MethodOutput out;
    out.fetches.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
        fn(params, sc, at(r.begin()), pts.data() + r.begin(), D ? D + r.begin() : nullptr, r.size(),
           uv.data() + r.begin(), out.fetches.data() + r.begin(), nullptr,
           z.empty() ? nullptr : z.data() + r.begin(),
           ze.empty() ? nullptr : ze.data() + r.begin());
    });
    out.uv.resize(n);
    for (size_t k = 0; k < n; ++k) out.uv[k] = Vec2d(uv[k]);
    out.hit_z.assign(z.begin(), z.end());
    out.engine_z.assign(ze.begin(), ze.end());
    if (repeats > 0 && n > 0) {
        std::vector<Vec2<T>> scratch(n);
        std::vector<int> fscratch(n);
        std::vector<double> times;
        for (int rep = 0; rep <= repeats; ++rep) {  // rep 0 is the warm-up
            const auto t0 = std::chrono::steady_clock::now();
            fn(params, sc, in, pts.data(), D, n, scratch.data(), fscratch.data(), nullptr, nullptr,
               nullptr);
            const auto t1 = std::chrono::steady_clock::now();
            if (rep > 0) times.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
        }
        for (double& t : times) t /= double(n);
        out.timing = timing_of(cpu_timing().unit, std::move(times));
    }
    return out;
}

template <typename T>
void add_shadows_typed(MethodOutput& out, const LightSpec& light, const Scene<double>& scene,
                       const HeightField& hf) {
    const Scene<T> sc = scene_cast<T>(scene);
    const Vec3<T> L(view_vector(light.theta_deg, light.phi_deg));
    const ShadowConfig cfg{light.layers_min, light.layers_max};
    const size_t n = out.uv.size();
    out.shadow_hard.resize(n);
    out.shadow_soft.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            HeightSampler<T> hs(hf, sc.scale, sc.bias);
            const auto f = shadow_factors(cfg, sc, L, hs, Vec2<T>(out.uv[k]));
            out.shadow_hard[k] = float(f.hard);
            out.shadow_soft[k] = float(f.soft);
        }
    });
}

}  // namespace

MethodOutput run_cpu(const MethodSpec& m, const std::string& precision, const Scene<double>& scene,
                     const HeightField& hf, const std::vector<Vec2d>& P, int repeats,
                     const MethodResources* resources, const std::vector<Vec3d>* V,
                     const TextureLevels* levels, const std::vector<double>* lambda) {
    if (V && V->size() != P.size())
        throw std::logic_error("run_cpu: " + std::to_string(V->size()) + " directions for " +
                               std::to_string(P.size()) + " samples");
    if (levels && !lambda)
        throw std::logic_error("run_cpu: texture levels without the samples' lambda");
    if (lambda && lambda->size() != P.size())
        throw std::logic_error("run_cpu: " + std::to_string(lambda->size()) + " lambdas for " +
                               std::to_string(P.size()) + " samples");
    if (precision == "double")
        return run_cpu_typed<double>(m.method->run_double, m.params, scene, hf, P, repeats,
                                     resources, V, levels, lambda, m.depth);
    return run_cpu_typed<float>(m.method->run_float, m.params, scene, hf, P, repeats, resources, V,
                                levels, lambda, m.depth);
}

void add_shadows(MethodOutput& out, const LightSpec& light, const std::string& precision,
                 const Scene<double>& scene, const HeightField& hf) {
    if (precision == "double") add_shadows_typed<double>(out, light, scene, hf);
    else add_shadows_typed<float>(out, light, scene, hf);
}

// The experiment's top-level precision (float | double, a value or a list) and
// timing_repeats (timed passes, the median reported; 0: untimed).
void read_cpu_settings(const ParamDict& ex, BackendSettings& s) {
    s.timing_repeats = ex.integer("timing_repeats", s.timing_repeats, 0, 1000);
    s.precisions = ex.strings("precision", s.precisions);
    for (const auto& p : s.precisions)
        if (p != "float" && p != "double")
            throw InputError(ex.where("precision"),
                             "unknown precision '" + p + "' (known: float, double)");
}

const TimingSpec& cpu_timing() {
    static const TimingSpec t{
        "ns/sample",
        "single-thread wall time (steady_clock) of one pass over every sample, divided by the "
        "samples, after one untimed warm-up pass",
        {}};
    return t;
}

int cpu_repeats(const BackendSettings& s) { return s.timing_repeats; }

std::vector<Variant> cpu_variants(const BackendSettings& settings) {
    std::vector<Variant> out;
    for (const auto& p : settings.precisions) out.push_back({p, ""});
    return out;
}

std::vector<Variant> CpuBackend::variants() const { return cpu_variants(settings_); }

MethodOutput CpuBackend::run(const MethodSpec& m, const ViewInput& view, const Variant& v) {
    const View& rays = view.rays;
    const bool levels = m.lod == LodMode::level;
    if (levels && (!view.levels || !view.lambda))
        throw std::logic_error("lod = level without the view's texture levels");
    MethodOutput out =
        run_cpu(m, v.precision, view.scene, view.hf, rays.P,
                view.timed ? settings_.timing_repeats : 0, view.resources,
                rays.parallel ? nullptr : &rays.V, levels ? view.levels : nullptr, view.lambda);
    if (view.light) add_shadows(out, *view.light, v.precision, view.scene, view.hf);
    add_written_depths(m, view, out, v.precision == "float");
    // A silhouette method's NaN answer is its discard (the GLSL twin's `discard`): counted as
    // the GL side counts it, its fetches not (a discarded fragment writes none back).
    if (m.method->may_discard) {
        out.discarded.assign(out.uv.size(), 0);
        for (size_t k = 0; k < out.uv.size(); ++k) {
            if (std::isfinite(out.uv[k].x) && std::isfinite(out.uv[k].y)) continue;
            if (!rays.is_inside(k)) continue;
            out.discarded[k] = 1;
            out.fetches[k] = 0;
            ++out.samples_discarded;
        }
    }
    return out;
}

std::unique_ptr<Backend> make_cpu_backend(const BackendSettings& settings);

// Its registry entry (harness/backends/registry.cpp's PXH_BACKENDS).
std::string cpu_skips(const MethodSpec& m) {
    // A plug-in shader has no C++ twin: that it has GLSL rows only is what a plug-in is (and
    // said where it is declared), not a setting skipped.
    if (!m.method->run_float || !m.method->run_double) return "";
    if (lod_glsl_only(m.lod))
        return std::string("lod '") + lod_name(m.lod) +
               "' samples through the GPU's own level selection: glsl only";
    return "";
}

const BackendEntry& cpu_backend_entry() {
    static const BackendEntry e = [] {
        BackendEntry b{"cpu",       &read_cpu_settings, &make_cpu_backend, &cpu_variants,
                       &cpu_timing, &cpu_repeats,       &cpu_skips};
        b.reference = true;  // the C++ reference: other backends' rows agree_* with its float rows
        return b;
    }();
    return e;
}

std::unique_ptr<Backend> make_cpu_backend(const BackendSettings& settings) {
    return std::make_unique<CpuBackend>(settings);
}

}  // namespace pxh
