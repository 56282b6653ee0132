#include "harness/metrics/columns.h"

#include <algorithm>
#include <deque>
#include <stdexcept>
#include <unordered_map>

#include "harness/backends/backend.h"
#include "harness/metrics/column_groups.h"
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
        {"radius", kNum, kKey, "curved bases: the radius R (tiles)", kNamed, "R", "", "tiles"},
        {"theta_deg", kNum, kKey, "view angle from the normal (degrees)", kNamed, "theta", "",
         "degrees"},
        {"phi_deg", kNum, kKey, "view azimuth (degrees)", kNamed, "phi", "", "degrees"},
        {"samples", kInt, kKey,
         "samples per side: the N x N grid, or the N x N pixels measured of a camera's image",
         kQuiet},
        {"width", kInt, kKey, "height field width (texels)"},
        {"height", kInt, kKey, "height field height (texels)"},
        {"camera", kText, kKey, "orthographic | perspective ([views] camera)", kQuiet},
        // Here: each camera's own keys (CameraEntry::keys, harness/scene/), in registry order.
        {"lod", kText, kKey, "texture level mode: base | level | grad | implicit", kNamed},
        ColumnSpec{"depth", kText, kKey,
                   "depth mode: the point whose depth is written: base | hit | engine", kNamed}
            .affecting({"depth", "cut", "timing", "agreement"}),
        ColumnSpec{"cut", kNum, kKey,
                   "[views] cut: height c of the opaque plane z = s (c - b) tested", kNamed}
            .affecting({"cut"}),
    };
}

// The error statistics and the height fetches.
std::vector<ColumnSpec> error_columns() {
    std::vector<ColumnSpec> out = error_stats_columns();
    for (ColumnSpec& c : fetches_columns()) out.push_back(std::move(c));
    return out;
}

// Timing, agreement between backends and precisions, sweeps.
std::vector<ColumnSpec> timing_group_columns() {
    std::vector<ColumnSpec> out = timing_columns();
    for (auto group : {agreement_columns, sweep_columns})
        for (ColumnSpec& c : group()) out.push_back(std::move(c));
    return out;
}

// Error maps, pictures, ground truth, method resources, outcome.
std::vector<ColumnSpec> output_columns() {
    std::vector<ColumnSpec> out = {
        // Error map (harness/run/view_writers.cpp writes it: harness/results/error_maps.cpp).
        {"map", kText, kMeasured, "error map PNG, relative to the results folder"}};
    for (ColumnSpec& c : image_columns()) out.push_back(std::move(c));  // metrics/image_metrics
    for (ColumnSpec c : std::vector<ColumnSpec>{
             // The [render] pictures' files (harness/results/pictures.cpp writes them).
             {"picture", kText, kMeasured, "[render]: its picture (PNG, relative to the folder)"},
             {"picture_diff", kText, kMeasured, "[render]: |its picture - the truth's| (PNG)"},
             {"picture_truth", kText, kMeasured, "[render]: the truth's picture of the view (PNG)"},
             {"picture_use", kText, kMeasured, "[render]: montage | strip | montage strip"},
             // [shading] with [render]: the shaded images and the FLIP map (harness/run/
             // shaded_images.cpp writes them).
             {"shaded", kText, kMeasured, "[shading]+[render]: its shaded image (PNG, sRGB)"},
             {"shaded_truth", kText, kMeasured, "[shading]+[render]: the truth's shaded image"},
             {"flip_map", kText, kMeasured, "[shading]+[render]: its FLIP map (PNG, magma)"},
             ColumnSpec{"shade_cpu_diff_max", kNum, kMeasured,
                        "[shading], GLSL: largest |GLSL-shaded - CPU-shaded| of its uv (8-bit "
                        "steps)"}
                 .in("agreement", "8-bit steps")})
        out.push_back(std::move(c));
    for (ColumnSpec& c : reference_columns()) out.push_back(std::move(c));  // metrics/reference
    // Here: the columns the per-output metrics declare (Metric::columns, in metric order:
    // shadows.cpp's shadow_err, shadow_soft_mae, depth.cpp's, coverage.cpp's).
    for (ColumnSpec c : std::vector<ColumnSpec>{
             // Method resources (harness/run/runner.cpp; methods/resource.h).
             ColumnSpec{"precompute_ms", kNum, kMeasured,
                        "ms to build the method's resources (this field; 0: none)"}
                 .in("resources", "ms")
                 .lead(),
             ColumnSpec{"aux_bytes", kInt, kMeasured,
                        "bytes of the method's resources as uploaded (0: none)"}
                 .in("resources", "bytes"),
             // Added columns go here, before status and error.
             // Outcome (always last).
             {"status", kText, kKey, "ok | failed"},
             {"error", kText, kKey, "the message when failed"}})
        out.push_back(std::move(c));
    return out;
}

