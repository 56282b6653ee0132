#include "harness/run/runner.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "harness/backends/gl_worker.h"
#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/agreement.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/reference.h"
#include "harness/metrics/sweep.h"
#include "harness/scene/perspective_camera.h"
#include "harness/scene/texture_levels.h"

namespace pxh {
namespace {

std::string fmt_angle(double a) {
    std::ostringstream os;
    os << a;
    return os.str();
}

}  // namespace

ResultRow score(const MethodOutput& out, const GroundTruth& gt, int width, int height,
                const std::vector<uint8_t>* exclude, const View* view) {
    ResultRow row;
    apply_output_metrics({out, gt, width, height, exclude, view}, row);
    row.set_text("shader", out.shader);
    row.set_text("shader_sha256", out.shader_sha256);
    return row;
}

namespace {

// Everything one view produces: its rows and, per row, the per-sample error vectors (empty
// for a failed row), in a fixed order (methods x backends x variants).
struct ViewRows {
    std::vector<ResultRow> rows;
    std::vector<std::vector<Vec2d>> errors;
    std::vector<Vec2d> truth_uv;  // the view's true hits (per sample, unwrapped)
    std::vector<uint8_t> inside;  // the view's inside mask (View::inside)
};

// One field (with its s, b) and what every view of it shares.
struct FieldContext {
    const Experiment& ex;
    const std::vector<std::unique_ptr<Backend>>& backends;
    CpuBackend& reference;  // the CPU float run other backends are compared with
    const HeightField& hf;
    const HeightfieldSpec& spec;
    const Tracer& exact;          // the reference: heights, true shadows, cost (gt_cells_mean)
    const Tracer& other;          // the second reference, compared with it (gt_agree_*)
    ResourceCache& resources;     // the methods' precomputed textures for this field
    const TextureLevels* levels;  // the field's texture levels when a setting samples them
};

// The references of one field (and s, b), built once and shared by its views.
struct References {
    std::unique_ptr<Tracer> exact, other;
};

References make_references(const HeightField& hf, const HeightfieldSpec& spec) {
    References r;
    r.other = make_tracer("embree", hf, spec.scale, spec.bias);
    r.exact = make_tracer("exact", hf, spec.scale, spec.bias);
    return r;
}

// What the truth stage gives a view: its ground truth and the two references' disagreement.
struct ViewTruth {
    GroundTruth gt;
    ErrorStats agree;  // |hit_other - hit_exact| in texels (NaN when the other did not run)
};

// The truth stage: a view's rays -> their ground truth (uv from the experiment's reference,
// heights, true shadows and cost from the exact tracer) and the references' agreement on the
// same rays. A sweep's companion view (timed = false) traces the other reference only when it
// is the ground truth.
ViewTruth truth_stage(const FieldContext& c, const View& view, bool timed) {
    const Experiment& ex = c.ex;
    const Vec3d L = ex.light ? view_vector(ex.light->theta_deg, ex.light->phi_deg) : Vec3d{};
    ViewTruth t;
    t.gt = trace_ground_truth(c.exact, view, ex.light ? &L : nullptr);
    t.agree.p50 = t.agree.p99 = t.agree.max = t.agree.frac_gt_0_5 = NAN;
    const bool other_is_truth = ex.ground_truth == c.other.name();
    if (timed || other_is_truth) {
        Hits other;
        c.other.trace(view, other);
        t.agree = reference_agreement(other.uv, t.gt.uv, c.hf.width, c.hf.height);
        if (other_is_truth) t.gt.uv = std::move(other.uv);
    }
    return t;
}

// Measured fields: which true hits depend on a filled hole (any of the 4 texels the bilinear
// surface there interpolates).
struct HoleMask {
    std::vector<uint8_t> on_filled;  // empty for fields without holes
    double frac = NAN;
};

HoleMask hole_mask(const HeightField& hf, const GroundTruth& gt) {
    HoleMask m;
    if (hf.filled.empty()) return m;
    m.on_filled.resize(gt.uv.size());
    size_t count = 0;
    for (size_t k = 0; k < gt.uv.size(); ++k) {
        const double x = gt.uv[k].x * hf.width - 0.5, y = gt.uv[k].y * hf.height - 0.5;
        const int64_t i = int64_t(std::floor(x)), j = int64_t(std::floor(y));
        bool f = false;
        for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di)
                f = f || hf.filled[size_t(wrap_index(j + dj, hf.height)) * hf.width +
                                   size_t(wrap_index(i + di, hf.width))];
        m.on_filled[k] = f;
        count += f;
    }
    m.frac = double(count) / double(gt.uv.size());
    return m;
}

// One view being evaluated: its scene, truth, holes, and the rows it has produced so far.
struct ViewJob {
    const FieldContext& c;
    double theta, phi;
    size_t camera;  // index into the experiment's camera settings
    bool timed;
    const View& view;  // the samples' rays, from the experiment's camera
    Scene<double> scene;
    ViewTruth truth;
    HoleMask holes;
    const std::vector<uint8_t>* exclude = nullptr;  // samples left out of the errors
    ViewRows out;
    std::vector<double> lambda;  // each sample's level of detail (its footprint's)
    double lod_mean = NAN;       // mean max(lambda, 0) over the inside samples

