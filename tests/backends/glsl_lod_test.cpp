// The GLSL backend beyond the orthographic grid at level 0 (docs/conventions.md section 10):
// perspective views drawn per pixel (P and V of each sample from per-sample maps, outside pixels
// masked), the field's texture levels uploaded as the height texture's mip chain in the row's
// format, and the level modes (level, grad, implicit) behind pxh_height, with pxh_lod().
// Checked against the CPU float twin in the same mode, against what was uploaded (read back),
// and against closed forms (a constant field's levels, the lambda a plug-in returns).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/metrics/agreement.h"
#include "harness/metrics/metrics.h"
#include "harness/metrics/row.h"
#include "harness/results/csv_table.h"
#include "harness/scene/perspective_camera.h"
#include "harness/scene/texture_levels.h"
#include "heightfields/heightfields.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

GlslBackend& gl() {
    static GlslBackend b(GlslOptions{"", 0});
    return b;
}

HeightField generated(const char* name, int w, int h) {
    const GeneratorInfo* g = find_generator(name);
    return generate_heightfield(*g, w, h, resolve_params(g->params, {}, "test", name));
}

// The built-ins that take every level mode: those without precomputed maps.
std::vector<std::string> level_methods() {
    std::vector<std::string> out;
    for (const std::string& n : test::method_names())
        if (find_method(n)->resources.empty()) out.push_back(n);
    return out;
}

struct Cam {
    double theta, distance, fov;
};

// One view through the runner's lens: its rays, each sample's lambda (footprint_lod, as the
// runner computes it), the scene along the look-at direction.
struct TestView {
    View rays;
    std::vector<double> lambda;
    Scene<double> scene;
};

TestView perspective(const HeightField& hf, double s, double b, Cam c, int n, double phi = 25) {
    PerspectiveParams p{c.theta, phi, c.distance, c.fov, n};
    check_eye_above_slab(p, s, b, "test");
    TestView v{
        PerspectiveCamera(p).view(), {}, {s, b, view_vector(c.theta, phi), hf.width, hf.height}};
    v.lambda = sample_lods(v.rays.J, hf.width, hf.height);
    return v;
}

TestView orthographic(const HeightField& hf, double s, double b, double theta, int n) {
    TestView v{orthographic_view(view_vector(theta, 25), n),
               {},
               {s, b, view_vector(theta, 25), hf.width, hf.height}};
    v.lambda.assign(v.rays.size(), footprint_lod(v.rays.J[0], hf.width, hf.height));
    return v;
}

// Samples inside the view whose GLSL uv lies more than 1e-3 texel from the CPU float twin's;
// also checks that outside samples carry no uv and none is counted as discarded.
struct Far {
    size_t inside = 0, far = 0;
    double worst = 0;
};
Far compare(const MethodOutput& gpu, const MethodOutput& cpu, const View& rays,
            const HeightField& hf) {
    Far f;
    EXPECT_EQ(gpu.uv.size(), rays.size());
    for (size_t k = 0; k < rays.size(); ++k) {
        if (!rays.is_inside(k)) {
            EXPECT_TRUE(std::isnan(gpu.uv[k].x)) << "outside sample " << k << " has a uv";
            continue;
        }
        ++f.inside;
        const Vec2d e = texel_error(gpu.uv[k], cpu.uv[k], hf.width, hf.height);
        const double d = std::hypot(e.x, e.y);
        f.far += !(d <= 1e-3);
        if (!(d <= f.worst)) f.worst = d;
    }
    return f;
}

class GlslPerspective : public ::testing::TestWithParam<std::string> {};

