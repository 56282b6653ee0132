// The exact tracer's per-ray fast path (trace_ray, the path perspective views take): on
// perspective rays (several angles, eye distances and fields of view; random, procedural and
// measured fields) and on the rays that stress a DDA (starts on grid lines, axis-parallel and
// vertical directions, flat and spiky fields, odd sizes) every hit equals the per-cell DDA's
// (trace_naive) bit for bit, uv and z; the view's outside pixels too (they carry the look-at
// ray). The walk solves a subset of the DDA's cells (on smooth fields far fewer): a
// different path, the same answers. Views larger than one of the tracer's work chunks are
// traced through the interface too (its runs of identical rays are traced once: every pixel
// still equals its own DDA hit, and rays one bit apart are traced each on its own). Views
// are traced in packets of neighbouring pixels that descend through the slab together:
// near eyes on spikes, thin walls, smooth and measured fields, partial packets, views that
// are not square images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/scene/perspective_camera.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/exact_tracer.h"
#include "harness/truth/travel_limit.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

HeightField generated(const char* name, int size) {
    const GeneratorInfo* g = find_generator(name);
    return generate_heightfield(*g, size, size, resolve_params(g->params, {}, "test", name));
}

struct Tally {
    long long rays = 0, differ = 0, walk_cells = 0, naive_cells = 0;
};

// The walk itself (trace_walk, for every ray) and trace_ray (the DDA for short rays) against
// the DDA.
void compare_ray(const ExactTracer& t, Vec2d P, Vec3d V, Tally& tally) {
    const TruthHit a = t.trace_walk(P, V), b = t.trace_naive(P, V), c = t.trace_ray(P, V);
    const bool same = a.uv.x == b.uv.x && a.uv.y == b.uv.y && a.z == b.z && c.uv.x == b.uv.x &&
                      c.uv.y == b.uv.y && c.z == b.z;
    if (!same && tally.differ < 5)
        ADD_FAILURE() << "P = (" << P.x << ", " << P.y << "), V = (" << V.x << ", " << V.y << ", "
                      << V.z << "): walk (" << a.uv.x << ", " << a.uv.y << ", " << a.z
                      << "), naive (" << b.uv.x << ", " << b.uv.y << ", " << b.z << ")";
    tally.differ += !same;
    EXPECT_LE(a.cells, b.cells);  // a subset of the DDA's cells
    tally.walk_cells += a.cells;
    tally.naive_cells += b.cells;
    ++tally.rays;
}

PerspectiveParams params(double theta, double phi, double distance, double fov, int n) {
    return {theta, phi, distance, fov, n};
}

// Every pixel of perspective views through the walk, the DDA and the Tracer interface.
Tally perspective_views(const HeightField& hf, double s, double b, int n) {
    const ExactTracer t(hf, s, b);
    Tally tally;
    size_t outside = 0;
    for (double theta : {0.0, 30.0, 60.0, 75.0, 85.0, 89.0})
        for (double distance : {1.5, 4.0, 16.0})
            for (double fov : {45.0, 90.0}) {
                const PerspectiveParams p = params(theta, 20 + 37 * theta, distance, fov, n);
                if (!eye_slab_problem(p, s, b).empty()) continue;
                const PerspectiveCamera cam(p);
                const View view = cam.view();
                outside += cam.outside_count();
                Hits through;
                t.trace(view, through);  // the interface: a perspective view is traced per ray
                for (size_t k = 0; k < view.size(); ++k) {
                    compare_ray(t, view.P[k], view.V[k], tally);
                    const TruthHit ref = t.trace_naive(view.P[k], view.V[k]);
                    tally.differ += through.uv[k].x != ref.uv.x || through.uv[k].y != ref.uv.y ||
                                    through.z[k] != ref.z;
                }
            }
    EXPECT_GT(outside, 0u);  // grazing views have pixels past the horizon: traced alike
    return tally;
}