    ViewInput input() const {
        ViewInput in{scene, c.hf, view, c.ex.light ? &*c.ex.light : nullptr, timed};
        in.levels = c.levels;
        in.lambda = &lambda;
        return in;
    }

    // Per-sample error vectors; excluded and outside samples are NaN (left out of the sweep
    // metrics too).
    std::vector<Vec2d> errors_of(const MethodOutput& o) const {
        std::vector<Vec2d> e(o.uv.size());
        for (size_t k = 0; k < e.size(); ++k)
            e[k] = (exclude && (*exclude)[k]) || !view.is_inside(k)
                       ? Vec2d{NAN, NAN}
                       : texel_error(o.uv[k], truth.gt.uv[k], c.hf.width, c.hf.height);
        return e;
    }

    // The method's declared bound per sample, over every ray's direction.
    int fetches_bound(const MethodSpec& m) const {
        if (!m.method->max_fetches) return m.method->declared_max_fetches;  // a plug-in's
        if (view.parallel) return m.method->max_fetches(m.params, scene);
        int bound = 0;
        Scene<double> s = scene;
        for (const Vec3d& V : view.V) {
            s.V = V;
            bound = std::max(bound, m.method->max_fetches(m.params, s));
        }
        return bound;
    }

    // The keys and the view-wide columns of a row; returns its index in the view.
    size_t emit(ResultRow row, std::vector<Vec2d> errs, const MethodSpec& m,
                const std::string& backend, const Variant& v) {
        row.set_text("method", m.method->name);
        row.set_text("params", m.params.canonical());
        row.set_text("heightfield", c.spec.name);
        row.set_text("heightfield_id", c.spec.identity);
        row.set_text("backend", backend);
        row.set_text("precision", v.precision);
        row.set_text("texture_format", v.texture_format);
        row.set("scale", c.spec.scale);
        row.set("bias", c.spec.bias);
        row.set("theta_deg", theta);
        row.set("phi_deg", phi);
        row.set_text("camera", c.ex.camera);
        for (const auto& [key, value] : c.ex.camera_settings[camera].values) row.set(key, value);
        row.set_text("lod", lod_name(m.lod));
        row.set("lod_mean", lod_mean);
        row.set("samples", c.ex.samples);
        row.set("width", c.hf.width);
        row.set("height", c.hf.height);
        row.set("fetches_bound", fetches_bound(m));
        add_reference_columns({c.ex.ground_truth, truth.gt.cells_mean, truth.agree, holes.frac},
                              row);
        out.rows.push_back(std::move(row));
        out.errors.push_back(std::move(errs));
        return out.rows.size() - 1;
    }
};

ResultRow failed_row(const std::exception& e) {
    ResultRow row;
    row.fail(e.what());
    return row;
}

// One method setting on every backend and variant of one view. The CPU float output is kept:
// the float row gets its distance to double, other backends their agreement with it.
void run_method(ViewJob& job, const MethodSpec& m) {
    const HeightField& hf = job.c.hf;
    const ViewInput in = job.input();
    std::optional<MethodOutput> cpu_float, cpu_double;
    std::optional<size_t> float_row;
    for (const auto& backend : job.c.backends) {
        const bool is_cpu = backend->name() == "cpu";
        if (!backend->runs(m)) continue;
        for (const Variant& v : backend->variants()) {
            try {
                // Built on first use, then shared by every view and backend (a failed build
                // fails this row).
                const MethodResources res =
                    job.c.resources.get(m.method->name, m.method->resources, job.scene.scale,
                                        job.scene.bias, &m.params);
                ViewInput vin = in;
                if (!res.items.empty()) vin.resources = &res;
                MethodOutput o = backend->run(m, vin, v);
                ResultRow row = score(o, job.truth.gt, hf.width, hf.height, job.exclude, &job.view);
                // Every sample non-finite (a parameter combination that gives no answer at
                // this view, e.g. a layer count of 0, or a shader that discards every sample):
                // a failure, never a row of NaN "ok".
                if (row.num("nonfinite") > 0 && !std::isfinite(row.num("err_mean")))
                    throw std::runtime_error(
                        "every sample (" + format_number(row.num("nonfinite")) + ") " +
                        (o.samples_discarded > 0 &&
                                 double(o.samples_discarded) >= row.num("nonfinite")
                             ? std::string("was discarded or left unwritten by the shader "
                                           "(samples_discarded)")
                             : std::string("gave a non-finite uv: the method's parameters give no "
                                           "answer at this view")));
                // The declared bound is enforced: a row over it fails, naming both numbers.
                if (const int bound = job.fetches_bound(m);
                    bound >= 0 && row.num("fetches_max") > bound)
                    throw std::runtime_error(
                        "fetches_max = " + format_number(row.num("fetches_max")) +
                        " exceeds the declared bound fetches_bound = " + std::to_string(bound) +
                        (m.method->plugin_shader.empty() ? " (the method's max_fetches)"
                                                         : " (the entry's max_fetches)"));
                if (o.samples_discarded > 0)  // says so; the numbers stay (samples_discarded)
                    row.set_text("error", "note: " + std::to_string(o.samples_discarded) + " of " +
                                              std::to_string(o.uv.size()) +
                                              " samples discarded or unwritten by the shader "
                                              "(no uv: counted in samples_discarded and "
                                              "nonfinite, left out of the errors)");
                row.set("precompute_ms", res.precompute_ms());
                row.set("aux_bytes", double(res.aux_bytes()));
                if (is_cpu) {
                    const size_t i = job.emit(std::move(row), job.errors_of(o), m, "cpu", v);
                    if (v.precision == "float") {
                        float_row = i;
                        cpu_float = std::move(o);
                    } else {
                        cpu_double = std::move(o);
                    }
                    continue;
                }
                // The CPU float twin (a plug-in's: its `reference`, if it names one), in the
                // same level mode; grad and implicit are compared with the level twin.
                MethodSpec twin = m.reference ? MethodSpec{m.reference, m.reference_params} : m;
                twin.lod = m.lod == LodMode::base ? LodMode::base : LodMode::level;
                if (!cpu_float && twin.method->run_float) {
                    ViewInput tin{in.scene, in.hf, in.rays, nullptr, false, vin.resources};
                    tin.levels = in.levels;
                    tin.lambda = in.lambda;
                    cpu_float = job.c.reference.run(twin, tin, {"float", ""});
                }
                if (cpu_float)
                    add_agreement(row, o, *cpu_float, hf.width, hf.height,
                                  job.view.inside.empty() ? nullptr : &job.view.inside);
                job.emit(std::move(row), job.errors_of(o), m, backend->name(), v);
            } catch (const std::exception& e) {
                ResultRow row = failed_row(e);
                row.set_text("shader", backend->shader_of(*m.method));
                job.emit(std::move(row), {}, m, backend->name(), v);
            }
        }
        if (is_cpu && float_row && cpu_double) {  // what float precision itself costs
            add_precision_agreement(
                compare_outputs(*cpu_float, *cpu_double, hf.width, hf.height,
                                job.view.inside.empty() ? nullptr : &job.view.inside),
                job.out.rows[*float_row]);
        }
    }
}

// timed = false (a sweep's companion view, whose rows are not reported): no CPU timing passes,
// no timed GLSL frames, no agreement statistics.
ViewRows evaluate_view(const FieldContext& c, double theta, double phi, size_t camera, bool timed) {
    const View view =
        Camera::create(c.ex.camera, c.ex.camera_settings[camera], {theta, phi, c.ex.samples})
            ->view();
    if (const std::string why = view_problem(view); !why.empty())
        throw std::logic_error("camera '" + c.ex.camera + "': " + why);
    // V: the view's direction; a camera whose rays are not parallel gives each sample its own.
    const Scene<double> scene{c.spec.scale, c.spec.bias, view_vector(theta, phi), c.hf.width,
                              c.hf.height};
    ViewJob job{c,  theta,   phi, camera, timed, view, scene, truth_stage(c, view, timed),
                {}, nullptr, {},  {},     NAN};
    // Each sample's lambda from its footprint (section 10), and their mean over the inside.
    job.lambda.resize(view.size());
    double lod_sum = 0;
    size_t inside = 0;
    for (size_t k = 0; k < view.size(); ++k) {
        job.lambda[k] =
            view.J.empty() ? 0.0 : footprint_lod(view.footprint(k), c.hf.width, c.hf.height);
        if (!view.is_inside(k)) continue;
        ++inside;
        lod_sum += std::max(job.lambda[k], 0.0);
    }
    job.lod_mean = inside ? lod_sum / double(inside) : NAN;
    job.holes = hole_mask(c.hf, job.truth.gt);
    if (c.ex.exclude_filled && !job.holes.on_filled.empty()) job.exclude = &job.holes.on_filled;
    for (const auto& m : c.ex.methods)
        if (m.runs_on(c.spec.name)) run_method(job, m);
    job.out.truth_uv = std::move(job.truth.gt.uv);
    job.out.inside = view.inside;
    return std::move(job.out);
}

// The backends a run uses, created in the experiment's order (GLSL creates its GL context).
std::vector<std::unique_ptr<Backend>> make_backends(const Experiment& ex, const RunOptions& opt,
                                                    const BackendSettings& settings) {
    const auto& names = opt.backends.empty() ? ex.backends : opt.backends;
    for (const auto& b : names) check_backend_name(b, "--backend");
    std::vector<std::unique_ptr<Backend>> out;
    for (const auto& b : names) out.push_back(make_backend(b, settings));
    return out;
}

// Image files and scans are loaded once up front and dropped, so that a bad file fails before
// any work.
void check_field_files(const Experiment& ex) {
    std::set<std::string> checked;
    for (const auto& spec : ex.heightfields)
        if (spec.generator.empty() && checked.insert(spec.file + "|" + spec.scan).second)
            (void)make_heightfield(spec);
}

bool same_field(const HeightfieldSpec& a, const HeightfieldSpec& b) {
    return a.generator == b.generator && a.file == b.file && a.scan == b.scan &&
           a.width == b.width && a.height == b.height && a.channel == b.channel &&
           a.gen_params.canonical() == b.gen_params.canonical() && a.name == b.name;
}

// Where one sweep is in the run: its indices, which of its views run, and the index its
// first row has in the whole (unsharded) run.
struct SweepPlace {
    size_t field, phi, camera;
    std::vector<bool> runs;  // per theta
    size_t first_row, rows_per_view;
};

// The distance sweep of a perspective run (docs/conventions.md section 5.3): each view of a
// camera setting with a successor (the next distance, the other keys equal) pairs pixel by pixel
// with the view at the same field, phi and theta there, and the nearer view's rows carry the
// pair. Settings run in order (distance outer), so a view waits, with its error vectors and
// where its rows are, until its successor's view runs; a slice without that view traces it as a
// companion instead (timed = false), so a sharded run gives the unsharded numbers.
struct DistancePairs {
    std::vector<DistanceStep> steps;  // per camera setting (distance_steps)
    std::vector<size_t> before;       // per camera setting: the one whose successor it is, or npos
    struct Waiting {
        std::vector<std::vector<Vec2d>> errors;
        std::vector<size_t> index;  // the rows' indices in the run
    };
    std::map<std::array<size_t, 3>, Waiting> waiting;  // (phi, camera, theta) of the nearer view

