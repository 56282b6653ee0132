// The GL contexts (harness/gl): every registered one creates a real OpenGL 4.5 core context
// and renders; OSMesa and EGL (both Mesa's llvmpipe here) give the same pixels and, through
// the pxh binary, the same GLSL rows; GPU times come from timer queries.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "harness/backends/glsl_backend.h"
#include "harness/core/error.h"
#include "harness/gl/context.h"
#include "harness/results/csv_table.h"
#include "heightfields/heightfields.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

TEST(GlContext, RegistryListsOsmesaAndEgl) {
    EXPECT_EQ(gl_context_names(), "egl, osmesa");
    ASSERT_NE(find_gl_context("egl"), nullptr);
    EXPECT_EQ(find_gl_context("vulkan"), nullptr);
    try {
        make_gl_context("vulkan");
        FAIL() << "an unknown context was made";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "--gl: unknown GL context 'vulkan' (known: egl, osmesa)");
    }
}

class EveryGlContext : public ::testing::TestWithParam<std::string> {};

// (a) Each context is a 4.5 core context that names its renderer and its driver.
TEST_P(EveryGlContext, CreatesA45CoreContextAndReportsItsRenderer) {
    auto ctx = make_gl_context(GetParam());
    ASSERT_NE(ctx, nullptr);
    EXPECT_EQ(ctx->name(), GetParam());
    use_gl_context(*ctx);
    const GlInfo info = current_gl_info();
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_NE(info.renderer, "unknown");
    EXPECT_NE(info.vendor, "unknown");
    EXPECT_NE(info.version.find("4.5"), std::string::npos) << info.version;
    EXPECT_NE(info.version.find("Core"), std::string::npos) << info.version;
    const auto driver = ctx->driver();
    if (GetParam() == "egl") {
        ASSERT_TRUE(driver.count("platform"));
        EXPECT_FALSE(driver.at("EGL_VENDOR").empty());
        EXPECT_EQ(driver.at("EGL_VERSION").rfind("1.", 0), 0u) << driver.at("EGL_VERSION");
    } else {
        EXPECT_EQ(driver.at("OSMESA_VERSION").rfind("11.", 0), 0u) << driver.at("OSMESA_VERSION");
    }
}

// (c) GPU time: llvmpipe reports a 64-bit GL_TIME_ELAPSED counter, so every timed frame has a
// positive GPU time, and min <= median <= max; an untimed render has none. (A context without
// timer queries, GL_QUERY_COUNTER_BITS = 0, must leave them empty instead.)
TEST_P(EveryGlContext, TimerQueriesGiveGpuTimes) {
    GlslBackend gl(GlslOptions{"", 3, {"r32f"}, GetParam()});
    EXPECT_EQ(gl.context_name(), GetParam());
    const MethodInfo& m = *find_method("pom");
    const MethodSpec spec{&m, test::params_for(m)};
    const GeneratorInfo* g = find_generator("fbm");
    const HeightField hf =
        generate_heightfield(*g, 64, 64, resolve_params(g->params, {}, "test", "fbm"));
    const Scene<double> sc{0.05, 1.0, view_vector(60, 20), hf.width, hf.height};
    const MethodOutput timed = gl.run(spec, sc, hf, 64, "r32f", nullptr);
    const MethodOutput untimed = gl.run(spec, sc, hf, 64, "r32f", nullptr, 0);
    EXPECT_TRUE(untimed.counters.empty());
    EXPECT_TRUE(untimed.timing.repeats.empty());
    EXPECT_EQ(untimed.timing.unit, "");
    EXPECT_TRUE(std::isnan(untimed.timing.stats.median));
    EXPECT_EQ(timed.timing.unit, "ms/frame");
    EXPECT_EQ(timed.timing.repeats.size(), 3u);
    if (gl.timer_bits() == 0) {
        EXPECT_TRUE(timed.counters.empty());
        GTEST_SKIP() << GetParam() << " has no timer queries (GL_QUERY_COUNTER_BITS = 0)";
    }
    EXPECT_GE(gl.timer_bits(), 30);
    ASSERT_EQ(timed.counters.size(), 1u);
    const Counter& gpu = timed.counters[0];
    EXPECT_EQ(gpu.name, "gpu_ms_per_frame");
    EXPECT_GT(gpu.value.min, 0.0);
    EXPECT_LE(gpu.value.min, gpu.value.median);
    EXPECT_LE(gpu.value.median, gpu.value.max);
    EXPECT_TRUE(std::isfinite(gpu.value.max));
}

