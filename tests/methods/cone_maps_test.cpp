// Cone maps (methods/cone/cone_map.h) and the methods that read them, cone and relaxed_cone:
// the accelerated generation equals the brute force bit for bit; closed forms; conservative
// where claimed (no cone step passes the first hit of the exact bilinear surface) and tight
// (the same test fails with the ratios 5% larger); the classic cones are not conservative
// under bilinear filtering (Ban et al. 2024); the relaxed maps' size limit.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/core/error.h"
#include "harness/metrics/metrics.h"
#include "harness/truth/exact_tracer.h"
#include "heightfields/heightfields.h"
#include "methods/cone/cone_map.h"
#include "tests/glsl_agreement.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

const MethodInfo& cone() { return *find_method("cone"); }
const MethodInfo& relaxed() { return *find_method("relaxed_cone"); }

// A random field with plateaus (ties) as well as distinct heights.
HeightField stepped_field(int w, int h, uint32_t seed) {
    HeightField hf = test::random_field(w, h, seed);
    for (size_t k = 0; k < hf.texels.size(); k += 3)
        hf.texels[k] = std::floor(hf.texels[k] * 4) / 4;
    return hf;
}

void expect_same_bytes(const std::vector<float>& a, const std::vector<float>& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float))) << what;
}

TEST(ConeMaps, AcceleratedGenerationEqualsBruteForceBitForBit) {
    for (const HeightField& hf :
         {test::random_field(16, 16, 1), stepped_field(13, 7, 2), test::random_field(32, 24, 3),
          stepped_field(5, 9, 4), test::random_field(2, 3, 5)}) {
        expect_same_bytes(cone_maps::dummer(hf), cone_maps::dummer_brute(hf), "dummer");
        expect_same_bytes(cone_maps::bilinear(hf), cone_maps::bilinear_brute(hf), "bilinear");
        expect_same_bytes(cone_maps::relaxed_ban(hf), cone_maps::relaxed_ban_brute(hf), "ban");
        if (hf.texels.size() <= 256)
            expect_same_bytes(cone_maps::relaxed_book(hf), cone_maps::relaxed_book_brute(hf),
                              "book");
    }
}

TEST(ConeMaps, ResourcesAreTheSameBytesForOneAndManyThreads) {
    const HeightField hf = test::random_field(40, 24, 6);
    auto built = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        std::vector<std::vector<float>> out;
        for (const MethodInfo* m : {&cone(), &relaxed()})
            out.push_back(build_resource(m->resources[0], hf, 0.05, 1).image->levels[0].texels);
        return out;
    };
    const auto one = built(1), many = built(8);
    for (size_t k = 0; k < one.size(); ++k) expect_same_bytes(one[k], many[k], "resource");
}

// A relaxed cone's candidates are a conservative cone's (Ban et al.: a subset of the texels;
// the book: a point beyond each, farther and lower), so no relaxed ratio is below Dummer's;
// and they are wider somewhere.
TEST(ConeMaps, RelaxedConesAreNeverNarrowerThanConservativeOnes) {
    for (const char* name : {"sine", "fbm", "bricks"}) {
        const GeneratorInfo* g = find_generator(name);
        const HeightField hf =
            generate_heightfield(*g, 32, 32, resolve_params(g->params, {}, "t", name));
        const std::vector<float> d = cone_maps::dummer(hf);
        for (const auto& relaxed : {cone_maps::relaxed_ban(hf), cone_maps::relaxed_book(hf)}) {
            int wider = 0;
            for (size_t k = 0; k < d.size(); ++k) {
                EXPECT_GE(relaxed[k], d[k]) << name << " " << k;
                wider += relaxed[k] > d[k];
            }
            EXPECT_GT(wider, 0) << name;
            std::printf("[ cone ] %s 32^2: relaxed wider than Dummer's at %d of %zu texels\n", name,
                        wider, d.size());
        }
    }
}

// One texel at height 1, the rest at 0: Dummer's ratio is the distance (uv) to the nearest
// image of the peak, capped at 1; the peak itself has no higher texel: 1.
TEST(ConeMaps, DummerRatioIsTheDistanceToTheNearestPeakImage) {
    HeightField hf = test::flat_field(16, 8, 0.0f);
    hf.at(3, 2) = 1.0f;
    const std::vector<float> r = cone_maps::dummer(hf);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 16; ++i) {
            const int dx = std::min(std::abs(i - 3), 16 - std::abs(i - 3));
            const int dy = std::min(std::abs(j - 2), 8 - std::abs(j - 2));
            const double want = (i == 3 && j == 2) ? 1.0 : std::hypot(dx / 16.0, dy / 8.0);
            EXPECT_EQ(r[size_t(j) * 16 + i], cone_maps::round_down(std::min(1.0, want)))
                << i << " " << j;
        }
    // Ban et al.'s 3 x 3 minimum: the peak's neighbours' smallest ratio reaches the peak.
    const std::vector<float> m = cone_maps::min3x3(r, 16, 8);
    EXPECT_EQ(m[size_t(2) * 16 + 3], cone_maps::round_down(1.0 / 16));
}

