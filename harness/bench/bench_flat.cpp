#include "harness/bench/bench_flat.h"

#include <tbb/parallel_for.h>

#include <cstdio>

#include "harness/metrics/agreement.h"

namespace pxh {

ViewTimings time_view(const ExactTracer& exact, const EmbreeTracer& embree, const View& view,
                      const BenchOptions& opt) {
    // Both write into buffers kept from run to run (so neither pays for fresh pages).
    ViewTimings t;
    auto run_exact = [&] { exact.trace(view, t.hits); };
    auto run_embree = [&] { embree.trace(view, t.em); };
    run_exact();  // warm-up
    run_embree();
    auto per_ray = [&](auto&& trace_one) {
        return bench_seconds([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, view.size(), 256), [&](const auto& r) {
                for (size_t k = r.begin(); k < r.end(); ++k) trace_one(view.P[k], view.dir(k));
            });
        });
    };
    for (int rep = 0; rep < opt.repeats; ++rep) {
        // Alternate the order so drift on a shared machine hits both alike.
        if (rep % 2 == 0) {
            t.exact.push_back(bench_seconds(run_exact));
            t.embree.push_back(bench_seconds(run_embree));
        } else {
            t.embree.push_back(bench_seconds(run_embree));
            t.exact.push_back(bench_seconds(run_exact));
        }
        if (opt.naive) {
            t.per_ray.push_back(per_ray([&](Vec2d p, Vec3d v) { return exact.trace(p, v); }));
            t.walk.push_back(per_ray([&](Vec2d p, Vec3d v) { return exact.trace_ray(p, v); }));
            t.naive.push_back(per_ray([&](Vec2d p, Vec3d v) { return exact.trace_naive(p, v); }));
        }
    }
    return t;
}

// One view's line on stdout and its entry in the JSON (build times in seconds).
nlohmann::json report_view(const BenchOptions& opt, int size, const BenchView& bv, const View& view,
                           const ViewTimings& t, double exact_build, double embree_build) {
    const size_t n = t.hits.uv.size();
    const double rays = double(n);
    // Agreement over the pixels that are measured (a perspective view's inside pixels).
    std::vector<Vec2d> em_uv, exact_uv;
    for (size_t k = 0; k < n; ++k)
        if (view.is_inside(k)) {
            em_uv.push_back(t.em.uv[k]);
            exact_uv.push_back(t.hits.uv[k]);
        }
    const ErrorStats agree = reference_agreement(em_uv, exact_uv, size, size);
    const double exact_mrays = rays / bench_median(t.exact) / 1e6;
    const double embree_mrays = rays / bench_median(t.embree) / 1e6;
    const bool persp = bv.eye;
    std::printf("%-6d %-6g", size, bv.theta);
    if (persp) std::printf(" %-6g %8zu", bv.distance, view.outside_count());
    std::printf(" %12.2f %12.2f %8.2f", exact_mrays, embree_mrays, exact_mrays / embree_mrays);
    if (opt.naive)
        std::printf(" %12.2f %12.2f %12.2f", rays / bench_median(t.per_ray) / 1e6,
                    rays / bench_median(t.walk) / 1e6, rays / bench_median(t.naive) / 1e6);
    std::printf(" %10.4f %10.4f %10.3f %10.5f %5.2f %5.2f\n", agree.p50, agree.p99, agree.max,
                agree.frac_gt_0_5, bench_spread(t.exact), bench_spread(t.embree));
    std::fflush(stdout);
    nlohmann::json row = {{"size", size},
                          {"camera", opt.camera},
                          {"theta_deg", bv.theta},
                          {"phi_deg", opt.phi},
                          {"rays", n},
                          {"exact_mrays_per_s", exact_mrays},
                          {"embree_mrays_per_s", embree_mrays},
                          {"ratio_exact_over_embree", exact_mrays / embree_mrays},
                          {"exact_seconds", t.exact},
                          {"embree_seconds", t.embree},
                          {"exact_spread", bench_spread(t.exact)},
                          {"embree_spread", bench_spread(t.embree)},
                          {"exact_build_ms", exact_build * 1e3},
                          {"embree_build_ms", embree_build * 1e3},
                          {"agree_p50_texel", agree.p50},
                          {"agree_p99_texel", agree.p99},
                          {"agree_max_texel", agree.max},
                          {"agree_frac_gt_0_5", agree.frac_gt_0_5}};
    if (persp) {  // the rays of outside pixels are traced (the look-at ray) but not compared
        row["distance"] = bv.distance;
        row["fov_deg"] = opt.fov;
        row["samples_outside"] = view.outside_count();
    }
    if (opt.naive) {  // measured only with --naive (otherwise left out, never NaN)
        row["per_ray_mipmap_mrays_per_s"] = rays / bench_median(t.per_ray) / 1e6;
        row["trace_ray_mrays_per_s"] = rays / bench_median(t.walk) / 1e6;
        row["naive_mrays_per_s"] = rays / bench_median(t.naive) / 1e6;
        row["trace_ray_seconds"] = t.walk;
        row["per_ray_mipmap_seconds"] = t.per_ray;
        row["naive_seconds"] = t.naive;
    }
    return row;
}

void print_flat_header(const BenchOptions& opt, bool eye) {
    std::printf("%-6s %-6s", "size", "theta");
    if (eye) std::printf(" %-6s %8s", "D", "outside");
    std::printf(" %12s %12s %8s", "exact Mr/s", "embree Mr/s", "ratio");
    if (opt.naive) std::printf(" %12s %12s %12s", "per-ray Mr/s", "ray Mr/s", "naive Mr/s");
    std::printf(" %10s %10s %10s %10s %5s %5s\n", "agree p50", "agree p99", "agree max", "frac>0.5",
                "sprdX", "sprdE");
}

}  // namespace pxh
