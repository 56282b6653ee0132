// `pxh run FILE`: runs an experiment, writes results.csv and run.json into a results folder.
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "harness/commands/commands.h"
#include "harness/commands/summary.h"
#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/core/safe_files.h"
#include "harness/core/sha256.h"
#include "harness/experiment/experiment.h"
#include "harness/experiment/shard.h"
#include "harness/gl/context.h"
#include "harness/results/provenance.h"
#include "harness/results/run_folder.h"
#include "harness/run/runner.h"
#include "harness/run/view_writers.h"

namespace fs = std::filesystem;

namespace pxh {
namespace {

// "0:07", "12:34", "1:02:03": a duration in seconds as the progress line shows it.
std::string clock_time(double secs) {
    const long t = long(secs + 0.5), h = t / 3600, m = t / 60 % 60, sec = t % 60;
    char b[32];
    if (h) std::snprintf(b, sizeof b, "%ld:%02ld:%02ld", h, m, sec);
    else std::snprintf(b, sizeof b, "%ld:%02ld", m, sec);
    return b;
}

struct RunArgs {
    std::string file, out_dir, shader_dir;
    std::string gl;  // GL context; empty: the experiment's (default osmesa)
    int threads = 0;
    std::vector<std::string> backends;
    bool quiet = false, maps = false, force = false;
    long long max_rows = (long long)kDefaultMaxRows;  // checked >= 1 (-1 must not wrap)
    bool out_given = false;                           // --out given (then never empty)
    std::string max_memory;                           // e.g. "8G"; empty = kDefaultMaxMemoryBytes
    std::string only;            // --only KEY=V,...: a subset of the experiment
    std::optional<int> samples;  // --samples N: overrides the file (absent: the file's)
    std::string shard;           // --shard I/N: run slice I of N (harness/experiment/shard.h)
    double gl_time_limit = 0;    // --gl-time-limit S: overrides the file's gl_time_limit_s
    bool gl_time_limit_given = false;
};

// "123", "512M", "8G", "1.5T" (binary units) -> bytes.
size_t parse_bytes(const std::string& text) {
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (...) {
        used = 0;
    }
    std::string unit = text.substr(used);
    for (auto& c : unit) c = char(std::toupper((unsigned char)c));
    if (!unit.empty() && unit.back() == 'B') unit.pop_back();
    if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();  // GiB, MiB
    const std::map<std::string, double> mult = {
        {"", 1.0}, {"K", 1024.0}, {"M", 1048576.0}, {"G", 1073741824.0}, {"T", 1099511627776.0}};
    if (used == 0 || !mult.count(unit) || !(v > 0) || !std::isfinite(v * mult.at(unit)) ||
        v * mult.at(unit) > 1e18)
        throw InputError("--max-memory", "'" + text + "' is not a size (e.g. 512M, 8G)");
    return size_t(v * mult.at(unit));
}

// The run's size, estimated before any work: a small file must not take the machine.
void check_run_size(const Experiment& ex, const RunArgs& a) {
    const size_t max_memory =
        a.max_memory.empty() ? kDefaultMaxMemoryBytes : parse_bytes(a.max_memory);
    const RunEstimate est = estimate_run(ex, a.backends);
    if (est.rows > size_t(a.max_rows))
        throw InputError(ex.path, "the run would write " + std::to_string(est.rows) +
                                      " rows, over the limit of " + std::to_string(a.max_rows) +
                                      " (raise it with --max-rows N)");
    if (est.peak_bytes > max_memory)
        throw InputError(ex.path, "the run would need about " + format_bytes(est.peak_bytes) +
                                      " of memory, over the limit of " + format_bytes(max_memory) +
                                      " (" + est.detail + "; raise it with --max-memory SIZE)");
}

// run.json's record of the inputs: every image a height field was read from, with its sha256.
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

nlohmann::json run_record(const Experiment& ex, const RunArgs& a, const RunInfo& info,
                          const std::string& command_line, int nthreads) {
    nlohmann::json run = provenance(nthreads);
    run["command_line"] = command_line;
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
    if (!info.gl_renderer.empty()) {
        run["gl_renderer"] = info.gl_renderer;
        run["gl_version"] = info.gl_version;
        const char* lp = std::getenv("LP_NUM_THREADS");
        run["LP_NUM_THREADS"] = lp ? lp : "";
        run["shader_dir"] = a.shader_dir.empty() ? "" : fs::absolute(a.shader_dir).string();
        run["shaders"] = info.shaders;
        run["gl"] = {{"context", info.gl_context},
                     {"GL_VENDOR", info.gl_vendor},
                     {"GL_RENDERER", info.gl_renderer},
                     {"GL_VERSION", info.gl_version},
                     {"GL_QUERY_COUNTER_BITS", info.gl_timer_bits},
                     {"driver", info.gl_driver}};
    }
    return run;
}

// A failure is never a success: name the failed rows (their metrics are empty).
void print_failed_rows(const std::vector<ResultRow>& rows, size_t failed) {
    size_t shown = 0;
    for (const auto& r : rows) {
        if (r.ok()) continue;
        if (++shown > 10) {
            std::cerr << "pxh: ... and " << failed - 10
                      << " more failed rows (status=failed in results.csv)\n";
            break;
        }
        std::cerr << "pxh: failed row: " << setting_of(r) << " | " << r.text("heightfield")
                  << " | theta " << format_number(r.num("theta_deg")) << " phi "
                  << format_number(r.num("phi_deg")) << " | " << group_of(r) << ": "
                  << one_line(r.text("error")) << "\n";
    }
}

// --shard I/N: which units of the run this slice takes.
struct Slice {
    ShardSpec shard;
    std::vector<WorkUnit> units;  // all of the run's
    std::vector<size_t> mine;     // indices into units
    std::vector<int> unit_of;     // per (field, phi, camera, theta) view: its unit, -1 another's
    size_t view_index(const Experiment& ex, size_t f, size_t p, size_t c, size_t t) const {
        return ((f * ex.phi_deg.size() + p) * ex.camera_settings.size() + c) * ex.theta_deg.size() +
               t;
    }
};

Slice make_slice(const Experiment& ex, const RunArgs& a) {
    Slice s;
    s.shard = parse_shard(a.shard);
    s.units = work_units(ex, a.backends);
    s.mine = shard_units(s.units, s.shard);
    s.unit_of.assign(ex.heightfields.size() * ex.phi_deg.size() * ex.camera_settings.size() *
                         ex.theta_deg.size(),
                     -1);
    for (size_t u : s.mine)
        for (size_t t = s.units[u].theta_begin; t < s.units[u].theta_end; ++t)
            s.unit_of[s.view_index(ex, s.units[u].field, s.units[u].phi, s.units[u].camera, t)] =
                int(u);
    return s;
}

// run.json's "shard": what the slice is of (pxh merge checks that every slice is of the same
// run) and what it covers, unit by unit with its rows in results.csv order.
nlohmann::json shard_record(const Experiment& ex, const RunArgs& a, const Slice& s,
                            const RunInfo& info) {
    nlohmann::json units = nlohmann::json::array();
    std::map<size_t, size_t> rows;  // unit -> rows
    for (const auto& v : info.views)
        rows[size_t(s.unit_of[s.view_index(ex, v.field, v.phi, v.camera, v.theta)])] += v.rows;
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
    const auto& backends = a.backends.empty() ? ex.backends : a.backends;
    return {{"index", s.shard.index},
            {"count", s.shard.count},
            {"partition", kPartitionScheme},
            {"experiment_sha256", sha256_hex(ex.text)},
            {"selection",
             {{"only", a.only},
              {"samples", ex.samples},
              {"backends", backends},
              {"gl", a.gl},
              {"shader_dir", a.shader_dir.empty() ? "" : fs::absolute(a.shader_dir).string()},
              {"maps", ex.maps}}},
            {"build", build_record()},
            {"units_total", s.units.size()},
            {"cost", cost},
            {"cost_total", total},
            {"units", units}};
}

void print_slice(const Slice& s, const nlohmann::json& rec) {
    std::cout << "shard " << s.shard.text() << ": " << s.mine.size() << " of " << s.units.size()
              << " units, " << std::setprecision(1) << std::fixed
              << 100.0 * rec["cost"].get<double>() / rec["cost_total"].get<double>()
              << "% of the estimated cost (pxh merge OUT DIR... joins the slices)\n";
}

// The command line's own checks, before the experiment is read: --out and every argument go
// into run.json, so they must be UTF-8 (else the run would end in a JSON error).
void check_run_args(const RunArgs& a, const std::string& command_line) {
    if (a.out_given && a.out_dir.empty())
        throw InputError("--out",
                         "is empty: name the results folder (or leave --out out for "
                         "results/runs/NAME-DATE)");
    if (const std::string why = utf8_problem(a.out_dir); !why.empty())
        throw InputError("--out", "is not UTF-8 (" + why + "); run.json records it");
    if (const std::string why = utf8_problem(command_line); !why.empty())
        throw InputError("command line", "an argument is not UTF-8 (" +
                                             why.substr(why.find(',') + 2) +
                                             "); run.json records the command line");
    if (!a.shader_dir.empty())  // recorded as an absolute path: the current folder's too
        if (const std::string why = utf8_problem(fs::absolute(a.shader_dir).string()); !why.empty())
            throw InputError("--shader-dir",
                             "its absolute path is not UTF-8 (" + why + "); run.json records it");
    for (const auto& b : a.backends) check_backend_name(b, "--backend");
    if (a.max_rows < 1)
        throw InputError("--max-rows", std::to_string(a.max_rows) + " is not a row count (>= 1)");
    if (!a.gl.empty() && !find_gl_context(a.gl))
        throw InputError("--gl",
                         "unknown GL context '" + a.gl + "' (known: " + gl_context_names() + ")");
}

int cmd_run(const RunArgs& a, const std::string& command_line) {
    check_run_args(a, command_line);
    ParseLimits limits;  // sweeps are counted against these before they are expanded
    limits.max_rows = size_t(a.max_rows);
    limits.max_memory = a.max_memory.empty() ? kDefaultMaxMemoryBytes : parse_bytes(a.max_memory);
    limits.backends = a.backends;
    Experiment ex = load_experiment(a.file, limits);
    ex.maps = ex.maps || a.maps;
    if (!a.only.empty()) apply_only(ex, a.only);
    if (a.samples) {  // given, so checked: 0 is refused, not read as "the file's"
        if (*a.samples < 1 || *a.samples > 8192)
            throw InputError("--samples", std::to_string(*a.samples) + " is not in [1, 8192]");
        ex.samples = *a.samples;
    }
    check_plugin_backends(ex, a.backends);
    check_camera_samples(ex, a.samples ? "--samples" : "");
    for (const std::string& w : skipped_settings(ex, a.backends)) {  // said, never silent
        std::cerr << "pxh: warning: " << w << "\n";
        ex.warnings.push_back(w);
    }
    if (a.gl_time_limit_given && !(a.gl_time_limit > 0 && a.gl_time_limit <= kMaxGlTimeLimitS))
        throw InputError("--gl-time-limit", format_number(a.gl_time_limit) +
                                                " is outside (0, 86400] (seconds per row)");
    check_run_size(ex, a);  // of the whole run, also for a slice (merge holds every row)
    std::optional<Slice> slice;
    if (!a.shard.empty()) slice = make_slice(ex, a);
    const std::string out_dir =
        a.out_dir.empty() ? "results/runs/" + ex.name + "-" + utc_timestamp("%Y%m%d-%H%M%S")
                          : a.out_dir;
    const int nthreads = a.threads > 0 ? a.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(nthreads));
    // llvmpipe's rasteriser threads follow --threads unless LP_NUM_THREADS is set already.
    setenv("LP_NUM_THREADS", std::to_string(nthreads).c_str(), 0);

