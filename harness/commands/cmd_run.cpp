// `pxh run FILE`: runs an experiment, writes results.csv and run.json into a results folder.
// The command's path: flags -> load (the experiment with the command line's overrides) -> plan
// (its size checked, a slice) -> preflight -> run -> write -> print.
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>

#include "harness/commands/commands.h"
#include "harness/commands/summary.h"
#include "harness/core/error.h"
#include "harness/core/limits.h"
#include "harness/core/params.h"
#include "harness/core/safe_files.h"
#include "harness/experiment/experiment.h"
#include "harness/experiment/shard.h"
#include "harness/gl/context.h"
#include "harness/metrics/columns.h"
#include "harness/results/provenance.h"
#include "harness/results/run_folder.h"
#include "harness/run/run_record.h"
#include "harness/run/runner.h"
#include "harness/run/view_writers.h"

namespace fs = std::filesystem;

namespace pxh {
namespace {

struct RunArgs {
    std::string file, out_dir, shader_dir;
    std::string gl;  // GL context; empty: the experiment's (default osmesa)
    int threads = 0;
    bool quiet = false, force = false;
    RunOverrides o;  // --only, --samples, --backend, --maps (the limits: below)
    long long max_rows = (long long)kDefaultMaxRows;  // checked >= 1 (-1 must not wrap)
    bool out_given = false;                           // --out given (then never empty)
    std::string max_memory;                           // e.g. "8G"; empty = kDefaultMaxMemoryBytes
    std::string shard;         // --shard I/N: run slice I of N (harness/experiment/shard.h)
    double gl_time_limit = 0;  // --gl-time-limit S: overrides the file's gl_time_limit_s
    bool gl_time_limit_given = false;
    std::string command_line;
};

// The command line's own checks, before the experiment is read: --out and every argument go
// into run.json, so they must be UTF-8 (else the run would end in a JSON error).
void check_run_args(const RunArgs& a) {
    if (a.out_given && a.out_dir.empty())
        throw InputError("--out",
                         "is empty: name the results folder (or leave --out out for "
                         "results/runs/NAME-DATE)");
    if (const std::string why = utf8_problem(a.out_dir); !why.empty())
        throw InputError("--out", "is not UTF-8 (" + why + "); run.json records it");
    if (const std::string why = utf8_problem(a.command_line); !why.empty())
        throw InputError("command line", "an argument is not UTF-8 (" +
                                             why.substr(why.find(',') + 2) +
                                             "); run.json records the command line");
    if (!a.shader_dir.empty())  // recorded as an absolute path: the current folder's too
        if (const std::string why = utf8_problem(fs::absolute(a.shader_dir).string()); !why.empty())
            throw InputError("--shader-dir",
                             "its absolute path is not UTF-8 (" + why + "); run.json records it");
    for (const auto& b : a.o.backends) check_backend_name(b, "--backend");
    if (a.max_rows < 1)
        throw InputError("--max-rows", std::to_string(a.max_rows) + " is not a row count (>= 1)");
    if (!a.gl.empty() && !find_gl_context(a.gl))
        throw InputError("--gl",
                         "unknown GL context '" + a.gl + "' (known: " + gl_context_names() + ")");
    if (a.o.samples && (*a.o.samples < 1 || *a.o.samples > kMaxSamples))  // given: 0 is refused
        throw InputError("--samples", std::to_string(*a.o.samples) + " is not in [1, " +
                                          std::to_string(kMaxSamples) + "]");
    if (a.gl_time_limit_given && !(a.gl_time_limit > 0 && a.gl_time_limit <= kMaxGlTimeLimitS))
        throw InputError("--gl-time-limit", format_number(a.gl_time_limit) +
                                                " is outside (0, 86400] (seconds per row)");
}

RunOptions run_options(const RunArgs& a, const std::optional<Slice>& slice) {
    RunOptions opt;
    opt.backends = a.o.backends;
    opt.shader_dir = a.shader_dir;
    opt.gl = a.gl;
    opt.gl_time_limit_s = a.gl_time_limit;
    if (slice) opt.include = [&s = *slice](const ViewAt& v) { return s.includes(v); };
    opt.warning = [](const std::string& line) {
        std::cerr << "pxh: warning: " << one_line(line) << "\n";
    };
    if (!a.quiet) opt.progress = progress_printer();
    return opt;
}

// The results writers (error maps, pictures) the experiment wants, per view, into `dir`.
void write_views_into(RunOptions& opt, const Experiment& ex, const fs::path& dir) {
    if (const auto writers = wanted_view_writers(ex); !writers.empty())
        opt.on_view = [&ex, dir, writers](std::vector<ResultRow>& rows, const auto& errors,
                                          const auto& truth, const auto& inside, size_t first) {
            ViewOutput view{rows, errors, truth, inside, first};
            for (const ViewWriter* w : writers) w->write({ex, dir}, view);
        };
}

int cmd_run(const RunArgs& a) {
    check_run_args(a);
    RunOverrides o = a.o;
    o.max_rows = size_t(a.max_rows);
    if (!a.max_memory.empty()) o.max_memory = parse_bytes(a.max_memory, "--max-memory");
    const Experiment ex = load_run_experiment(a.file, o);
    std::optional<Slice> slice;
    if (!a.shard.empty()) slice = make_slice(ex, parse_shard(a.shard), a.o.backends);
    const int nthreads = a.threads > 0 ? a.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(nthreads));
    // llvmpipe's rasteriser threads follow --threads unless LP_NUM_THREADS is set already.
    setenv("LP_NUM_THREADS", std::to_string(nthreads).c_str(), 0);
    RunOptions opt = run_options(a, slice);
    // Every backend's own checks (plug-in shaders compiled and linked) before any row runs and
    // before anything is written: one line per problem, exit 2.
    const std::vector<std::string> problems = preflight_backends(ex, opt);
    for (const auto& p : problems) std::cerr << "pxh: error: " << one_line(p) << "\n";
    if (!problems.empty()) return 2;