// Base level, perspective views: the GLSL render agrees with the CPU float twin as on the grid
// (within 1e-3 texel but for one sample in a thousand), and the outside pixels are masked.
TEST_P(GlslPerspective, BaseAgreesWithTheCpuFloatTwin) {
    const MethodInfo& m = *find_method(GetParam());
    const MethodSpec spec{&m, test::params_for(m)};
    const HeightField hf = generated("fbm", 64, 64);
    const double s = 0.05, b = 1.0;
    ResourceCache cache(hf);
    const MethodResources res = cache.get(m.name, m.resources, s, b);
    CpuBackend cpu(BackendSettings{});
    size_t outside_views = 0;
    for (double theta : {30.0, 60.0, 80.0})
        for (double D : {1.5, 4.0})
            for (double fov : {45.0, 60.0}) {
                const TestView v = perspective(hf, s, b, {theta, D, fov}, 32);
                ViewInput in{v.scene, hf, v.rays, nullptr, false, &res};
                in.lambda = &v.lambda;
                const MethodOutput g = gl().run(spec, in, {"float", "r32f"});
                const MethodOutput c = cpu.run(spec, in, {"float", ""});
                const Far f = compare(g, c, v.rays, hf);
                EXPECT_LE(f.far, f.inside / 1000)
                    << m.name << " theta=" << theta << " D=" << D << " fov=" << fov << ": worst "
                    << f.worst << " texel";
                EXPECT_GT(f.inside, 0u);
                EXPECT_LE(g.samples_discarded + v.rays.outside_count(), v.rays.size());
                if (v.rays.outside_count() > 0) {
                    ++outside_views;
                    // Masked, not discarded: a method that never discards reports none.
                    if (c.samples_discarded == 0) {
                        EXPECT_EQ(g.samples_discarded, 0) << m.name;
                    }
                }
            }
    EXPECT_GT(outside_views, 0u) << "no view reached past the horizon";
}

INSTANTIATE_TEST_SUITE_P(Registry, GlslPerspective, ::testing::ValuesIn(test::method_names()),
                         test::MethodName());

class GlslLevelMode : public ::testing::TestWithParam<std::string> {};

