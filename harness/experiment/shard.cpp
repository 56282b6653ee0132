#include "harness/experiment/shard.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "harness/core/error.h"
#include "harness/core/sha256.h"
#include "harness/results/provenance.h"
#include "harness/scene/scene.h"
#include "harness/scene/view.h"

namespace pxh {

ShardSpec parse_shard(const std::string& text) {
    const auto bad = [&](const std::string& why) {
        return InputError("--shard", "'" + text + "' " + why +
                                         " (I/N with 0 <= I < N, e.g. "
                                         "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)");
    };
    const auto slash = text.find('/');
    if (slash == std::string::npos) throw bad("is not I/N");
    const auto number = [&](const std::string& s) -> size_t {
        if (s.empty() || s.size() > 9 ||
            !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }))
            throw bad("is not I/N");
        return size_t(std::stoul(s));
    };
    ShardSpec s{number(text.substr(0, slash)), number(text.substr(slash + 1))};
    if (s.count == 0) throw bad("has N = 0");
    if (s.index >= s.count) throw bad("has I >= N (slices are numbered from 0)");
    return s;
}

namespace {

constexpr double kSetupPerTexel = 64;  // Embree's BVH and the mipmap, in sample-steps per texel

// One view's cost per sample: both references and every row's method evaluations.
double view_cost(const Experiment& ex, const HeightfieldSpec& h, const FieldSize& size,
                 double theta, double phi, const std::vector<std::string>& backends,
                 const BackendSettings& settings, bool timed) {
    const double side = double(std::max(size.width, size.height));
    const double t = std::min(theta, 89.9) * std::numbers::pi / 180.0;
    double cost = 2 + h.scale * std::tan(t) * side;
    const Scene<double> scene{h.scale, h.bias, view_vector(theta, phi), int(size.width),
                              int(size.height)};
    for (const auto& m : ex.methods) {
        if (!m.runs_on(h.name)) continue;
        const double fetches = m.method->max_fetches
                                   ? double(m.method->max_fetches(m.params, scene))
                                   : double(std::max(1, m.method->declared_max_fetches));
        for (const auto& b : backends) {
            if (b == "cpu" && !m.method->run_float) continue;  // no C++ twin, no CPU row
            // One untimed pass (the results), then the backend's own timed repeats.
            const double passes = timed ? 1.0 + backend_repeats(b, settings) : 1.0;
            cost += double(backend_variants(b, settings).size()) * std::max(1.0, fetches) * passes;
        }
    }
    return cost;
}

}  // namespace

std::vector<WorkUnit> work_units(const Experiment& ex,
                                 const std::vector<std::string>& backends_override) {
    const auto& backends = backends_override.empty() ? ex.backends : backends_override;
    const BackendSettings settings = backend_settings(ex);
    const double samples = double(ex.samples) * double(ex.samples);
    const bool per_view = ex.sweep_dt_deg > 0;
    std::vector<WorkUnit> units;
    const ViewGrid grid(ex);
    std::vector<FieldSize> sizes;  // each field's, read once (a file's from its header)
    for (const auto& h : ex.heightfields) sizes.push_back(field_size(h));
    for (size_t s = 0; s < grid.sweeps(); ++s) {  // in run order
        const ViewAt at = grid.sweep(s);
        const HeightfieldSpec& h = ex.heightfields[at.field];
        const FieldSize& size = sizes[at.field];
        const double setup = double(size.width) * double(size.height) * kSetupPerTexel;
        const double phi = ex.phi_deg[at.phi];
        WorkUnit u{at.field, at.phi, 0, 0, setup, at.camera};
        for (size_t t = 0; t < grid.thetas; ++t) {
            const double theta = ex.theta_deg[t];
            u.cost += samples * view_cost(ex, h, size, theta, phi, backends, settings, true);
            if (per_view) {
                const double other = theta + ex.sweep_dt_deg < 90 ? theta + ex.sweep_dt_deg
                                                                  : theta - ex.sweep_dt_deg;
                u.cost += samples * view_cost(ex, h, size, other, phi, backends, settings, false);
                u.theta_begin = t;
                u.theta_end = t + 1;
                units.push_back(u);
                u.cost = setup;
            }
        }
        if (!per_view) {
            u.theta_end = grid.thetas;
            units.push_back(u);
        }
    }
    return units;
}

std::vector<size_t> shard_units(const std::vector<WorkUnit>& units, const ShardSpec& shard) {
    if (shard.count > units.size())
        throw InputError(
            "--shard",
            shard.text() + ": the run has " + std::to_string(units.size()) +
                " units of work (theta sweeps of a field at an azimuth and camera setting; "
                "views with sweep_dt_deg), so at most " +
                std::to_string(units.size()) + " slices");
    std::vector<size_t> order(units.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return units[a].cost > units[b].cost; });
    std::vector<double> load(shard.count, 0.0);
    std::vector<size_t> mine;
    for (size_t u : order) {
        const size_t s = size_t(std::min_element(load.begin(), load.end()) - load.begin());
        load[s] += units[u].cost;
        if (s == shard.index) mine.push_back(u);
    }
    std::sort(mine.begin(), mine.end());
    return mine;
}

Slice make_slice(const Experiment& ex, const ShardSpec& shard,
                 const std::vector<std::string>& backends_override) {
    Slice s{shard, work_units(ex, backends_override), {}, ViewGrid(ex), {}};
    s.mine = shard_units(s.units, s.shard);
    s.unit_of.assign(s.grid.views(), -1);
    for (size_t u : s.mine)
        for (size_t t = s.units[u].theta_begin; t < s.units[u].theta_end; ++t)
            s.unit_of[s.grid.index({s.units[u].field, s.units[u].phi, s.units[u].camera, t})] =
                int(u);
    return s;
}

nlohmann::json build_record() {
    const nlohmann::json p = provenance(0);
    nlohmann::json b;
    // The release, not the source tree's state when the slice ran (git describe, commit and
    // dirty flag are in the slice's own provenance): a tree edited or pulled while an array
    // waits in the queue does not change the binary that runs.
    const std::string version = p["pxh_version"].get<std::string>();
    b["pxh_version"] = version.substr(0, version.find(" ("));
    for (const char* k : {"compiler", "compile_flags", "build_type", "libraries"}) b[k] = p[k];
    b["binary_sha256"] = sha256_file("/proc/self/exe");
    return b;
}

}  // namespace pxh