// A field and its slab (scale s, bias b), named for failure messages.
struct FieldCase {
    const char* what;
    HeightField hf;
    double s, b;
};

TEST(RayWalk, PerspectiveRaysHitWhatTheCellDdaHitsBitForBit) {
    struct Case {
        const char* what;
        HeightField hf;
        double s, b;
        int n;
        bool smooth;
    };
    const Case cases[] = {
        {"random 64", test::random_field(64, 64, 7), 0.05, 1.0, 24, false},
        {"random 37 x 129", test::random_field(37, 129, 8), 0.1, 0.5, 20, false},
        {"fbm 256", generated("fbm", 256), 0.05, 1.0, 24, true},
        {"luxembourg (measured)", load_scan("luxembourg", "test"), 0.05, 1.0, 24, true},
    };
    for (const Case& c : cases) {
        const Tally t = perspective_views(c.hf, c.s, c.b, c.n);
        EXPECT_EQ(t.differ, 0) << c.what << ": of " << t.rays << " rays";
        EXPECT_GT(t.rays, 1000) << c.what;
        // A different path, solving a subset of the DDA's cells: on smooth fields the block
        // maxima rule most of them out (on white noise every block holds a high corner).
        EXPECT_LE(t.walk_cells, t.naive_cells) << c.what;
        if (c.smooth) {
            EXPECT_LT(t.walk_cells, t.naive_cells / 2) << c.what;
        }
    }
}

TEST(RayWalk, RaysThatStressTheDdaHitWhatItHits) {
    HeightField flat = test::random_field(32, 32, 1);
    for (float& v : flat.texels) v = 0.25f;
    HeightField bottom = flat;
    for (float& v : bottom.texels) v = 0.0f;
    HeightField spike = bottom;
    spike.texels[17 * 32 + 9] = 1.0f;
    const FieldCase cases[] = {{"flat", flat, 0.05, 1.0},
                               {"at the slab bottom", bottom, 0.2, 0.5},
                               {"one spike", spike, 0.3, 1.0},
                               {"random 3 x 200", test::random_field(3, 200, 4), 0.5, 0.5},
                               {"random 128 x 96", test::random_field(128, 96, 5), 0.1, 0.7}};
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0, 1);
    for (const FieldCase& c : cases) {
        const ExactTracer t(c.hf, c.s, c.b);
        const int W = c.hf.width, H = c.hf.height;
        Tally tally;
        for (double theta : {0.0, 10.0, 45.0, 70.0, 85.0, 89.5})
            for (double phi : {0.0, 45.0, 90.0, 135.0, 180.0, 200.0, 270.0, 333.0}) {
                const Vec3d V = view_vector(theta, phi);
                for (int k = 0; k < 60; ++k) {
                    Vec2d P{unit(rng) * 3 - 1, unit(rng) * 3 - 1};
                    // Starts on grid lines (the entry point's X0 or Y0 an integer, or both:
                    // at phi = 45 on a square field such a ray passes through cell corners).
                    const double zt = c.s * (1 - c.b);
                    if (k % 3 != 2) P.x = (std::floor(unit(rng) * W) + 0.5) / W - V.x / V.z * zt;
                    if (k % 3 != 1) P.y = (std::floor(unit(rng) * H) + 0.5) / H - V.y / V.z * zt;
                    compare_ray(t, P, V, tally);
                }
            }
        EXPECT_EQ(tally.differ, 0) << c.what << ": of " << tally.rays << " rays";
    }
}

