// The backend stage: runs one method setting over every sample of one view and returns the
// per-sample output (uv, fetches, shadow factors, timing). Scoring is the metrics' job.
//
// Adding a backend: one file harness/backends/NAME_backend.cpp defining a Backend subclass, a
// factory, the reader of its own experiment keys (into BackendSettings::own), its variants and
// timing, gathered in `const BackendEntry& NAME_backend_entry()`, plus one line X(NAME) in
// PXH_BACKENDS (harness/backends/registry.cpp).
#pragma once
#include <any>
#include <cmath>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "harness/core/limits.h"  // kDefaultGlTimeLimitS, kMaxGlTimeLimitS
#include "harness/scene/heightfield.h"
#include "harness/scene/scene.h"
#include "harness/scene/shading.h"
#include "harness/scene/texture_levels.h"
#include "harness/scene/view.h"
#include "methods/method.h"

namespace pxh {

class ParamDict;

// Median, minimum and maximum of repeated timings (NaN when there are none).
struct Spread {
    double median = NAN, min = NAN, max = NAN;
};
Spread spread(std::vector<double> times);

// How long a method took, as its backend measures it (Google Benchmark's Run: one time, its
// unit, its repeats): results.csv's time, time_unit, time_min, time_max, time_repeats.
struct Timing {
    std::string unit;             // as the backend names it: "ns/sample", "ms/frame"; "": untimed
    std::vector<double> repeats;  // every timed repeat, in the order measured
    Spread stats;                 // median, min, max of repeats
};
// Sets unit and repeats and computes their spread (no repeats: untimed, unit left empty).
Timing timing_of(std::string unit, std::vector<double> repeats);

// A counter a backend declares: results.csv's NAME (median), NAME_min, NAME_max.
struct CounterSpec {
    std::string name, unit, meaning;  // meaning: one line (columns, run.json, docs)
};
// What a backend's timing is: the unit of its time, what one repeat measures, its counters.
struct TimingSpec {
    std::string unit, measures;
    std::vector<CounterSpec> counters;
};

// Anything else a backend measures per row (Google Benchmark's UserCounters), declared in its
// registry entry (CounterSpec): results.csv's columns NAME, NAME_min, NAME_max.
struct Counter {
    std::string name;
    Spread value;  // median, min, max over the repeats it was measured in
};

struct MethodOutput {
    std::vector<Vec2d> uv;  // per sample (unwrapped)
    std::vector<int> fetches;
    std::vector<float> shadow_hard, shadow_soft;  // light factors at uv, when a light is given
    // The depth it writes (docs/conventions.md section 11; the setting's depth mode): per sample
    // depth(X_w) = (X_w - P) . f along the view's depth axis (methods/depth.h), in tiles; NaN
    // where there is no uv.
    std::vector<double> depth;
    // CPU: per sample the height z_m the method handed back with its uv (methods/depth.h
    // MethodHit::z; the surface's at uv for a single-step method), in its own precision, and the
    // height its engine's depth formula reads (MethodHit::engine_z); NaN where there is no uv;
    // empty where the setting's depth mode does not read them (base; engine_z: all but engine).
    std::vector<double> hit_z, engine_z;
    // Per sample, how far rounding alone may move the written depth (tiles; empty: 1e-9 at
    // every sample, the double twin's and the GPU's): a write nearer the eye than the polygon
    // by no more than this is not counted in depth_toward_frac.
    std::vector<double> depth_tol;
    // The span of depth the GL twin's depth target holds, [-span / 2, span / 2] tiles
    // (depth_target_span); 0: unknown. Both twins set it, so both count depth_clamped alike.
    double depth_span = 0;
    // Its timing and its declared counters (empty when not timed).
    Timing timing;
    std::vector<Counter> counters;
    std::string shader;         // GLSL: "builtin" or the shader file(s) compiled
    std::string shader_sha256;  // GLSL: sha256 of the method's shader source
    // GLSL: samples the shader discarded or left unwritten (their uv is NaN, fetches 0); 0 on
    // the CPU.
    long long samples_discarded = 0;
    // Per sample, 1 where the method discarded it (both twins alike: the GLSL fragment wrote
    // nothing; the C++ twin of a may_discard method answered NaN); empty: none. Its fetches are
    // 0 and not counted (fetches_mean is over the answered samples); it is not in nonfinite.
    std::vector<uint8_t> discarded;
    // GLSL with [shading]: its image shaded by the GLSL twin of the shading
    // (harness/backends/shade_gl.h) from the uv it read back, sRGB 8-bit values / 255, 3 a
    // sample; empty otherwise (the CPU's rows are shaded by the CPU twin in the run's writer).
    std::vector<float> shaded;
};

// What a run asks of its backends (the experiment's keys and the command line's overrides).
struct BackendSettings {
    std::vector<std::string> precisions{"float"};      // CPU: float | double
    std::vector<std::string> texture_formats{"r32f"};  // GLSL height texture: r32f | r16 | r8
    int timing_repeats = 5;                            // CPU: timed passes (median)
    int gl_frames = 5;                                 // GLSL: timed frames (median)
    std::string shader_dir;                            // GLSL sources override (development)
    std::string gl = "osmesa";                         // GLSL: the GL context (harness/gl)
    // GLSL: a row's GL work (compile, upload, frames, read-back) runs in a child process that
    // is killed after this many seconds (the row fails; the next row gets a fresh context).
    double gl_time_limit_s = kDefaultGlTimeLimitS;
    // Another backend's own settings, by its name: what its `read` parsed from its keys, in a
    // type of its own (its factory takes them back with std::any_cast), so a new backend's keys
    // need no field above.
    std::map<std::string, std::any> own;
};

// The variant a row of a backend runs in: its precision and (GLSL) height texture format.
struct Variant {
    std::string precision, texture_format;
};

// One view, as every backend gets it.
struct ViewInput {
    const Scene<double>& scene;  // s, b, field size; V: the view's direction (parallel rays)
    const HeightField& hf;
    // The samples' rays (harness/scene/view.h): P_k, and V_k when not parallel (then a
    // method sees sample k's V_k as its scene's V). The GLSL backend draws N x N pixel views
    // (sample j N + i at pixel (i, j)) and refuses other sample counts.
    const View& rays;
    const LightSpec* light;  // when given: hard and soft light factors at the output uv
    bool timed;              // false: no timing passes (a sweep's companion view)
    // The method's precomputed textures for this field at (s, b) (methods/resource.h), built
    // once and shared by every backend; nullptr for a method without resources.
    const MethodResources* resources = nullptr;
    // The field's texture levels (harness/scene/texture_levels.h), built once per field when a
    // setting samples them; nullptr otherwise. A setting whose lod is not base reads them.
    const TextureLevels* levels = nullptr;
    // Each sample's lambda (footprint_lod of its footprint at the field's size), in sample
    // order; what lod = level samples at and what a shader's pxh_lod() returns.
    const std::vector<double>* lambda = nullptr;
    // [shading] (harness/scene/shading.h): a backend that shades in its own shader (GLSL)
    // shades its image with it; nullptr: none. Needs `levels` and `lambda`.
    const ShadingSpec* shading = nullptr;
};

class Backend {
  public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;
    // The variants each method setting runs in, in row order.
    virtual std::vector<Variant> variants() const = 0;
    // Throws std::exception (the row fails with its message) when the method cannot run.
    virtual MethodOutput run(const MethodSpec& m, const ViewInput& view, const Variant& v) = 0;
    // Whether it runs this method setting at all (the CPU backend: only methods with a C++
    // twin, a plug-in shader has none; and not the GLSL-only level modes grad, implicit). A
    // setting it does not run has no rows on it.
    virtual bool runs(const MethodSpec&) const { return true; }
    // The results' shader column for this method ("" where there is no shader).
    virtual std::string shader_of(const MethodInfo&) const { return ""; }
    // Whether its rows are drawn in a process of its own (the GLSL backend's GL worker; not
    // when it draws in this one): where nothing is timed, the runner draws them on a thread of
    // its own beside the truth and the other backends' rows (harness/run/side_lane.h). Such a
    // backend's run is then called from that one thread; shader_of from any.
    virtual bool own_process() const { return false; }
    // Facts for run.json (e.g. gl_renderer, gl_version); empty by default.
    virtual std::map<std::string, std::string> facts() const { return {}; }
    // Every source compiled so far -> sha256 (run.json); empty by default.
    virtual std::map<std::string, std::string> sources() const { return {}; }
    // Its block of run.json's "backends": facts, sources, its timing (unit, what a repeat
    // measures, repeats per row, counters); a backend adds what else it knows.
    virtual nlohmann::json record(const BackendSettings& settings) const;
};

// What a backend's preflight check is given (BackendEntry::preflight): the run's plug-in shader
// settings, each with every level mode its rows use, and whether the camera's rays are parallel
// (a camera whose rays are not draws through per-pixel maps: another program).
struct PluginSettings {
    const MethodSpec* first;    // the plug-in's first setting: every setting has its uniforms
    std::vector<LodMode> lods;  // each level mode its settings run in, once, in order
};
struct Preflight {
    std::vector<PluginSettings> plugins;
    bool parallel_camera = true;
};

// The registry (harness/backends/registry.cpp): one line per backend.
struct BackendEntry {
    const char* name;
    // Reads its own keys of the experiment's top level into `settings` (the CPU backend:
    // precision, timing_repeats; GLSL: texture_format, gl, gl_time_limit_s), each checked
    // there (an InputError at its FILE:LINE).
    void (*read)(const ParamDict& experiment, BackendSettings& settings);
    std::unique_ptr<Backend> (*make)(const BackendSettings&);
    // Its variants under these settings, without creating it (a run's row estimate).
    std::vector<Variant> (*variants)(const BackendSettings&);
    // Its timing's unit and meaning and the counters it measures (results.csv's columns of
    // each counter come from here: harness/metrics/columns.cpp).
    const TimingSpec& (*timing)();
    // Timed repeats per row under these settings (run.json).
    int (*repeats)(const BackendSettings&);
    // Why it makes no rows of this method setting ("" when it runs it; nullptr: it runs every
    // setting): pxh run warns, on stderr and in run.json, naming what was skipped and why.
    std::string (*skips)(const MethodSpec&) = nullptr;
    // Checked before any row runs and before anything is written, when the run uses it (the
    // GLSL backend: every plug-in shader compiled and linked in each program its rows use, its
    // uniforms checked): one line per problem, empty when ready; nullptr: nothing to check.
    std::vector<std::string> (*preflight)(const Preflight&, const BackendSettings&) = nullptr;
    // Warnings about the backend as the run made it (the GLSL backend: --gl egl that gave a
    // software renderer), one line each; nullptr: none.
    std::vector<std::string> (*warnings)(const Backend&, const BackendSettings&) = nullptr;
    // What else its block of run.json records of the run (the GLSL backend: its GL context and
    // driver, shader_dir, LP_NUM_THREADS), added to Backend::record's; nullptr: nothing.
    void (*record)(const Backend&, const BackendSettings&, nlohmann::json& block) = nullptr;
    // Whether its float rows are the reference the other backends' rows are compared with
    // (agree_*) and its float and double rows with each other (the CPU backend).
    bool reference = false;
};
const BackendEntry& backend_entry(const std::string& name);
const std::vector<BackendEntry>& backend_registry();
std::vector<std::string> backend_names();  // in registry order
// Throws InputError(where, "unknown backend 'x' (known: cpu, glsl)") for an unknown name.
void check_backend_name(const std::string& name, const std::string& where);
// Every registered backend reads its keys (whichever backends the experiment runs: pxh run
// --backend may pick another).
void read_backend_settings(const ParamDict& experiment, BackendSettings& settings);
// Creates it (a GL backend creates its context here; its failure is a std::runtime_error).
std::unique_ptr<Backend> make_backend(const std::string& name, const BackendSettings& settings);
// The registry's reference backend (BackendEntry::reference), created: the float run every
// other backend's rows are compared with.
std::unique_ptr<Backend> make_reference_backend(const BackendSettings& settings);
// The variants a backend would run under these settings (its rows per method setting).
std::vector<Variant> backend_variants(const std::string& name, const BackendSettings& settings);
// Its timing (unit, meaning, counters); every registered backend's counters, in registry order.
const TimingSpec& backend_timing(const std::string& name);
// How many timed repeats a row of backend NAME makes under these settings (its entry's repeats).
int backend_repeats(const std::string& name, const BackendSettings& settings);
std::vector<CounterSpec> backend_counters();
// "" when backend NAME runs method setting m, else why it makes no rows of it (its entry's
// skips).
std::string backend_skips(const std::string& name, const MethodSpec& m);

}  // namespace pxh
