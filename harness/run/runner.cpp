#include "harness/run/runner.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/experiment/view_grid.h"
#include "harness/metrics/agreement.h"
#include "harness/metrics/depth.h"
#include "harness/metrics/measured.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/reference.h"
#include "harness/metrics/sweep_pairs.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/curved_view.h"
#include "harness/scene/footprint.h"
#include "harness/scene/texture_levels.h"
#include "harness/truth/curved_tracer.h"

namespace pxh {
namespace {

std::string fmt_angle(double a) {
    std::ostringstream os;
    os << a;
    return os.str();
}

}  // namespace

ResultRow score(const MethodOutput& out, const GroundTruth& gt, int width, int height,
                const std::vector<uint8_t>* exclude, const View* view, const Coverage* cover) {
    ResultRow row;
    MetricInput in{out, gt, width, height, exclude, view};
    in.cover = cover;
    apply_output_metrics(in, row);
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
    std::vector<Vec2d> truth_uv;                  // the view's true hits (per sample, unwrapped)
    std::vector<uint8_t> inside;                  // the view's inside mask (View::inside)
    std::vector<std::vector<uint8_t>> cut_shows;  // per row: ViewOutput::cut_shows
    std::vector<std::vector<Vec2d>> shown_uv;     // per row, curved bases: ViewOutput::shown_uv
    std::vector<uint8_t> truth_hit;               // curved bases: ViewOutput::truth_hit
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
    // A curved base (nullptr: the plane): its views are the base hits (curved_view), its truth
    // the curved tracer's, checked against the same walk at half the step.
    const BaseSurface* base = nullptr;
    const CurvedTracer* curved = nullptr;
    const CurvedTracer* curved_check = nullptr;
};

// The references of one field (and s, b), built once and shared by its views.
struct References {
    std::unique_ptr<Tracer> exact, other;
    std::unique_ptr<BaseSurface> base;  // a curved base's, with its two walks
    std::unique_ptr<CurvedTracer> curved, curved_check;
};

References make_references(const HeightField& hf, const HeightfieldSpec& spec) {
    References r;
    r.other = make_tracer(TracerRole::cross_check, hf, spec.scale, spec.bias);
    r.exact = make_tracer(TracerRole::exact_reference, hf, spec.scale, spec.bias);
    if (spec.base != "plane") {
        r.base = make_base(spec.base, spec.radius);
        r.curved = make_curved_truth(hf, spec.scale, spec.bias, *r.base);
        r.curved_check = std::make_unique<CurvedTracer>(hf, spec.scale, spec.bias, *r.base,
                                                        r.curved->step_texels() / 2);
    }
    return r;
}

// What the truth stage gives a view: its ground truth and the two references' disagreement.
struct ViewTruth {
    GroundTruth gt;
    ErrorStats agree;  // |hit_other - hit_exact| in texels (NaN when the other did not run)
    std::optional<Coverage> cover;  // a curved base's: base and true hits per sample
    double residual_max = NAN;      // a curved base's: max |g| at the true hits (tiles)
};

// A curved base's truth stage: the walk's hits (uv NaN where the ray misses the displaced
// surface), its residual, and (timed views) its agreement with the walk at half the step over
// the rays both hit.
ViewTruth curved_truth_stage(const FieldContext& c, const CurvedView& cv, bool timed) {
    ViewTruth t;
    // Both walks count against one budget per view, kMaxCurvedWalkSteps: the same limit, and
    // the same steps, as the estimate the experiment was checked with when it was read.
    CurvedHits h = c.curved->trace(cv.rays, kMaxCurvedWalkSteps);
    const double check_budget = kMaxCurvedWalkSteps - h.steps;
    // depths from the base hit along the camera's axis (docs/conventions.md sections 11, 12)
    t.gt.depth.assign(h.uv.size(), NAN);
    for (size_t k = 0; k < h.uv.size(); ++k)
        if (h.hit[k] && cv.base_hit[k])
            t.gt.depth[k] = v3_dot(v3_sub(h.point[k], cv.base_point[k]), cv.forward);
    const BaseSurface* base = c.base;
    t.gt.shell_depth = [base, &cv](size_t k, double z) {
        if (!cv.base_hit[k]) return double(NAN);
        const WorldRay& r = cv.rays[k];
        const double tc = base->hit(r.o, r.d, z, 0, false);
        if (!std::isfinite(tc)) return double(NAN);
        return v3_dot(v3_sub(v3_add(r.o, v3_scale(r.d, tc)), cv.base_point[k]), cv.forward);
    };
    t.gt.uv = std::move(h.uv);
    t.gt.z = std::move(h.z);
    t.gt.cells_mean = NAN;
    t.residual_max = h.residual_max;
    t.cover = Coverage{cv.base_hit, std::move(h.hit)};
    t.agree.p50 = t.agree.p99 = t.agree.max = t.agree.frac_gt_0_5 = NAN;
    if (timed) {
        CurvedHits fine;
        try {
            fine = c.curved_check->trace(cv.rays, check_budget);
        } catch (const CurvedWalkTooLong& e) {  // the view's steps: both walks'
            throw CurvedWalkTooLong(e.what(), h.steps + e.steps, kMaxCurvedWalkSteps);
        }
        std::vector<Vec2d> a, b;
        for (size_t k = 0; k < fine.uv.size(); ++k)
            if (t.cover->truth_hit[k] && fine.hit[k]) {
                a.push_back(fine.uv[k]);
                b.push_back(t.gt.uv[k]);
            }
        t.agree = reference_agreement(a, b, c.hf.width, c.hf.height);
    }
    return t;
}

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
        if (!std::isfinite(gt.uv[k].x) || !std::isfinite(gt.uv[k].y)) continue;  // no true hit
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
    // The coarsest spacing of float values at the inside samples' uv (texels, the larger of u
    // and v): a float row cannot place its uv closer than half of it to the truth.
    double float_spacing = 0;
    // The first inside sample where it is coarsest (its P).
    Vec2d float_spacing_at{0, 0};

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
                const std::string& backend, const Variant& v, std::vector<uint8_t> cut_shows = {},
                const MethodOutput* o = nullptr) {
        row.set_text("method", m.method->name);
        row.set_text("params", m.params.canonical());
        row.set_text("heightfield", c.spec.name);
        row.set_text("heightfield_id", c.spec.identity);
        row.set_text("backend", backend);
        row.set_text("precision", v.precision);
        row.set_text("texture_format", v.texture_format);
        row.set("scale", c.spec.scale);
        row.set("bias", c.spec.bias);
        // empty on the plane: rows, names and keys as before bases existed
        row.set_text("base", c.spec.base == "plane" ? "" : c.spec.base);
        row.set("radius", c.spec.radius);
        row.set("theta_deg", theta);
        row.set("phi_deg", phi);
        row.set_text("camera", c.ex.camera);
        for (const auto& [key, value] : c.ex.camera_settings[camera].values) row.set(key, value);
        row.set_text("lod", lod_name(m.lod));
        row.set_text("depth", depth_name(m.depth));
        row.set("cut", m.cut);
        row.set("lod_mean", lod_mean);
        row.set("samples", c.ex.samples);
        row.set("width", c.hf.width);
        row.set("height", c.hf.height);
        row.set("fetches_bound", fetches_bound(m));
        add_reference_columns(
            {c.ex.ground_truth, truth.gt.cells_mean, truth.agree, holes.frac, truth.residual_max},
            row);
        out.rows.push_back(std::move(row));
        out.errors.push_back(std::move(errs));
        out.cut_shows.push_back(std::move(cut_shows));
        std::vector<Vec2d> shown;  // a curved base's pictures: what the method shows
        if (c.base && o) {
            shown = o->uv;
            for (size_t k = 0; k < shown.size(); ++k)
                if (!view.is_inside(k)) shown[k] = {NAN, NAN};
        }
        out.shown_uv.push_back(std::move(shown));
        return out.rows.size() - 1;
    }
};