// Every sample of `view` through the Tracer interface equals trace_naive of its own ray, bit
// for bit (uv, z); returns how many differ.
size_t interface_differences(const ExactTracer& t, const View& view) {
    Hits through;
    t.trace(view, through);
    EXPECT_EQ(through.uv.size(), view.size());
    size_t differ = 0;
    for (size_t k = 0; k < view.size(); ++k) {
        const TruthHit ref = t.trace_naive(view.P[k], view.dir(k));
        const bool same =
            through.uv[k].x == ref.uv.x && through.uv[k].y == ref.uv.y && through.z[k] == ref.z;
        if (!same && differ < 5)
            ADD_FAILURE() << "sample " << k << ": (" << through.uv[k].x << ", " << through.uv[k].y
                          << ", " << through.z[k] << ") vs the DDA's (" << ref.uv.x << ", "
                          << ref.uv.y << ", " << ref.z << ")";
        differ += !same;
    }
    return differ;
}

// The per-ray paths this CPU can take (ExactTracer::RayPath, widest first).
std::vector<ExactTracer::RayPath> cpu_paths() {
    using P = ExactTracer::RayPath;
    std::vector<P> paths;
    for (P p : {P::avx512, P::avx2, P::scalar})
        if (p <= ExactTracer::cpu_best_path()) paths.push_back(p);
    return paths;
}

// A view's every sample through every per-ray path the CPU has (the AVX-512 and AVX2 square
// walks where it has them, and the scalar walk): how many differ from trace_naive's hit, bit for
// bit, plus how many samples solve more cells than trace_naive does (`excess`; each path's count
// is a subset).
size_t all_paths_differences(ExactTracer& t, const View& view, size_t& excess) {
    size_t differ = 0;
    for (ExactTracer::RayPath path : cpu_paths()) {
        t.set_path(path);
        EXPECT_EQ(t.ray_path(), path);
        differ += interface_differences(t, view);
        Hits through;
        t.trace(view, through);
        for (size_t k = 0; k < view.size(); ++k)
            excess += through.cells[k] > t.trace_naive(view.P[k], view.dir(k)).cells;
    }
    t.set_simd(true);
    return differ;
}

TEST(RayWalk, LargePerspectiveViewsThroughTheInterfaceHitWhatTheDdaHits) {
    // 96 x 96 pixels: several of the tracer's work chunks; at 85 and 89 degrees the top rows are
    // outside (each the look-at ray, a run that spans chunks), at 30 none are.
    struct Case {
        const char* what;
        HeightField hf;
    };
    const Case cases[] = {{"fbm 128", generated("fbm", 128)},
                          {"luxembourg (measured)", load_scan("luxembourg", "test")},
                          {"random 50 x 70", test::random_field(50, 70, 3)}};
    for (const Case& c : cases) {
        ExactTracer t(c.hf, 0.05, 1.0);
        size_t excess = 0;
        for (double theta : {30.0, 85.0, 89.0})
            for (double distance : {1.5, 16.0})
                for (double fov : {30.0, 60.0}) {
                    const PerspectiveParams p = params(theta, 20, distance, fov, 96);
                    const PerspectiveCamera cam(p);
                    const View view = cam.view();
                    EXPECT_EQ(all_paths_differences(t, view, excess), 0u)
                        << c.what << ", theta " << theta << ", D " << distance << ", fov " << fov;
                    if (theta >= 85) {
                        // Outside pixels: the look-at ray's own hit, every one of them.
                        ASSERT_GT(cam.outside_count(), 96u) << c.what;
                        const std::vector<uint8_t> inside = cam.inside();
                        Hits through;
                        t.trace(view, through);
                        const TruthHit look = t.trace_naive({0.5, 0.5}, view_vector(theta, 20));
                        size_t outside_same = 0;
                        for (size_t k = 0; k < view.size(); ++k)
                            if (!inside[k])
                                outside_same += through.uv[k].x == look.uv.x &&
                                                through.uv[k].y == look.uv.y &&
                                                through.z[k] == look.z;
                        EXPECT_EQ(outside_same, cam.outside_count()) << c.what;
                    }
                }
    }
}