    explicit DistancePairs(const std::vector<CameraSetting>& settings)
        : steps(distance_steps(settings)), before(settings.size(), size_t(-1)) {
        for (size_t c = 0; c < steps.size(); ++c)
            if (steps[c].pairs()) before[steps[c].next] = c;
    }
};

// Runs the theta sweep of one field and azimuth; rows join `rows` view by view.
void run_sweep(const FieldContext& ctx, const SweepPlace& at, const RunOptions& opt, size_t& step,
               size_t steps, std::vector<ResultRow>& rows, RunInfo* info, DistancePairs& dist) {
    const Experiment& ex = ctx.ex;
    const double phi = ex.phi_deg[at.phi];
    ViewRows prev;  // the previous view of this sweep (same field and phi)
    std::vector<size_t> prev_index;
    for (size_t t = 0; t < ex.theta_deg.size(); ++t) {
        if (!at.runs[t]) continue;
        const double theta = ex.theta_deg[t];
        ++step;
        if (opt.progress) {
            std::ostringstream os;
            const std::string cam = ex.camera_settings[at.camera].label();
            os << ctx.spec.name << " s=" << ctx.spec.scale
               << " b=" << ctx.spec.bias << " theta=" << fmt_angle(theta)
               << " phi=" << fmt_angle(phi) << (cam.empty() ? "" : " " + cam);
            opt.progress(step, steps, os.str());
        }
        ViewRows view = evaluate_view(ctx, theta, phi, at.camera, true);
        if (ex.sweep_dt_deg > 0) {
            // A companion view dt away (below when theta + dt would reach 90).
            const bool up = theta + ex.sweep_dt_deg < 90;
            const double other = up ? theta + ex.sweep_dt_deg : theta - ex.sweep_dt_deg;
            const ViewRows comp = evaluate_view(ctx, other, phi, at.camera, false);
            for (size_t i = 0; i < view.rows.size(); ++i)
                add_sweep(up ? view.errors[i] : comp.errors[i],
                          up ? comp.errors[i] : view.errors[i], ex.sweep_dt_deg, view.rows[i]);
        } else if (t > 0) {
            // Consecutive views: the pair (theta_{k-1}, theta_k) goes on row k-1.
            const double dt = theta - ex.theta_deg[t - 1];
            for (size_t i = 0; i < view.rows.size() && i < prev_index.size(); ++i)
                if (dt > 0) add_sweep(prev.errors[i], view.errors[i], dt, rows[prev_index[i]]);
        }
        // The distance sweep: this view is the farther one of a pair waiting for it, and the
        // nearer one of its own pair (now, with a companion view, or when its successor runs).
        if (const size_t near = dist.before[at.camera]; near != size_t(-1)) {
            const auto it = dist.waiting.find({at.phi, near, t});
            if (it != dist.waiting.end()) {
                const double dd = dist.steps[near].dd;
                for (size_t i = 0; i < view.rows.size() && i < it->second.index.size(); ++i)
                    add_distance_sweep(it->second.errors[i], view.errors[i], dd,
                                       rows[it->second.index[i]]);
                dist.waiting.erase(it);
            }
        }
        const DistanceStep& next = dist.steps[at.camera];
        const bool wait =
            next.pairs() && (!opt.include || opt.include(at.field, at.phi, next.next, t));
        if (next.pairs() && !wait) {
            const ViewRows far = evaluate_view(ctx, theta, phi, next.next, false);
            for (size_t i = 0; i < view.rows.size(); ++i)
                add_distance_sweep(view.errors[i], far.errors[i], next.dd, view.rows[i]);
        }
        if (view.rows.size() != at.rows_per_view)
            throw std::logic_error("a view made " + std::to_string(view.rows.size()) +
                                   " rows, not the " + std::to_string(at.rows_per_view) +
                                   " its place in the run assumes");
        const size_t first = at.first_row + t * at.rows_per_view;
        if (!opt.include && first != rows.size())
            throw std::logic_error("row index " + std::to_string(first) + " of a view is not " +
                                   std::to_string(rows.size()));
        if (opt.on_view) opt.on_view(view.rows, view.errors, view.truth_uv, view.inside, first);
        if (info) info->views.push_back({at.field, at.phi, at.camera, t, view.rows.size()});
        prev_index.clear();
        for (auto& r : view.rows) {
            prev_index.push_back(rows.size());
            rows.push_back(std::move(r));
        }
        if (wait) {  // the theta pairing keeps this view's errors only while it needs them
            const bool theta_next = ex.sweep_dt_deg <= 0 && t + 1 < ex.theta_deg.size();
            dist.waiting[{at.phi, at.camera, t}] = {
                theta_next ? view.errors : std::move(view.errors), prev_index};
        }
        prev = std::move(view);
    }
}

// Which views run (all, or a slice's), and where each sweep's rows are in the whole run:
// every view of a field has one row per method setting it runs x backend x variant. `steps`:
// the views that run.
std::vector<SweepPlace> plan_sweeps(const Experiment& ex, const RunOptions& opt,
                                    const std::vector<std::unique_ptr<Backend>>& backends,
                                    size_t& steps) {
    const size_t nt = ex.theta_deg.size(), np = ex.phi_deg.size();
    const size_t nc = ex.camera_settings.size();
    std::vector<SweepPlace> places;
    size_t first_row = 0;
    for (size_t h = 0; h < ex.heightfields.size(); ++h) {
        size_t per_view = 0;
        for (const auto& m : ex.methods)
            if (m.runs_on(ex.heightfields[h].name))
                for (const auto& b : backends)
                    if (b->runs(m)) per_view += b->variants().size();
        for (size_t p = 0; p < np; ++p)
            for (size_t c = 0; c < nc; ++c) {
                SweepPlace at{h, p, c, std::vector<bool>(nt, true), first_row, per_view};
                size_t n = 0;
                for (size_t t = 0; t < nt; ++t) {
                    if (opt.include) at.runs[t] = opt.include(h, p, c, t);
                    n += at.runs[t];
                }
                if (n != 0 && n != nt && ex.sweep_dt_deg <= 0)
                    throw std::logic_error(
                        "a slice must take a theta sweep whole (its consecutive "
                        "views pair up)");
                steps += n;
                first_row += nt * per_view;
                places.push_back(std::move(at));
            }
    }
    return places;
}

}  // namespace