    // Every plug-in shader compiled, linked and its uniforms checked before any row runs and
    // before anything is written: one line per problem, exit 2.
    if (!ex.plugins.empty()) {
        RunOptions pre;
        pre.backends = a.backends;
        pre.shader_dir = a.shader_dir;
        pre.gl = a.gl;
        pre.gl_time_limit_s = a.gl_time_limit;
        const std::vector<std::string> problems = check_plugin_shaders(ex, pre);
        for (const auto& p : problems) std::cerr << "pxh: error: " << one_line(p) << "\n";
        if (!problems.empty()) return 2;
    }

    // Written into DIR.partial-PID, renamed into place only when complete (before any worker
    // thread exists: the folder's signal clean-up needs every thread to block the signals).
    RunFolder folder(out_dir, a.force);
    const fs::path tmp_dir = folder.partial();

    const bool tty = isatty(STDERR_FILENO);
    RunOptions opt;
    opt.backends = a.backends;
    opt.shader_dir = a.shader_dir;
    opt.gl = a.gl;
    if (slice)
        opt.include = [&](size_t f, size_t p, size_t c, size_t t) {
            return slice->unit_of[slice->view_index(ex, f, p, c, t)] >= 0;
        };
    opt.gl_time_limit_s = a.gl_time_limit;
    opt.warning = [](const std::string& line) {
        std::cerr << "pxh: warning: " << one_line(line) << "\n";
    };
    // The results writers (error maps, pictures) the experiment wants, per view.
    const std::vector<const ViewWriter*> writers = wanted_view_writers(ex);
    if (!writers.empty())
        opt.on_view =
            [&](std::vector<ResultRow>& rows, const std::vector<std::vector<Vec2d>>& errors,
                const std::vector<Vec2d>& truth, const std::vector<uint8_t>& inside, size_t first) {
                ViewOutput view{rows, errors, truth, inside, first};
                for (const ViewWriter* w : writers) w->write({ex, tmp_dir}, view);
            };
    const auto t0 = std::chrono::steady_clock::now();
    if (!a.quiet)
        opt.progress = [tty, t0](size_t step, size_t steps, const std::string& what) {
            // Elapsed, and what is left at the mean pace of the views done so far.
            const double secs =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::string line = "[" + std::to_string(step) + "/" + std::to_string(steps) + " " +
                               clock_time(secs);
            if (step > 1)
                line += ", ~" + clock_time(secs / double(step - 1) * double(steps - step + 1)) +
                        " left";
            line += "] " + what;
            if (tty) std::cerr << "\r\033[K" << line << std::flush;
            else std::cerr << line << "\n";
        };
    RunInfo info;
    const auto rows = run_experiment(ex, opt, &info);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!a.quiet && tty) std::cerr << "\r\033[K";

