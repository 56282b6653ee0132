#include "harness/run/runner.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "harness/truth/embree_truth.h"
#include "harness/core/error.h"
#include "harness/backends/glsl_backend.h"
#include "methods/shadow.h"

namespace pxh {
namespace {

template <typename T>
MethodOutput run_cpu_typed(BatchFn<T> fn, const ParamValues& params, const Scene<double>& scene,
                           const HeightField& hf, const std::vector<Vec2d>& P, int repeats) {
    const Scene<T> sc = scene_cast<T>(scene);
    const size_t n = P.size();
    std::vector<Vec2<T>> pts(n), uv(n);
    for (size_t k = 0; k < n; ++k) pts[k] = Vec2<T>(P[k]);
    MethodOutput out;
    out.fetches.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
        fn(params, sc, hf, pts.data() + r.begin(), r.size(), uv.data() + r.begin(),
           out.fetches.data() + r.begin());
    });
    out.uv.resize(n);
    for (size_t k = 0; k < n; ++k) out.uv[k] = Vec2d(uv[k]);
    if (repeats > 0 && n > 0) {
        std::vector<Vec2<T>> scratch(n);
        std::vector<int> fscratch(n);
        std::vector<double> times;
        for (int rep = 0; rep <= repeats; ++rep) {  // rep 0 is the warm-up
            const auto t0 = std::chrono::steady_clock::now();
            fn(params, sc, hf, pts.data(), n, scratch.data(), fscratch.data());
            const auto t1 = std::chrono::steady_clock::now();
            if (rep > 0) times.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
        }
        const Spread t = spread(times);
        out.ns_per_sample = t.median / double(n);
        out.ns_per_sample_min = t.min / double(n);
        out.ns_per_sample_max = t.max / double(n);
    }
    return out;
}

std::string fmt_angle(double a) {
    std::ostringstream os;
    os << a;
    return os.str();
}

}  // namespace

Spread spread(std::vector<double> times) {
    Spread s;
    if (times.empty()) return s;
    std::sort(times.begin(), times.end());
    const size_t m = times.size();
    s.median = m % 2 ? times[m / 2] : 0.5 * (times[m / 2 - 1] + times[m / 2]);
    s.min = times.front();
    s.max = times.back();
    return s;
}

MethodOutput run_cpu(const MethodSpec& m, const std::string& precision, const Scene<double>& scene,
                     const HeightField& hf, const std::vector<Vec2d>& P, int repeats) {
    if (precision == "double")
        return run_cpu_typed<double>(m.method->run_double, m.params, scene, hf, P, repeats);
    return run_cpu_typed<float>(m.method->run_float, m.params, scene, hf, P, repeats);
}

