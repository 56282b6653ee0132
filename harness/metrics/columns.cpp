#include "harness/metrics/columns.h"

#include <algorithm>
#include <deque>
#include <stdexcept>
#include <unordered_map>

#include "harness/backends/backend.h"
#include "harness/metrics/metric.h"
#include "harness/scene/view.h"

namespace pxh {
namespace {

constexpr ColumnType kText = ColumnType::text, kInt = ColumnType::integer,
                     kNum = ColumnType::number;
constexpr ColumnRole kKey = ColumnRole::key, kMeasured = ColumnRole::measured;
constexpr ColumnAxis kNamed = ColumnAxis::named, kQuiet = ColumnAxis::quiet;

// What ran: the keys of a row.
std::vector<ColumnSpec> run_columns() {
    return {
        // What ran (harness/run/runner.cpp fills them).
        {"method", kText, kKey, "the method (methods/NAME)", kNamed},
        {"params", kText, kKey, "its parameters, canonical (k=v;k=v)", kNamed},
        {"heightfield", kText, kKey, "the height field's name in the experiment", kNamed},
        {"heightfield_id", kText, kKey, "generator + parameters, or file + sha256"},
        {"backend", kText, kKey, "cpu | glsl", kNamed},
        {"precision", kText, kKey, "float | double (GLSL: float)", kNamed},
        {"texture_format", kText, kKey, "GLSL rows: r32f | r16 | r8", kNamed},
        {"shader", kText, kKey, "GLSL rows: builtin, or the shader file(s) compiled"},
        {"shader_sha256", kText, kKey, "GLSL rows: sha256 of the method's shader source compiled"},
        {"scale", kNum, kKey, "height scale s", kNamed, "s"},
        {"bias", kNum, kKey, "height bias b", kNamed, "b"},
        {"base", kText, kKey,
         "the base surface the field displaces: plane | cylinder | sphere (empty: the plane)",
         kNamed},
        {"radius", kNum, kKey, "curved bases: the radius R (tiles)", kNamed, "R"},
        {"theta_deg", kNum, kKey, "view angle from the normal (degrees)", kNamed, "theta"},
        {"phi_deg", kNum, kKey, "view azimuth (degrees)", kNamed, "phi"},
        {"samples", kInt, kKey,
         "samples per side: the N x N grid, or the N x N pixels measured of a camera's image",
         kQuiet},
        {"width", kInt, kKey, "height field width (texels)"},
        {"height", kInt, kKey, "height field height (texels)"},
        {"camera", kText, kKey, "orthographic | perspective ([views] camera)", kQuiet},
        // Here: each camera's own keys (CameraEntry::keys, harness/scene/), in registry order.
        {"lod", kText, kKey, "texture level mode: base | level | grad | implicit", kNamed},
        {"depth", kText, kKey, "depth mode: the point whose depth is written: base | hit | engine",
         kNamed},
        {"cut", kNum, kKey, "[views] cut: height c of the opaque plane z = s (c - b) tested",
         kNamed},
    };
}

// The error statistics and the height fetches.
std::vector<ColumnSpec> error_columns() {
    return {
        // Error statistics (harness/metrics/error_stats.cpp).
        {"err_mean", kNum, kMeasured, "mean texel error |e| over the finite samples"},
        {"err_rms", kNum, kMeasured, "root mean square texel error"},
        {"err_p50", kNum, kMeasured, "median texel error"},
        {"err_p95", kNum, kMeasured, "95th-percentile texel error"},
        {"err_p99", kNum, kMeasured, "99th-percentile texel error"},
        {"err_max", kNum, kMeasured, "largest texel error"},
        {"frac_gt_0_5", kNum, kMeasured, "fraction of finite samples more than 0.5 texel off"},
        {"frac_gt_1", kNum, kMeasured, "fraction of finite samples more than 1 texel off"},
        {"nonfinite", kInt, kMeasured,
         "samples whose output is NaN/Inf, discards not included (left out above)"},
        {"samples_discarded", kInt, kMeasured,
         "samples the method discarded (a silhouette method's miss: GLSL `discard`, the C++ "
         "twin's NaN answer; a GLSL fragment left unwritten too); not in nonfinite, fetches "
         "not counted"},
        {"samples_outside", kInt, kMeasured,
         "pixels outside the view (V.z <= cos 89 deg), left out of every statistic"},
        {"lod_mean", kNum, kMeasured, "mean of max(lambda, 0) over the inside pixels"},
        {"err_px_mean", kNum, kMeasured, "mean pixel error |J^-1 e_uv| (screen pixels)"},
        {"err_px_p50", kNum, kMeasured, "median pixel error"},
        {"err_px_p95", kNum, kMeasured, "95th-percentile pixel error"},
        {"err_px_max", kNum, kMeasured, "largest pixel error"},
        // Height fetches (harness/metrics/fetches.cpp).
        {"fetches_mean", kNum, kMeasured,
         "filtered lookups (height map or precomputed map) per sample, mean"},
        {"fetches_max", kNum, kMeasured,
         "filtered lookups (height map or precomputed map) per sample, max"},
        {"fetches_bound", kInt, kKey, "the method's declared fetch bound for this view"},
    };
}

// Timing, agreement between backends and precisions, sweeps.
std::vector<ColumnSpec> timing_columns() {
    return {
        // Timing (harness/metrics/timing.cpp), in the unit the row's backend names; each
        // backend's counters follow time_repeats (from the backends' registry entries).
        {"time", kNum, kMeasured, "median time of the timed repeats, in time_unit"},
        {"time_unit", kText, kMeasured, "the backend's unit: ns/sample (cpu), ms/frame (glsl)"},
        {"time_min", kNum, kMeasured, "fastest repeat (time_unit)"},
        {"time_max", kNum, kMeasured, "slowest repeat (time_unit)"},
        {"time_repeats", kText, kMeasured,
         "every timed repeat (time_unit), ';'-separated, in the order measured"},
        // Agreement between backends and precisions (harness/metrics/agreement.cpp).
        {"cpu_diff_max", kNum, kMeasured, "GLSL: max |uv_glsl - uv_cpu_float| (texels)"},
        {"cpu_diff_p999", kNum, kMeasured, "GLSL: p99.9 |uv_glsl - uv_cpu_float| (texels)"},
        {"decision_mismatch", kInt, kMeasured, "GLSL: samples whose fetch count differs from CPU"},
        {"cpu_diff_skipped", kInt, kMeasured,
         "GLSL: samples neither twin answered (both discarded or non-finite): left out of "
         "cpu_diff_* and decision_mismatch"},
        {"depth_cpu_diff_p999", kNum, kMeasured,
         "GLSL: p99.9 |depth written - the CPU float twin's| (tiles, read back from the depth "
         "target)"},
        {"double_diff_max", kNum, kMeasured, "CPU float: max |uv_float - uv_double| (texels)"},
        {"double_diff_p999", kNum, kMeasured, "CPU float: p99.9 |uv_float - uv_double| (texels)"},
        {"double_diff_skipped", kInt, kMeasured,
         "CPU float: samples neither precision answered: left out of double_diff_*"},
        // Sweeps (harness/metrics/sweep.cpp).
        {"sliding", kNum, kMeasured, "|mean change of e| / dt (texels per degree)"},
        {"shimmering", kNum, kMeasured, "mean |change of e - mean change| / dt (texels/degree)"},
        {"sweep_dt_deg", kNum, kMeasured, "the dt the two above were measured over (degrees)"},
        {"sliding_dist", kNum, kMeasured,
         "perspective: |mean change of e| / dd to the next distance (texels per tile)"},
        {"shimmering_dist", kNum, kMeasured,
         "perspective: mean |change of e - mean change| / dd (texels per tile)"},
        {"sweep_dd", kNum, kMeasured,
         "the distance step dd the two above were measured over (tiles)"},
    };
}

// Error maps, pictures, ground truth, method resources, outcome.
std::vector<ColumnSpec> output_columns() {
    return {
        // Error map (harness/results/error_maps.cpp).
        {"map", kText, kMeasured, "error map PNG, relative to the results folder"},
        // Pictures of the [render] views (harness/results/pictures.cpp, metrics/image_metrics).
        {"img_psnr_db", kNum, kMeasured,
         "[render]: PSNR of its picture vs the truth's (dB; inf: =)"},
        {"img_ssim", kNum, kMeasured, "[render]: mean SSIM (Wang et al. 2004) of the pictures"},
        {"picture", kText, kMeasured, "[render]: its picture (PNG, relative to the folder)"},
        {"picture_diff", kText, kMeasured, "[render]: |its picture - the truth's| (PNG)"},
        {"picture_truth", kText, kMeasured, "[render]: the truth's picture of the view (PNG)"},
        {"picture_use", kText, kMeasured, "[render]: montage | strip | montage strip"},
        // Ground truth (harness/metrics/ground_truth_metrics.cpp).
        {"gt_on_filled", kNum, kMeasured,
         "measured fields: fraction of true hits on a filled hole"},
        {"excluded", kInt, kMeasured, "samples left out of err_* (exclude_filled = true)"},
        {"gt_cells_mean", kNum, kMeasured, "exact tracer: cells per ray given to the solver"},
        {"ground_truth", kText, kKey, "exact | embree: the reference of the err_* columns", kQuiet},
        {"gt_agree_p50", kNum, kMeasured, "|hit_exact - hit_embree| median (texels)"},
        {"gt_agree_p99", kNum, kMeasured, "|hit_exact - hit_embree| 99th percentile (texels)"},
        {"gt_agree_max", kNum, kMeasured, "|hit_exact - hit_embree| max (texels)"},
        {"gt_agree_frac_gt_0_5", kNum, kMeasured,
         "fraction of samples where they differ > 0.5 texel"},
        {"gt_residual_max", kNum, kMeasured,
         "curved bases: max |height above the base - s (h - b)| at the true hits (tiles); the "
         "gt_agree_* columns there compare the walk with itself at half the step"},
        // Here: the columns the per-output metrics declare (Metric::columns, in metric order:
        // shadows.cpp's shadow_err, shadow_soft_mae).
        // Method resources (harness/run/runner.cpp; methods/resource.h).
        {"precompute_ms", kNum, kMeasured,
         "ms to build the method's resources (this field; 0: none)"},
        {"aux_bytes", kInt, kMeasured, "bytes of the method's resources as uploaded (0: none)"},
        // Added columns go here, before status and error.
        // Outcome (always last).
        {"status", kText, kKey, "ok | failed"},
        {"error", kText, kKey, "the message when failed"},
    };
}

// THE table: every column of results.csv, in file order, grouped by the metric that fills it.
// One line per column; a new column goes where it should appear in results.csv (a new metric's
// columns before status, error).
// It is the groups above, concatenated in file order.
const std::vector<ColumnSpec>& builtin_columns() {
    static const std::vector<ColumnSpec> cols = [] {
        std::vector<ColumnSpec> all;
        for (auto group : {run_columns, error_columns, timing_columns, output_columns})
            for (ColumnSpec& c : group()) all.push_back(std::move(c));
        return all;
    }();
    return cols;
}

// Each backend's counters (its registry entry's TimingSpec): NAME (median), NAME_min, NAME_max;
// a name two backends declare is one set of columns (the first one's meaning).
std::vector<ColumnSpec> counter_columns() {
    std::vector<ColumnSpec> out;
    for (const BackendEntry& e : backend_registry())
        for (const CounterSpec& c : e.timing().counters) {
            if (std::any_of(out.begin(), out.end(),
                            [&](const ColumnSpec& s) { return s.name == c.name; }))
                continue;
            const std::string about = std::string(e.name) + ": " + c.meaning + " (" + c.unit + ")";
            out.push_back({c.name, kNum, kMeasured, "median " + about});
            out.push_back({c.name + "_min", kNum, kMeasured, "fastest repeat, " + about});
            out.push_back({c.name + "_max", kNum, kMeasured, "slowest repeat, " + about});
        }
    return out;
}

struct Hash {
    using is_transparent = void;
    size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};

struct Registry {
    std::deque<ColumnSpec> specs;  // by id; ids are never reused
    std::vector<size_t> order;     // ids in results.csv order
    std::unordered_map<std::string, size_t, Hash, std::equal_to<>> ids;

