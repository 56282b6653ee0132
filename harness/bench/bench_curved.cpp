#include "harness/bench/bench_curved.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "harness/bench/bench_util.h"
#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/scene/curved_view.h"
#include "harness/truth/curved_embree.h"
#include "harness/truth/curved_pyramid.h"
#include "harness/truth/curved_tracer.h"
#include "harness/truth/embree_truth.h"

namespace pxh {

namespace {

// The p-quantile of v (sorted in place); NaN when empty.
double quantile(std::vector<double>& v, double p) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))];
}

struct Agreement {
    size_t hit_miss = 0;  // rays one hits and the other misses
    size_t both = 0;
    double p50 = NAN, p99 = NAN, max = NAN;  // texels, max over u and v, rays both hit
};

Agreement agreement(const std::vector<uint8_t>& hit_a, const std::vector<Vec2d>& uv_a,
                    const std::vector<uint8_t>& hit_b, const std::vector<Vec2d>& uv_b, int n) {
    Agreement a;
    std::vector<double> e;
    for (size_t k = 0; k < hit_a.size(); ++k) {
        if (bool(hit_a[k]) != bool(hit_b[k])) {
            ++a.hit_miss;
            continue;
        }
        if (!hit_a[k]) continue;
        e.push_back(double(n) *
                    std::max(std::abs(uv_a[k].x - uv_b[k].x), std::abs(uv_a[k].y - uv_b[k].y)));
    }
    a.both = e.size();
    if (!e.empty()) {
        a.max = *std::max_element(e.begin(), e.end());
        a.p99 = quantile(e, 0.99);
        a.p50 = quantile(e, 0.5);
    }
    return a;
}

// The three tracers' timings on one view's rays, and their last results.
struct CurvedTimings {
    CurvedHits walk, pyramid;
    std::vector<double> embree_t;  // Embree's t per ray (NaN: a miss)
    std::vector<double> s_walk, s_pyr, s_emb;
    double pyramid_build = 0;
    std::unique_ptr<CurvedEmbreeGrid> grid;
    std::string grid_problem;  // why the grid was not built ("" when it was)
};

// Warm-ups, then the pyramid and Embree alternated repeat by repeat, then the walk. Each
// walk's budget: the view's (kMaxCurvedWalkSteps, checked before any work with bench_walks()
// walks) shared by the warm-up and the repeats; the pyramid's the same.
void run_curved(const BenchOptions& opt, const HeightField& hf, const BaseSurface& base,
                const CurvedView& cv, CurvedTimings& ct) {
    const CurvedTracer walk(hf, opt.scale, opt.bias, base);
    std::unique_ptr<CurvedTracer> pyramid;
    ct.pyramid_build = bench_seconds([&] {
        pyramid = std::make_unique<CurvedTracer>(hf, opt.scale, opt.bias, base, 0.25,
                                                 CurvedMethod::pyramid);
    });
    try {
        ct.grid = std::make_unique<CurvedEmbreeGrid>(hf, opt.scale, opt.bias, base, cv.rays);
    } catch (const std::exception& e) {
        ct.grid_problem = e.what();
    }
    const double budget = kMaxCurvedWalkSteps / bench_walks(opt);
    ct.pyramid = pyramid->trace(cv.rays, budget);
    if (ct.grid) ct.grid->trace(cv.rays, ct.embree_t);
    for (int r = 0; r < opt.repeats; ++r) {
        ct.s_pyr.push_back(bench_seconds([&] { ct.pyramid = pyramid->trace(cv.rays, budget); }));
        if (ct.grid)
            ct.s_emb.push_back(bench_seconds([&] { ct.grid->trace(cv.rays, ct.embree_t); }));
    }
    ct.walk = walk.trace(cv.rays, budget);
    for (int r = 0; r < opt.repeats; ++r)
        ct.s_walk.push_back(bench_seconds([&] { ct.walk = walk.trace(cv.rays, budget); }));
}

