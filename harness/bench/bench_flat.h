// pxh bench on the flat relief: the exact tracer and Embree through the Tracer interface on the
// same view (an orthographic grid view takes the exact tracer's band path, any other its per-ray
// path), repeated, and the view's line and JSON entry.
#pragma once
#include <nlohmann/json.hpp>
#include <vector>

#include "harness/bench/bench_util.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/exact_tracer.h"
#include "harness/truth/tracer.h"

namespace pxh {

// The repeated timings of one view (seconds), and the last run's results of both tracers.
struct ViewTimings {
    std::vector<double> exact, embree, per_ray, walk, naive;
    Hits hits, em;  // the exact tracer's, Embree's
};

// Both tracers through the Tracer interface on the same view (an orthographic grid view takes
// the exact tracer's band path, any other its per-ray path), and with --naive the two other
// per-ray tracers on the same rays.
ViewTimings time_view(const ExactTracer& exact, const EmbreeTracer& embree, const View& view,
                      const BenchOptions& opt);

// One view's line on stdout and its entry in the JSON (build times in seconds).
nlohmann::json report_view(const BenchOptions& opt, int size, const BenchView& bv, const View& view,
                           const ViewTimings& t, double exact_build, double embree_build);

// The table's header line: only the columns measured (the per-ray tracers' with --naive).
void print_flat_header(const BenchOptions& opt, bool eye);

}  // namespace pxh
