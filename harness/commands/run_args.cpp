#include "harness/commands/run_args.h"

#include <filesystem>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/core/registry.h"
#include "harness/experiment/shard.h"
#include "harness/gl/context.h"
#include "harness/metrics/columns.h"
#include "harness/run/run_record.h"

namespace pxh {

void add_run_flags(CLI::App& run, RunArgs& a) {
    run.add_option("experiment", a.file, "experiment file (TOML)")->required();
    run.add_option("--out", a.out_dir,
                   "results folder (default results/runs/NAME-DATE); must not exist, be empty, "
                   "or (with --force) hold earlier pxh results");
    run.add_flag("--force", a.force,
                 "replace the earlier pxh results in --out (only pxh's own files there)");
    run.add_option("--threads", a.threads, "worker threads, >= 1 (default: all cores)");
    run.add_option("--backend", a.o.backends,
                   "backends to run, overriding the file (" + join_names(backend_names()) + ")");
    run.add_option("--shader-dir", a.shader_dir,
                   "read GLSL from this folder (NAME.frag.glsl, common.glsl) instead of the "
                   "embedded copies; a file missing there is taken from the embedded copies, "
                   "and the shader column says which ran");
    run.add_option("--gl", a.gl,
                   "GL context of the glsl backend, overriding the file's gl key: osmesa "
                   "(default; software) or egl (headless: a GPU's device, else Mesa's "
                   "surfaceless llvmpipe)");
    run.add_option("--gl-time-limit", a.gl_time_limit,
                   "seconds a GLSL row's GL work may take, overriding the file's "
                   "gl_time_limit_s (default 120): past it the row fails and the run goes on "
                   "in a fresh GL context");
    run.add_flag("--quiet", a.quiet,
                 "no progress or summary (the final one-line count is still printed)");
    run.add_flag("--maps", a.o.maps, "write an error map (EXR + false-colour PNG) per row");
    std::string axes;  // the rows' axes, from the column registry
    for (const std::string& k : only_keys()) axes += (axes.empty() ? "" : ", ") + k;
    run.add_option(
        "--only", a.o.only,
        "run a subset: KEY=VALUE[|VALUE],... with KEY one of the rows' axes (" + axes +
            "), a numeric one also as a range KEY=LO..HI or KEY_min=V, KEY_max=V (theta_min "
            "for theta_deg) (e.g. method=pom,base=cylinder,radius=1.5..4,"
            "distance_max=4)");
    run.add_option("--samples", a.o.samples,
                   "samples per side N, overriding the file (1.." + std::to_string(kMaxSamples) +
                       "; a perspective camera's image keeps its resolution: N x N of its "
                       "pixels)");
    run.add_option("--shard", a.shard,
                   "run slice I of N (0 <= I < N): whole theta sweeps, balanced by estimated "
                   "cost; pxh merge joins the N results folders into the whole run's");
    run.add_option("--max-rows", a.max_rows,
                   "refuse a run estimated to write more rows (default " +
                       std::to_string(kDefaultMaxRows) + ")");
    run.add_option("--max-memory", a.max_memory,
                   "refuse a run estimated to need more memory, e.g. 512M, 16G (default " +
                       format_bytes(kDefaultMaxMemoryBytes) + ")");
}

// The command line's own checks, before the experiment is read.
void check_run_args(const CLI::App& run, RunArgs& a) {
    a.out_given = run.get_option("--out")->count() > 0;
    a.gl_time_limit_given = run.count("--gl-time-limit") > 0;
    if (a.threads < 0 || (run.count("--threads") && a.threads == 0))
        throw InputError("--threads", std::to_string(a.threads) + " is not a thread count (>= 1)");
    // Given, so checked: --shard '' is refused, not read as "unsharded".
    if (run.count("--shard") && a.shard.empty()) (void)parse_shard(a.shard);
    if (a.out_given && a.out_dir.empty())
        throw InputError("--out",
                         "is empty: name the results folder (or leave --out out for "
                         "results/runs/NAME-DATE)");
    check_recordable(a.out_dir, a.command_line, a.shader_dir);
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

}  // namespace pxh