// lod = level: the CPU float twin (level_fetch over pxh's levels) and the GLSL twin (textureLod
// over the same levels uploaded as the mip chain) agree within 1e-3 texel at p99.9, on
// orthographic and perspective views, a power-of-two field and an odd-sized one, r32f.
TEST_P(GlslLevelMode, CpuFloatTwinEqualsTheGlslTwin) {
    const MethodInfo& m = *find_method(GetParam());
    MethodSpec spec{&m, test::params_for(m)};
    spec.lod = LodMode::level;
    MethodSpec base = spec;
    base.lod = LodMode::base;
    CpuBackend cpu(BackendSettings{});
    const double s = 0.05, b = 1.0;
    for (const auto& [w, h] : {std::pair{64, 64}, std::pair{60, 44}}) {
        const HeightField hf = generated("fbm", w, h);
        const TextureLevels levels = build_texture_levels(hf);
        std::vector<TestView> views = {orthographic(hf, s, b, 50, 16),
                                       perspective(hf, s, b, {60, 1.5, 60}, 32),
                                       perspective(hf, s, b, {80, 4, 45}, 32)};
        size_t level_differs = 0;
        for (const TestView& v : views) {
            ViewInput in{v.scene, hf, v.rays, nullptr, false, nullptr};
            in.levels = &levels;
            in.lambda = &v.lambda;
            const MethodOutput g = gl().run(spec, in, {"float", "r32f"});
            const MethodOutput c = cpu.run(spec, in, {"float", ""});
            const Far f = compare(g, c, v.rays, hf);
            EXPECT_LE(f.far, f.inside / 1000)
                << m.name << " " << w << "x" << h << " worst " << f.worst << " texel";
            for (size_t k = 0; k < v.rays.size(); ++k)
                if (v.rays.is_inside(k)) {
                    EXPECT_EQ(g.fetches[k], c.fetches[k]) << m.name << k;
                }
            // The levels are in use: the level render is not the base one.
            const MethodOutput g0 = gl().run(base, in, {"float", "r32f"});
            for (size_t k = 0; k < v.rays.size(); ++k)
                level_differs += v.rays.is_inside(k) && g0.uv[k].x != g.uv[k].x;
        }
        if (m.name != "none") {
            EXPECT_GT(level_differs, 0u) << m.name;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, GlslLevelMode, ::testing::ValuesIn(level_methods()),
                         test::MethodName());

// parallax at lod = level on an orthographic view of `hf` (theta 40, 8 x 8 samples), with the
// field's levels and the view's lambda: what the upload tests draw.
struct ParallaxAtLevel {
    explicit ParallaxAtLevel(const HeightField& hf)
        : levels(build_texture_levels(hf)),
          v(orthographic(hf, 0.05, 1.0, 40, 8)),
          spec{find_method("parallax"), test::params_for(*find_method("parallax"))},
          in{v.scene, hf, v.rays, nullptr, false, nullptr} {
        spec.lod = LodMode::level;
        in.levels = &levels;
        in.lambda = &v.lambda;
    }
    TextureLevels levels;
    TestView v;
    MethodSpec spec;
    ViewInput in;
};

// The levels as uploaded (glGetTexImage): the CPU's levels, each in the row's format (r32f as
// built, r16 and r8 rounded to the nearest 1/65535, 1/255), the mip chain q levels long; a base
// draw afterwards goes back to level 0 alone.
TEST(GlslLevels, UploadedLevelsAreTheCpuLevelsInTheRowsFormat) {
    const HeightField hf = test::random_field(48, 40, 7);
    const ParallaxAtLevel run(hf);
    const auto& [levels, v, spec, in] = run;
    ASSERT_EQ(levels.last(), 5);
    for (const auto& [format, steps] :
         std::vector<std::pair<std::string, double>>{{"r32f", 0}, {"r16", 65535}, {"r8", 255}}) {
        gl().run(spec, in, {"float", format});
        EXPECT_EQ(gl().height_texture_max_level(), levels.last()) << format;
        for (int L = 0; L <= levels.last(); ++L) {
            const HeightField& cpu = levels.levels[size_t(L)];
            int w = 0, h = 0;
            const std::vector<float> up = gl().height_texture_level(L, w, h);
            ASSERT_EQ(w, cpu.width) << format << " level " << L;
            ASSERT_EQ(h, cpu.height) << format << " level " << L;
            size_t off = 0;
            for (size_t i = 0; i < up.size(); ++i) {
                const double want =
                    steps == 0 ? double(cpu.texels[i])
                               : double(std::lround(double(cpu.texels[i]) * steps)) / steps;
                off += !(std::abs(double(up[i]) - want) <= 1e-7);
            }
            EXPECT_EQ(off, 0u) << format << " level " << L;
        }
    }
    MethodSpec b = spec;
    b.lod = LodMode::base;
    gl().run(b, in, {"float", "r32f"});
    EXPECT_EQ(gl().height_texture_max_level(), 0);
}

// A constant field stays constant on every level in every format (the uploaded texels are all
// the level-0 texel's value as stored).
TEST(GlslLevels, ConstantFieldIsConstantOnEveryLevelInEveryFormat) {
    const HeightField hf = test::flat_field(36, 20, 0.3721f);
    const ParallaxAtLevel run(hf);
    const auto& [levels, v, spec, in] = run;
    for (const char* format : {"r32f", "r16", "r8"}) {
        gl().run(spec, in, {"float", format});
        int w = 0, h = 0;
        const float v0 = gl().height_texture_level(0, w, h)[0];
        EXPECT_NEAR(v0, 0.3721, std::string(format) == "r8" ? 0.5 / 255 : 0.5 / 65535);
        for (int L = 0; L <= levels.last(); ++L)
            for (float t : gl().height_texture_level(L, w, h))
                ASSERT_EQ(t, v0) << format << " level " << L;
    }
}

// grad and implicit run on every level method; on a field whose levels are all equal (a
// constant field) every fetch returns the same height whatever the level, so they equal base
// exactly, sample by sample; on a real field they stay near the level twin (finite, and the
// hit within a few texels: the level differs, not the method).
TEST(GlslLodModes, GradAndImplicitEqualBaseOnAConstantField) {
    const double s = 0.05, b = 1.0;
    const HeightField flat = test::flat_field(64, 64, 0.55f);
    const TextureLevels flat_levels = build_texture_levels(flat);
    const HeightField fbm = generated("fbm", 64, 64);
    const TextureLevels fbm_levels = build_texture_levels(fbm);
    CpuBackend cpu(BackendSettings{});
    for (const std::string& name : level_methods()) {
        const MethodInfo& m = *find_method(name);
        for (const TestView& v :
             {perspective(flat, s, b, {70, 1.5, 60}, 24), orthographic(flat, s, b, 60, 16)}) {
            ViewInput in{v.scene, flat, v.rays, nullptr, false, nullptr};
            in.levels = &flat_levels;
            in.lambda = &v.lambda;
            MethodSpec spec{&m, test::params_for(m)};
            const MethodOutput g0 = gl().run(spec, in, {"float", "r32f"});
            for (LodMode mode : {LodMode::level, LodMode::grad, LodMode::implicit}) {
                spec.lod = mode;
                const MethodOutput g = gl().run(spec, in, {"float", "r32f"});
                for (size_t k = 0; k < v.rays.size(); ++k) {
                    if (!v.rays.is_inside(k)) continue;
                    ASSERT_EQ(g.uv[k].x, g0.uv[k].x) << name << " " << lod_name(mode) << k;
                    ASSERT_EQ(g.uv[k].y, g0.uv[k].y) << name << " " << lod_name(mode) << k;
                    ASSERT_EQ(g.fetches[k], g0.fetches[k]) << name << " " << lod_name(mode);
                }
            }
        }
        const TestView v = perspective(fbm, s, b, {60, 1.5, 60}, 24);
        ViewInput in{v.scene, fbm, v.rays, nullptr, false, nullptr};
        in.levels = &fbm_levels;
        in.lambda = &v.lambda;
        MethodSpec spec{&m, test::params_for(m)};
        spec.lod = LodMode::level;
        const MethodOutput twin = cpu.run(spec, in, {"float", ""});
        for (LodMode mode : {LodMode::grad, LodMode::implicit}) {
            spec.lod = mode;
            const MethodOutput g = gl().run(spec, in, {"float", "r32f"});
            ResultRow row;
            add_agreement(row, g, twin, fbm.width, fbm.height, &v.rays.inside);
            EXPECT_TRUE(std::isfinite(row.num("cpu_diff_max"))) << name << " " << lod_name(mode);
            EXPECT_LT(row.num("cpu_diff_p999"), 8.0) << name << " " << lod_name(mode);
        }
    }
}

// A shader's pxh_lod() is the sample's lambda, in base and level mode, from the runner's lambdas
// (none given: 0, as on the CPU): a method returning P + (pxh_lod(), 0) / 1024 shows it.
TEST(GlslLodModes, PluginPxhLodIsTheSamplesLambda) {
    GlslDraw d;
    d.method.name = "test_lod_probe";
    d.method.shader_file = "tests/lod_probe.frag.glsl";
    d.method.has_builtin_text = true;
    d.method.builtin_text =
        "vec2 pxh_method(vec2 P) { return P + vec2(pxh_lod(), 0.0) / 1024.0; }\n";
    const HeightField hf = generated("fbm", 64, 32);
    const TextureLevels levels = build_texture_levels(hf);
    const TestView v = perspective(hf, 0.05, 1.0, {65, 2.5, 50}, 24, 40);
    d.scene = v.scene;
    d.hf = &hf;
    d.samples = 24;
    d.frames = 0;
    d.V = &v.rays.V;
    d.P = &v.rays.P;
    d.inside = &v.rays.inside;
    d.J = &v.rays.J;
    d.levels = &levels;
    double lo = 1e9, hi = -1e9;
    for (LodMode mode : {LodMode::base, LodMode::level}) {
        for (bool given : {true, false}) {
            d.lod = mode;
            d.lambda = given ? &v.lambda : nullptr;
            const MethodOutput o = gl().draw(d);
            EXPECT_EQ(o.samples_discarded, 0);
            for (size_t k = 0; k < v.rays.size(); ++k) {
                if (!v.rays.is_inside(k)) continue;
                const double got = (o.uv[k].x - float(v.rays.P[k].x)) * 1024.0;
                const double want = given ? v.lambda[k] : 0.0;
                ASSERT_NEAR(got, want, 1e-3 * std::max(1.0, std::abs(want)))
                    << lod_name(mode) << " k=" << k << (given ? " given" : " none given");
                lo = std::min(lo, v.lambda[k]);
                hi = std::max(hi, v.lambda[k]);
            }
        }
    }
    EXPECT_GT(hi - lo, 1.0) << "the view's lambdas hardly vary: a constant would pass";
}

// pxh run end to end: a small perspective experiment on both backends, every level mode; every
// row ok, the same outside count on both backends, grad and implicit rows with their agreement
// with the level twin.
class GlslLodCli : public test::CliTest {};

TEST_F(GlslLodCli, PerspectiveExperimentWithEveryLevelMode) {
    write("e.toml", test::ExperimentToml("lod")
                        .samples(24)
                        .backends("\"cpu\", \"glsl\"")
                        .theta("[45, 80]")
                        .phi("[20]")
                        .view("camera", "\"perspective\"")
                        .view("distance", "[1.5, 4]")
                        .view("fov_deg", "60")
                        .field("fbm", 64, "scale = 0.05\nbias = 1.0")
                        .method("pom", "lod = [\"base\", \"level\", \"grad\", \"implicit\"]")
                        .method("parallax", "lod = [\"base\", \"level\"]"));

    const test::CliResult r =
        pxh("run " + (dir / "e.toml").string() + " --quiet --out " + (dir / "r").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const CsvTable t = read_csv((dir / "r" / "results.csv").string());
    std::map<std::string, std::string> outside;  // by view
    std::map<std::string, int> rows_by;          // backend/lod
    for (size_t i = 0; i < t.rows.size(); ++i) {
        EXPECT_EQ(t.get(i, "status"), "ok") << t.get(i, "method") << " " << t.get(i, "error");
        const std::string view = t.get(i, "theta_deg") + "/" + t.get(i, "distance");
        const auto [it, fresh] = outside.emplace(view, t.get(i, "samples_outside"));
        EXPECT_EQ(it->second, t.get(i, "samples_outside")) << view << " " << t.get(i, "backend");
        const std::string lod = t.get(i, "lod"), backend = t.get(i, "backend");
        ++rows_by[backend + "/" + lod];
        if (backend == "glsl") {
            EXPECT_TRUE(std::isfinite(t.number(i, "cpu_diff_max"))) << lod;
            if (lod == "base" || lod == "level") {
                EXPECT_LE(t.number(i, "cpu_diff_p999"), 1e-3) << t.get(i, "method") << " " << lod;
            }
        }
    }
    EXPECT_EQ(rows_by["cpu/base"], 8);
    EXPECT_EQ(rows_by["cpu/level"], 8);
    EXPECT_EQ(rows_by["cpu/grad"], 0);
    EXPECT_EQ(rows_by["glsl/base"], 8);
    EXPECT_EQ(rows_by["glsl/level"], 8);
    EXPECT_EQ(rows_by["glsl/grad"], 4);
    EXPECT_EQ(rows_by["glsl/implicit"], 4);
    EXPECT_EQ(outside.size(), 4u);
    EXPECT_NE(outside["80/1.5"], "0") << "the 80 degree view reaches past the horizon";
}

// A plug-in calling pxh_lod() passes the check before the run and runs in every lod mode; it
// fetches nothing, so its rows are the same in every mode (what it returns is the lambda: the
// probe of PluginPxhLodIsTheSamplesLambda, in process).
TEST_F(GlslLodCli, PluginCallingPxhLodRunsInEveryMode) {
    write("probe.frag.glsl",
          "vec2 pxh_method(vec2 P) { return P + vec2(pxh_lod(), 0.0) / 1024.0; }\n");
    write("p.toml", test::ExperimentToml("probe")
                        .samples(24)
                        .backends("\"glsl\"")
                        .theta("[60]")
                        .view("camera", "\"perspective\"")
                        .view("distance", "[2]")
                        .field("fbm", 64, "scale = 0.05\nbias = 1.0")
                        .method("probe",
                                "shader = \"probe.frag.glsl\"\nmax_fetches = 1\n"
                                "lod = [\"base\", \"level\", \"grad\", \"implicit\"]")
                        .method("none"));

    const test::CliResult r =
        pxh("run " + (dir / "p.toml").string() + " --quiet --out " + (dir / "r").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const CsvTable t = read_csv((dir / "r" / "results.csv").string());
    ASSERT_EQ(t.rows.size(), 5u);
    ASSERT_EQ(t.get(4, "method"), "none");  // returns P: the probe with pxh_lod() = 0
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(t.get(i, "status"), "ok") << t.get(i, "lod") << " " << t.get(i, "error");
        EXPECT_EQ(t.get(i, "samples_discarded"), "0") << t.get(i, "lod");
        EXPECT_EQ(t.get(i, "err_mean"), t.get(0, "err_mean")) << t.get(i, "lod");
        EXPECT_GT(std::abs(t.number(i, "err_mean") - t.number(4, "err_mean")), 1e-3)
            << "the probe returned P: pxh_lod() = 0?";
    }
}

}  // namespace
}  // namespace pxh