namespace {

BackendSettings settings_of(const Experiment& ex, const RunOptions& opt) {
    BackendSettings settings = backend_settings(ex);
    settings.gl_frames = opt.gl_frames;
    settings.shader_dir = opt.shader_dir;
    if (!opt.gl.empty()) settings.gl = opt.gl;
    if (opt.gl_time_limit_s > 0) settings.gl_time_limit_s = opt.gl_time_limit_s;
    return settings;
}

}  // namespace

bool software_renderer(const std::map<std::string, std::string>& f) {
    auto has = [](const std::string& s, const char* what) {
        std::string low;
        for (char c : s) low += char(std::tolower(static_cast<unsigned char>(c)));
        return low.find(what) != std::string::npos;
    };
    const auto r = f.find("gl_renderer");
    const auto p = f.find("gl_driver.platform");
    const std::string renderer = r == f.end() ? "" : r->second;
    const std::string platform = p == f.end() ? "" : p->second;
    return has(renderer, "llvmpipe") || has(renderer, "softpipe") || has(renderer, "swiftshader") ||
           has(renderer, "software") || has(platform, "software");
}

std::vector<std::string> check_plugin_shaders(const Experiment& ex, const RunOptions& opt) {
    // Each plug-in's first setting (left out by --only: none): every setting of a plug-in has
    // the same uniforms (names and types), so one check each.
    std::vector<const MethodSpec*> firsts;
    for (const auto& p : ex.plugins)
        for (const auto& m : ex.methods)
            if (m.method == p.get()) {
                firsts.push_back(&m);
                break;
            }
    if (firsts.empty()) return {};
    GlslChildBackend gl(settings_of(ex, opt));
    std::vector<std::string> problems;
    for (const MethodSpec* m : firsts)
        for (auto& line :
             gl.check(GlslMethod::of(*m->method), method_uniforms(*m->method, m->params)))
            problems.push_back(std::move(line));
    return problems;
}

