// `pxh bench`: ground-truth throughput, the exact tracer against Embree on the same rays.
#pragma once
#include <cmath>
#include <string>
#include <vector>

namespace pxh {

struct BenchOptions {
    std::vector<int> sizes{512, 2048};
    std::vector<double> thetas{60, 85};
    double phi = 20;
    std::string field = "fbm";
    double scale = 0.05, bias = 1.0;
    int samples = 512;  // N x N rays
    int repeats = 5;
    int threads = 2;
    bool naive = false;  // also time the per-ray tracers: max-mipmap walk and per-cell DDA
    // "orthographic" (the sample grid: the exact tracer's band path) or "perspective" (a
    // PerspectiveCamera per theta and distance: the exact tracer's per-ray path, trace_ray).
    std::string camera = "orthographic";
    std::vector<double> distances{1.5, 4, 16};  // perspective: eye distances in tiles
    double fov = 45;                            // perspective: full field of view, degrees
    // A curved base (docs/conventions.md section 12): also time the curved truth's walk over the
    // same camera's rays on it ("plane": not timed).
    std::string base = "plane";
    std::vector<double> radii;  // a curved base's radii (tiles), each timed in turn
    double radius = NAN;        // the one being timed (run_bench sets it from radii)
    std::string out;            // JSON file (default: results/runs/bench-DATE.json)
    bool force = false;         // replace `out` when it is an earlier pxh bench file (only then)
};

// The bench's JSON is a new file of its own: `out` must not exist, or be (with force) an
// earlier pxh bench file; a link, a device (/dev/full), a folder or anyone else's file is an
// InputError before any measurement. Written to OUT.partial-PID-HEX (never through a link),
// then renamed into place; a write error is a std::runtime_error naming the file.
void check_bench_out(const std::string& out, bool force);

int run_bench(const BenchOptions& opt);

}  // namespace pxh
