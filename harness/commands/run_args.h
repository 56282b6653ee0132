// pxh run's flags: what each means (its --help), and the checks a flag's value gets before the
// experiment is read (cmd_run.cpp runs them).
#pragma once
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/core/limits.h"
#include "harness/experiment/experiment.h"

namespace pxh {

struct RunArgs {
    // pxh run FILE [flags]: the flags as given (checked by check_run_args).
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

// Adds pxh run's arguments and flags to its subcommand, read into `a`.
void add_run_flags(CLI::App& run, RunArgs& a);

// The flags' own checks, before the experiment is read (after add_run_flags' values are read;
// `run` tells which were given): one InputError naming the flag.
void check_run_args(const CLI::App& run, RunArgs& a);

}  // namespace pxh