    // Written into DIR.partial-PID, renamed into place only when complete (before any worker
    // thread exists: the folder's signal clean-up needs every thread to block the signals).
    RunFolder folder(a.out_dir.empty()
                         ? "results/runs/" + ex.name + "-" + utc_timestamp("%Y%m%d-%H%M%S")
                         : a.out_dir,
                     a.force);
    write_views_into(opt, ex, folder.partial());
    const auto t0 = std::chrono::steady_clock::now();
    RunInfo info;
    const auto rows = run_experiment(ex, opt, &info);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!a.quiet) end_progress();

    write_file_synced(folder.partial() / "results.csv", results_csv(rows));
    nlohmann::json run = run_record(ex, {a.command_line, nthreads}, info);
    if (slice) {
        const std::string shader_dir =
            a.shader_dir.empty() ? "" : fs::absolute(a.shader_dir).string();
        run["shard"] = shard_record(
            ex, *slice,
            {a.o.only, a.o.backends.empty() ? ex.backends : a.o.backends, a.gl, shader_dir}, info);
    }
    finish_run_record(run, rows, secs, folder.partial());
    folder.commit();

    const size_t failed = run["failed_rows"].get<size_t>();
    if (!a.quiet) print_summary(rows);
    std::cout << rows.size() << " rows (" << failed << " failed) in " << std::setprecision(1)
              << std::fixed << secs << " s -> " << folder.final_dir().string() << std::endl;
    if (slice) print_slice(*slice, run["shard"]);
    if (failed) print_failed_rows(rows);
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
    run->add_option("--backend", ra->o.backends,
                    "backends to run, overriding the file (cpu, glsl)");
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
    run->add_flag("--maps", ra->o.maps, "write an error map (EXR + false-colour PNG) per row");
    std::string axes;  // the rows' axes, from the column registry
    for (const ColumnSpec* c : row_axes()) axes += (axes.empty() ? "" : ", ") + c->name;
    run->add_option("--only", ra->o.only,
                    "run a subset: KEY=VALUE[|VALUE],... with KEY one of the rows' axes (" + axes +
                        "), a numeric one also as a range KEY_min=V, KEY_max=V (theta_min for "
                        "theta_deg) (e.g. method=pom,heightfield=bricks,distance_max=4)");
    run->add_option("--samples", ra->o.samples,
                    "samples per side N, overriding the file (1.." + std::to_string(kMaxSamples) +
                        "; a perspective camera's image keeps its resolution: N x N of its "
                        "pixels)");
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
                // Given, so checked: --shard '' is refused, not read as "unsharded".
                if (run->count("--shard") && ra->shard.empty()) (void)parse_shard(ra->shard);
                ra->command_line = command_line;
                return cmd_run(*ra);
            }};
}

}  // namespace pxh
