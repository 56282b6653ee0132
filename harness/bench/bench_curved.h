// `pxh bench --base B --radius R` (issue 62, item 3): on each view, the same camera's rays on
// the curved base traced by the pyramid tracer (the curved truth), Embree on a displaced
// triangle grid of the same surface and the walk (the test oracle), one after the other in the
// same run; throughput, ratios, hit agreement and Embree's error against the exact hits.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "harness/bench/bench.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/view.h"

namespace pxh {

// The walks pxh bench times on each view of a curved base: the warm-up and the repeats
// (bench.cpp).
double bench_walks(const BenchOptions& opt);

// Times the three tracers over `camera`'s rays on `base` (`at` names the view in errors), prints
// its lines under the view's and adds its fields to the view's JSON entry `row`; `exact_mrays`:
// the exact tracer's throughput on the plane over the same camera in the same run.
void time_curved(const BenchOptions& opt, const HeightField& hf, const BaseSurface& base,
                 const Camera& camera, const std::string& at, double exact_mrays,
                 nlohmann::json& row);

}  // namespace pxh