template <typename T>
static void add_shadows_typed(MethodOutput& out, const LightSpec& light,
                              const Scene<double>& scene, const HeightField& hf) {
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

void add_shadows(MethodOutput& out, const LightSpec& light, const std::string& precision,
                 const Scene<double>& scene, const HeightField& hf) {
    if (precision == "double") add_shadows_typed<double>(out, light, scene, hf);
    else add_shadows_typed<float>(out, light, scene, hf);
}

ResultRow score(const MethodOutput& out, const GroundTruth& gt, int width, int height,
                const std::vector<uint8_t>* exclude) {
    ResultRow row;
    const size_t n = out.uv.size();
    std::vector<double> mag;
    mag.reserve(n);
    for (size_t k = 0; k < n; ++k) {
        if (exclude && (*exclude)[k]) {
            ++row.excluded;
            continue;
        }
        const Vec2d e = texel_error(out.uv[k], gt.uv[k], width, height);
        mag.push_back(std::hypot(e.x, e.y));
    }
    row.err = error_stats(mag);
    double fsum = 0;
    int fmax = 0;
    for (int f : out.fetches) { fsum += f; fmax = std::max(fmax, f); }
    row.fetches_mean = n ? fsum / double(n) : NAN;
    row.fetches_max = n ? double(fmax) : NAN;
    row.ns_per_sample = out.ns_per_sample;
    row.ns_per_sample_min = out.ns_per_sample_min;
    row.ns_per_sample_max = out.ns_per_sample_max;
    if (!gt.lit.empty() && out.shadow_hard.size() == n && n > 0) {
        double wrong = 0, mae = 0;
        for (size_t k = 0; k < n; ++k) {
            const double truth = gt.lit[k] ? 1.0 : 0.0;
            wrong += (out.shadow_hard[k] != truth);
            mae += std::abs(double(out.shadow_soft[k]) - truth);
        }
        row.shadow_err = wrong / double(n);
        row.shadow_soft_mae = mae / double(n);
    }
    return row;
}

OutputDiff compare_outputs(const MethodOutput& a, const MethodOutput& b, int width, int height) {
    OutputDiff r;
    const size_t n = std::min(a.uv.size(), b.uv.size());
    std::vector<double> d;
    d.reserve(n);
    for (size_t k = 0; k < n; ++k) {
        const Vec2d e = texel_error(a.uv[k], b.uv[k], width, height);
        d.push_back(std::isfinite(e.x) ? std::hypot(e.x, e.y) : INFINITY);
        r.decision_mismatch += a.fetches[k] != b.fetches[k];
    }
    if (d.empty()) return r;
    std::sort(d.begin(), d.end());
    r.max = d.back();
    r.p999 = percentile_sorted(d, 0.999);
    return r;
}

void add_agreement(ResultRow& row, const MethodOutput& glsl, const MethodOutput& cpu,
                   int width, int height) {
    const OutputDiff d = compare_outputs(glsl, cpu, width, height);
    row.cpu_diff_max = d.max;
    row.cpu_diff_p999 = d.p999;
    row.decision_mismatch = double(d.decision_mismatch);
}

namespace {

// Everything one view produces: its rows and, per row, the per-sample error vectors (empty
// for a failed row), in a fixed order (methods x backends x precisions/formats).
struct ViewRows {
    std::vector<ResultRow> rows;
    std::vector<std::vector<Vec2d>> errors;
};

struct ViewContext {
    const Experiment& ex;
    const std::vector<std::string>& backends;
    GlslBackend* gl;
    const std::vector<Vec2d>& P;
    const HeightField& hf;
    const HeightfieldSpec& spec;
    const EmbreeTracer& embree;
    const ExactTracer& exact;
};

std::vector<Vec2d> error_vectors(const MethodOutput& out, const GroundTruth& gt, int w, int h) {
    std::vector<Vec2d> e(out.uv.size());
    for (size_t k = 0; k < e.size(); ++k) e[k] = texel_error(out.uv[k], gt.uv[k], w, h);
    return e;
}

// timed = false (a sweep's companion view, whose rows are not reported): no CPU timing passes,
// no timed GLSL frames, no agreement statistics.
ViewRows evaluate_view(const ViewContext& c, double theta, double phi, bool timed) {
    const Experiment& ex = c.ex;
    const HeightField& hf = c.hf;
    const HeightfieldSpec& spec = c.spec;
    const Scene<double> scene{spec.scale, spec.bias, view_vector(theta, phi), hf.width, hf.height};
    const Vec3d L = ex.light ? view_vector(ex.light->theta_deg, ex.light->phi_deg) : Vec3d{};
    GroundTruth gt = trace_ground_truth(c.exact, scene.V, ex.samples, ex.light ? &L : nullptr);
    // Both references on the same rays; their disagreement goes on every reported row (a
    // sweep's companion view needs Embree only when it is the reference).
    ErrorStats agree;
    if (timed || ex.ground_truth == "embree") {
        std::vector<Vec2d> embree_uv = c.embree.trace(c.P, scene.V);
        std::vector<double> gap(c.P.size());
        for (size_t k = 0; k < c.P.size(); ++k) {
            const Vec2d e = texel_error(embree_uv[k], gt.uv[k], hf.width, hf.height);
            gap[k] = std::hypot(e.x, e.y);
        }
        agree = error_stats(gap);
        if (ex.ground_truth == "embree") gt.uv = std::move(embree_uv);
    }
    // Measured fields: which true hits depend on a filled hole (any of the 4 texels the
    // bilinear surface there interpolates).
    std::vector<uint8_t> on_filled;
    double filled_frac = NAN;
    if (!hf.filled.empty()) {
        on_filled.resize(gt.uv.size());
        size_t count = 0;
        for (size_t k = 0; k < gt.uv.size(); ++k) {
            const double x = gt.uv[k].x * hf.width - 0.5, y = gt.uv[k].y * hf.height - 0.5;
            const int64_t i = int64_t(std::floor(x)), j = int64_t(std::floor(y));
            bool f = false;
            for (int dj = 0; dj < 2; ++dj)
                for (int di = 0; di < 2; ++di)
                    f = f || hf.filled[size_t(wrap_index(j + dj, hf.height)) * hf.width +
                                       size_t(wrap_index(i + di, hf.width))];
            on_filled[k] = f;
            count += f;
        }
        filled_frac = double(count) / double(gt.uv.size());
    }
    const std::vector<uint8_t>* exclude = ex.exclude_filled && !on_filled.empty() ? &on_filled : nullptr;
    auto errors_of = [&](const MethodOutput& out) {
        std::vector<Vec2d> e = error_vectors(out, gt, hf.width, hf.height);
        if (exclude)
            for (size_t k = 0; k < e.size(); ++k)
                if ((*exclude)[k]) e[k] = {NAN, NAN};  // left out of the sweep metrics too
        return e;
    };

    ViewRows view;
    for (const auto& m : ex.methods) {
        auto emit = [&](ResultRow row, std::vector<Vec2d> errs, const std::string& backend,
                        const std::string& precision, const std::string& format) {
            row.method = m.method->name;
            row.params = m.params.canonical();
            row.heightfield = spec.name;
            row.heightfield_id = spec.identity;
            row.backend = backend;
            row.precision = precision;
            row.texture_format = format;
            row.scale = spec.scale;
            row.bias = spec.bias;
            row.theta_deg = theta;
            row.phi_deg = phi;
            row.samples = ex.samples;
            row.width = hf.width;
            row.height = hf.height;
            row.fetches_bound = m.method->max_fetches(m.params, scene);
            row.gt_cells_mean = gt.cells_mean;
            row.ground_truth = ex.ground_truth;
            row.gt_agree_p50 = agree.p50;
            row.gt_agree_p99 = agree.p99;
            row.gt_agree_max = agree.max;
            row.gt_agree_frac_gt_0_5 = agree.frac_gt_0_5;
            row.gt_on_filled = filled_frac;
            view.rows.push_back(std::move(row));
            view.errors.push_back(std::move(errs));
            return view.rows.size() - 1;
        };
        auto failed = [](const std::exception& e) {
            ResultRow row;
            row.status = "failed";
            row.error = e.what();
            return row;
        };
        std::optional<MethodOutput> cpu_float, cpu_double;
        std::optional<size_t> float_row;
        for (const auto& backend : c.backends) {
            if (backend == "cpu") {
                for (const auto& precision : ex.precisions) {
                    try {
                        MethodOutput out =
                            run_cpu(m, precision, scene, hf, c.P, timed ? ex.timing_repeats : 0);
                        if (ex.light) add_shadows(out, *ex.light, precision, scene, hf);
                        const size_t i = emit(score(out, gt, hf.width, hf.height, exclude),
                                              errors_of(out), backend, precision, "");
                        if (precision == "float") {
                            float_row = i;
                            cpu_float = std::move(out);
                        } else {
                            cpu_double = std::move(out);
                        }
                    } catch (const std::exception& e) {
                        emit(failed(e), {}, backend, precision, "");
                    }
                }
                if (float_row && cpu_double) {  // what float precision itself costs
                    const OutputDiff d = compare_outputs(*cpu_float, *cpu_double, hf.width, hf.height);
                    view.rows[*float_row].double_diff_max = d.max;
                    view.rows[*float_row].double_diff_p999 = d.p999;
                }
                continue;
            }
            for (const auto& format : ex.texture_formats) {
                try {
                    const MethodOutput out =
                        c.gl->run(m, scene, hf, ex.samples, format,
                                  ex.light ? &*ex.light : nullptr, timed ? -1 : 0);
                    ResultRow row = score(out, gt, hf.width, hf.height, exclude);
                    row.ms_per_frame = out.ms_per_frame;
                    row.ms_per_frame_min = out.ms_per_frame_min;
                    row.ms_per_frame_max = out.ms_per_frame_max;
                    row.shader = out.shader;
                    if (!cpu_float) cpu_float = run_cpu(m, "float", scene, hf, c.P, 0);
                    add_agreement(row, out, *cpu_float, hf.width, hf.height);
                    emit(std::move(row), errors_of(out), backend, "float", format);
                } catch (const std::exception& e) {
                    ResultRow row = failed(e);
                    row.shader = c.gl->shader_description(*m.method);
                    emit(std::move(row), {}, backend, "float", format);
                }
            }
        }
    }
    return view;
}

void set_sweep(ResultRow& row, const std::vector<Vec2d>& lo, const std::vector<Vec2d>& hi,
               double dt) {
    if (lo.empty() || hi.empty()) return;
    const SweepMetrics sm = sweep_metrics(lo, hi, dt, row.width, row.height);
    row.sliding = sm.sliding;
    row.shimmering = sm.shimmering;
    row.sweep_dt_deg = dt;
}

}  // namespace

std::vector<ResultRow> run_experiment(const Experiment& ex, const RunOptions& opt,
                                      RunInfo* info) {
    const auto& backends = opt.backends.empty() ? ex.backends : opt.backends;
    for (const auto& b : backends)
        if (b != "cpu" && b != "glsl")
            throw InputError("--backend", "unknown backend '" + b + "' (known: cpu, glsl)");
    std::unique_ptr<GlslBackend> gl;
    if (std::find(backends.begin(), backends.end(), "glsl") != backends.end()) {
        gl = std::make_unique<GlslBackend>(GlslOptions{opt.shader_dir, opt.gl_frames});
        if (info) {
            info->gl_renderer = gl->renderer();
            info->gl_version = gl->version();
        }
    }
    // Height fields are built one at a time (a sweep of thousands of fields, or of scales on
    // a large one, holds one field in memory); entries that share a field (a scale/bias sweep)
    // reuse it. Image files and scans are loaded once up front and dropped, so that a bad file
    // fails before any work.
    {
        std::set<std::string> checked;
        for (const auto& spec : ex.heightfields)
            if (spec.generator.empty() && checked.insert(spec.file + "|" + spec.scan).second)
                (void)make_heightfield(spec);
    }
    auto same_field = [](const HeightfieldSpec& a, const HeightfieldSpec& b) {
        return a.generator == b.generator && a.file == b.file && a.scan == b.scan &&
               a.width == b.width && a.height == b.height && a.channel == b.channel &&
               a.gen_params.canonical() == b.gen_params.canonical() && a.name == b.name;
    };

    const auto P = sample_grid(ex.samples);
    std::vector<ResultRow> rows;
    const size_t steps = ex.heightfields.size() * ex.theta_deg.size() * ex.phi_deg.size();
    size_t step = 0;
    std::optional<HeightField> field;
    for (size_t h = 0; h < ex.heightfields.size(); ++h) {
        const HeightfieldSpec& spec = ex.heightfields[h];
        if (!field || !same_field(spec, ex.heightfields[h - 1])) {
            field.reset();  // free the previous one first
            field = make_heightfield(spec);
        }
        const HeightField& hf = *field;
        // Both references built once per field (and s, b), shared by all its views.
        const EmbreeTracer embree(hf, spec.scale, spec.bias);
        const ExactTracer exact(hf, spec.scale, spec.bias);
        const ViewContext ctx{ex, backends, gl.get(), P, hf, spec, embree, exact};
        for (double phi : ex.phi_deg) {
            ViewRows prev;  // the previous view of this sweep (same field and phi)
            std::vector<size_t> prev_index;
            for (size_t t = 0; t < ex.theta_deg.size(); ++t) {
                const double theta = ex.theta_deg[t];
                ++step;
                if (opt.progress) {
                    std::ostringstream os;
                    os << "[" << step << "/" << steps << "] " << spec.name << " s="
                       << spec.scale << " b=" << spec.bias << " theta=" << fmt_angle(theta)
                       << " phi=" << fmt_angle(phi);
                    opt.progress(os.str());
                }
                ViewRows view = evaluate_view(ctx, theta, phi, true);
                if (ex.sweep_dt_deg > 0) {
                    // A companion view dt away (below when theta + dt would reach 90).
                    const bool up = theta + ex.sweep_dt_deg < 90;
                    const double other = up ? theta + ex.sweep_dt_deg : theta - ex.sweep_dt_deg;
                    const ViewRows comp = evaluate_view(ctx, other, phi, false);
                    for (size_t i = 0; i < view.rows.size(); ++i)
                        set_sweep(view.rows[i], up ? view.errors[i] : comp.errors[i],
                                  up ? comp.errors[i] : view.errors[i], ex.sweep_dt_deg);
                } else if (t > 0) {
                    // Consecutive views: the pair (theta_{k-1}, theta_k) goes on row k-1.
                    const double dt = theta - ex.theta_deg[t - 1];
                    for (size_t i = 0; i < view.rows.size() && i < prev_index.size(); ++i)
                        if (dt > 0)
                            set_sweep(rows[prev_index[i]], prev.errors[i], view.errors[i], dt);
                }
                if (opt.on_view) opt.on_view(view.rows, view.errors, rows.size());
                prev_index.clear();
                for (auto& r : view.rows) {
                    prev_index.push_back(rows.size());
                    rows.push_back(std::move(r));
                }
                prev = std::move(view);
            }
        }
    }
    if (info && gl) info->shaders = gl->compiled_sources();
    return rows;
}

}  // namespace pxh
