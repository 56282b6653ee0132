// `pxh bench`: its options (the measurement itself is bench.cpp).
#include <memory>

#include "harness/commands/bench.h"
#include "harness/commands/commands.h"
#include "harness/core/error.h"

namespace pxh {

Command add_bench_command(CLI::App& app) {
    auto* bench = app.add_subcommand(
        "bench", "ground-truth throughput: exact tracer vs Embree on the same rays (medians)");
    auto bo = std::make_shared<BenchOptions>();
    bench->add_option("--sizes", bo->sizes, "height field sizes (default 512 2048)")
        ->check(CLI::Range(1, 16384));
    bench->add_option("--theta", bo->thetas, "view angles in degrees (default 60 85)")
        ->check(CLI::Range(0.0, 89.999));
    bench->add_option("--phi", bo->phi, "azimuth in degrees (default 20)");
    bench->add_option("--field", bo->field, "generator (default fbm)");
    bench->add_option("--samples", bo->samples, "N: N x N rays (default 512)")
        ->check(CLI::Range(1, 8192));
    bench->add_option("--repeats", bo->repeats, "timed repeats (default 5)")
        ->check(CLI::Range(1, 1000));
    bench->add_option("--threads", bo->threads, "threads (default 2)")->check(CLI::Range(1, 1024));
    bench->add_flag(
        "--naive", bo->naive,
        "also time the per-ray tracers (max-mipmap walk, per-cell DDA) on the same rays");
    auto* out = bench->add_option("--out", bo->out,
                                  "JSON output, a new file (default results/runs/bench-DATE.json)");
    bench->add_flag("--force", bo->force,
                    "replace --out when it is an earlier pxh bench file (never anything else)");
    return {bench, [bo, out] {
                if (out->count() && bo->out.empty())
                    throw InputError("--out", "is empty: name the JSON file");
                return run_bench(*bo);
            }};
}

}  // namespace pxh