std::vector<ResultRow> run_experiment(const Experiment& ex, const RunOptions& opt, RunInfo* info) {
    const BackendSettings settings = settings_of(ex, opt);
    const auto backends = make_backends(ex, opt, settings);
    if (opt.warning && settings.gl == "egl")
        for (const auto& b : backends)
            if (b->name() == "glsl" && software_renderer(b->facts())) {
                const auto f = b->facts();
                opt.warning("--gl egl gave a software renderer (GL_RENDERER '" +
                            (f.count("gl_renderer") ? f.at("gl_renderer") : "") +
                            "', EGL platform '" +
                            (f.count("gl_driver.platform") ? f.at("gl_driver.platform") : "") +
                            "'): no GPU's EGL device was usable, so the GLSL timings are the "
                            "CPU's");
            }
    CpuBackend reference(settings);
    if (info)
        for (const auto& b : backends)
            for (const auto& [k, v] : b->facts()) {
                if (k == "gl_renderer") info->gl_renderer = v;
                if (k == "gl_version") info->gl_version = v;
                if (k == "gl_context") info->gl_context = v;
                if (k == "gl_vendor") info->gl_vendor = v;
                if (k == "gl_timer_bits") info->gl_timer_bits = std::stoi(v);
                if (k.rfind("gl_driver.", 0) == 0) info->gl_driver[k.substr(10)] = v;
            }
    // Height fields are built one at a time (a sweep of thousands of fields, or of scales on
    // a large one, holds one field in memory); entries that share a field (a scale/bias sweep)
    // reuse it.
    check_field_files(ex);
    const size_t nt = ex.theta_deg.size(), np = ex.phi_deg.size();
    const size_t per_field = np * ex.camera_settings.size();  // sweeps per field
    size_t steps = 0;
    const std::vector<SweepPlace> places = plan_sweeps(ex, opt, backends, steps);
    std::vector<ResultRow> rows;
    size_t step = 0;
    std::optional<HeightField> field;
    const HeightfieldSpec* built = nullptr;  // the entry `field` was built for
    std::optional<ResourceCache> resources;  // one per field, dropped with it
    std::optional<TextureLevels> levels;     // ... when a setting samples the levels
    const bool any_levels = std::any_of(ex.methods.begin(), ex.methods.end(),
                                        [](const MethodSpec& m) { return m.lod != LodMode::base; });
    for (size_t h = 0; h < ex.heightfields.size(); ++h) {
        const HeightfieldSpec& spec = ex.heightfields[h];
        bool any = false;
        for (size_t p = 0; p < per_field; ++p)
            for (size_t t = 0; t < nt; ++t) any = any || places[h * per_field + p].runs[t];
        if (!any) continue;  // another slice's field
        if (!field || !same_field(spec, *built)) {
            if (info && resources) info->resource_builds += resources->builds();
            resources.reset();
            levels.reset();
            field.reset();  // free the previous one first
            field = make_heightfield(spec);
            built = &spec;
            resources.emplace(*field);
            if (any_levels) levels = build_texture_levels(*field);
        }
        // Both references built once per field (and s, b), shared by all its views.
        const References refs = make_references(*field, spec);
        const FieldContext ctx{ex,          backends,   reference,
                               *field,      spec,       *refs.exact,
                               *refs.other, *resources, levels ? &*levels : nullptr};
        DistancePairs dist(ex.camera_settings);  // the field's views waiting for the next distance
        for (size_t p = 0; p < per_field; ++p) {
            const SweepPlace& at = places[h * per_field + p];
            if (std::count(at.runs.begin(), at.runs.end(), true))
                run_sweep(ctx, at, opt, step, steps, rows, info, dist);
        }
    }
    if (info && resources) info->resource_builds += resources->builds();
    if (info)
        for (const auto& b : backends) {
            for (const auto& [k, v] : b->sources()) info->shaders[k] = v;
            info->backends[b->name()] = b->record(settings);
        }
    return rows;
}

}  // namespace pxh
