// pxh merge: the slices of a sharded run (pxh run --shard I/N) joined into the
// whole run's results folder. Every slice is verified as `check` verifies a folder; slices of
// another experiment, selection, pxh version or build, inputs (height-field files, plug-in and
// compiled shaders by sha256) or tracer path, slices that overlap and a missing slice are refused
// (exit 2, one line naming the slice); OUT is written as `run` writes a folder (a partial folder
// renamed into place when complete) and its results.csv holds the rows in the unsharded run's
// order.
#pragma once
#include <string>
#include <vector>

namespace pxh {

struct MergeRequest {
    std::string out;                // the whole run's results folder to write
    std::vector<std::string> dirs;  // the slices' results folders, every shard 0..N-1 once
    bool force = false;             // replace the earlier pxh results in out
};

// Verifies and joins the slices into `out` (run.json records `command_line`); prints what it
// did on stdout. Returns 0 when every row is ok, 1 when some row failed; throws InputError for
// a slice it refuses (nothing written).
int merge_slices(const MergeRequest& request, const std::string& command_line);

}  // namespace pxh
