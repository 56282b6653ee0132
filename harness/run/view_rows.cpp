#include "harness/run/view_rows.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/agreement.h"
#include "harness/metrics/depth.h"
#include "harness/metrics/reference.h"
#include "harness/metrics/score.h"
#include "harness/scene/footprint.h"

namespace pxh {

namespace {

// One view being evaluated: its scene, truth, holes, and the rows it has produced so far.
struct ViewJob {
    const FieldContext& c;
    double theta, phi;
    size_t camera;  // index into the experiment's camera settings
    bool timed;
    const View& view;  // the samples' rays, as the base's entry gave them
    Scene<double> scene;
    ViewTruth truth;
    HoleMask holes;
    const std::vector<uint8_t>* exclude = nullptr;  // samples left out of the errors
    ViewRows out;
    std::vector<double> lambda;  // each sample's level of detail (its footprint's)
    double lod_mean = NAN;       // mean max(lambda, 0) over the inside samples
    FloatSpacing spacing;        // float's coarsest spacing at the inside samples
    bool shade = false;          // [shading]: a backend with its own shading shades its image
    // The rows of backends in a process of their own, drawn on the run's lane (FieldContext::
    // lane) in row order; nullptr: drawn here.
    SideRows* side = nullptr;

    // Setting m's resources at this view's s, b: built on first use, then shared by every
    // view and backend (thread-safe: the side lane fetches them too).
    MethodResources resources_of(const MethodSpec& m) const {
        return c.resources.get(m.method->name, m.method->resources, scene.scale, scene.bias,
                               &m.params);
    }

