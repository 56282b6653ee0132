#include "harness/commands/bench.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>

#include "harness/truth/embree_truth.h"
#include "harness/core/error.h"
#include "harness/truth/ground_truth.h"
#include "harness/metrics/agreement.h"
#include "harness/results/provenance.h"
#include "heightfields/heightfields.h"

namespace pxh {
namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double seconds(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int run_bench(const BenchOptions& opt) {
    const GeneratorInfo* gen = find_generator(opt.field);
    if (!gen) throw InputError("--field", "unknown generator '" + opt.field + "'");
    // Views the ground truths would refuse (the travel limit), before any work.
    for (double theta : opt.thetas)
        if (const std::string why = ray_travel_problem(opt.scale, theta); !why.empty())
            throw InputError("--theta", why);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(opt.threads));
    const auto P = sample_grid(opt.samples);
    const double rays = double(P.size());
    nlohmann::json results = nlohmann::json::array();
    // Only the columns measured: the per-ray tracers' throughput with --naive alone.
    std::printf("%-6s %-6s %12s %12s %8s", "size", "theta", "exact Mr/s", "embree Mr/s", "ratio");
    if (opt.naive) std::printf(" %12s %12s", "per-ray Mr/s", "naive Mr/s");
    std::printf(" %10s %10s %10s %10s\n", "agree p50", "agree p99", "agree max", "frac>0.5");
    for (int size : opt.sizes) {
        const HeightField hf = generate_heightfield(
            *gen, size, size, resolve_params(gen->params, {}, "bench", gen->name));
        double exact_build = 0, embree_build = 0;
        std::unique_ptr<ExactTracer> exact;
        exact_build = seconds([&] { exact = std::make_unique<ExactTracer>(hf, opt.scale, opt.bias); });
        std::unique_ptr<EmbreeTracer> embree;
        embree_build = seconds([&] { embree = std::make_unique<EmbreeTracer>(hf, opt.scale, opt.bias); });
        for (double theta : opt.thetas) {
            const OrthographicCamera camera(theta, opt.phi, opt.samples);
            const View view = camera.view();
            const Vec3d V = camera.direction();
            // Both write into buffers kept from run to run (so neither pays for fresh pages).
            Hits hits, em;
            auto run_exact = [&] { exact->trace(view, hits); };  // trace_grid: on the sample grid
            auto run_embree = [&] { embree->trace(view, em); };
            run_exact();  // warm-up
            run_embree();
            std::vector<double> t_exact, t_embree, t_naive, t_per_ray;
            auto per_ray = [&](auto&& trace_one) {
                return seconds([&] {
                    tbb::parallel_for(tbb::blocked_range<size_t>(0, P.size(), 256), [&](const auto& r) {
                        for (size_t k = r.begin(); k < r.end(); ++k) trace_one(P[k]);
                    });
                });
            };
            for (int rep = 0; rep < opt.repeats; ++rep) {
                // Alternate the order so drift on a shared machine hits both alike.
                if (rep % 2 == 0) {
                    t_exact.push_back(seconds(run_exact));
                    t_embree.push_back(seconds(run_embree));
                } else {
                    t_embree.push_back(seconds(run_embree));
                    t_exact.push_back(seconds(run_exact));
                }
                if (opt.naive) {
                    t_per_ray.push_back(per_ray([&](Vec2d p) { return exact->trace(p, V); }));
                    t_naive.push_back(per_ray([&](Vec2d p) { return exact->trace_naive(p, V); }));
                }
            }
            const ErrorStats agree = reference_agreement(em.uv, hits.uv, size, size);
            const double exact_mrays = rays / median(t_exact) / 1e6;
            const double embree_mrays = rays / median(t_embree) / 1e6;
            std::printf("%-6d %-6g %12.2f %12.2f %8.2f", size, theta, exact_mrays, embree_mrays,
                        exact_mrays / embree_mrays);
            if (opt.naive)
                std::printf(" %12.2f %12.2f", rays / median(t_per_ray) / 1e6, rays / median(t_naive) / 1e6);
            std::printf(" %10.4f %10.4f %10.3f %10.5f\n", agree.p50, agree.p99, agree.max, agree.frac_gt_0_5);
            std::fflush(stdout);
            nlohmann::json row = {{"size", size},
                                  {"theta_deg", theta},
                                  {"phi_deg", opt.phi},
                                  {"rays", P.size()},
                                  {"exact_mrays_per_s", exact_mrays},
                                  {"embree_mrays_per_s", embree_mrays},
                                  {"ratio_exact_over_embree", exact_mrays / embree_mrays},
                                  {"exact_seconds", t_exact},
                                  {"embree_seconds", t_embree},
                                  {"exact_build_ms", exact_build * 1e3},
                                  {"embree_build_ms", embree_build * 1e3},
                                  {"agree_p50_texel", agree.p50},
                                  {"agree_p99_texel", agree.p99},
                                  {"agree_max_texel", agree.max},
                                  {"agree_frac_gt_0_5", agree.frac_gt_0_5}};
            if (opt.naive) {  // measured only with --naive (otherwise left out, never NaN)
                row["per_ray_mipmap_mrays_per_s"] = rays / median(t_per_ray) / 1e6;
                row["naive_mrays_per_s"] = rays / median(t_naive) / 1e6;
                row["per_ray_mipmap_seconds"] = t_per_ray;
                row["naive_seconds"] = t_naive;
            }
            results.push_back(std::move(row));
        }
    }
    nlohmann::json doc = provenance(opt.threads);
    doc["benchmark"] =
        "ground truth throughput: exact (trace_grid: the view's parallel rays in bands over "
        "max-mipmap bounds) vs Embree rtcIntersect16, both on the same sample grid";
    doc["field"] = opt.field;
    doc["scale"] = opt.scale;
    doc["bias"] = opt.bias;
    doc["repeats"] = opt.repeats;
    doc["statistic"] = "median over repeats; ratio from medians measured in the same run";
    doc["results"] = results;
    const std::string out =
        opt.out.empty() ? "results/runs/bench-" + utc_timestamp("%Y%m%d-%H%M%S") + ".json" : opt.out;
    const auto parent = std::filesystem::path(out).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    std::ofstream(out) << doc.dump(2) << "\n";
    std::cout << "ratio = exact / Embree throughput (median of " << opt.repeats << " repeats, "
              << opt.threads << " threads, " << P.size() << " rays); agreement in texels -> "
              << out << "\n";
    return 0;
}

}  // namespace pxh