INSTANTIATE_TEST_SUITE_P(GlContext, EveryGlContext, ::testing::Values("osmesa", "egl"),
                         [](const auto& p) { return p.param; });

// Two contexts of different types alive in one process, used in turn: each renders the same
// bits (both are llvmpipe here), which also shows the loader follows the current context.
TEST(GlContext, OsmesaAndEglRenderTheSameBitsInOneProcess) {
    GlslBackend a(GlslOptions{"", 1, {"r16"}, "osmesa"});
    GlslBackend b(GlslOptions{"", 1, {"r16"}, "egl"});
    const GeneratorInfo* g = find_generator("bricks");
    const HeightField hf =
        generate_heightfield(*g, 96, 96, resolve_params(g->params, {}, "test", "bricks"));
    const LightSpec light{40, 210, 8, 32};
    for (const char* name : {"relief", "parallax"}) {
        const MethodInfo& m = *find_method(name);
        const MethodSpec spec{&m, test::params_for(m)};
        const Scene<double> sc{0.05, 1.0, view_vector(75, 30), hf.width, hf.height};
        const MethodOutput oa = a.run(spec, sc, hf, 80, "r16", &light, 0);
        const MethodOutput ob = b.run(spec, sc, hf, 80, "r16", &light, 0);
        const MethodOutput oa2 = a.run(spec, sc, hf, 80, "r16", &light, 0);  // after b ran
        ASSERT_EQ(oa.uv.size(), ob.uv.size());
        long long differ = 0;
        for (size_t k = 0; k < oa.uv.size(); ++k)
            differ += oa.uv[k].x != ob.uv[k].x || oa.uv[k].y != ob.uv[k].y ||
                      oa.fetches[k] != ob.fetches[k] || oa.shadow_soft[k] != ob.shadow_soft[k] ||
                      oa2.uv[k].x != oa.uv[k].x || oa2.uv[k].y != oa.uv[k].y;
        EXPECT_EQ(differ, 0) << name;
    }
}

// ---- Through the pxh binary ----
class GlCli : public test::CliTest {};