// A square view of n x n pixels through the eye at `distance` tiles (the Tracer interface
// traces it in packets of neighbouring pixels, each ray going on alone from the packet's
// floor): every sample bit for bit its own DDA hit. Returns the number of rays compared.
size_t packet_view_differences(const ExactTracer& t, double theta, double distance, double fov,
                               int n, size_t& differ) {
    const PerspectiveCamera cam(params(theta, 20 + 37 * theta, distance, fov, n));
    differ += interface_differences(t, cam.view());
    return size_t(n) * size_t(n);
}

// Thin walls (0.9) on flat ground (0.1), 48 x 40 texels.
HeightField walls_field() {
    HeightField walls = test::random_field(48, 40, 2);
    for (int j = 0; j < walls.height; ++j)
        for (int i = 0; i < walls.width; ++i)
            walls.texels[size_t(j) * walls.width + i] = (i % 11 == 3 || j % 13 == 5) ? 0.9f : 0.1f;
    return walls;
}

// 30 single-texel spikes (1) on ground at 0, 40 x 40 texels, placed from `seed`.
HeightField spikes_field(uint32_t seed) {
    HeightField spikes = test::random_field(40, 40, 3);
    for (float& v : spikes.texels) v = 0.0f;
    std::mt19937 rng(seed);
    for (int k = 0; k < 30; ++k) spikes.texels[rng() % spikes.texels.size()] = 1.0f;
    return spikes;
}

TEST(RayWalk, PacketsOfNeighbouringPixelsHitWhatTheDdaHits) {
    // Near eyes and many pixels per cell make packets whose rays lie close together (their
    // descent skips most of the slab), on fields where skipping one cell too many changes a
    // hit: single-texel spikes and thin walls beside flat ground (a ray that clips a spike's
    // corner hits it; its packet's box must hold that corner), smooth and measured fields.
    // Image sides that are not multiples of the packet's (partial packets at the right and
    // top edges), grazing views whose top rows are outside (the look-at ray, kept out of
    // the packets) and far eyes (packets too spread out to descend) are in the mix.
    const HeightField walls = walls_field(), spikes = spikes_field(17);
    const FieldCase cases[] = {
        {"spikes 40", spikes, 0.1, 1.0},
        {"walls 48 x 40", walls, 0.05, 0.8},
        {"fbm 128", generated("fbm", 128), 0.05, 1.0},
        {"luxembourg (measured)", load_scan("luxembourg", "test"), 0.05, 1.0}};
    for (const FieldCase& c : cases) {
        const ExactTracer t(c.hf, c.s, c.b);
        size_t rays = 0, differ = 0;
        for (double theta : {20.0, 60.0, 80.0, 88.0})
            for (double distance : {1.2, 3.0, 20.0})
                for (const auto& [fov, n] : {std::pair{45.0, 61}, std::pair{20.0, 64}}) {
                    const PerspectiveParams p = params(theta, 20 + 37 * theta, distance, fov, n);
                    if (!eye_slab_problem(p, c.s, c.b).empty()) continue;
                    rays += packet_view_differences(t, theta, distance, fov, n, differ);
                }
        EXPECT_EQ(differ, 0u) << c.what << ": of " << rays << " rays";
        EXPECT_GT(rays, 40000u) << c.what;
    }
}

TEST(RayWalk, ViewsThatAreNotSquareImagesHitWhatTheDdaHits) {
    // A view whose size is not a square is traced in runs of consecutive samples: the rows
    // of a 70 x 33 perspective image, one ray, two equal rays, and a view cut short.
    const HeightField hf = generated("fbm", 96);
    ExactTracer t(hf, 0.05, 1.0);
    size_t excess = 0;
    const PerspectiveCamera cam(params(70, 30, 1.5, 50, 70));
    const View full = cam.view();
    for (size_t count : {size_t(70 * 33), size_t(1), size_t(2), size_t(4899)}) {
        View view;
        view.P.assign(full.P.begin(), full.P.begin() + long(count));
        view.V.assign(full.V.begin(), full.V.begin() + long(count));
        if (count == 2) view.P[1] = view.P[0], view.V[1] = view.V[0];
        EXPECT_EQ(all_paths_differences(t, view, excess), 0u) << count << " samples";
    }
}

