// The test-only method test_maxlevel (tests/methods/test_maxlevel): a method with precomputed
// textures in both twins. Closed forms on simple fields, CPU float vs double vs GLSL, fetches
// per texture, sizes, built once per field, the same bytes for any thread count, and a
// misspelt sampler in its shader is a one-line error naming it.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include "harness/backends/glsl_backend.h"
#include "harness/metrics/metrics.h"
#include "harness/run/runner.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

const MethodInfo& maxlevel() { return *find_method("test_maxlevel"); }

// Closed form of mode "max": uv = P + V.xy / V.z * s (M_L(P) - b), M_0 = max of the four
// corners of the bilinear cell at the texel under P (nearest), M_L over 2^L x 2^L blocks.
Vec2d closed_form_max(const HeightField& hf, const Scene<double>& sc, Vec2d P, int level) {
    const int W = hf.width, H = hf.height;
    auto wrap = [](long long i, int n) { return int(((i % n) + n) % n); };
    const int block = 1 << level;
    const int i = wrap((long long)std::floor(P.x * (W >> level)), W >> level) * block;
    const int j = wrap((long long)std::floor(P.y * (H >> level)), H >> level) * block;
    float m = 0;
    for (int jj = j; jj < j + block; ++jj)
        for (int ii = i; ii < i + block; ++ii)
            m = std::max({m, hf.at(ii, jj), hf.at((ii + 1) % W, jj), hf.at(ii, (jj + 1) % H),
                          hf.at((ii + 1) % W, (jj + 1) % H)});
    const double z = sc.scale * (double(m) - sc.bias);
    return {P.x + sc.V.x / sc.V.z * z, P.y + sc.V.y / sc.V.z * z};
}

TEST(TestMaxLevel, IsRegisteredInTheTestBinaryWithItsResources) {
    ASSERT_NE(find_method("test_maxlevel"), nullptr);
    ASSERT_EQ(maxlevel().resources.size(), 2u);
    EXPECT_EQ(maxlevel().shader_file(), "tests/methods/test_maxlevel/test_maxlevel.frag.glsl");
    ASSERT_NE(maxlevel().shader_text, nullptr);
}

TEST(TestMaxLevel, MatchesTheClosedFormInDoubleAndFloat) {
    const HeightField hf = test::random_field(16, 8, 21);
    const auto P = test::random_points(500, 22);
    for (int level : {0, 1, 3}) {
        const ParamValues p = test::params_for(maxlevel(), {{"level", level}});
        const auto sc = test::make_scene(hf, 0.07, 0.4, 50, 30);
        const auto d = test::run_method<double>(maxlevel(), p, sc, hf, P);
        const auto f = test::run_method<float>(maxlevel(), p, sc, hf, P);
        int off_f = 0;
        for (size_t k = 0; k < P.size(); ++k) {
            const Vec2d want = closed_form_max(hf, sc, P[k], level);
            EXPECT_NEAR(d[k].x, want.x, 1e-7) << level;  // texels stored as float
            EXPECT_NEAR(d[k].y, want.y, 1e-7) << level;
            const Vec2d e = texel_error(f[k], d[k], hf.width, hf.height);
            off_f += !(std::hypot(e.x, e.y) <= 1e-4);
        }
        EXPECT_LE(off_f, 1) << "float vs double, level " << level;  // a nearest-texel edge
    }
    // The top of the pyramid (16 x 8 -> level 4 is 1 x 1... level 3 is 2 x 1): every sample at
    // level 16 (clamped to the last) takes the global maximum.
    const ParamValues top = test::params_for(maxlevel(), {{"level", 16}});
    const auto sc = test::make_scene(hf, 0.05, 1.0, 30, 0);
    const float hmax = *std::max_element(hf.texels.begin(), hf.texels.end());
    const auto uv = test::run_method<double>(maxlevel(), top, sc, hf, P);
    for (size_t k = 0; k < P.size(); ++k)
        EXPECT_NEAR(uv[k].x, P[k].x + sc.V.x / sc.V.z * 0.05 * (double(hmax) - 1.0), 1e-12);
}

TEST(TestMaxLevel, ZmapModeIsClassicParallaxAwayFromTheClampedBorder) {
    const HeightField hf = test::random_field(32, 32, 23);
    const auto sc = test::make_scene(hf, 0.05, 1.0, 40, 70);
    std::vector<Vec2d> P;
    for (const Vec2d& q : test::random_points(300, 24))
        P.push_back({0.1 + 0.8 * q.x, 0.1 + 0.8 * q.y});
    const auto zmap = test::run_method<double>(
        maxlevel(), test::params_for(maxlevel(), {{"mode", "zmap"}}), sc, hf, P);
    const auto par = test::run_method<double>(
        *find_method("parallax"), test::params_for(*find_method("parallax")), sc, hf, P);
    for (size_t k = 0; k < P.size(); ++k) {
        // z from the texels s (h - b) stored in float, blended: ~1e-8 of a texel.
        EXPECT_NEAR(zmap[k].x, par[k].x, 1e-8);
        EXPECT_NEAR(zmap[k].y, par[k].y, 1e-8);
    }
}

