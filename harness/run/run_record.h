// run.json, a results folder's record of its run: what ran (the experiment as read, its inputs
// with their sha256, the plug-in shaders as compiled, each backend's own block), on what (the
// provenance: pxh version, host, CPU, compiler, libraries), with what result (rows, failed
// rows, seconds), a slice's shard record, and, written last, the sha256 of every file of the
// folder (pxh check, report, compare and merge verify them). pxh run writes it here; pxh merge
// writes the joined run's from its slices' records read here.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/experiment/experiment.h"
#include "harness/experiment/shard.h"
#include "harness/results/results.h"
#include "harness/run/runner.h"

namespace pxh {

// What the run was given besides the experiment: the command line as typed and the threads.
struct RunCall {
    std::string command_line;
    int threads = 0;
};

// The record of a run before its rows are counted: provenance, command line, the experiment
// (file, text, name), its inputs, warnings, plug-in shaders and each backend's block (RunInfo).
nlohmann::json run_record(const Experiment& ex, const RunCall& call, const RunInfo& info);

// run.json's "tracers": the exact tracer's per-ray path as taken (PXH_TRACER_PATH capped by the
// CPU) and the CPU's best, Embree's ISA (by Embree's own CPU tests under the device's max_isa)
// and device configuration, and PXH_TRACER_PATH as set ("" when not).
nlohmann::json tracer_record();

// What a slice was cut from, as pxh merge checks that every slice is of the same run: the
// command line's selection of the experiment.
struct ShardSelection {
    std::string only;                   // --only
    std::vector<std::string> backends;  // the backends that ran
    std::string gl;                     // --gl
    std::string shader_dir;             // --shader-dir (recorded absolute; "" for none)
};

// run.json's "shard": the slice, the partition, the experiment's sha256, the selection, the
// build, and the slice's units in results.csv order, each with its rows (from info.views).
nlohmann::json shard_record(const Experiment& ex, const Slice& s, const ShardSelection& sel,
                            const RunInfo& info);

// Completes the record once the rows are written into `dir`: rows, failed_rows, seconds and,
// last, the sha256 of every file in `dir`; then writes it there as run.json (synced).
void finish_run_record(nlohmann::json& run, const std::vector<ResultRow>& rows, double seconds,
                       const std::filesystem::path& dir);

// What run.json records of the command line must be UTF-8 (else the run would end in a JSON
// error): --out, every argument, --shader-dir's absolute path ("" for none). InputError naming
// the option otherwise, before any work.
void check_recordable(const std::string& out_dir, const std::string& command_line,
                      const std::string& shader_dir);

// A run.json's text as a record: InputError(path, "unreadable: ...") when it does not parse
// as a JSON object.
nlohmann::json parse_run_record(const std::string& text, const std::string& path);

// Its shard record, checked for the keys pxh merge reads (InputError naming `path` and the key
// otherwise; "is not a slice" naming `dir` when it has none).
const nlohmann::json& shard_record_of(const nlohmann::json& run, const std::string& path,
                                      const std::string& dir);

}  // namespace pxh