TEST(RayWalk, RunsOfEqualRaysAndRaysOneBitApartHitWhatTheDdaHits) {
    // A view of random rays in runs of equal rays (lengths 1 to 40, across the tracer's work
    // chunks), each run's neighbour one bit away in one of P.x, P.y, V.x, V.y, V.z: a tracer that
    // reused a hit for a ray that only looks alike would differ from the DDA.
    const HeightField hf = test::random_field(64, 48, 21);
    ExactTracer t(hf, 0.1, 0.6);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    View view;
    const double inf = std::numeric_limits<double>::infinity();
    while (view.size() < 5000) {
        const double theta = 5 + 80 * unit(rng), phi = 360 * unit(rng);
        Vec2d P{unit(rng) * 4 - 2, unit(rng) * 4 - 2};
        Vec3d V = view_vector(theta, phi);
        const int run = 1 + int(unit(rng) * 40);
        for (int r = 0; r < run; ++r) {
            view.P.push_back(P);
            view.V.push_back(V);
        }
        switch (int(unit(rng) * 5)) {  // the next ray: one bit away
            case 0:
                P.x = std::nextafter(P.x, inf);
                break;
            case 1:
                P.y = std::nextafter(P.y, -inf);
                break;
            case 2:
                V.x = std::nextafter(V.x, inf);
                break;
            case 3:
                V.y = std::nextafter(V.y, -inf);
                break;
            default:
                V.z = std::nextafter(V.z, inf);
                break;
        }
        view.P.push_back(P);
        view.V.push_back(V);
    }
    size_t excess = 0;
    EXPECT_EQ(all_paths_differences(t, view, excess), 0u);
}

TEST(RayWalk, TheVectorPathIsTakenWhereTheCpuHasIt) {
    // The AVX-512 path needs the CPU's avx512f and avx512dq, the AVX2 path its avx2 and fma, both
    // a field of 2 x 2 cells or more (their tables); set_path takes any the CPU has, and no wider
    // one; set_simd(false) forces the scalar walk. The default is the widest (unless
    // PXH_TRACER_PATH caps it).
    using P = ExactTracer::RayPath;
    const HeightField hf = test::random_field(16, 16, 1), thin = test::random_field(1, 40, 2);
    ExactTracer t(hf, 0.1, 1.0);
    const ExactTracer one_column(thin, 0.1, 1.0);
    EXPECT_EQ(t.ray_path(), ExactTracer::default_path());
    EXPECT_LE(ExactTracer::default_path(), ExactTracer::cpu_best_path());
    if (!std::getenv("PXH_TRACER_PATH")) {
        EXPECT_EQ(ExactTracer::default_path(), ExactTracer::cpu_best_path());
    }
    EXPECT_EQ(t.simd_path(), ExactTracer::cpu_has_simd_path());
    EXPECT_EQ(one_column.ray_path(), P::scalar);
    t.set_simd(false);
    EXPECT_FALSE(t.simd_path());
    EXPECT_EQ(t.ray_path(), P::scalar);
    t.set_simd(true);
    EXPECT_EQ(t.simd_path(), ExactTracer::cpu_has_simd_path());
    for (P p : {P::scalar, P::avx2, P::avx512}) {
        t.set_path(p);
        EXPECT_EQ(t.ray_path(), std::min(p, ExactTracer::cpu_best_path()));
    }
    EXPECT_STREQ(ExactTracer::path_name(P::avx2), "avx2");
    if (ExactTracer::cpu_best_path() != P::avx512)
        GTEST_SKIP() << "this CPU's widest per-ray path is "
                     << ExactTracer::path_name(ExactTracer::cpu_best_path())
                     << ": the wider ones are not tested here";
}