    write_file_synced(tmp_dir / "results.csv", results_csv(rows));
    nlohmann::json run = run_record(ex, a, info, command_line, nthreads);
    size_t failed = 0;
    for (const auto& r : rows) failed += !r.ok();
    run["rows"] = rows.size();
    run["failed_rows"] = failed;
    run["seconds"] = secs;
    if (slice) run["shard"] = shard_record(ex, a, *slice, info);
    // Written last: the sha256 of every file above (pxh check and report verify them).
    run["files"] = file_records(tmp_dir);
    write_file_synced(tmp_dir / "run.json", run.dump(2) + "\n");
    folder.commit();

    if (!a.quiet) print_summary(rows);
    std::cout << rows.size() << " rows (" << failed << " failed) in " << std::setprecision(1)
              << std::fixed << secs << " s -> " << folder.final_dir().string() << std::endl;
    if (slice) print_slice(*slice, run["shard"]);
    if (failed) print_failed_rows(rows, failed);
    // A closed pipe (SIGPIPE is ignored): the results are complete, the output is not.
    if (!std::cout)
        throw std::runtime_error(
            "cannot write to standard output (a closed pipe?); the results "
            "are complete in " +
            folder.final_dir().string());
    return failed ? 1 : 0;
}

}  // namespace

Command add_run_command(CLI::App& app, const std::string& command_line) {
    auto* run = app.add_subcommand("run",
                                   "run an experiment file, write results.csv and run.json "
                                   "(exit 0: all rows ok; 1: some row failed, results "
                                   "written; 2: bad input, nothing written)");
    auto ra = std::make_shared<RunArgs>();
    run->add_option("experiment", ra->file, "experiment file (TOML)")->required();
    run->add_option("--out", ra->out_dir,
                    "results folder (default results/runs/NAME-DATE); must not exist, be empty, "
                    "or (with --force) hold earlier pxh results");
    run->add_flag("--force", ra->force,
                  "replace the earlier pxh results in --out (only pxh's own files there)");
    run->add_option("--threads", ra->threads, "worker threads, >= 1 (default: all cores)");
    run->add_option("--backend", ra->backends, "backends to run, overriding the file (cpu, glsl)");
    run->add_option("--shader-dir", ra->shader_dir,
                    "read GLSL from this folder (NAME.frag.glsl, common.glsl) instead of the "
                    "embedded copies; a file missing there is taken from the embedded copies, "
                    "and the shader column says which ran");
    run->add_option("--gl", ra->gl,
                    "GL context of the glsl backend, overriding the file's gl key: osmesa "
                    "(default; software) or egl (headless: a GPU's device, else Mesa's "
                    "surfaceless llvmpipe)");
    run->add_option("--gl-time-limit", ra->gl_time_limit,
                    "seconds a GLSL row's GL work may take, overriding the file's "
                    "gl_time_limit_s (default 120): past it the row fails and the run goes on "
                    "in a fresh GL context");
    run->add_flag("--quiet", ra->quiet,
                  "no progress or summary (the final one-line count is still printed)");
    run->add_flag("--maps", ra->maps, "write an error map (EXR + false-colour PNG) per row");
    run->add_option("--only", ra->only,
                    "run a subset: KEY=VALUE[|VALUE],... with KEY method, heightfield, backend, "
                    "theta_deg, phi_deg, scale or bias (e.g. method=pom,heightfield=bricks)");
    run->add_option("--samples", ra->samples, "samples per side N, overriding the file (1..8192)");
    run->add_option("--shard", ra->shard,
                    "run slice I of N (0 <= I < N): whole theta sweeps, balanced by estimated "
                    "cost; pxh merge joins the N results folders into the whole run's");
    auto* out_opt = run->get_option("--out");
    run->add_option("--max-rows", ra->max_rows,
                    "refuse a run estimated to write more rows (default " +
                        std::to_string(kDefaultMaxRows) + ")");
    run->add_option("--max-memory", ra->max_memory,
                    "refuse a run estimated to need more memory, e.g. 512M, 16G (default " +
                        format_bytes(kDefaultMaxMemoryBytes) + ")");
    return {run, [run, ra, out_opt, &command_line] {
                ra->out_given = out_opt->count() > 0;
                if (ra->threads < 0 || (run->count("--threads") && ra->threads == 0))
                    throw InputError("--threads",
                                     std::to_string(ra->threads) + " is not a thread count (>= 1)");
                ra->gl_time_limit_given = run->count("--gl-time-limit") > 0;
                return cmd_run(*ra, command_line);
            }};
}

}  // namespace pxh
