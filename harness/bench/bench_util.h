// pxh bench's shared pieces (harness/bench/): statistics of repeated timings, the clock, the
// views it times on a camera, and the JSON file's title and writer.
#pragma once
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/bench/bench.h"
#include "harness/scene/view.h"

namespace pxh {

// The median of `v` (NaN when empty).
double bench_median(std::vector<double> v);
// (max - min) / median of repeated times: how much the machine moved them (NaN when empty).
double bench_spread(const std::vector<double>& seconds_list);
// The wall-clock seconds f takes.
double bench_seconds(const std::function<void()>& f);

// One view pxh bench times: its camera at one theta (and, for a camera with an eye, one
// distance), and the words that name it in errors ("theta 60 distance 2").
struct BenchView {
    std::unique_ptr<Camera> camera;
    double theta = 0;
    double distance = 0;  // a camera with an eye: its distance (tiles); else 0
    bool eye = false;     // the camera has an eye (its rays are not parallel)
    std::string at;
};
// The views of --camera at `theta`: the orthographic grid (one view) or the perspective camera
// at each --distance. A camera of the registry pxh bench has no sweep for is an InputError at
// --camera naming the ones it times.
std::vector<BenchView> bench_views(const BenchOptions& opt, double theta);

// The paths both tracers take on this CPU (as capped by PXH_TRACER_PATH) and its vector flags.
nlohmann::json paths_taken();
// Writes the JSON document (provenance, the settings and every view's entry) to opt.out and
// prints the table's closing line.
void write_bench(const BenchOptions& opt, const nlohmann::json& results, size_t rays);

}  // namespace pxh