TEST(RayWalk, PxhTracerPathCapsTheDefaultPathAndEmbreesKernels) {
    // PXH_TRACER_PATH caps the default per-ray path (never above what the CPU has) and Embree's
    // instruction set alike; another value is refused.
    using P = ExactTracer::RayPath;
    const char* before = std::getenv("PXH_TRACER_PATH");
    const std::string saved = before ? before : "";
    const struct {
        const char* value;
        P path;
        const char* embree;
    } cases[] = {{"scalar", P::scalar, "max_isa=sse4.2"},
                 {"avx2", P::avx2, "max_isa=avx2"},
                 {"avx512", P::avx512, ""}};
    for (const auto& c : cases) {
        ::setenv("PXH_TRACER_PATH", c.value, 1);
        EXPECT_EQ(ExactTracer::default_path(), std::min(c.path, ExactTracer::cpu_best_path()))
            << c.value;
        EXPECT_EQ(EmbreeTracer::device_config(), c.embree) << c.value;
        const HeightField hf = test::random_field(16, 16, 1);
        EXPECT_EQ(ExactTracer(hf, 0.1, 1.0).ray_path(), ExactTracer::default_path()) << c.value;
    }
    ::setenv("PXH_TRACER_PATH", "avx3", 1);
    EXPECT_THROW(ExactTracer::default_path(), std::invalid_argument);
    ::unsetenv("PXH_TRACER_PATH");
    EXPECT_EQ(ExactTracer::default_path(), ExactTracer::cpu_best_path());
    EXPECT_EQ(EmbreeTracer::device_config(), "");
    if (before) ::setenv("PXH_TRACER_PATH", saved.c_str(), 1);
}

TEST(RayWalk, TheVectorAndScalarPathsHitWhatTheDdaHits) {
    // Perspective views (near and far eyes, grazing and steep) and views of the rays that
    // stress a DDA (starts on grid lines, axis-parallel, vertical and diagonal directions) on
    // fields where one cell too many skipped changes a hit: single-texel spikes, thin walls,
    // flat ground, white noise at sizes that are not powers of two, 3 cells wide (square
    // tables of one level only), a thick slab whose grazing rays cross many tiles, smooth and
    // measured fields.
    const HeightField walls = walls_field(), spikes = spikes_field(23);
    std::mt19937 rng(23);
    HeightField flat = test::random_field(32, 32, 1);
    for (float& v : flat.texels) v = 0.25f;
    const FieldCase cases[] = {
        {"spikes 40", spikes, 0.1, 1.0},
        {"walls 48 x 40", walls, 0.05, 0.8},
        {"flat 32", flat, 0.05, 1.0},
        {"random 37 x 129", test::random_field(37, 129, 8), 0.1, 0.5},
        {"random 3 x 200", test::random_field(3, 200, 4), 0.5, 0.5},
        {"random 64, thick slab", test::random_field(64, 64, 9), 1.0, 0.5},
        {"fbm 256", generated("fbm", 256), 0.05, 1.0},
        {"luxembourg (measured)", load_scan("luxembourg", "test"), 0.05, 1.0}};
    std::uniform_real_distribution<double> unit(0, 1);
    for (const FieldCase& c : cases) {
        ExactTracer t(c.hf, c.s, c.b);
        size_t rays = 0, differ = 0, excess = 0;
        for (double theta : {0.0, 40.0, 70.0, 85.0, 89.0})
            for (double distance : {1.2, 4.0, 20.0}) {
                const PerspectiveParams p = params(theta, 20 + 37 * theta, distance, 50, 40);
                if (!eye_slab_problem(p, c.s, c.b).empty()) continue;
                const View view = PerspectiveCamera(p).view();
                differ += all_paths_differences(t, view, excess);
                rays += view.size();
            }
        View stress;
        const int W = c.hf.width, H = c.hf.height;
        const double zt = c.s * (1 - c.b);
        for (double theta : {0.0, 10.0, 45.0, 70.0, 85.0, 89.5})
            for (double phi : {0.0, 45.0, 90.0, 135.0, 180.0, 200.0, 270.0, 333.0}) {
                const Vec3d V = view_vector(theta, phi);
                if (!ray_travel_problem(c.s, V).empty()) continue;
                for (int k = 0; k < 40; ++k) {
                    Vec2d P{unit(rng) * 3 - 1, unit(rng) * 3 - 1};
                    if (k % 3 != 2) P.x = (std::floor(unit(rng) * W) + 0.5) / W - V.x / V.z * zt;
                    if (k % 3 != 1) P.y = (std::floor(unit(rng) * H) + 0.5) / H - V.y / V.z * zt;
                    stress.P.push_back(P);
                    stress.V.push_back(V);
                }
            }
        differ += all_paths_differences(t, stress, excess);
        rays += stress.size();
        EXPECT_EQ(differ, 0u) << c.what << ": of " << rays << " rays, every path the CPU has";
        EXPECT_EQ(excess, 0u) << c.what << ": cells solved beyond the DDA's";
        EXPECT_GT(rays, 10000u) << c.what;
    }
}

