// The GLSL backend, rendered for real through OSMesa (llvmpipe): every registered method's
// shader against its CPU float reference, shader errors, and texture quantisation.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "harness/backends/glsl_backend.h"
#include "harness/metrics/metrics.h"
#include "harness/run/runner.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

GlslBackend& backend() {
    static GlslBackend gl(GlslOptions{"", 1});
    return gl;
}

HeightField generated(const char* name, int size) {
    const GeneratorInfo* g = find_generator(name);
    return generate_heightfield(*g, size, size, resolve_params(g->params, {}, "test", name));
}

TEST(Glsl, ContextIsCoreProfileOnLlvmpipe) {
    EXPECT_NE(backend().version().find("4.5"), std::string::npos) << backend().version();
    EXPECT_NE(backend().version().find("Core"), std::string::npos);
    EXPECT_FALSE(backend().renderer().empty());
}

class EveryMethodGlsl : public ::testing::TestWithParam<std::string> {};

// For every registered method on two height fields and three angles, at least 99.9% of samples
// agree with the CPU float reference within 1e-3 texel, and so do the shadow factors.
TEST_P(EveryMethodGlsl, AgreesWithCpuFloatReference) {
    const MethodInfo& m = *find_method(GetParam());
    const MethodSpec spec{&m, test::params_for(m)};
    const int N = 96;
    const auto P = sample_grid(N);
    const LightSpec light{40, 210, 8, 32};
    for (const char* field : {"fbm", "bricks"}) {
        const HeightField hf = generated(field, 128);
        ResourceCache cache(hf);  // the method's precomputed textures, if it declares any
        const MethodResources res = cache.get(m.name, m.resources, 0.05, 1.0);
        for (double theta : {0.0, 55.0, 82.0}) {
            const Scene<double> sc{0.05, 1.0, view_vector(theta, 25), hf.width, hf.height};
            MethodOutput gpu = backend().run(spec, sc, hf, N, "r32f", &light, -1, &res);
            MethodOutput cpu = run_cpu(spec, "float", sc, hf, P, 0, &res);
            add_shadows(cpu, light, "float", sc, hf);
            ResultRow row;
            add_agreement(row, gpu, cpu, hf.width, hf.height);
            long long far = 0, shadow_off = 0, one_discards = 0;
            for (size_t k = 0; k < P.size(); ++k) {
                // a method that may discard: both twins discard, or at a source's own tie (the
                // curved relief search ending on the relief's floor, float against the
                // driver's float) only one does; the uv are compared where both answer
                const bool gd = std::isnan(gpu.uv[k].x), cd = std::isnan(cpu.uv[k].x);
                if (m.may_discard && (gd || cd)) {
                    one_discards += gd != cd;
                    continue;
                }
                const Vec2d e = texel_error(gpu.uv[k], cpu.uv[k], hf.width, hf.height);
                far += !(std::hypot(e.x, e.y) <= 1e-3);
                shadow_off += gpu.shadow_hard[k] != cpu.shadow_hard[k] ||
                              std::abs(gpu.shadow_soft[k] - cpu.shadow_soft[k]) > 1e-3;
            }
            EXPECT_LE(far, (long long)P.size() / 1000)
                << m.name << " " << field << " theta=" << theta << " max diff "
                << row.num("cpu_diff_max") << " texel, p99.9 " << row.num("cpu_diff_p999");
            EXPECT_LE(one_discards, (long long)P.size() / 100) << m.name << " " << field;
            if (!m.may_discard) {
                EXPECT_LE(shadow_off, (long long)P.size() / 1000) << m.name << " shadows";
                EXPECT_LE(row.num("decision_mismatch"), double(P.size()) / 1000) << m.name;
            }
            EXPECT_GT(gpu.timing.stats.median, 0.0);
            EXPECT_EQ(gpu.timing.unit, "ms/frame");
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryMethodGlsl, ::testing::ValuesIn(test::method_names()),
                         test::MethodName());

TEST(Glsl, EveryMethodHasAShaderBesideItsCpuReference) {
    for (const auto& m : all_methods()) {
        const auto p = std::filesystem::path(PXH_SOURCE_DIR) / m.shader_file();
        EXPECT_TRUE(std::filesystem::exists(p)) << p;
    }
}

// A broken shader from an override folder: a readable error naming the method, the file and
// the driver's log, and no crash; the next method still renders.
TEST(Glsl, BrokenShaderGivesReadableError) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("pxh_glsl_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "parallax.frag.glsl") << "vec2 pxh_method(vec2 P) { return P + oops; }\n";
    GlslBackend gl(GlslOptions{dir.string(), 1});
    const HeightField hf = generated("sine", 32);
    const Scene<double> sc{0.05, 1.0, view_vector(30, 0), 32, 32};
    const MethodInfo& par = *find_method("parallax");
    try {
        gl.run({&par, test::params_for(par)}, sc, hf, 16, "r32f", nullptr);
        FAIL() << "a broken shader rendered";
    } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("method 'parallax'"), std::string::npos) << msg;
        EXPECT_NE(msg.find("parallax.frag.glsl"), std::string::npos) << msg;
        EXPECT_NE(msg.find("oops"), std::string::npos) << "driver log missing: " << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
    }
    const MethodInfo& pom = *find_method("pom");
    const MethodOutput ok = gl.run({&pom, test::params_for(pom)}, sc, hf, 16, "r32f", nullptr);
    EXPECT_EQ(ok.uv.size(), 256u);
    std::filesystem::remove_all(dir);
}

// 8-bit heights move the parallax offset by up to half an LSB of the height range: |duv| <=
// s tan(theta) (0.5/255 + filter-weight rounding). The mean over samples must be of that order,
// and 16 bit must be ~256x closer.
TEST(Glsl, TextureQuantisationErrorHasTheExpectedOrder) {
    const HeightField hf = generated("fbm", 256);
    const double s = 0.05, theta = 60;
    const Scene<double> sc{s, 1.0, view_vector(theta, 0), 256, 256};
    const MethodInfo& par = *find_method("parallax");
    const MethodSpec spec{&par, test::params_for(par)};
    const auto f32 = backend().run(spec, sc, hf, 128, "r32f", nullptr);
    const auto r8 = backend().run(spec, sc, hf, 128, "r8", nullptr);
    const auto r16 = backend().run(spec, sc, hf, 128, "r16", nullptr);
    double d8 = 0, d16 = 0;
    for (size_t k = 0; k < f32.uv.size(); ++k) {
        d8 += std::hypot(r8.uv[k].x - f32.uv[k].x, r8.uv[k].y - f32.uv[k].y) * 256;
        d16 += std::hypot(r16.uv[k].x - f32.uv[k].x, r16.uv[k].y - f32.uv[k].y) * 256;
    }
    d8 /= double(f32.uv.size());
    d16 /= double(f32.uv.size());
    const double lsb_offset = s * std::tan(theta * M_PI / 180) / 255 * 256;  // texels per LSB
    EXPECT_GT(d8, 0.1 * lsb_offset) << "r8 mean diff " << d8 << ", one LSB moves " << lsb_offset;
    EXPECT_LT(d8, 1.0 * lsb_offset) << "r8 mean diff " << d8 << ", one LSB moves " << lsb_offset;
    EXPECT_LT(d16, d8 / 50) << "r16 " << d16 << " vs r8 " << d8;
}

}  // namespace
}  // namespace pxh
