// `pxh bench`: its options (the measurement itself is harness/bench/).
#include <cmath>
#include <memory>

#include "harness/bench/bench.h"
#include "harness/commands/commands.h"
#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/core/registry.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/view.h"

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
    bench->add_option("--field", bo->field,
                      "generator, or scan:NAME for a measured field at its own size (default fbm)");
    bench->add_option("--samples", bo->samples, "N: N x N rays (default 512)")
        ->check(CLI::Range(1, 8192));
    bench->add_option("--repeats", bo->repeats, "timed repeats (default 5)")
        ->check(CLI::Range(1, 1000));
    bench->add_option("--threads", bo->threads, "threads (default 2)")->check(CLI::Range(1, 1024));
    bench->add_flag(
        "--naive", bo->naive,
        "also time the per-ray tracers (trace: the tile-local max-mipmap walk; trace_ray: the "
        "fast path, bit for bit trace_naive; trace_naive: the per-cell DDA) on the same rays");
    bench
        ->add_option("--camera", bo->camera,
                     "a camera (" + join_names(camera_names()) + "; default " + bo->camera +
                         "): parallel rays time the exact tracer's band path, others its "
                         "per-ray path")
        ->check(CLI::IsMember(camera_names()));
    auto* distance = bench->add_option("--distance", bo->distances,
                                       "perspective: eye distances in tiles (default 1.5 4 16)");
    auto* fov = bench->add_option("--fov", bo->fov, "perspective: field of view, deg (default 45)");
    fov->check(CLI::Range(0.001, 179.999));
    bench
        ->add_option("--base", bo->base,
                     "a base surface (" + join_names(base_names()) +
                         "; default plane): a curved one also times the curved truth's walk "
                         "over the same rays, as a ratio to the exact tracer on the plane")
        ->check(CLI::IsMember(base_names()));
    auto* radius = bench->add_option("--radius", bo->radii,
                                     "a curved base's radii in tiles, each timed in turn (e.g. "
                                     "--radius 1.5 4)");
    auto* out = bench->add_option("--out", bo->out,
                                  "JSON output, a new file (default results/runs/bench-DATE.json)");
    bench->add_flag("--force", bo->force,
                    "replace --out when it is an earlier pxh bench file (never anything else)");
    return {
        bench, [bo, out, distance, fov, radius] {
            if (out->count() && bo->out.empty())
                throw InputError("--out", "is empty: name the JSON file");
            const bool curved = find_base(bo->base) && find_base(bo->base)->curved;
            if (curved && bo->radii.empty())
                throw InputError("--base", "--base " + bo->base +
                                               " needs --radius R, a finite number above scale * "
                                               "bias");
            for (double r : bo->radii)
                if (curved && !(std::isfinite(r) && r > bo->scale * bo->bias))
                    throw InputError("--radius", "radius " + format_number(r) +
                                                     " is not a finite number above scale * "
                                                     "bias (" +
                                                     format_number(bo->scale * bo->bias) + ")");
            if (!curved && radius->count())
                throw InputError("--radius", "applies to a curved --base (cylinder, sphere)");
            // An eye distance and field of view: a camera whose rays are not parallel.
            if (camera_entry(bo->camera, "--camera").parallel &&
                (distance->count() || fov->count()))
                throw InputError(distance->count() ? "--distance" : "--fov",
                                 "applies to a camera with an eye, not --camera " + bo->camera);
            // Checked here, in pxh's words (CLI11's ranges let NaN through and print the
            // largest double in full).
            for (double t : bo->thetas)
                if (!(t >= 0 && t <= 89.999))
                    throw InputError("--theta", format_number(t) + " is not in [0, 89.999]");
            if (!std::isfinite(bo->phi))
                throw InputError("--phi", format_number(bo->phi) + " is not a finite angle");
            if (!(bo->fov >= 0.001 && bo->fov <= 179.999))
                throw InputError("--fov", format_number(bo->fov) + " is not in [0.001, 179.999]");
            for (double d : bo->distances)
                if (!(d > 0 && std::isfinite(d)))
                    throw InputError("--distance",
                                     format_number(d) + " is not a positive number of tiles");
            return run_bench(*bo);
        }};
}

}  // namespace pxh