TEST(RayWalk, RaysAtAndBeyondTheFloatSquareWalksBoundsHitWhatTheDdaHits) {
    // The AVX2 path's square walk computes in float for rays whose start lies within 2^20 cells
    // of the origin and whose travel is below 2^15 cells along each axis, and in double beyond
    // (ray_walk_avx2_f32.cpp): rays just inside those bounds (the float walk's largest rounding
    // errors) and just beyond them (the double walk), on a field of 8 x 8 cells (a tile is 8
    // cells: grazing rays travel thousands of tiles), every hit trace_naive's, on every path. The
    // field is flat ground with a few low bumps, so that rays travel far before they hit.
    HeightField hf = test::random_field(8, 8, 31);
    for (float& v : hf.texels) v = v > 0.9f ? 0.3f : 0.25f;
    const double s = 0.05, zt = s * (1 - 1.0);
    ExactTracer t(hf, s, 1.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    size_t differ = 0, excess = 0, rays = 0;
    // Travel along the ray's major axis: tan(theta) s W cells (about 30000 and 40000 here).
    for (double travel : {30000.0, 40000.0})
        for (double start : {0.0, 131070.5, 131072.5, -131072.5}) {  // tiles: X0 = 8 P.x - 0.5
            View view;
            const double theta = std::atan(travel / (s * hf.width)) * 180 / M_PI;
            for (int k = 0; k < 48; ++k) {
                const Vec3d V = view_vector(theta, 360 * unit(rng));
                ASSERT_EQ(ray_travel_problem(s, V), "");
                view.P.push_back({start + unit(rng) - V.x / V.z * zt, start + unit(rng)});
                view.V.push_back(V);
            }
            differ += all_paths_differences(t, view, excess);
            rays += view.size();
        }
    EXPECT_EQ(differ, 0u) << "of " << rays << " rays, every path the CPU has";
    EXPECT_EQ(excess, 0u) << "cells solved beyond the DDA's";
}

// The band tracer on every path the CPU has (the scalar walk; on a vector path its candidates'
// cells walked by that path's DDA, BandDdaRun): trace_naive's hits bit for bit, with dense
// samples (bands one cell wide, bounds from the cells), sparse ones (wider bands, coarser
// bounds, odd sizes) and rays through cell corners: with zt = 0 (b = 1) every ray of a grid
// of one sample per cell starts on a corner, and with |V.x| == |V.y| exactly on a square field
// it crosses a column line and a row line at the very same time wherever it enters a column
// (ViewTracer::column_start's tie, where the DDA must start before the column).
TEST(RayWalk, GridViewsOnEveryPathHitWhatTheDdaHits) {
    struct Case {
        const char* what;
        HeightField hf;
        double s, b;
        int n;
    };
    const Case cases[] = {
        {"random 64, a sample per cell, zt = 0", test::random_field(64, 64, 21), 0.05, 1.0, 64},
        {"random 64, a sample per cell", test::random_field(64, 64, 22), 0.1, 0.5, 64},
        {"fbm 128, sparse samples", generated("fbm", 128), 0.05, 1.0, 32},
        {"random 129 x 67, sparse", test::random_field(129, 67, 23), 0.3, 0.5, 20}};
    std::vector<Vec3d> views;
    for (double theta : {45.0, 80.0, 85.0, 89.0})
        for (double phi : {17.0, 163.0, 200.0, 290.0}) views.push_back(view_vector(theta, phi));
    for (double theta : {60.0, 84.0}) {  // |V.x| == |V.y| exactly
        const double a = std::sin(theta * M_PI / 180) / std::sqrt(2.0),
                     z = std::cos(theta * M_PI / 180);
        for (const Vec3d V : {Vec3d{a, a, z}, Vec3d{-a, a, z}, Vec3d{-a, -a, z}, Vec3d{a, -a, z}})
            views.push_back(V);
    }
    for (const Case& c : cases) {
        ExactTracer t(c.hf, c.s, c.b);
        const std::vector<Vec2d> P = sample_grid(c.n);
        for (ExactTracer::RayPath path : cpu_paths()) {
            t.set_path(path);
            long long rays = 0, differ = 0;
            for (const Vec3d& V : views) {
                std::vector<TruthHit> g;
                t.trace_grid(c.n, V, g);
                ASSERT_EQ(g.size(), P.size());
                for (size_t k = 0; k < P.size(); ++k) {
                    const TruthHit ref = t.trace_naive(P[k], V);
                    const bool same =
                        g[k].uv.x == ref.uv.x && g[k].uv.y == ref.uv.y && g[k].z == ref.z;
                    if (!same && differ < 3)
                        ADD_FAILURE() << c.what << ", " << ExactTracer::path_name(path) << ", V = ("
                                      << V.x << ", " << V.y << ", " << V.z << "), sample " << k;
                    differ += !same;
                    ++rays;
                }
            }
            EXPECT_EQ(differ, 0) << c.what << ", " << ExactTracer::path_name(path) << ": of "
                                 << rays << " rays";
        }
    }
}

TEST(RayWalk, OrthographicGridViewsTakeTheVectorPathUpTo78Degrees) {
    // An orthographic grid view takes the per-ray vector path up to kGridRaysMaxThetaDeg where
    // the tracer has one, the band tracer otherwise; the two give the same hits bit for bit.
    const HeightField hf = generated("fbm", 128);
    ExactTracer t(hf, 0.05, 1.0);
    for (ExactTracer::RayPath path : cpu_paths()) {
        t.set_path(path);
        const bool vec = path != ExactTracer::RayPath::scalar;
        EXPECT_EQ(t.grid_takes_rays(view_vector(0, 0)), vec);
        EXPECT_EQ(t.grid_takes_rays(view_vector(77.9, 200)), vec);
        EXPECT_FALSE(t.grid_takes_rays(view_vector(78.1, 20)));
        for (double theta : {30.0, 77.0, 85.0}) {
            const View view = OrthographicCamera(theta, 20, 96).view();
            Hits through;
            t.trace(view, through);
            std::vector<TruthHit> band;
            t.trace_grid(96, view.V[0], band);
            size_t differ = 0;
            for (size_t k = 0; k < view.size(); ++k)
                differ += !(through.uv[k].x == band[k].uv.x && through.uv[k].y == band[k].uv.y &&
                            through.z[k] == band[k].z);
            EXPECT_EQ(differ, 0u) << ExactTracer::path_name(path) << ", theta " << theta;
        }
    }
    t.set_simd(true);
}

}  // namespace
}  // namespace pxh