TEST(TestMaxLevel, FetchesAreCountedPerTexture) {
    const HeightField hf = test::random_field(8, 8, 25);
    const auto sc = test::make_scene(hf, 0.05, 1.0, 30, 10);
    const auto P = test::random_points(10, 26);
    struct Case {
        const char* mode;
        std::vector<int> per_texture;
    };  // height, r_maxmip, r_zmap
    for (const Case& c :
         {Case{"max", {0, 1, 0}}, Case{"mid", {1, 1, 0}}, Case{"zmap", {0, 0, 1}}}) {
        std::vector<int> total, split;
        test::run_method<float>(maxlevel(), test::params_for(maxlevel(), {{"mode", c.mode}}), sc,
                                hf, P, &total, &split);
        ASSERT_EQ(split.size(), P.size() * 3);
        for (size_t k = 0; k < P.size(); ++k) {
            EXPECT_EQ(std::vector<int>(split.begin() + 3 * k, split.begin() + 3 * k + 3),
                      c.per_texture)
                << c.mode;
            EXPECT_EQ(total[k], c.per_texture[0] + c.per_texture[1] + c.per_texture[2]) << c.mode;
        }
    }
}

TEST(TestMaxLevel, ResourcesAreSizedExactlyAndTimed) {
    const HeightField hf = test::random_field(16, 8, 27);
    ResourceCache cache(hf);
    const MethodResources r = cache.get(maxlevel().name, maxlevel().resources, 0.05, 1.0);
    // r_maxmip: 16x8 + 8x4 + 4x2 + 2x1 + 1x1 floats; r_zmap: 16 x 8 x 4 floats.
    EXPECT_EQ(r.items[0].bytes, (128u + 32 + 8 + 2 + 1) * 4);
    EXPECT_EQ(r.items[1].bytes, 16u * 8 * 4 * 4);
    EXPECT_EQ(r.aux_bytes(), (128u + 32 + 8 + 2 + 1) * 4 + 16u * 8 * 4 * 4);
    EXPECT_GT(r.precompute_ms(), 0.0);
}

TEST(TestMaxLevel, ResourceBytesAreTheSameForOneAndManyThreads) {
    const HeightField hf = test::random_field(257, 129, 28);  // odd sizes: the uneven pyramid
    auto built = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        std::vector<std::vector<float>> out;
        for (const ResourceSpec& s : maxlevel().resources) {
            const BuiltResource r = build_resource(s, hf, 0.05, 0.5);
            for (const ResourceLevel& lv : r.image->levels) out.push_back(lv.texels);
        }
        return out;
    };
    const auto one = built(1), many = built(8);
    ASSERT_EQ(one.size(), many.size());
    for (size_t k = 0; k < one.size(); ++k)
        EXPECT_EQ(0, std::memcmp(one[k].data(), many[k].data(), one[k].size() * sizeof(float)))
            << k;
}

// GLSL twin: the same numbers as the CPU float reference for every mode and two levels, and the
// same total fetch count (the shader counts all textures together).
TEST(TestMaxLevel, GlslAgreesWithCpuFloat) {
    static GlslBackend gl(GlslOptions{"", 0});
    const HeightField hf = test::random_field(64, 64, 29);
    const int N = 48;
    const auto P = sample_grid(N);
    for (const char* mode : {"max", "mid", "zmap"})
        for (int level : {0, 2})
            for (double theta : {0.0, 60.0}) {
                const MethodSpec spec{
                    &maxlevel(), test::params_for(maxlevel(), {{"mode", mode}, {"level", level}})};
                const Scene<double> sc{0.05, 0.7, view_vector(theta, 35), hf.width, hf.height};
                ResourceCache cache(hf);
                const MethodResources res =
                    cache.get(maxlevel().name, maxlevel().resources, sc.scale, sc.bias);
                const MethodOutput gpu = gl.run(spec, sc, hf, N, "r32f", nullptr, 0, &res);
                std::vector<int> fetches;
                const auto cpu =
                    test::run_method<float>(maxlevel(), spec.params, sc, hf, P, &fetches);
                long long far = 0;
                for (size_t k = 0; k < P.size(); ++k) {
                    const Vec2d e = texel_error(gpu.uv[k], cpu[k], hf.width, hf.height);
                    far += !(std::hypot(e.x, e.y) <= 1e-3);
                    EXPECT_EQ(gpu.fetches[k], fetches[k]);
                }
                EXPECT_LE(far, (long long)P.size() / 1000)
                    << mode << " level " << level << " theta " << theta;
            }
}