// Float rows whose uv float spaces this coarsely (texels) or more at some inside sample say so:
// from there on their error grows with the eye's distance whatever the method (a perspective
// eye far out puts the samples far from the origin; double rows stay exact).
constexpr double kFloatSpacingNote = 1.0 / 16;

std::string float_spacing_note(const ViewJob& job) {
    return "float spaces uv " + format_number(job.float_spacing) +
           " texels apart at inside samples (e.g. uv " + format_number(job.float_spacing_at.x) +
           ", " + format_number(job.float_spacing_at.y) +
           "): float rounding alone costs up to half that; the double rows are exact there";
}

// The spacing of floats at |u| (the gap to the next float up), in double.
double float_gap(double u) {
    const float f = float(std::abs(u));
    return double(std::nextafter(f, std::numeric_limits<float>::infinity())) - double(f);
}

// What an ok row says beside its numbers: samples the shader discarded (samples_discarded), and
// float's spacing at far samples.
std::string row_notes(const ViewJob& job, const MethodSpec& m, const MethodOutput& o,
                      const Variant& v) {
    std::string notes;
    if (o.samples_discarded > 0)
        notes =
            "note: " + std::to_string(o.samples_discarded) + " of " + std::to_string(o.uv.size()) +
            (m.method->discard_test.empty() ? " samples discarded or unwritten by the shader"
                                            : " samples discarded by " + m.method->name +
                                                  "'s own test (" + m.method->discard_test + ")") +
            " (no uv: counted in samples_discarded, not in nonfinite; left out of the "
            "errors and of fetches_mean)";
    if (v.precision == "float" && job.float_spacing >= kFloatSpacingNote)
        notes += (notes.empty() ? "note: " : "; ") + float_spacing_note(job);
    return notes;
}

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
        const bool is_cpu = backend_entry(backend->name()).reference;
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
                ResultRow row = score(o, job.truth.gt, hf.width, hf.height, job.exclude, &job.view,
                                      job.truth.cover ? &*job.truth.cover : nullptr);
                // Nothing measured: a failure with its reason, never an ok row of empty cells.
                if (const std::string why = nothing_measured(row, o, job.truth.cover.has_value());
                    !why.empty())
                    throw std::runtime_error(why);
                // The declared bound is enforced: a row over it fails, naming both numbers.
                if (const int bound = job.fetches_bound(m);
                    bound >= 0 && row.num("fetches_max") > bound)
                    throw std::runtime_error(
                        "fetches_max = " + format_number(row.num("fetches_max")) +
                        " exceeds the declared bound fetches_bound = " + std::to_string(bound) +
                        (m.method->plugin_shader.empty() ? " (the method's max_fetches)"
                                                         : " (the entry's max_fetches)"));
                if (const std::string notes = row_notes(job, m, o, v); !notes.empty())
                    row.set_text("error", notes);  // said in the row; the numbers stay
                std::vector<uint8_t> shows;
                if (!std::isnan(m.cut))
                    shows = add_cut_flips(o, job.truth.gt, job.view, job.exclude,
                                          job.scene.scale * (m.cut - job.scene.bias), row);
                row.set("precompute_ms", res.precompute_ms());
                row.set("aux_bytes", double(res.aux_bytes()));
                if (is_cpu) {
                    const size_t i = job.emit(std::move(row), job.errors_of(o), m, backend->name(),
                                              v, std::move(shows), &o);
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
                twin.depth = m.depth;
                if (!cpu_float && twin.method->run_float) {
                    ViewInput tin{in.scene, in.hf, in.rays, nullptr, false, vin.resources};
                    tin.levels = in.levels;
                    tin.lambda = in.lambda;
                    cpu_float = job.c.reference.run(twin, tin, {"float", ""});
                }
                if (cpu_float)
                    add_agreement(row, o, *cpu_float, hf.width, hf.height,
                                  job.view.inside.empty() ? nullptr : &job.view.inside);
                job.emit(std::move(row), job.errors_of(o), m, backend->name(), v, std::move(shows),
                         &o);
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
    const auto cam =
        Camera::create(c.ex.camera, c.ex.camera_settings[camera], {theta, phi, c.ex.samples});
    // A curved base: the methods see the base hits (P, V in the tangent frame, J).
    std::optional<CurvedView> curved;
    if (c.base) curved = curved_view(*cam, *c.base, c.spec.scale * (1 - c.spec.bias));
    const View view = curved ? curved->view : cam->view();
    if (const std::string why = view_problem(view); !why.empty())
        throw std::logic_error("camera '" + c.ex.camera + "': " + why);
    // V: the view's direction; a camera whose rays are not parallel gives each sample its own.
    const Scene<double> scene{
        c.spec.scale, c.spec.bias, view_vector(theta, phi),
        c.hf.width,   c.hf.height, c.base ? c.base->curvature() : Vec2d{0, 0}};
    // A view's curved walks over their step budget (kMaxCurvedWalkSteps; views the estimate
    // lets through whose rays skim the relief) refuse the run at the field's entry, naming the
    // view, the steps, the limit and the knobs.
    auto truth = [&]() {
        if (!curved) return truth_stage(c, view, timed);
        try {
            return curved_truth_stage(c, *curved, timed);
        } catch (const CurvedWalkTooLong& e) {
            throw InputError(c.spec.where, "heightfield '" + c.spec.name + "' (base " +
                                               c.spec.base + " radius " +
                                               format_number(c.spec.radius) + ") at theta " +
                                               format_number(theta) + " phi " + format_number(phi) +
                                               ": the curved truth's walk stopped after " +
                                               format_number(e.steps) + " steps for the " +
                                               std::to_string(curved->rays.size()) +
                                               " rays of this view (the walk and its check "
                                               "together), over the limit of 2^28 steps a view "
                                               "(kMaxCurvedWalkSteps; rays that skim the relief "
                                               "step shorter than the quarter texel the estimate "
                                               "before the run assumes): lower theta, the scale, "
                                               "the field's size or samples");
        }
    };
    ViewJob job{c, theta, phi, camera, timed, view, scene, truth(), {}, nullptr, {}, {}, NAN};
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
    for (size_t k = 0; k < view.size(); ++k) {  // float's coarsest spacing over the inside samples
        if (!view.is_inside(k)) continue;
        const Vec2d P = view.P[k];
        const double gap = std::max(float_gap(P.x) * c.hf.width, float_gap(P.y) * c.hf.height);
        if (gap > job.float_spacing) {
            job.float_spacing = gap;
            job.float_spacing_at = P;
        }
    }
    job.holes = hole_mask(c.hf, job.truth.gt);
    if (c.ex.exclude_filled && !job.holes.on_filled.empty()) job.exclude = &job.holes.on_filled;
    for (const auto& m : c.ex.methods)
        if (m.runs_on(c.spec.name)) run_method(job, m);
    job.out.truth_uv = std::move(job.truth.gt.uv);
    if (job.truth.cover) job.out.truth_hit = job.truth.cover->truth_hit;
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

// Where one sweep is in the run: its place in the view grid, which of its views run, and the
// index its first row has in the whole (unsharded) run.
struct SweepPlace {
    ViewAt at;               // theta 0
    std::vector<bool> runs;  // per theta
    size_t first_row, rows_per_view;
};

// "bricks s=0.05 b=1 theta=45 phi=0 distance=4 fov_deg=45": a view, as progress names it.
std::string view_label(const FieldContext& ctx, double theta, double phi, const std::string& cam) {
    std::ostringstream os;
    os << ctx.spec.name << " s=" << ctx.spec.scale << " b=" << ctx.spec.bias
       << " theta=" << fmt_angle(theta) << " phi=" << fmt_angle(phi)
       << (cam.empty() ? "" : " " + cam);
    return os.str();
}

// A view's rows against the row count and index its place in the run assumes.
void check_view_place(const ViewRows& view, const SweepPlace& sw, size_t t, bool whole_run,
                      size_t rows_so_far) {
    if (view.rows.size() != sw.rows_per_view)
        throw std::logic_error("a view made " + std::to_string(view.rows.size()) +
                               " rows, not the " + std::to_string(sw.rows_per_view) +
                               " its place in the run assumes");
    const size_t first = sw.first_row + t * sw.rows_per_view;
    if (whole_run && first != rows_so_far)
        throw std::logic_error("row index " + std::to_string(first) + " of a view is not " +
                               std::to_string(rows_so_far));
}

// Runs the theta sweep of one field, azimuth and camera setting; rows join `rows` view by view,
// their sliding and shimmering pairs through `pairs` (a view that pairs with one this run does
// not make, a slice's, is traced as a companion, timed = false: the unsharded numbers).
void run_sweep(const FieldContext& ctx, const SweepPlace& sw, const RunOptions& opt, size_t& step,
               size_t steps, std::vector<ResultRow>& rows, RunInfo* info, SweepPairer& pairs) {
    const Experiment& ex = ctx.ex;
    const size_t p = sw.at.phi, c = sw.at.camera;
    const double phi = ex.phi_deg[p];
    pairs.start_sweep();
    for (size_t t = 0; t < ex.theta_deg.size(); ++t) {
        if (!sw.runs[t]) continue;
        const double theta = ex.theta_deg[t];
        ++step;
        if (opt.progress)
            opt.progress(step, steps, view_label(ctx, theta, phi, ex.camera_settings[c].label()));
        ViewRows view = evaluate_view(ctx, theta, phi, c, true);
        if (const auto other = pairs.theta_companion(theta))
            pairs.pair_companion(theta, view.errors,
                                 evaluate_view(ctx, *other, phi, c, false).errors, view.rows);
        pairs.pair_earlier(p, c, t, view.errors, rows);
        const DistanceStep& next = pairs.successor(c);
        const bool wait =
            next.pairs() && (!opt.include || opt.include({sw.at.field, p, next.next, t}));
        if (next.pairs() && !wait)
            pairs.pair_successor(
                c, view.errors, evaluate_view(ctx, theta, phi, next.next, false).errors, view.rows);
        check_view_place(view, sw, t, !opt.include, rows.size());
        const size_t first = sw.first_row + t * sw.rows_per_view;
        if (opt.on_view) {
            ViewOutput out{view.rows,      view.errors,   view.truth_uv,  view.inside,
                           view.cut_shows, view.shown_uv, view.truth_hit, first};
            opt.on_view(out);
        }
        if (info) info->views.push_back({{sw.at.field, p, c, t}, view.rows.size()});
        std::vector<size_t> index;
        for (auto& r : view.rows) {
            index.push_back(rows.size());
            rows.push_back(std::move(r));
        }
        pairs.keep(p, c, t, std::move(view.errors), std::move(index), wait);
    }
}

// Which views run (all, or a slice's), and where each sweep's rows are in the whole run:
// every view of a field has one row per method setting it runs x backend x variant, in sweep
// order (ViewGrid). `steps`: the views that run.
std::vector<SweepPlace> plan_sweeps(const Experiment& ex, const RunOptions& opt,
                                    const std::vector<std::unique_ptr<Backend>>& backends,
                                    size_t& steps) {
    const ViewGrid grid(ex);
    std::vector<SweepPlace> places;
    size_t first_row = 0;
    for (size_t s = 0; s < grid.sweeps(); ++s) {
        const ViewAt at = grid.sweep(s);
        size_t per_view = 0;
        for (const auto& m : ex.methods)
            if (m.runs_on(ex.heightfields[at.field].name))
                for (const auto& b : backends)
                    if (b->runs(m)) per_view += b->variants().size();
        SweepPlace sw{at, std::vector<bool>(grid.thetas, true), first_row, per_view};
        size_t n = 0;
        for (size_t t = 0; t < grid.thetas; ++t) {
            if (opt.include) sw.runs[t] = opt.include({at.field, at.phi, at.camera, t});
            n += sw.runs[t];
        }
        if (n != 0 && n != grid.thetas && ex.sweep_dt_deg <= 0)
            throw std::logic_error(
                "a slice must take a theta sweep whole (its consecutive views pair up)");
        steps += n;
        first_row += grid.thetas * per_view;
        places.push_back(std::move(sw));
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

std::vector<std::string> preflight_backends(const Experiment& ex, const RunOptions& opt) {
    // Each plug-in's first setting (left out by --only: none) and every level mode its settings
    // run in: every setting of a plug-in has the same uniforms, so one check per program.
    Preflight pre;
    pre.parallel_camera = camera_entry(ex.camera, "camera").parallel;
    for (const auto& p : ex.plugins) {
        PluginSettings s{nullptr, {}};
        for (const auto& m : ex.methods) {
            if (m.method != p.get()) continue;
            if (!s.first) s.first = &m;
            if (std::find(s.lods.begin(), s.lods.end(), m.lod) == s.lods.end())
                s.lods.push_back(m.lod);
        }
        if (s.first) pre.plugins.push_back(std::move(s));
    }
    const BackendSettings settings = settings_of(ex, opt);
    std::vector<std::string> problems;
    for (const auto& name : opt.backends.empty() ? ex.backends : opt.backends)
        if (const BackendEntry& e = backend_entry(name); e.preflight)
            for (auto& line : e.preflight(pre, settings)) problems.push_back(std::move(line));
    return problems;
}

std::vector<ResultRow> run_experiment(const Experiment& ex, const RunOptions& opt, RunInfo* info) {
    const BackendSettings settings = settings_of(ex, opt);
    const auto backends = make_backends(ex, opt, settings);
    if (opt.warning)
        for (const auto& b : backends)
            if (const BackendEntry& e = backend_entry(b->name()); e.warnings)
                for (const auto& line : e.warnings(*b, settings)) opt.warning(line);
    CpuBackend reference(settings);
    // Height fields are built one at a time (a sweep of thousands of fields, or of scales on
    // a large one, holds one field in memory); entries that share a field (a scale/bias sweep)
    // reuse it.
    check_field_files(ex);
    const ViewGrid grid(ex);
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
    SweepPairer pairs(ex.theta_deg, ex.sweep_dt_deg, ex.camera_settings,
                      camera_entry(ex.camera, "camera").pair_key());
    for (size_t h = 0; h < ex.heightfields.size(); ++h) {
        const HeightfieldSpec& spec = ex.heightfields[h];
        const auto sweeps = places.begin() + long(h * grid.sweeps_per_field());
        if (std::none_of(sweeps, sweeps + long(grid.sweeps_per_field()), [](const SweepPlace& s) {
                return std::count(s.runs.begin(), s.runs.end(), true) > 0;
            }))
            continue;  // another slice's field
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
        const FieldContext ctx{ex,
                               backends,
                               reference,
                               *field,
                               spec,
                               *refs.exact,
                               *refs.other,
                               *resources,
                               levels ? &*levels : nullptr,
                               refs.base.get(),
                               refs.curved.get(),
                               refs.curved_check.get()};
        pairs.start_field();
        for (auto sw = sweeps; sw != sweeps + long(grid.sweeps_per_field()); ++sw)
            if (std::count(sw->runs.begin(), sw->runs.end(), true))
                run_sweep(ctx, *sw, opt, step, steps, rows, info, pairs);
    }
    if (info && resources) info->resource_builds += resources->builds();
    if (info)
        for (const auto& b : backends) info->backends[b->name()] = b->record(settings);
    return rows;
}

}  // namespace pxh