// THE table: every column of results.csv, in file order, grouped by the metric that fills it.
// One line per column; a new column goes where it should appear in results.csv (a new metric's
// columns before status, error).
// It is the groups above, concatenated in file order.
const std::vector<ColumnSpec>& builtin_columns() {
    static const std::vector<ColumnSpec> cols = [] {
        std::vector<ColumnSpec> all;
        for (auto group : {run_columns, error_columns, timing_group_columns, output_columns})
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
            out.push_back(
                ColumnSpec{c.name, kNum, kMeasured, "median " + about}.in("timing", c.unit));
            out.push_back(
                ColumnSpec{c.name + "_min", kNum, kMeasured, "fastest repeat, " + about}.in(
                    "timing", c.unit));
            out.push_back(
                ColumnSpec{c.name + "_max", kNum, kMeasured, "slowest repeat, " + about}.in(
                    "timing", c.unit));
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
                        ColumnSpec spec{k.name, kNum, kKey, k.meaning, kNamed};
                        spec.unit = k.unit;
                        add(spec, order.size());
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

std::string family_title(const std::string& family) {
    static const std::pair<const char*, const char*> kTitles[] = {
        {"texel", "Texel error: |uv_method - uv_true| in texels"},
        {"pixel", "Pixel error: the texel error seen on screen (camera views)"},
        {"depth", "Depth error: |depth written - true depth| (tiles)"},
        {"cut", "Cut flips: the depth test against an opaque plane decided wrongly"},
        {"coverage", "Coverage: surface shown where the truth shows none, or missing"},
        {"sliding", "Sliding and shimmering: the error's change with the view"},
        {"image", "What a viewer sees: [render] pictures (PSNR, SSIM), [shading] images (FLIP)"},
        {"fetches", "Height fetches per sample"},
        {"timing", "Time"},
        {"agreement", "Agreement between backends and precisions"},
        {"truth",
         "Ground truth checked: by Embree (plane), by the walk at half the step on "
         "gt_agree_rays rays (curved)"},
        {"resources", "Method resources"},
        {"shadow", "Self-shadowing error"},
    };
    for (const auto& [name, title] : kTitles)
        if (family == name) return title;
    return family;
}

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

bool series_key(std::string_view c) {
    for (const char* k :
         {"method", "params", "lod", "depth", "cut", "backend", "precision", "texture_format"})
        if (c == k) return true;
    return false;
}
bool field_key(std::string_view c) { return c == "heightfield" || c == "scale" || c == "bias"; }
bool sweep_key(std::string_view c) { return c == "theta_deg" || c == "phi_deg"; }
bool context_key(const ColumnSpec& c) {
    return c.axis != ColumnAxis::none && !series_key(c.name) && !field_key(c.name) &&
           !sweep_key(c.name);
}

std::vector<std::string> varying_context_keys(
    size_t rows, const std::function<std::string(size_t, const std::string&)>& cell) {
    std::vector<std::string> keys;
    for (const ColumnSpec* c : row_axes()) {
        if (!context_key(*c) || rows == 0) continue;
        const std::string first = cell(0, c->name);
        for (size_t r = 1; r < rows; ++r)
            if (cell(r, c->name) != first) {
                keys.push_back(c->name);
                break;
            }
    }
    return keys;
}

std::string axes_name(const std::function<std::string(const std::string&)>& cell) {
    std::string s;
    for (const ColumnSpec* c : row_axes()) {
        if (c->axis != ColumnAxis::named) continue;
        if (series_key(c->name) || field_key(c->name)) continue;
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
