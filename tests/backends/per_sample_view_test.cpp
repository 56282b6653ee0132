// Views whose rays are not parallel (what a perspective camera makes): every method, on both
// backends, sees sample k's own direction V_k. Checked against the same method run on a
// parallel view along V_k, sample by sample (bit for bit: the same code on the same numbers),
// and the GLSL render against the CPU reference.
#include <gtest/gtest.h>

#include <cmath>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/metrics.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

GlslBackend& gl() {
    static GlslBackend b(GlslOptions{"", 0});
    return b;
}

HeightField field(int size) {
    const GeneratorInfo* g = find_generator("fbm");
    return generate_heightfield(*g, size, size, resolve_params(g->params, {}, "test", "fbm"));
}

// Four directions, one per sample by a pattern that is neither row- nor column-constant, so
// that a transposed or flipped direction map would show.
const Vec3d kDirs[4] = {view_vector(0, 0), view_vector(35, 20), view_vector(62, 200),
                        view_vector(80, 290)};
int dir_of(size_t k, int n) {
    const size_t i = k % size_t(n), j = k / size_t(n);
    return int((i + 2 * j + (i * j) % 3) % 4);
}

View fan_view(int n) {
    View v = orthographic_view(kDirs[0], n);
    v.parallel = false;
    v.V.resize(v.P.size());
    for (size_t k = 0; k < v.P.size(); ++k) v.V[k] = kDirs[dir_of(k, n)];
    return v;
}

class PerSampleView : public ::testing::TestWithParam<std::string> {};

TEST_P(PerSampleView, EachSampleSeesItsOwnDirectionOnBothBackends) {
    const MethodInfo& m = *find_method(GetParam());
    const MethodSpec spec{&m, test::params_for(m)};
    const int N = 24;
    const HeightField hf = field(64);
    ResourceCache cache(hf);
    const MethodResources res = cache.get(m.name, m.resources, 0.06, 1.0);
    const View fan = fan_view(N);
    ASSERT_EQ(view_problem(fan), "");
    const Scene<double> sc{0.06, 1.0, kDirs[0], hf.width, hf.height};
    BackendSettings settings;
    settings.precisions = {"float", "double"};
    CpuBackend cpu(settings);
    const ViewInput in{sc, hf, fan, nullptr, false, &res};
    for (const Variant& v : cpu.variants()) {
        const MethodOutput each = cpu.run(spec, in, v);
        ASSERT_EQ(each.uv.size(), fan.size());
        for (int d = 0; d < 4; ++d) {  // the parallel view along direction d, same samples
            Scene<double> along = sc;
            along.V = kDirs[d];
            const MethodOutput par = run_cpu(spec, v.precision, along, hf, fan.P, 0, &res);
            for (size_t k = 0; k < fan.size(); ++k) {
                if (dir_of(k, N) != d) continue;
                ASSERT_EQ(each.uv[k].x, par.uv[k].x) << m.name << " " << v.precision << " k=" << k;
                ASSERT_EQ(each.uv[k].y, par.uv[k].y) << m.name << " k=" << k;
                ASSERT_EQ(each.fetches[k], par.fetches[k]) << m.name << " k=" << k;
            }
        }
    }
    // GLSL: the per-sample render equals, sample by sample, four parallel renders (the same
    // float V, from a texture instead of a uniform), and agrees with the CPU float reference.
    const MethodOutput each = gl().run(spec, in, {"float", "r32f"});
    for (int d = 0; d < 4; ++d) {
        Scene<double> along = sc;
        along.V = kDirs[d];
        const MethodOutput par = gl().run(spec, along, hf, N, "r32f", nullptr, 0, &res);
        for (size_t k = 0; k < fan.size(); ++k) {
            if (dir_of(k, N) != d) continue;
            ASSERT_EQ(each.uv[k].x, par.uv[k].x) << m.name << " glsl k=" << k;
            ASSERT_EQ(each.uv[k].y, par.uv[k].y) << m.name << " glsl k=" << k;
            ASSERT_EQ(each.fetches[k], par.fetches[k]) << m.name << " glsl k=" << k;
        }
    }
    const MethodOutput ref = cpu.run(spec, in, {"float", ""});
    size_t far = 0;
    for (size_t k = 0; k < fan.size(); ++k) {
        const Vec2d e = texel_error(each.uv[k], ref.uv[k], hf.width, hf.height);
        far += !(std::hypot(e.x, e.y) <= 1e-3);
    }
    EXPECT_LE(far, size_t(1)) << m.name << ": GLSL vs CPU float beyond 1e-3 texel";
}

INSTANTIATE_TEST_SUITE_P(Registry, PerSampleView, ::testing::ValuesIn(test::method_names()),
                         test::MethodName());

// A sample set that is not N x N pixels cannot be drawn: a clear error, no numbers.
TEST(PerSampleView, GlslRefusesAViewThatIsNotSquare) {
    const MethodInfo& m = *find_method("parallax");
    const HeightField hf = field(16);
    View v;
    v.P = {{0.1, 0.2}, {0.7, 0.3}};
    v.V = {view_vector(30, 0)};
    v.parallel = true;
    const Scene<double> sc{0.05, 1.0, v.V[0], hf.width, hf.height};
    try {
        gl().run({&m, test::params_for(m)}, {sc, hf, v, nullptr, false, nullptr},
                 {"float", "r32f"});
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("N x N pixels"), std::string::npos) << e.what();
    }
}

// The experiment names its camera under [views]; an unknown one is one line with the known.
TEST(PerSampleView, ExperimentCameraKey) {
    const std::string base = "[views]\ntheta_deg = [0, 30]\n";
    const std::string rest =
        "[[heightfields]]\ngenerator = \"flat\"\nsize = 8\n"
        "[[methods]]\nname = \"parallax\"\n";
    EXPECT_EQ(parse_experiment(base + rest, "e.toml").camera, "orthographic");
    EXPECT_EQ(parse_experiment(base + "camera = \"orthographic\"\n" + rest, "e.toml").camera,
              "orthographic");
    EXPECT_EQ(test::input_error(
                  [&] { parse_experiment(base + "camera = \"pinhole\"\n" + rest, "e.toml"); }),
              "e.toml:3: unknown camera 'pinhole' (known: orthographic, perspective)");
}

}  // namespace
}  // namespace pxh
