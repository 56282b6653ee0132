// Sharded runs (pxh run --shard I/N, pxh merge): the run's work cut into units, each unit's
// estimated cost, and a deterministic partition of the units into N slices balanced by cost.
//
// A unit is a whole theta sweep of one height-field entry (field, s, b) at one azimuth and
// camera setting (a perspective camera's distance, fov_deg): every
// view of it, so that each (field, s, b, view) is traced in exactly one slice, the sliding and
// shimmering pairs of consecutive views stay in one slice, and so do the [render] pictures of
// the sweep. With sweep_dt_deg > 0 each view pairs with its own companion view, so a unit is one
// view (the companion is traced with it, as in the unsharded run). A distance sweep's pairs
// span units (one per camera setting): a slice traces a successor distance it does not run as a
// companion view (harness/run/runner.cpp), so its numbers are the unsharded run's.
#pragma once
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/experiment/experiment.h"
#include "harness/experiment/view_grid.h"

namespace pxh {

// "I/N" with 0 <= I < N (SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT as they are).
struct ShardSpec {
    size_t index = 0, count = 1;
    std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};
// Throws InputError("--shard", ...) on anything else.
ShardSpec parse_shard(const std::string& text);

// One unit of work: views theta_deg[theta_begin, theta_end) of heightfields[field] at
// phi_deg[phi] and camera_settings[camera], in the run's order (units are numbered in the
// order the runner meets them).
struct WorkUnit {
    size_t field = 0, phi = 0, theta_begin = 0, theta_end = 0;
    double cost = 0;  // the estimate below, in sample-steps
    size_t camera = 0;
};

// The run's units in run order, with their cost (estimated before any work, like
// estimate_run):
//   per unit, once: the field's set-up, texels x kSetupPerTexel (Embree's BVH, the exact
//     tracer's maximum mipmap, the methods' resources);
//   per view (and again per companion view with sweep_dt_deg): samples^2 x
//     ( the references: 2 + the cells a ray crosses in the height band, s tan(theta) x side
//     + per row (method setting x backend variant, as estimate_run counts them): the method's
//       declared fetch bound at this view x (1 + timing_repeats) on the CPU, x (1 + frames) on
//       GLSL (the timed frames).
// `backends_override`: pxh run --backend.
std::vector<WorkUnit> work_units(const Experiment& ex,
                                 const std::vector<std::string>& backends_override);

// The units of slice `shard` (indices into `units`, ascending): longest-processing-time
// first (units by cost, largest first, ties by index; each to the slice with the least cost
// so far, ties to the lowest slice). Deterministic, every unit in exactly one slice, and no
// slice above 4/3 of the best possible largest slice. Needs shard.count <= units.size()
// (an InputError naming --shard otherwise: a slice with nothing to do is refused).
std::vector<size_t> shard_units(const std::vector<WorkUnit>& units, const ShardSpec& shard);

// One slice of a sharded run: the run's units, the slice's, and each view's unit.
struct Slice {
    ShardSpec shard;
    std::vector<WorkUnit> units;  // all of the run's
    std::vector<size_t> mine;     // indices into units, ascending
    ViewGrid grid;
    std::vector<int> unit_of;  // per view (ViewGrid::index): its unit, -1 another slice's
    bool includes(const ViewAt& v) const { return unit_of[grid.index(v)] >= 0; }
    size_t unit(const ViewAt& v) const { return size_t(unit_of[grid.index(v)]); }
};
// Slice `shard` of the run (work_units, shard_units); InputError("--shard", ...) as they throw.
Slice make_slice(const Experiment& ex, const ShardSpec& shard,
                 const std::vector<std::string>& backends_override);

// What built this pxh, as run.json's "shard" record keeps it (pxh merge refuses slices whose
// records differ): pxh_version (the release), compiler, compile_flags, build_type, libraries
// (from provenance) and binary_sha256 (of the running executable).
nlohmann::json build_record();

// The partition's name, recorded in run.json: pxh merge refuses slices cut by another one.
inline constexpr const char* kPartitionScheme = "sweeps by estimated cost, LPT (v1)";

}  // namespace pxh