    ViewInput input() const {
        ViewInput in{scene, c.hf, view, c.ex.light ? &*c.ex.light : nullptr, timed};
        in.levels = c.levels;
        in.lambda = &lambda;
        // [shading]: the GLSL backend shades its image itself (not a sweep's companion view's)
        in.shading = shade && c.ex.shading ? &*c.ex.shading : nullptr;
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
        return m.method->max_fetches_over(m.params, scene, view.V);
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
        row.set_text("base", c.spec.base);
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
        std::vector<Vec2d> shown;  // where the truth reports coverage: what the method shows
        if (truth.cover && o) {
            shown = o->uv;
            for (size_t k = 0; k < shown.size(); ++k)
                if (!view.is_inside(k)) shown[k] = {NAN, NAN};
        }
        out.shown_uv.push_back(std::move(shown));
        out.shaded.push_back(o ? o->shaded : std::vector<float>{});
        return out.rows.size() - 1;
    }
};

// A backend's output scored into its row: the statistics, the failure rules (thrown), the
// notes beside the numbers, the cut flips (their per-sample shows returned) and the method's
// precomputation.
ResultRow scored_row(const ViewJob& job, const MethodSpec& m, const MethodOutput& o,
                     const Variant& v, const MethodResources& res, std::vector<uint8_t>& shows) {
    const HeightField& hf = job.c.hf;
    const Coverage* cover = job.truth.cover ? &*job.truth.cover : nullptr;
    ResultRow row = score(o, job.truth.gt, hf.width, hf.height, job.exclude, &job.view, cover);
    if (const std::string why =
            row_failure(row, o, cover != nullptr, job.fetches_bound(m), *m.method);
        !why.empty())
        throw std::runtime_error(why);
    if (const std::string notes = row_notes(o, *m.method, v, job.spacing); !notes.empty())
        row.set_text("error", notes);  // said in the row; the numbers stay
    if (!std::isnan(m.cut))
        shows = add_cut_flips(o, job.truth.gt, job.view, job.exclude,
                              job.scene.scale * (m.cut - job.scene.bias), row);
    row.set("precompute_ms", res.precompute_ms());
    row.set("aux_bytes", double(res.aux_bytes()));
    return row;
}

// The reference backend's float twin of setting m (a plug-in's: its `reference`, if it names
// one), in the same level mode (grad and implicit are compared with the level twin); nullopt
// when the twin has no float run.
std::optional<MethodOutput> reference_twin(const ViewJob& job, const MethodSpec& m,
                                           const ViewInput& in, const MethodResources* res) {
    MethodSpec twin = m.reference ? MethodSpec{m.reference, m.reference_params} : m;
    twin.lod = m.lod == LodMode::base ? LodMode::base : LodMode::level;
    twin.depth = m.depth;
    if (!twin.method->run_float) return std::nullopt;
    ViewInput tin{in.scene, in.hf, in.rays, nullptr, false, res};
    tin.levels = in.levels;
    tin.lambda = in.lambda;
    return job.c.reference.run(twin, tin, {"float", ""});
}

// One method setting on every backend and variant of one view. The reference backend's float
// output is kept: its float row gets its distance to double, other backends their agreement
// with it.
void run_method(ViewJob& job, const MethodSpec& m) {
    const HeightField& hf = job.c.hf;
    const ViewInput in = job.input();
    const std::vector<uint8_t>* inside = job.view.inside.empty() ? nullptr : &job.view.inside;
    std::optional<MethodOutput> ref_float, ref_double;
    std::optional<size_t> float_row;
    for (const auto& backend : job.c.backends) {
        const bool is_reference = backend_entry(backend->name()).reference;
        if (!backend->runs(m)) continue;
        for (const Variant& v : backend->variants()) {
            // drawn on the lane: taken first, whatever happens to the row here
            std::optional<SideRows::Row> drawn;
            if (job.side && backend->own_process()) drawn = job.side->take();
            if (drawn && !drawn->out) {  // it failed there: the row it fails with here
                ResultRow row;
                row.fail(drawn->error);
                row.set_text("shader", drawn->shader);
                job.emit(std::move(row), {}, m, backend->name(), v);
                continue;
            }
            try {
                // Built on first use, then shared by every view and backend (a failed build
                // fails this row).
                const MethodResources res = job.resources_of(m);
                ViewInput vin = in;
                if (!res.items.empty()) vin.resources = &res;
                MethodOutput o = drawn ? std::move(*drawn->out) : backend->run(m, vin, v);
                std::vector<uint8_t> shows;
                ResultRow row = scored_row(job, m, o, v, res, shows);
                if (is_reference) {
                    const size_t i = job.emit(std::move(row), job.errors_of(o), m, backend->name(),
                                              v, std::move(shows), &o);
                    if (v.precision == "float") {
                        float_row = i;
                        ref_float = std::move(o);
                    } else {
                        ref_double = std::move(o);
                    }
                    continue;
                }
                if (!ref_float) ref_float = reference_twin(job, m, in, vin.resources);
                if (ref_float) add_agreement(row, o, *ref_float, hf.width, hf.height, inside);
                job.emit(std::move(row), job.errors_of(o), m, backend->name(), v, std::move(shows),
                         &o);
            } catch (const std::exception& e) {
                ResultRow row;
                row.fail(e.what());
                row.set_text("shader", backend->shader_of(*m.method));
                job.emit(std::move(row), {}, m, backend->name(), v);
            }
        }
        if (is_reference && float_row && ref_double)  // what float precision itself costs
            add_precision_agreement(
                compare_outputs(*ref_float, *ref_double, hf.width, hf.height, inside),
                job.out.rows[*float_row]);
    }
}

// The view's rows of the backends in a process of their own, posted to the lane in the order
// run_method takes them (methods x those backends x variants).
void post_side_rows(const ViewJob& job, SideRows& side) {
    const FieldContext& c = job.c;
    const ViewInput in = job.input();
    for (const auto& m : c.ex.methods) {
        if (!m.runs_on(c.spec.name)) continue;
        for (const auto& backend : c.backends) {
            if (!backend->own_process() || !backend->runs(m)) continue;
            Backend* b = backend.get();
            for (const Variant& v : b->variants())
                side.add(
                    [&m, &job, b, in, v] {
                        const MethodResources res = job.resources_of(m);
                        ViewInput vin = in;
                        if (!res.items.empty()) vin.resources = &res;
                        return b->run(m, vin, v);
                    },
                    [&m, b] { return b->shader_of(*m.method); });
        }
    }
}

// Each sample's lambda from its footprint (section 10), and their mean over the inside.
void set_lambda(ViewJob& job) {
    const View& view = job.view;
    job.lambda.resize(view.size());
    double lod_sum = 0;
    size_t inside = 0;
    for (size_t k = 0; k < view.size(); ++k) {
        job.lambda[k] = view.J.empty()
                            ? 0.0
                            : footprint_lod(view.footprint(k), job.c.hf.width, job.c.hf.height);
        if (!view.is_inside(k)) continue;
        ++inside;
        lod_sum += std::max(job.lambda[k], 0.0);
    }
    job.lod_mean = inside ? lod_sum / double(inside) : NAN;
}

}  // namespace

namespace {

// One view at `samples` of the camera's pixels; `shade`: the backends with their own shading
// shade their images ([shading]).
ViewRows evaluate(const FieldContext& c, double theta, double phi, size_t camera, bool timed,
                  int samples, bool shade) {
    const auto cam =
        Camera::create(c.ex.camera, c.ex.camera_settings[camera], {theta, phi, samples});
    // The methods' view of the base (P, V, footprint, frame per sample) and its truth's rays.
    const BaseView bv = c.base_entry.view(*cam, c.base, c.spec.scale * (1 - c.spec.bias));
    const View& view = bv.view;
    if (const std::string why = view_problem(view); !why.empty())
        throw std::logic_error("camera '" + c.ex.camera + "': " + why);
    // V: the view's direction; a camera whose rays are not parallel gives each sample its own.
    const Scene<double> scene{c.spec.scale, c.spec.bias, view_vector(theta, phi),
                              c.hf.width,   c.hf.height, c.base.curvature()};
    ViewJob job{c, theta, phi, camera, timed, view, scene, {}, {}, nullptr, {}, {}, NAN, {}};
    job.shade = shade;
    set_lambda(job);
    // Where nothing is timed, the rows of backends in a process of their own are drawn on the
    // run's lane while this thread traces the truth and runs the other rows (declared after
    // `job`: it waits for the lane before what the drawing reads is gone).
    std::optional<SideRows> side;
    if (c.lane && (!timed || c.times_nothing)) {
        side.emplace(*c.lane);
        job.side = &*side;
        post_side_rows(job, *side);
    }
    job.truth = c.truth.trace(bv, theta, phi, timed);
    job.spacing = float_spacing(view, c.hf.width, c.hf.height);
    job.holes = hole_mask(c.hf, job.truth.gt);
    if (c.ex.exclude_filled && !job.holes.on_filled.empty()) job.exclude = &job.holes.on_filled;
    for (const auto& m : c.ex.methods)
        if (m.runs_on(c.spec.name)) run_method(job, m);
    job.out.truth_uv = std::move(job.truth.gt.uv);
    if (job.truth.cover) job.out.truth_hit = job.truth.cover->truth_hit;
    job.out.inside = view.inside;
    job.out.lambda = std::move(job.lambda);
    return std::move(job.out);
}

}  // namespace

ViewRows evaluate_view(const FieldContext& c, double theta, double phi, size_t camera, bool timed) {
    ViewRows out = evaluate(c, theta, phi, camera, timed, c.ex.samples, timed);
    // [shading] under a `samples` subset of the camera's image: the whole image's uv for the
    // shaded images (every setting run again at every pixel, untimed; its numbers unused).
    const double resolution = c.ex.camera_settings[camera].get("resolution");
    if (timed && c.ex.shading && std::isfinite(resolution) && int(resolution) > c.ex.samples)
        out.whole = std::make_shared<ViewRows>(
            evaluate(c, theta, phi, camera, false, int(resolution), true));
    return out;
}

}  // namespace pxh