// The view's lines on stdout and its fields in the JSON entry `row`.
void report_curved(const BaseSurface& base, const CurvedView& cv, int texels,
                   const CurvedTimings& ct, double exact_mrays, nlohmann::json& row) {
    const size_t n = cv.rays.size();
    const CurvedHits &hp = ct.pyramid, &hw = ct.walk;
    // Embree's hits in the base's coordinates, against the exact ones
    std::vector<uint8_t> he(n, 0);
    std::vector<Vec2d> ue(n, {NAN, NAN});
    if (ct.grid)
        for (size_t k = 0; k < n; ++k)
            if (std::isfinite(ct.embree_t[k])) {
                he[k] = 1;
                ue[k] =
                    base.coords(v3_add(cv.rays[k].o, v3_scale(cv.rays[k].d, ct.embree_t[k]))).uv;
            }
    const Agreement pw = agreement(hp.hit, hp.uv, hw.hit, hw.uv, texels);
    const Agreement ep = agreement(he, ue, hp.hit, hp.uv, texels);
    size_t hits = 0;
    for (uint8_t x : hp.hit) hits += x;
    const double mr_walk = double(n) / bench_median(ct.s_walk) / 1e6;
    const double mr_pyr = double(n) / bench_median(ct.s_pyr) / 1e6;
    const double mr_emb = ct.grid ? double(n) / bench_median(ct.s_emb) / 1e6 : NAN;
    std::printf(
        "       on %s R=%g (%zu of %zu rays hit): pyramid %.3f Mr/s (%.1f steps/ray, spread "
        "%.2f), Embree displaced grid %.3f Mr/s (spread %.2f), walk %.4f Mr/s (%.1f "
        "steps/ray, spread %.2f)\n",
        base.name().c_str(), base.radius(), hits, n, mr_pyr, hp.steps_mean, bench_spread(ct.s_pyr),
        mr_emb, bench_spread(ct.s_emb), mr_walk, hw.steps_mean, bench_spread(ct.s_walk));
    std::printf(
        "         pyramid / Embree %.2f, pyramid / walk %.1f, walk / exact on the plane %.3f; "
        "pyramid vs walk: %zu hit/miss apart, uv max %.2g texels; residual %.2g\n",
        mr_pyr / mr_emb, mr_pyr / mr_walk, mr_walk / exact_mrays, pw.hit_miss, pw.max,
        hp.residual_max);
    if (ct.grid)
        std::printf(
            "         Embree grid (%zu vertices, build %.0f ms) vs exact: %zu hit/miss apart, "
            "uv p50 %.2g p99 %.2g max %.2g texels; paths: pyramid %s, Embree %s\n",
            ct.grid->vertices(), ct.grid->build_ms(), ep.hit_miss, ep.p50, ep.p99, ep.max,
            CurvedPyramid::path_name().c_str(), EmbreeTracer::isa().c_str());
    else std::printf("         Embree grid not built: %s\n", ct.grid_problem.c_str());
    std::fflush(stdout);
    row["base"] = base.name();
    row["radius"] = base.radius();
    // the walk's, as before issue 62
    row["curved_mrays_per_s"] = mr_walk;
    row["ratio_curved_over_exact"] = mr_walk / exact_mrays;
    row["curved_seconds"] = ct.s_walk;
    row["curved_spread"] = bench_spread(ct.s_walk);
    row["curved_steps_per_ray"] = hw.steps_mean;
    row["curved_rays_hit"] = hits;
    row["curved_residual_max"] = hw.residual_max;
    // issue 62: the pyramid tracer and Embree's displaced grid on the same rays
    row["curved_pyramid_mrays_per_s"] = mr_pyr;
    row["curved_pyramid_seconds"] = ct.s_pyr;
    row["curved_pyramid_spread"] = bench_spread(ct.s_pyr);
    row["curved_pyramid_steps_per_ray"] = hp.steps_mean;
    row["curved_pyramid_build_ms"] = ct.pyramid_build * 1e3;
    row["curved_pyramid_residual_max"] = hp.residual_max;
    row["curved_pyramid_path"] = CurvedPyramid::path_name();
    row["curved_pyramid_vs_walk_hit_miss"] = pw.hit_miss;
    row["curved_pyramid_vs_walk_uv_max"] = pw.max;
    row["ratio_pyramid_over_walk"] = mr_pyr / mr_walk;
    if (!ct.grid) {
        row["curved_embree_problem"] = ct.grid_problem;
        return;
    }
    row["curved_embree_mrays_per_s"] = mr_emb;
    row["curved_embree_seconds"] = ct.s_emb;
    row["curved_embree_spread"] = bench_spread(ct.s_emb);
    row["curved_embree_vertices"] = ct.grid->vertices();
    row["curved_embree_build_ms"] = ct.grid->build_ms();
    row["curved_embree_hit_miss"] = ep.hit_miss;
    row["curved_embree_err_p50"] = ep.p50;
    row["curved_embree_err_p99"] = ep.p99;
    row["curved_embree_err_max"] = ep.max;
    row["ratio_pyramid_over_embree"] = mr_pyr / mr_emb;
}

}  // namespace

void time_curved(const BenchOptions& opt, const HeightField& hf, const BaseSurface& base,
                 const Camera& camera, const std::string& at, double exact_mrays,
                 nlohmann::json& row) {
    const CurvedView cv = curved_view(camera, base, opt.scale * (1 - opt.bias));
    CurvedTimings ct;
    try {
        run_curved(opt, hf, base, cv, ct);
    } catch (const CurvedWalkTooLong& e) {
        throw InputError("--base",
                         "base " + base.name() + " radius " + format_number(base.radius()) +
                             " on the " + std::to_string(hf.width) + " x " +
                             std::to_string(hf.height) + " field at " + at + ": " + e.what() +
                             " (kMaxCurvedWalkSteps shared by the warm-up and "
                             "--repeats; rays that skim the relief step shorter than "
                             "the quarter texel the estimate before the run assumes): "
                             "lower --theta, --sizes, --samples or --repeats");
    }
    report_curved(base, cv, std::max(hf.width, hf.height), ct, exact_mrays, row);
}

}  // namespace pxh
