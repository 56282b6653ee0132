// `pxh run FILE`: runs an experiment, writes results.csv and run.json into a results folder.
// The command's path: flags -> load (the experiment with the command line's overrides) -> plan
// (its size checked, a slice) -> preflight -> run -> write -> print.
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>

#include "harness/commands/commands.h"
#include "harness/commands/run_args.h"
#include "harness/commands/summary.h"
#include "harness/core/error.h"
#include "harness/core/limits.h"
#include "harness/core/params.h"
#include "harness/core/safe_files.h"
#include "harness/experiment/experiment.h"
#include "harness/experiment/shard.h"
#include "harness/results/provenance.h"
#include "harness/results/run_folder.h"
#include "harness/run/run_record.h"
#include "harness/run/runner.h"
#include "harness/run/view_writers.h"

namespace pxh {
namespace {

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

int cmd_run(const RunArgs& a) {
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
    opt.on_view = view_writers_into(ex, folder.partial());
    const auto t0 = std::chrono::steady_clock::now();
    RunInfo info;
    const auto rows = run_experiment(ex, opt, &info);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!a.quiet) end_progress();

    create_new_file(folder.partial() / "results.csv", results_csv(rows));
    nlohmann::json run = run_record(ex, {a.command_line, nthreads}, info);
    if (slice)
        run["shard"] = shard_record(
            ex, *slice,
            {a.o.only, a.o.backends.empty() ? ex.backends : a.o.backends, a.gl, a.shader_dir},
            info);
    finish_run_record(run, rows, secs, folder.partial());
    folder.commit();
    print_run(rows, secs, folder.final_dir(), a.quiet);
    if (slice) print_slice(*slice, run["shard"]);
    return run["failed_rows"].get<size_t>() ? 1 : 0;
}

}  // namespace

Command add_run_command(CLI::App& app, const std::string& command_line) {
    auto* run = app.add_subcommand("run",
                                   "run an experiment file, write results.csv and run.json "
                                   "(exit 0: all rows ok; 1: some row failed, results "
                                   "written; 2: bad input, nothing written)");
    auto ra = std::make_shared<RunArgs>();
    add_run_flags(*run, *ra);
    return {run, [run, ra, &command_line] {
                ra->command_line = command_line;
                check_run_args(*run, *ra);
                return cmd_run(*ra);
            }};
}

}  // namespace pxh