// Dummer's claim, in his terms: no texel centre (any image) lies strictly inside a texel's
// cone. Tight: with the ratios 5% larger, every texel whose ratio is below 1 / 1.05 has one.
TEST(ConeMaps, DummerConesHoldNoTexelCentreAndAreTight) {
    const HeightField hf = test::random_field(16, 16, 7);
    const std::vector<float> r = cone_maps::dummer(hf);
    int tight = 0, below = 0;
    for (int jk = 0; jk < 16; ++jk)
        for (int ik = 0; ik < 16; ++ik) {
            const double c = r[size_t(jk) * 16 + ik], hk = hf.at(ik, jk);
            bool inside = false, inside_scaled = false;
            for (int j = -16; j < 32; ++j)
                for (int i = -16; i < 32; ++i) {
                    const double d = std::hypot((i - ik) / 16.0, (j - jk) / 16.0);
                    const double rise = double(hf.wrapped(i, j)) - hk;
                    inside |= d < c * rise;
                    inside_scaled |= d < 1.05 * c * rise;
                }
            EXPECT_FALSE(inside) << ik << " " << jk;
            below += c < 1 / 1.05;
            tight += inside_scaled && c < 1 / 1.05;
        }
    EXPECT_GT(below, 200);
    EXPECT_EQ(tight, below);
}

// The cone loop of methods/cone/cone.md with min_step = none, in double, reading channel
// `channel` of r_cone with the ratio times `k`: the depth (units of h) after each step.
struct ConeWalk {
    const Scene<double>& sc;
    TextureSampler<double>& map;
    int channel;
    double k;
    std::vector<double> depths(Vec2d P, int steps) const {
        const Vec2d D = sc.V.xy() * (1 / sc.V.z), uv0 = P + D * sc.z_top(), m = D * -sc.scale;
        const double dist = std::sqrt(m.x * m.x + m.y * m.y);
        std::vector<double> out;
        double t = 0;
        for (int i = 0; i < steps; ++i) {
            const auto tex = map.fetch(uv0 + m * t, 0);
            const double gap = 1 - t - tex[0];
            if (!(gap > 0x1p-20)) break;
            const double c = tex[size_t(channel)] * k;
            t = t + c * gap / (dist + c);
            out.push_back(t);
        }
        return out;
    }
};

// Over many rays of a random field: how many cone steps land beyond the exact first hit.
struct PassCount {
    long long rays = 0, passing_rays = 0;
};
PassCount count_passing(const HeightField& hf, int channel, double k) {
    const double s = 0.05, b = 1;
    const ExactTracer tracer(hf, s, b);
    const BuiltResource res = build_resource(cone().resources[0], hf, s, b);
    TextureSampler<double> map(*res.spec, *res.image);
    PassCount n;
    const std::vector<Vec2d> P = sample_grid(48);
    for (double theta : {35.0, 60.0, 80.0})
        for (int phi = 0; phi < 360; phi += 15) {
            const Scene<double> sc = test::make_scene(hf, s, b, theta, phi);
            const ConeWalk walk{sc, map, channel, k};
            for (const Vec2d& p : P) {
                const double t_hit = (sc.z_top() - tracer.trace_naive(p, sc.V).z) / s;
                bool passed = false;
                for (double t : walk.depths(p, 64)) passed |= t > t_hit + 1e-10;
                n.rays += 1;
                n.passing_rays += passed;
            }
        }
    return n;
}

// The transcription above is the method's loop: the same uv as cone with min_step = none.
TEST(ConeMaps, TheTestsConeLoopIsTheMethods) {
    const HeightField hf = test::random_field(16, 16, 8);
    const Scene<double> sc = test::make_scene(hf, 0.05, 1, 60, 40);
    const BuiltResource res = build_resource(cone().resources[0], hf, 0.05, 1);
    TextureSampler<double> map(*res.spec, *res.image);
    const std::vector<Vec2d> P = test::random_points(200, 9);
    const auto uv = test::run_method<double>(
        cone(), test::params_for(cone(), {{"map", "bilinear"}, {"min_step", "none"}, {"steps", 9}}),
        sc, hf, P);
    const ConeWalk walk{sc, map, 3, 1.0};
    for (size_t i = 0; i < P.size(); ++i) {
        const auto d = walk.depths(P[i], 9);
        const double t = d.empty() ? 0 : d.back();
        const Vec2d D = sc.V.xy() * (1 / sc.V.z);
        const Vec2d want = P[i] + D * sc.z_top() + D * (-sc.scale * t);
        EXPECT_NEAR(uv[i].x, want.x, 1e-12);
        EXPECT_NEAR(uv[i].y, want.y, 1e-12);
    }
}

TEST(ConeMaps, BilinearConesNeverStepPastTheFirstHitAndAreTight) {
    for (const HeightField& hf : {test::random_field(16, 16, 10), test::random_field(24, 16, 11)}) {
        const PassCount exact = count_passing(hf, 3, 1.0);
        EXPECT_EQ(exact.passing_rays, 0) << "of " << exact.rays;
        const PassCount scaled = count_passing(hf, 3, 1.05);
        EXPECT_GT(scaled.passing_rays, 0) << "of " << scaled.rays;
        std::printf(
            "[ cone ] bilinear map, %dx%d: %lld of %lld rays pass the first hit; ratios "
            "x 1.05: %lld\n",
            hf.width, hf.height, exact.passing_rays, exact.rays, scaled.passing_rays);
    }
}