    Registry() {
        for (const auto& c : builtin_columns()) {
            if (c.name == "precompute_ms")
                for (const ColumnSpec& m : output_metric_columns()) add(m, order.size());
            add(c, order.size());
            if (c.name == "time_repeats")
                for (const auto& col : counter_columns()) add(col, order.size());
            if (c.name == "camera")
                for (const CameraEntry& cam : camera_registry())
                    for (const CameraKey& k : cam.keys) {
                        if (ids.count(k.name)) continue;  // two cameras may share a key
                        add({k.name, kNum, kKey, k.meaning, kNamed}, order.size());
                        camera_keys.push_back(k);
                    }
        }
    }
    std::vector<CameraKey> camera_keys;  // every camera's keys, in column order
    void add(const ColumnSpec& c, size_t pos) {
        if (c.name.empty() || ids.count(c.name))
            throw std::logic_error("column '" + c.name + "' registered twice (or unnamed)");
        specs.push_back(c);
        ids.emplace(c.name, specs.size() - 1);
        order.insert(order.begin() + std::ptrdiff_t(pos), specs.size() - 1);
    }
};

Registry& registry() {
    static Registry r;
    return r;
}

}  // namespace

std::vector<const ColumnSpec*> result_column_specs() {
    const Registry& r = registry();
    std::vector<const ColumnSpec*> out;
    for (size_t id : r.order) out.push_back(&r.specs[id]);
    return out;
}

const ColumnSpec* find_column(std::string_view name) {
    const Registry& r = registry();
    auto it = r.ids.find(name);
    return it == r.ids.end() ? nullptr : &r.specs[it->second];
}

size_t column_id(std::string_view name) {
    const Registry& r = registry();
    auto it = r.ids.find(name);
    if (it == r.ids.end())
        throw std::logic_error("no results column '" + std::string(name) +
                               "' is registered (harness/metrics/columns.cpp)");
    return it->second;
}

const ColumnSpec& column_spec(size_t id) { return registry().specs.at(id); }

const std::vector<CameraKey>& camera_key_columns() { return registry().camera_keys; }

std::vector<const ColumnSpec*> row_axes() {
    std::vector<const ColumnSpec*> out;
    for (const ColumnSpec* c : result_column_specs())
        if (c->axis != ColumnAxis::none) out.push_back(c);
    return out;
}

std::string range_key(const ColumnSpec& axis, bool max) {
    const std::string base = axis.name == "theta_deg" ? "theta"
                             : axis.name == "phi_deg" ? "phi"
                                                      : axis.name;
    return base + (max ? "_max" : "_min");
}

std::string axes_name(const std::function<std::string(const std::string&)>& cell) {
    // What series_of and field_of name already.
    static const char* const kInSeries[] = {"method",      "params",  "lod",       "depth",
                                            "cut",         "backend", "precision", "texture_format",
                                            "heightfield", "scale",   "bias"};
    std::string s;
    for (const ColumnSpec* c : row_axes()) {
        if (c->axis != ColumnAxis::named) continue;
        if (std::find(std::begin(kInSeries), std::end(kInSeries), c->name) != std::end(kInSeries))
            continue;
        const std::string v = cell(c->name);
        if (!v.empty()) s += " " + c->shown_as() + "=" + v;
    }
    return s;
}

ColumnRegistration::ColumnRegistration(ColumnSpec spec) : name_(spec.name) {
    Registry& r = registry();
    const size_t status =
        size_t(std::find(r.order.begin(), r.order.end(), column_id("status")) - r.order.begin());
    r.add(spec, status);
}

ColumnRegistration::~ColumnRegistration() {
    Registry& r = registry();
    auto it = r.ids.find(name_);
    if (it == r.ids.end()) return;
    r.order.erase(std::find(r.order.begin(), r.order.end(), it->second));
    r.ids.erase(it);
}

}  // namespace pxh
