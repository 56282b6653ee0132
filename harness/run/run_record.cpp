#include "harness/run/run_record.h"

#include <map>
#include <set>

#include "harness/core/error.h"
#include "harness/core/safe_files.h"
#include "harness/core/sha256.h"
#include "harness/results/provenance.h"
#include "harness/results/run_folder.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/exact_tracer.h"

namespace pxh {

namespace {

// run.json's record of the inputs: the experiment and every image a height field was read
// from, with its sha256.
nlohmann::json input_records(const Experiment& ex) {
    nlohmann::json inputs = nlohmann::json::array();
    std::set<std::string> seen;
    inputs.push_back({{"experiment", ex.path}, {"sha256", sha256_hex(ex.text)}});
    for (const auto& h : ex.heightfields)  // hashed once, when the experiment was read
        if (!h.source_path.empty() && seen.insert(h.source_path).second)
            inputs.push_back(
                {{"heightfield", h.name}, {"path", h.source_path}, {"sha256", h.source_sha256}});
    return inputs;
}

}  // namespace

nlohmann::json tracer_record() {
    const char* env = std::getenv("PXH_TRACER_PATH");
    return {{"exact_path", ExactTracer::path_name(ExactTracer::default_path())},
            {"exact_cpu_best_path", ExactTracer::path_name(ExactTracer::cpu_best_path())},
            {"embree_isa", EmbreeTracer::isa()},
            {"embree_device_config", EmbreeTracer::device_config()},
            {"pxh_tracer_path_env", env ? env : ""}};
}

nlohmann::json run_record(const Experiment& ex, const RunCall& call, const RunInfo& info) {
    nlohmann::json run = provenance(call.threads);
    run["command_line"] = call.command_line;
    run["experiment_file"] = ex.path;
    run["experiment"] = ex.text;
    run["experiment_name"] = ex.name;
    run["inputs"] = input_records(ex);
    run["warnings"] = ex.warnings;
    // Plug-in shaders: each file's source as read (and checked) when the experiment was
    // parsed, the text that was compiled, and its sha256.
    nlohmann::json plugins = nlohmann::json::array();
    for (const auto& p : ex.plugins)
        plugins.push_back({{"method", p->name},
                           {"path", p->plugin_shader},
                           {"sha256", sha256_hex(p->plugin_source)},
                           {"source", p->plugin_source}});
    if (!plugins.empty()) run["plugin_shaders"] = plugins;
    run["backends"] = info.backends;
    // The tracers' paths (results depend on them: Embree's hits differ between ISAs, the
    // exact tracer's cost columns between paths); merge refuses slices of other paths.
    run["tracers"] = tracer_record();
    return run;
}

nlohmann::json shard_record(const Experiment& ex, const Slice& s, const ShardSelection& sel,
                            const RunInfo& info) {
    std::map<size_t, size_t> rows;  // unit -> rows
    for (const auto& v : info.views) rows[s.unit(v.at)] += v.rows;
    nlohmann::json units = nlohmann::json::array();
    double cost = 0, total = 0;
    for (const auto& u : s.units) total += u.cost;
    for (size_t i : s.mine) {
        const WorkUnit& u = s.units[i];
        const HeightfieldSpec& h = ex.heightfields[u.field];
        std::vector<double> thetas(ex.theta_deg.begin() + long(u.theta_begin),
                                   ex.theta_deg.begin() + long(u.theta_end));
        units.push_back({{"unit", i},
                         {"heightfield", h.name},
                         {"scale", h.scale},
                         {"bias", h.bias},
                         {"phi_deg", ex.phi_deg[u.phi]},
                         {"camera", ex.camera_settings[u.camera].label()},
                         {"theta_deg", thetas},
                         {"rows", rows[i]},
                         {"cost", u.cost}});
        cost += u.cost;
    }
    return {{"index", s.shard.index},
            {"count", s.shard.count},
            {"partition", kPartitionScheme},
            {"experiment_sha256", sha256_hex(ex.text)},
            {"selection",
             {{"only", sel.only},
              {"samples", ex.samples},
              {"backends", sel.backends},
              {"gl", sel.gl},
              {"shader_dir",
               sel.shader_dir.empty() ? "" : std::filesystem::absolute(sel.shader_dir).string()},
              {"maps", ex.maps}}},
            {"build", build_record()},
            {"units_total", s.units.size()},
            {"cost", cost},
            {"cost_total", total},
            {"units", units}};
}

void finish_run_record(nlohmann::json& run, const std::vector<ResultRow>& rows, double seconds,
                       const std::filesystem::path& dir) {
    size_t failed = 0;
    for (const auto& r : rows) failed += !r.ok();
    run["rows"] = rows.size();
    run["failed_rows"] = failed;
    run["seconds"] = seconds;
    // Written last: the sha256 of every file above (pxh check and report verify them).
    run["files"] = file_records(dir);
    create_new_file(dir / "run.json", run.dump(2) + "\n");
}

void check_recordable(const std::string& out_dir, const std::string& command_line,
                      const std::string& shader_dir) {
    if (const std::string why = utf8_problem(out_dir); !why.empty())
        throw InputError("--out", "is not UTF-8 (" + why + "); run.json records it");
    if (const std::string why = utf8_problem(command_line); !why.empty())
        throw InputError("command line", "an argument is not UTF-8 (" +
                                             why.substr(why.find(',') + 2) +
                                             "); run.json records the command line");
    if (!shader_dir.empty())  // recorded as an absolute path: the current folder's too
        if (const std::string why = utf8_problem(std::filesystem::absolute(shader_dir).string());
            !why.empty())
            throw InputError("--shader-dir",
                             "its absolute path is not UTF-8 (" + why + "); run.json records it");
}

nlohmann::json parse_run_record(const std::string& text, const std::string& path) {
    nlohmann::json run;
    try {
        run = nlohmann::json::parse(text);
    } catch (const std::exception& e) {
        throw InputError(path, std::string("unreadable: ") + e.what());
    }
    if (!run.is_object()) throw InputError(path, "unreadable: not a JSON object");
    return run;
}

const nlohmann::json& shard_record_of(const nlohmann::json& run, const std::string& path,
                                      const std::string& dir) {
    if (!run.contains("shard") || !run["shard"].is_object())
        throw InputError(dir,
                         "is not a slice: its run.json has no shard record (written by pxh "
                         "run --shard I/N)");
    const nlohmann::json& shard = run["shard"];
    for (const char* k : {"index", "count", "units_total"})
        if (!shard.contains(k) || !shard[k].is_number_unsigned())
            throw InputError(path, std::string("shard record without '") + k + "'");
    for (const char* k : {"partition", "experiment_sha256", "selection", "build", "units"})
        if (!shard.contains(k))
            throw InputError(path, std::string("shard record without '") + k + "'");
    if (!shard["units"].is_array()) throw InputError(path, "shard record: 'units' is not a list");
    return shard;
}

}  // namespace pxh