// (b) pxh run --gl egl equals --gl osmesa on every GLSL row of the
// default experiment (results/experiments/default.toml itself at 48 samples, with --backend glsl:
// the GLSL rows only, the CPU float twin their agreement columns need is still run), cell by cell,
// every column but the timings (time, time_min, time_max, time_repeats, gpu_ms*: the unit is
// compared).
TEST_F(GlCli, EglEqualsOsmesaOnEveryGlslRowOfTheDefaultExperiment) {
    const std::string exp = std::string(PXH_SOURCE_DIR) + "/results/experiments/default.toml";
    for (const char* gl : {"osmesa", "egl"}) {
        // 48 samples a side, not the file's 192: every row, shader and view the same, at a
        // sixteenth of the pixels (the test is about the context, not the sample count)
        const auto r = pxh("run " + exp + " --backend glsl --samples 48 --quiet --gl " + gl +
                           " --out " + (dir / gl).string());
        ASSERT_EQ(r.status, 0) << gl << ": " << r.err;
    }
    const CsvTable a = read_csv((dir / "osmesa" / "results.csv").string());
    const CsvTable b = read_csv((dir / "egl" / "results.csv").string());
    ASSERT_EQ(a.columns, b.columns);
    ASSERT_EQ(a.rows.size(), b.rows.size());
    EXPECT_EQ(a.rows.size(), 6u * 14u * 10u);  // fields x views x method settings, r32f
    size_t compared = 0, differ = 0;
    for (size_t r = 0; r < a.rows.size(); ++r) {
        EXPECT_EQ(a.get(r, "backend"), "glsl");
        EXPECT_EQ(a.get(r, "status"), "ok") << a.where(r);
        for (size_t c = 0; c < a.columns.size(); ++c) {
            const std::string& col = a.columns[c];
            const bool timing =
                (col.rfind("time", 0) == 0 && col != "time_unit") || col.rfind("gpu_ms", 0) == 0;
            if (timing) continue;
            ++compared;
            if (a.rows[r][c] != b.rows[r][c] && ++differ <= 10)
                ADD_FAILURE() << "row " << r + 2 << " column " << col << ": osmesa " << a.rows[r][c]
                              << ", egl " << b.rows[r][c];
        }
        // Both measured their frames (the timings are not compared, but must be there).
        EXPECT_GT(b.number(r, "time"), 0.0);
        EXPECT_EQ(b.get(r, "time_unit"), "ms/frame");
        EXPECT_GT(b.number(r, "gpu_ms_per_frame"), 0.0);  // llvmpipe: 64-bit timer queries
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_EQ(compared, a.rows.size() * (a.columns.size() - 7));  // all but 7 timing columns
    // run.json records which context ran, and what is behind it.
    for (const char* gl : {"osmesa", "egl"}) {
        const auto run = nlohmann::json::parse(slurp(dir / gl / "run.json"));
        ASSERT_TRUE(run["backends"]["glsl"].contains("gl")) << gl;
        const auto& g = run["backends"]["glsl"]["gl"];
        EXPECT_EQ(g["context"], gl);
        EXPECT_FALSE(g["GL_RENDERER"].get<std::string>().empty());
        EXPECT_FALSE(g["GL_VENDOR"].get<std::string>().empty());
        EXPECT_NE(g["GL_VERSION"].get<std::string>().find("4.5"), std::string::npos);
        EXPECT_EQ(g["GL_QUERY_COUNTER_BITS"], 64);
        EXPECT_TRUE(g["driver"].contains(std::string(gl) == "egl" ? "platform" : "OSMESA_VERSION"));
    }
}

const std::string kTiny = test::ExperimentToml("tiny")
                              .timing_repeats(1)
                              .backends("\"cpu\", \"glsl\"")
                              .theta("[45]")
                              .field("sine", 16)
                              .method("parallax");

// (d) An unknown context: one line, exit 2, the known names, nothing written.
TEST_F(GlCli, UnknownGlNameIsAOneLineInputError) {
    const auto exp = write("tiny.toml", kTiny);
    const auto r = pxh("run " + exp + " --gl vulkan --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err, "pxh: error: --gl: unknown GL context 'vulkan' (known: egl, osmesa)\n");
    EXPECT_FALSE(fs::exists(dir / "out"));
    // The experiment key: named at its file and line.
    const auto bad = write("bad.toml", std::string(kTiny).insert(0, "\n\ngl = \"glx\"\n"));
    const auto rb = pxh("run " + bad + " --out " + (dir / "out").string());
    EXPECT_EQ(rb.status, 2);
    EXPECT_EQ(rb.err, "pxh: error: " + bad + ":3: unknown GL context 'glx' (known: egl, osmesa)\n");
    EXPECT_FALSE(fs::exists(dir / "out"));
}

// The file's gl key selects the context, the flag overrides it; CPU rows have no GPU times.
TEST_F(GlCli, FlagOverridesTheExperimentKey) {
    const auto exp = write("tiny.toml", std::string(kTiny).insert(0, "gl = \"egl\"\n"));
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + (dir / "file").string()).status, 0);
    ASSERT_EQ(pxh("run " + exp + " --quiet --gl osmesa --out " + (dir / "flag").string()).status,
              0);
    EXPECT_EQ(nlohmann::json::parse(
                  slurp(dir / "file" / "run.json"))["backends"]["glsl"]["gl"]["context"],
              "egl");
    EXPECT_EQ(nlohmann::json::parse(
                  slurp(dir / "flag" / "run.json"))["backends"]["glsl"]["gl"]["context"],
              "osmesa");
    const CsvTable t = read_csv((dir / "file" / "results.csv").string());
    ASSERT_EQ(t.rows.size(), 2u);
    EXPECT_EQ(t.get(0, "backend"), "cpu");
    EXPECT_EQ(t.get(0, "gpu_ms_per_frame"), "");
    EXPECT_EQ(t.get(1, "backend"), "glsl");
    EXPECT_GT(t.number(1, "gpu_ms_per_frame"), 0.0);
}

}  // namespace
}  // namespace pxh
