// Experiment files (TOML): what to run. Every component reads its own keys through one
// ParamDict (harness/core/param_dict.h), and a key nobody read is an InputError naming the
// file and line; so is any other bad value. The code, by concept: parse.cpp (the file, its
// top-level keys, [views], [light], [render]), heightfield_entries.cpp ([[heightfields]]),
// method_entries.cpp ([[methods]], plug-in shaders, sweeps), only.cpp (--only) and
// estimate.cpp (the run estimate).
#pragma once
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/core/limits.h"
#include "harness/core/param_dict.h"
#include "harness/core/params.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/shading.h"
#include "heightfields/field_spec.h"
#include "methods/method.h"

namespace pxh {

// [render]: the views whose pictures a run writes (harness/results/pictures.h): a numbered
// checkerboard seen through the truth's uv and through each row's uv, their difference, and the
// image-space columns img_psnr_db and img_ssim for every row of these fields at this azimuth.
struct RenderSpec {
    std::vector<std::string> heightfields;  // [[heightfields]] names
    double phi_deg = 0;                     // one of [views] phi_deg (default: the first)
    std::vector<double> theta_deg;          // the montage views, each one of [views] theta_deg
    std::string strip_method;               // "": no strip; else its first [[methods]] setting
    std::string strip_params;               //   (canonical params) over the whole theta sweep
    bool covers(const std::string& field, double phi) const {
        if (phi != phi_deg) return false;
        for (const auto& f : heightfields)
            if (f == field) return true;
        return false;
    }
};

struct Experiment {
    std::string name;
    std::string path;  // the file it came from
    std::string text;  // its content, recorded in provenance
    int samples = 256;
    std::vector<std::string> backends{"cpu"};
    // What every registered backend read from its own top-level keys (precision,
    // timing_repeats; texture_format, gl, gl_time_limit_s), whichever backends run: pxh run
    // --backend may pick another. The command line's overrides are the runner's.
    BackendSettings backend;
    std::string ground_truth = "exact";
    // truth_check: which rays of a timed view the truth's cross-check traces for the gt_agree_*
    // columns (the other reference on the plane, the walk at half the step on a curved base):
    // "all", "subset" (the samples (i, j) with i % 4 == j % 4 == 2 of the N x N view: one in
    // 16) or "none" (the columns empty). "": each truth's own default ("all" on the plane,
    // kCurvedTruthCheck = "subset" on a curved base: harness/run/truth_stage.cpp).
    std::string truth_check;
    double sweep_dt_deg = 0;      // > 0: sliding/shimmering from a companion view dt away
    bool maps = false;            // write per-row error maps
    bool exclude_filled = false;  // leave samples whose truth lands on filled holes out  // the
                                  // reference the errors are measured against
    std::vector<double> theta_deg, phi_deg{0.0};
    // [views] cut: the heights (height-map units) of opaque planes z = s (c - b) through the
    // relief (docs/conventions.md section 11); each method setting gets rows per cut (key column
    // cut, cut_flip_frac). Empty: no cut.
    std::vector<double> cuts;
    std::string camera = "orthographic";  // [views] camera: makes each view's rays (harness/scene)
    ParamDict camera_params;              // [views], where the camera reads its own keys
    // The camera's settings from its own keys (one per value of a swept key: the perspective
    // camera's distance x fov_deg; the orthographic camera: one, empty). The run sweeps them
    // between phi_deg and theta_deg: field, phi, setting, theta.
    std::vector<CameraSetting> camera_settings{CameraSetting{}};
    std::optional<LightSpec> light;
    std::optional<RenderSpec> render;  // [render]: pictures of these views
    // [shading]: every row's view shaded through its uv and the truth's, compared by FLIP
    // (flip_mean, flip_p95, flip_max; docs/conventions.md section 13); its albedo already read.
    std::optional<ShadingSpec> shading;
    std::vector<HeightfieldSpec> heightfields;  // arrays of scale/bias already expanded
    // Arrays of parameter values already expanded; a setting given twice (same method and
    // canonical parameters) is kept once, with a warning, its fields merged.
    std::vector<MethodSpec> methods;
    // Plug-in shaders' methods ([[methods]] shader = FILE), owned here (MethodSpec points in).
    std::vector<std::shared_ptr<const MethodInfo>> plugins;
    // "FILE:LINE: ..." one line each (radian-looking theta, phi normalised, theta sorted or
    // deduplicated, a scale whose errors saturate); load_experiment prints them to stderr as
    // "pxh: warning: ..." (parse_experiment prints nothing).
    std::vector<std::string> warnings;
};

// Limits checked while the file is read, before any sweep is expanded (pxh run's --max-rows,
// --max-memory and --backend): the rows of every [[heightfields]] and [[methods]] entry are
// counted from its factors (values per swept key x fields x theta x phi x backend variants;
// a field entry at least one method) and added to the entries before it; past max_rows, or
// past max_memory for the rows alone (kBytesPerRow each), the entry is an InputError at its
// FILE:LINE naming the product, e.g. "would write 9000000 rows (3000 p_a x 3000 p_b x 1
// heightfield x 1 theta x 1 phi x 1 backend variant) > --max-rows 1000000". The counts are
// of the whole file (pxh run --only selects after it is read).
struct ParseLimits {
    size_t max_rows = kDefaultMaxRows;
    size_t max_memory = kDefaultMaxMemoryBytes;
    std::vector<std::string> backends;  // pxh run --backend (empty: the file's)
};

// Reads a regular file (anything else, e.g. a FIFO, is refused without opening it), parses
// it, and prints the warnings to stderr. The text must be UTF-8 (else "FILE:LINE: ... byte 0xNN
// is not UTF-8"), and so must the path (it is recorded in run.json).
Experiment load_experiment(const std::string& path, const ParseLimits& limits = {});
Experiment parse_experiment(const std::string& text, const std::string& path,
                            const ParseLimits& limits = {});

// What pxh run's command line overrides in the experiment: --only, --samples, --backend,
// --maps, and the limits --max-rows and --max-memory (each checked where it is given).
struct RunOverrides {
    std::string only;
    std::optional<int> samples;         // in [1, kMaxSamples] (checked by the caller)
    std::vector<std::string> backends;  // empty: the file's
    bool maps = false;
    size_t max_rows = kDefaultMaxRows;
    size_t max_memory = kDefaultMaxMemoryBytes;
};
// The experiment as pxh run takes it: the file read (load_experiment, its sweeps counted
// against the limits), --only applied, --samples set, plug-ins against the backends and the
// camera against the samples checked, the settings a backend makes no rows of said (stderr
// and warnings), and the whole run's estimate against the limits (also for a slice: merge holds
// every row). InputError at the key's FILE:LINE, or naming the flag, otherwise.
Experiment load_run_experiment(const std::string& path, const RunOverrides& o);

// A method's resolved parameter set: given values checked against its declarations (an
// InputError naming `where` otherwise), defaults and the values unset optional parameters
// stand for filled in; canonical() then names every declared parameter.
ParamValues resolve_method_params(const MethodInfo& m, const GivenParams& given,
                                  const std::string& where);

// pxh run --only KEY=V[|V...],...: keeps the method settings, height-field entries, views,
// camera settings and backend variants that match. The keys are the rows' axes (row_axes():
// method, params, lod, heightfield, scale, bias, theta_deg, phi_deg, backend, precision,
// texture_format, camera, the camera's own keys such as distance), each numeric one also as a
// range KEY_min=V, KEY_max=V (inclusive; theta_min, theta_max for theta_deg); a repeated key or
// V|V is "any of". An unknown key is an InputError("--only", ...) listing the keys (and the
// nearest one); a key that matches nothing names what there is.
// A numeric axis also takes KEY=LO..HI (either end may be left out). base selects the height
// fields by their base surface (plane, cylinder, sphere), radius by their radius.
void apply_only(Experiment& ex, const std::string& spec);
// The axes --only selects by (row_axes() less those a run sets otherwise, such as samples).
std::vector<std::string> only_keys();

// A run with plug-in shaders needs the glsl backend: an InputError naming them otherwise (the
// experiment's backends after --only, or `backends_override`, pxh run --backend, when given).
void check_plugin_backends(const Experiment& ex, const std::vector<std::string>& backends_override);

// The method settings a backend of the run makes no rows of, one line per backend and reason
// ("backend cpu makes no rows of 2 method setting(s) (pom lod=grad, ...): lod 'grad' samples
// through the GPU's own level selection: glsl only"): pxh run prints them as warnings and
// records them in run.json.
std::vector<std::string> skipped_settings(const Experiment& ex,
                                          const std::vector<std::string>& backends_override);

// Whether the camera can measure ex.samples per side at each of its settings (the perspective
// camera: samples <= resolution): an InputError at `where` (pxh run's "--samples"), or at
// [views] when `where` is empty, otherwise. parse_experiment checks the file's samples.
void check_camera_samples(const Experiment& ex, const std::string& where);

// What the experiment's keys ask of the backends (ex.backend); the command line's overrides
// are the runner's.
BackendSettings backend_settings(const Experiment& ex);

// What a run will take, estimated before any work (the lead's --max-rows / --max-memory).
//   rows = height field entries (scale/bias expanded) x theta x phi x method settings x
//          (precisions if cpu runs + texture formats if glsl runs)
//   peak_bytes, with fields built one at a time (only the largest matters):
//     kBaseBytes (the process: libraries, Embree's and TBB's threads; 64 MiB, 192 MiB once
//     an image is read or written: OpenImageIO's module)
//     + per texel of the largest field: 4 (its floats) + 1 (filled mask, scans only)
//       + 6 (the exact tracer's maximum mipmap: 4/3 of a float per cell)
//       + kEmbreeBytesPerTexel (Embree's GRID vertices and BVH, measured)
//     + per sample of a view (samples^2): kViewBytesPerSample (sample points, both truths'
//       hits, their gap) + 16 bytes per row of the view (error vectors) x 2, or 3 with
//       sweep_dt_deg (the previous and the companion view), + the views of a distance
//       sweep waiting for the next distance (theta count x settings between a setting and its
//       successor) and one companion there + kOutputBytesPerSample per
//       method output alive at once (CPU float, CPU double and the current one: 3)
//       + with maps, one error image being written (16 bytes per sample)
//     + kBytesPerRow per result row (the rows are kept until results.csv is written).
// `backends_override` (pxh run --backend) replaces the experiment's backends when non-empty.
// File fields' sizes are read from their headers (the loader's limit when unreadable).
struct RunEstimate {
    size_t rows = 0;
    size_t peak_bytes = 0;
    std::string detail;  // one line: the terms above, in MiB
};
RunEstimate estimate_run(const Experiment& ex, const std::vector<std::string>& backends_override);
// The run's estimate against pxh run's --max-rows and --max-memory: an InputError at the
// experiment file naming the estimate and the flag that raises the limit.
void check_run_size(const Experiment& ex, const std::vector<std::string>& backends_override,
                    size_t max_rows, size_t max_memory);

}  // namespace pxh
