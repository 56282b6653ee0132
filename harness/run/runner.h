// The pipeline: HeightField -> views -> GroundTruth (once per view) -> MethodOutput -> ResultRow.
#pragma once
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/backends/cpu_backend.h"
#include "harness/experiment/experiment.h"
#include "harness/experiment/view_grid.h"
#include "harness/metrics/agreement.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/score.h"
#include "harness/results/results.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

struct ViewRows;  // harness/run/view_rows.h

// One view's rows and what they were scored on, as RunOptions::on_view gets them.
struct ViewOutput {
    std::vector<ResultRow>& rows;
    const std::vector<std::vector<Vec2d>>& errors;  // per row (empty: a failed row)
    const std::vector<Vec2d>& truth;                // the truth's uv per sample (unwrapped)
    const std::vector<uint8_t>& inside;             // the view's inside mask (empty: all)
    // Per row with a [views] cut, per sample: bit 0 the plane shows in truth, bit 1 it shows
    // for the method (metrics/depth.h's add_cut_flips); empty for rows without a cut.
    const std::vector<std::vector<uint8_t>>& cut_shows;
    // Where the truth reports coverage (a curved base's; empty on the plane): per row the
    // method's own uv per sample (NaN where it shows nothing), and per sample whether the truth
    // shows surface (docs/conventions.md section 12): its pictures are drawn from these,
    // background where a side shows nothing.
    const std::vector<std::vector<Vec2d>>& shown_uv;
    const std::vector<uint8_t>& truth_hit;
    // The index the view's first row has in the whole run's results.csv (a slice's maps and
    // pictures are named as the unsharded run names them).
    size_t first;
    // Each sample's level of detail (its footprint's lambda, docs/conventions.md section 10.2),
    // and the field's texture levels (built when a setting samples them or [shading] is given;
    // nullptr otherwise): what the shaded images are read at.
    const std::vector<double>& lambda;
    const TextureLevels* levels;
    // Per row, its image as the backend's own shader shaded it ([shading] on the GLSL backend:
    // MethodOutput::shaded); empty: the writer shades it with the CPU twin.
    const std::vector<std::vector<float>>& shaded;
    // [shading] under a `samples` subset: the view's rows evaluated at every pixel of the
    // camera's image (in the same row order), what the shaded images are made of; nullptr when
    // the view measures the whole image.
    const ViewRows* whole;
};

struct RunOptions {
    std::vector<std::string> backends;  // overrides the experiment's list when non-empty
    std::string shader_dir;             // GLSL sources override (development)
    int gl_frames = 5;                  // timed GLSL frames per row
    std::string gl;                     // GL context (osmesa, egl); empty: the experiment's
    double gl_time_limit_s = 0;         // > 0: a GLSL row's time limit, overriding the experiment's
    // Called with a warning line (no "pxh: warning: " prefix), e.g. `--gl egl` that gave a
    // software renderer.
    std::function<void(const std::string&)> warning;
    // Called once per view with its rows before they join the run (ViewOutput).
    using ViewHook = std::function<void(ViewOutput&)>;
    ViewHook on_view;
    // One call per view, as it starts: its number (from 1) of `steps`, and what it is.
    std::function<void(size_t step, size_t steps, const std::string& what)> progress;
    // A slice of the run (pxh run --shard): only the views of the grid (ViewGrid) it accepts
    // are run; a field none of whose views runs is not built. Without sweep_dt_deg a theta sweep
    // must be accepted whole or not at all (its consecutive views pair up). Empty: every view.
    ViewFilter include;
};

struct RunInfo {
    // run.json's "backends": each backend's own block (Backend::record: its facts, sources,
    // timing unit, what a repeat measures, repeats per row, counters, and what its entry adds:
    // the GLSL backend's GL context and driver), by name.
    std::map<std::string, nlohmann::json> backends;
    int resource_builds = 0;  // method resources built (once per field, and s, b if they use them)
    // Every view run, in run order: its place in the grid and its rows.
    struct ViewDone {
        ViewAt at;
        size_t rows;
    };
    std::vector<ViewDone> views;
};

// Every backend the run uses checked before any row runs and before anything is written
// (BackendEntry::preflight: the GLSL backend compiles and links every plug-in shader in each
// program its rows use and checks its uniforms, in a GL process of its own): one line per
// problem, empty when all are ready. std::runtime_error when a check cannot be made (no GL
// context).
std::vector<std::string> preflight_backends(const Experiment& ex, const RunOptions& opt);

std::vector<ResultRow> run_experiment(const Experiment& ex, const RunOptions& opt,
                                      RunInfo* info = nullptr);

}  // namespace pxh
