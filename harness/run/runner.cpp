#include "harness/run/runner.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "harness/core/error.h"
#include "harness/experiment/view_grid.h"
#include "harness/metrics/sweep_pairs.h"
#include "harness/run/view_rows.h"
#include "harness/scene/texture_levels.h"

namespace pxh {
namespace {

std::string fmt_angle(double a) {
    std::ostringstream os;
    os << a;
    return os.str();
}

// The backends a run uses, created in the experiment's order (a GL backend creates its GL
// context).
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
                           view.cut_shows, view.shown_uv, view.truth_hit, first,
                           view.lambda,    ctx.levels,    view.shaded,    view.whole.get()};
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
    // The lane is made before the backends, so that it outlives them: a GL worker it started
    // again dies with its thread (harness/run/side_lane.h).
    std::optional<SideLane> lane;
    const auto backends = make_backends(ex, opt, settings);
    bool times_nothing = true;
    for (const auto& b : backends) {
        if (b->own_process() && !lane) lane.emplace();
        if (backend_repeats(b->name(), settings) > 0) times_nothing = false;
    }
    if (opt.warning)
        for (const auto& b : backends)
            if (const BackendEntry& e = backend_entry(b->name()); e.warnings)
                for (const auto& line : e.warnings(*b, settings)) opt.warning(line);
    const std::unique_ptr<Backend> reference = make_reference_backend(settings);
    // Height fields are built one at a time (a sweep of thousands of fields, or of scales on
    // a large one, holds one field in memory); entries that share a field (a scale/bias sweep)
    // reuse it. The image files are checked first, so that a bad file fails before any work.
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
    const bool any_levels =
        ex.shading || std::any_of(ex.methods.begin(), ex.methods.end(),
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
        // The base and its truth built once per field (and s, b, base), shared by its views.
        const BaseEntry& base = base_entry(spec.base);
        const std::unique_ptr<BaseSurface> surface = base.make(spec.radius);
        const std::unique_ptr<FieldTruth> truth =
            make_field_truth(base.truth, {ex, *field, spec, *surface});
        const FieldContext ctx{ex,
                               backends,
                               *reference,
                               *field,
                               spec,
                               *resources,
                               levels ? &*levels : nullptr,
                               base,
                               *surface,
                               *truth,
                               lane ? &*lane : nullptr,
                               times_nothing};
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
