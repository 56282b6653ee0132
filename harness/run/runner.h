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
#include "harness/metrics/agreement.h"
#include "harness/results/results.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

// Scores one method output against the truth: every per-output metric
// (harness/metrics/metric.h) and its shader column; samples flagged in `exclude` (when given)
// are left out of the error statistics and counted in `excluded`.
// `view` (when given): its outside samples are left out and counted, its footprints give the
// pixel error.
ResultRow score(const MethodOutput& out, const GroundTruth& gt, int width, int height,
                const std::vector<uint8_t>* exclude = nullptr, const View* view = nullptr);

struct RunOptions {
    std::vector<std::string> backends;  // overrides the experiment's list when non-empty
    std::string shader_dir;             // GLSL sources override (development)
    int gl_frames = 5;                  // timed GLSL frames per row
    std::string gl;                     // GL context (osmesa, egl); empty: the experiment's
    double gl_time_limit_s = 0;         // > 0: a GLSL row's time limit, overriding the experiment's
    // Called with a warning line (no "pxh: warning: " prefix), e.g. `--gl egl` that gave a
    // software renderer.
    std::function<void(const std::string&)> warning;
    // Called once per view with its rows (before they join the run), their per-sample error
    // vectors, the truth's uv (per sample, unwrapped) and the view's inside mask (empty: every
    // sample inside; View::inside); first_index is the index the view's first row has in the
    // whole run's results.csv (a slice's maps and pictures are named as the unsharded run
    // names them).
    std::function<void(std::vector<ResultRow>&, const std::vector<std::vector<Vec2d>>&,
                       const std::vector<Vec2d>&, const std::vector<uint8_t>&, size_t)>
        on_view;
    // One call per view, as it starts: its number (from 1) of `steps`, and what it is.
    std::function<void(size_t step, size_t steps, const std::string& what)> progress;
    // A slice of the run (pxh run --shard): only the views (heightfields[field], phi_deg[phi],
    // camera_settings[camera], theta_deg[theta]) it accepts are run; a field none of whose
    // views runs is not built. Without sweep_dt_deg a theta sweep must be accepted whole or not
    // at all (its consecutive views pair up). Empty: every view.
    std::function<bool(size_t field, size_t phi, size_t camera, size_t theta)> include;
};

struct RunInfo {
    std::string gl_renderer, gl_version;           // when the GLSL backend ran
    std::string gl_context, gl_vendor;             // ... the context (osmesa, egl) and GL_VENDOR
    std::map<std::string, std::string> gl_driver;  // ... the driver behind it (GlContext::driver)
    int gl_timer_bits = 0;                         // ... GL_QUERY_COUNTER_BITS of GL_TIME_ELAPSED
    std::map<std::string, std::string> shaders;    // every GLSL source compiled -> sha256
    // run.json's "backends": each backend's own block (Backend::record: its facts, sources,
    // timing unit, what a repeat measures, repeats per row, counters), by name.
    std::map<std::string, nlohmann::json> backends;
    int resource_builds = 0;  // method resources built (once per field, and s, b if they use them)
    // Every view run, in run order: its indices (as RunOptions::include takes them) and rows.
    struct ViewDone {
        size_t field, phi, camera, theta, rows;
    };
    std::vector<ViewDone> views;
};

// Every plug-in shader of the experiment compiled and linked, and its uniforms checked against
// its entry, in a GL process of its own, before any row runs: one line per problem (the
// driver's messages as FILE:LINE:COL: ... of the user's file), empty when all are ready (and
// at once, without GL, when there is no plug-in). std::runtime_error when no GL context can be
// made.
std::vector<std::string> check_plugin_shaders(const Experiment& ex, const RunOptions& opt);

// Whether a GL renderer is software (llvmpipe, softpipe, SwiftShader, an EGL software device).
bool software_renderer(const std::map<std::string, std::string>& backend_facts);

std::vector<ResultRow> run_experiment(const Experiment& ex, const RunOptions& opt,
                                      RunInfo* info = nullptr);

}  // namespace pxh