TEST(TestMaxLevel, MisspeltSamplerInItsShaderIsAOneLineErrorNamingIt) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("pxh_maxlevel_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    std::string text = maxlevel().shader_text;
    for (size_t pos = text.find("r_zmap"); pos != std::string::npos;
         pos = text.find("r_zmap", pos + 6))
        text.replace(pos, 6, "r_zmop");
    std::ofstream(dir / "test_maxlevel.frag.glsl") << text;
    GlslBackend gl(GlslOptions{dir.string(), 0});
    const HeightField hf = test::flat_field(8, 8, 0.5f);
    const Scene<double> sc{0.05, 1.0, view_vector(30, 0), 8, 8};
    ResourceCache cache(hf);
    const MethodResources res = cache.get(maxlevel().name, maxlevel().resources, sc.scale, sc.bias);
    std::string msg;
    try {
        gl.run({&maxlevel(), test::params_for(maxlevel())}, sc, hf, 4, "r32f", nullptr, 0, &res);
    } catch (const std::runtime_error& e) {
        msg = e.what();
    }
    std::filesystem::remove_all(dir);
    EXPECT_NE(msg.find("method 'test_maxlevel'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("test_maxlevel.frag.glsl"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sampler2D uniform 'r_zmap' but the shader does not use it"),
              std::string::npos)
        << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
}

// Through the runner: one field shared by two (s, b) entries, two settings of test_maxlevel
// and parallax, two views, CPU (float, double) and GLSL. r_maxmip is built once for the field,
// r_zmap once per (s, b): 3 builds for 2 x 2 x 2 x 3 = 24 rows that use them. Every row of a
// setting carries the same precompute_ms (the build's) and the exact aux_bytes; parallax 0.
TEST(TestMaxLevel, TheRunnerBuildsResourcesOncePerFieldAndSharesThem) {
    Experiment ex;
    ex.samples = 32;
    ex.backend.timing_repeats = 0;
    ex.theta_deg = {0, 50};
    ex.phi_deg = {30};
    ex.backends = {"cpu", "glsl"};
    ex.backend.precisions = {"float", "double"};
    HeightfieldSpec hs;
    hs.name = hs.generator = "fbm";
    hs.width = 64;
    hs.height = 32;
    hs.gen_params = resolve_params(find_generator("fbm")->params, {}, "t", "fbm");
    hs.bias = 0.5;
    for (double s : {0.05, 0.1}) {
        hs.scale = s;
        ex.heightfields.push_back(hs);
    }
    ex.methods.push_back(
        {&maxlevel(), test::params_for(maxlevel(), {{"mode", "mid"}, {"level", 1}})});
    ex.methods.push_back({&maxlevel(), test::params_for(maxlevel(), {{"mode", "zmap"}})});
    const MethodInfo& par = *find_method("parallax");
    ex.methods.push_back({&par, test::params_for(par)});
    RunOptions opt;
    opt.gl_frames = 1;
    RunInfo info;
    const auto rows = run_experiment(ex, opt, &info);
    ASSERT_EQ(rows.size(), 2u * 2 * 3 * 3);
    EXPECT_EQ(info.resource_builds, 3);
    // 64 x 32 pyramid: 2048 + 512 + 128 + 32 + 8 + 2 + 1 floats; zmap 64 x 32 x 4 floats.
    const double bytes = (2048.0 + 512 + 128 + 32 + 8 + 2 + 1) * 4 + 64.0 * 32 * 4 * 4;
    std::map<double, double> ms_by_scale;
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("method") << " " << r.text("backend") << ": "
                            << r.text("error");
        const double ms = r.num("precompute_ms"), scale = r.num("scale");
        if (r.text("method") == "parallax") {
            EXPECT_EQ(ms, 0.0);
            EXPECT_EQ(r.num("aux_bytes"), 0.0);
            EXPECT_EQ(r.cell("aux_bytes"), "0");
            continue;
        }
        EXPECT_EQ(r.num("aux_bytes"), bytes);
        EXPECT_GT(ms, 0.0);
        const auto it = ms_by_scale.emplace(scale, ms).first;
        EXPECT_EQ(it->second, ms) << "rebuilt? scale " << scale << " " << r.text("backend");
        if (r.text("backend") == "glsl") {
            EXPECT_LE(r.num("cpu_diff_p999"), 1e-3) << r.text("params");
        }
    }
    EXPECT_EQ(ms_by_scale.size(), 2u);
}

}  // namespace
}  // namespace pxh