// Ban et al. 2024: cones through texel centres are not conservative for the bilinear surface.
TEST(ConeMaps, ClassicConesStepPastTheFirstHitOfTheBilinearSurface) {
    const HeightField hf = test::random_field(16, 16, 10);
    const PassCount dummer = count_passing(hf, 1, 1.0), ban = count_passing(hf, 2, 1.0);
    EXPECT_GT(dummer.passing_rays, 0);
    std::printf(
        "[ cone ] 16x16 random: rays with a cone step past the first hit: dummer %lld, "
        "dummer_min %lld of %lld\n",
        dummer.passing_rays, ban.passing_rays, dummer.rays);
}

// One step on a flat field (every ratio is the cap, 1; the bilinear map keeps its rounding
// headroom, 1 - 2^-20): t = c gap / (s |V.xy / V.z| + c), gap in units of h.
TEST(ConeMaps, OneConeStepOnAFlatFieldIsTheClosedForm) {
    const HeightField hf = test::flat_field(8, 8, 0.25f);
    for (const char* map : {"dummer", "dummer_min", "bilinear"}) {
        const ParamValues p =
            test::params_for(cone(), {{"map", map}, {"min_step", "none"}, {"steps", 1}});
        const Scene<double> sc = test::make_scene(hf, 0.08, 0.5, 50, 20);
        const auto uv = test::run_method<double>(cone(), p, sc, hf, {{0.3, 0.6}});
        const double c = std::string(map) == "bilinear" ? 1 - 0x1p-20 : 1.0;
        const double tan_theta = std::tan(50 * M_PI / 180);
        const double t = c * 0.75 / (0.08 * tan_theta + c);
        const Vec2d D = sc.V.xy() * (1 / sc.V.z);
        EXPECT_NEAR(uv[0].x, 0.3 + D.x * (0.08 * 0.5 - 0.08 * t), 1e-12) << map;
        EXPECT_NEAR(uv[0].y, 0.6 + D.y * (0.08 * 0.5 - 0.08 * t), 1e-12) << map;
    }
}

TEST(ConeMaps, RelaxedMapsRefuseFieldsOverTheirSizeLimitInOneLine) {
    HeightField hf(257, 256, "big_scan");  // one column over the limit
    for (auto& t : hf.texels) t = 0.5f;
    try {
        build_resource(relaxed().resources[0], hf, 0.05, 1);
        FAIL() << "built";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("height field 'big_scan'"), std::string::npos) << msg;
        EXPECT_NE(msg.find("257 x 256"), std::string::npos) << msg;
        EXPECT_NE(msg.find("65536 texels (256 x 256)"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

// Every map, step and refinement choice (the registry-wide test covers the defaults): the GLSL twin
// within 1e-3 texel of the CPU float twin, and the same fetch counts, on 99.9% of samples.
TEST(ConeMaps, EverySettingsGlslTwinAgreesWithTheCpuFloatTwin) {
    static GlslBackend gl(GlslOptions{"", 0});
    const HeightField hf = test::generated_field("fbm", 64);
    const int N = 64;
    struct Setting {
        const MethodInfo* m;
        GivenParams p;
    };
    const std::vector<Setting> settings = {
        {&cone(), {{"map", "dummer_min"}, {"min_step", "cell"}}},
        {&cone(), {{"map", "bilinear"}, {"min_step", "texel"}}},
        {&cone(), {{"map", "bilinear"}, {"min_step", "cell"}}},
        {&cone(),
         {{"map", "dummer_min"}, {"min_step", "cell"}, {"steps", 20}, {"refine", "linear"}}},
        {&cone(),
         {{"map", "dummer"},
          {"min_step", "texel"},
          {"steps", 16},
          {"refine", "binary"},
          {"refine_steps", 7}}},
        {&relaxed(), {{"cones", "ban"}}},
        {&relaxed(), {{"cones", "ban_min"}, {"binary_steps", 3}}}};
    for (const Setting& st : settings) {
        ResourceCache cache(hf);
        const MethodResources res = cache.get(st.m->name, st.m->resources, 0.05, 1.0);
        const MethodSpec spec{st.m, test::params_for(*st.m, st.p)};
        for (double theta : {20.0, 70.0}) {
            const Scene<double> sc{0.05, 1.0, view_vector(theta, 35), hf.width, hf.height};
            const test::GlslCpuDiff d = test::glsl_vs_cpu(gl, spec, sc, hf, N, &res);
            EXPECT_LE(d.far, d.samples / 1000) << st.m->name << " " << spec.params.canonical();
            EXPECT_LE(d.fetch_off, d.samples / 1000)
                << st.m->name << " " << spec.params.canonical();
        }
    }
}

}  // namespace
}  // namespace pxh
