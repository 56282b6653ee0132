// The silhouette-aware methods (methods/curved_relief, methods/silhouette_pom; sources in
// docs/internals/silhouette_sources.md) against literal transcriptions of their sources' loops
// (each in the source's own variables and order), and what they do on bases: on the plane
// neither discards and both land near the truth; on a small sphere they discard where the
// flat methods show background (cover_extra_frac drops) and never where the truth shows surface
// head-on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <tuple>

#include "harness/experiment/experiment.h"
#include "harness/run/runner.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::method;
using test::params_for;
using test::random_field;
using test::run;
using test::run_method;

// three.js PR 33953, ParallaxOcclusion.js lines 205-350 and 376-426 (silhouette_sources.md
// section 1), transcribed with its names; depth = 1 - h, the polygon at the top (b = 1).
// Returns NaN uv where it discards.
Vec2d threejs_silhouette_pom(const HeightField& hf, double s, Vec3d Vt, Vec2d startUV, double ku,
                             double kv) {
    HeightSampler<double> hs(hf, s, 1.0);
    const double minLayers = 16, maxLayers = 48, minViewZ = 0.05;
    auto mix = [](double a, double b, double t) { return a * (1 - t) + b * t; };
    const double numLayers = mix(maxLayers, minLayers, std::clamp(std::abs(Vt.z), 0.0, 1.0));
    const double layerDepth = 1.0 / numLayers;
    const Vec2d shift{Vt.x / std::max(std::abs(Vt.z), minViewZ) * s,
                      Vt.y / std::max(std::abs(Vt.z), minViewZ) * s};
    const Vec2d deltaUV{shift.x / numLayers, shift.y / numLayers};
    const Vec2d bend{std::min(ku / std::max(2 * s, 1e-4), 6.0),
                     std::min(kv / std::max(2 * s, 1e-4), 6.0)};
    auto depthAt = [&](Vec2d uv) {
        const Vec2d o{uv.x - startUV.x, uv.y - startUV.y};
        return 1.0 - hs.height(uv) + (o.x * o.x * bend.x + o.y * o.y * bend.y);
    };
    Vec2d uv = startUV;
    double currentLayerDepth = 0, currentDepth = depthAt(uv);
    for (int i = 0; i < int(maxLayers); ++i) {
        if (currentLayerDepth >= currentDepth) break;
        uv = {uv.x - deltaUV.x, uv.y - deltaUV.y};
        currentLayerDepth += layerDepth;
        currentDepth = depthAt(uv);
    }
    for (int i = 0; i < 24; ++i) {  // the horizon chase
        if (currentLayerDepth >= currentDepth) break;
        uv = {uv.x - 4 * deltaUV.x, uv.y - 4 * deltaUV.y};
        currentLayerDepth += 4 * layerDepth;
        currentDepth = depthAt(uv);
    }
    const Vec2d prevUV{uv.x + deltaUV.x, uv.y + deltaUV.y};
    const double afterDepth = currentLayerDepth - currentDepth;
    const double beforeDepth = depthAt(prevUV) - (currentLayerDepth - layerDepth);
    const double weight =
        std::clamp(afterDepth / std::max(afterDepth + beforeDepth, 1e-4), 0.0, 1.0);
    const Vec2d finalUV{mix(uv.x, prevUV.x, weight), mix(uv.y, prevUV.y, weight)};
    const double miss = currentDepth - currentLayerDepth;
    const double coverage = std::clamp(1 - miss / 0.05, 0.0, 1.0);
    if (coverage < 0.5) return {NAN, NAN};
    return finalUV;
}

// Policarpo's curved relief shader as its ports carry it (silhouette_sources.md section 3), in
// tiles (the texel-size scaling of the source is the identity here), depth map 1 - h times s.
Vec2d policarpo_curved_relief(const HeightField& hf, double s, Vec3d V, Vec2d P, double a,
                              double b) {
    HeightSampler<double> hs(hf, s, 1.0);
    const Vec3d v{-V.x, -V.y, V.z};  // into the relief, depth growing
    const double dataz = a * v.x * v.x + b * v.y * v.y;
    double tmax = 50;
    double d = v.z * v.z - 4 * dataz * s;
    if (d > 0) tmax = std::min(tmax, (-v.z + std::sqrt(d)) / (-2 * dataz));
    d = v.z / dataz;
    if (d > 0) tmax = std::min(tmax, d);
    auto depth_below = [&](double t) { return v.z * t - dataz * t * t; };
    auto map = [&](double t) { return s * (1 - hs.height({P.x + v.x * t, P.y + v.y * t})); };
    double size = (tmax + 0.001) / 64, t = 0;
    for (int i = 0; i < 64; ++i)
        if (depth_below(t) < map(t)) t += size;
    for (int i = 0; i < 5; ++i) {
        size *= 0.5;
        if (depth_below(t) < map(t)) t += 2 * size;
        t -= size;
    }
    if (t > tmax) return {NAN, NAN};
    return {P.x + v.x * t, P.y + v.y * t};
}

TEST(Silhouette, MethodsAreTheirSourcesLoops) {
    const HeightField hf = random_field(24, 24, 5);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> U(0, 1);
    int discards[2] = {0, 0}, kept[2] = {0, 0};
    for (int i = 0; i < 400; ++i) {
        const double th = (5 + 84 * U(rng)) * M_PI / 180, ph = 2 * M_PI * U(rng);
        const Vec3d V{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
        const double s = 0.02 + 0.08 * U(rng);
        const double ku = 4 * U(rng), kv = i % 2 ? ku : 0.0;  // sphere-like, cylinder-like
        const Vec2d P{U(rng), U(rng)};
        Scene<double> sc{s, 1.0, V, hf.width, hf.height, {ku, kv}};
        const Vec2d sp = run_method<double>(method("silhouette_pom"),
                                            params_for(method("silhouette_pom")), sc, hf, {P})[0];
        const Vec2d tj = threejs_silhouette_pom(hf, s, V, P, ku, kv);
        ASSERT_EQ(std::isnan(sp.x), std::isnan(tj.x)) << i;
        if (!std::isnan(tj.x)) {
            EXPECT_NEAR(sp.x, tj.x, 1e-12) << i;
            EXPECT_NEAR(sp.y, tj.y, 1e-12) << i;
        }
        (std::isnan(tj.x) ? discards[0] : kept[0])++;
        // the source clamps |dataz| to at least 0.001: compare where that does not act
        if (0.5 * (ku * V.x * V.x + kv * V.y * V.y) < 0.001) continue;
        const Vec2d cr = run_method<double>(method("curved_relief"),
                                            params_for(method("curved_relief")), sc, hf, {P})[0];
        const Vec2d po = policarpo_curved_relief(hf, s, V, P, ku / 2, kv / 2);
        ASSERT_EQ(std::isnan(cr.x), std::isnan(po.x)) << i;
        if (!std::isnan(po.x)) {
            EXPECT_NEAR(cr.x, po.x, 1e-9) << i;
            EXPECT_NEAR(cr.y, po.y, 1e-9) << i;
        }
        (std::isnan(po.x) ? discards[1] : kept[1])++;
    }
    // both outcomes are exercised
    EXPECT_GT(discards[0], 10);
    EXPECT_GT(kept[0], 100);
    EXPECT_GT(discards[1], 10);
    EXPECT_GT(kept[1], 100);
}

const std::string kHead =
    "samples = 40\ntiming_repeats = 0\nbackends = [\"cpu\", \"glsl\"]\nprecision = \"float\"\n"
    "[views]\ntheta_deg = [0, 40, 70]\nphi_deg = [25]\ncamera = \"perspective\"\n"
    "distance = 2\nfov_deg = 40\n";
const std::string kMethods =
    "[[methods]]\nname = \"pom\"\nlayers = 32\n[[methods]]\nname = \"curved_relief\"\n"
    "[[methods]]\nname = \"silhouette_pom\"\n";

std::string field(const std::string& base) {
    return "[[heightfields]]\nname = \"f\"\ngenerator = \"bricks\"\nsize = 64\nscale = 0.08\n"
           "bias = 1.0\n" +
           base;
}

// On the plane silhouette_pom never discards; curved_relief only where its search ends at the
// relief's floor (the source's "t > tmax" with bricks' mortar at exactly h = 0: the halvings
// end a rounding step past tmax on about half of them). Both land as near the truth as POM, and
// the GLSL twins discard the same pixels as the CPU's: counted in samples_discarded on both
// (docs/conventions.md section 9), never in nonfinite.
TEST(Silhouette, OnThePlaneTheyDiscardNothing) {
    const auto rows = run(kHead + field("") + kMethods);
    std::map<std::tuple<std::string, double, std::string>, double> discarded;
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("method") << ": " << r.text("error");
        const std::string m = r.text("method");
        discarded[{m, r.num("theta_deg"), r.text("backend")}] = r.num("samples_discarded");
        EXPECT_EQ(r.num("nonfinite"), 0) << m << " " << r.text("backend");
        if (m == "silhouette_pom" || m == "pom") {
            EXPECT_EQ(r.num("samples_discarded"), 0) << m << " " << r.text("backend");
        }
        const double inside = 40.0 * 40.0 - r.num("samples_outside");
        EXPECT_LT(r.num("samples_discarded"), 0.05 * inside) << m;
        if (r.num("theta_deg") <= 40) {
            EXPECT_LT(r.num("err_mean"), 0.3) << m << " " << r.text("backend");
        }
    }
    for (const auto& [key, n] : discarded) {
        if (std::get<2>(key) != "glsl") continue;
        EXPECT_EQ(n, discarded.at({std::get<0>(key), std::get<1>(key), "cpu"}))
            << std::get<0>(key) << " theta " << std::get<1>(key);
    }
}

// Discards on a sphere, where both silhouette methods discard many pixels: both twins count
// them alike (samples_discarded equal, nonfinite 0), average their fetches over the same
// answered samples (fetches_mean equal: a discarded fragment's fetches are not known on the GL
// side) and leave the pixels neither answered out of the comparison (cpu_diff_skipped counts
// them; cpu_diff_max finite: no "inf" from two agreeing discards).
TEST(Silhouette, BothTwinsCountDiscardsAlike) {
    const auto rows = run(kHead + field("base = \"sphere\"\nradius = 0.25\n") + kMethods);
    std::map<std::pair<std::string, double>, const ResultRow*> cpu;
    for (const ResultRow& r : rows)
        if (r.text("backend") == "cpu") cpu[{r.text("method"), r.num("theta_deg")}] = &r;
    int compared = 0;
    for (const ResultRow& g : rows) {
        ASSERT_TRUE(g.ok()) << g.text("method") << ": " << g.text("error");
        const std::string m = g.text("method");
        if (g.text("backend") != "glsl" || m == "pom") continue;
        const ResultRow& c = *cpu.at({m, g.num("theta_deg")});
        const std::string at = m + " theta " + std::to_string(g.num("theta_deg"));
        EXPECT_GT(c.num("samples_discarded"), 0) << at;
        EXPECT_EQ(g.num("samples_discarded"), c.num("samples_discarded")) << at;
        EXPECT_EQ(g.num("nonfinite"), 0) << at;
        EXPECT_EQ(c.num("nonfinite"), 0) << at;
        EXPECT_NEAR(g.num("fetches_mean"), c.num("fetches_mean"), 1e-12) << at;
        EXPECT_EQ(g.num("cpu_diff_skipped"), c.num("samples_discarded")) << at;
        EXPECT_TRUE(std::isfinite(g.num("cpu_diff_max"))) << at;
        EXPECT_EQ(g.num("decision_mismatch"), 0) << at;
        ++compared;
    }
    EXPECT_EQ(compared, 6);
}

// On a small sphere with the relief under the base (b = 1): the flat POM shows the base's whole
// outline, background behind it included (cover_extra_frac); both silhouette methods discard
// there and cut that fraction.
TEST(Silhouette, OnASphereTheyCutTheFalseOutline) {
    const auto rows = run(kHead + field("base = \"sphere\"\nradius = 0.25\n") + kMethods);
    std::map<std::pair<std::string, double>, double> extra;
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("method") << ": " << r.text("error");
        if (r.text("backend") != "cpu") continue;
        extra[{r.text("method"), r.num("theta_deg")}] = r.num("cover_extra_frac");
    }
    // curved relief mapping removes most of it; three.js's rule (a ray still above the bent
    // relief by 0.025 s after 48 layers and the chase) less, but never adds any
    for (double th : {0.0, 40.0, 70.0}) {
        const double pom = extra.at({"pom", th});
        EXPECT_GT(pom, 0.02) << th;
        EXPECT_LT(extra.at({"curved_relief", th}), 0.6 * pom) << "theta " << th;
        EXPECT_LT(extra.at({"silhouette_pom", th}), pom) << "theta " << th;
    }
}

// A plug-in shader runs on a curved base as the built-ins do (P, V_ts and the footprint per
// pixel): Welsh's offset limiting written as a plug-in matches parallax_limited's rows.
TEST(Silhouette, APluginRunsOnACurvedBase) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("pxh_curved_plugin_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "limited.frag.glsl")
        << "vec2 pxh_method(vec2 P) { return P + pxh_V.xy * pxh_z(P); }\n";
    const std::string toml =
        "samples = 32\ntiming_repeats = 0\nbackends = [\"glsl\"]\n[views]\ntheta_deg = [50]\n"
        "phi_deg = [25]\ncamera = \"perspective\"\ndistance = 2\nfov_deg = 40\n" +
        field("base = \"cylinder\"\nradius = 0.3\n") +
        "[[methods]]\nname = \"limited\"\nshader = \"limited.frag.glsl\"\nmax_fetches = 1\n"
        "[[methods]]\nname = \"parallax_limited\"\n";
    const auto rows = run_experiment(parse_experiment(toml, (dir / "e.toml").string()), {});
    std::filesystem::remove_all(dir);
    ASSERT_EQ(rows.size(), 2u);
    for (const ResultRow& r : rows) ASSERT_TRUE(r.ok()) << r.text("error");
    EXPECT_GT(rows[0].num("cover_extra_frac"), 0);
    for (const char* c : {"err_mean", "err_max", "cover_extra_frac", "cover_missing_frac"})
        EXPECT_NEAR(rows[0].num(c), rows[1].num(c), 1e-4) << c;
}

}  // namespace
}  // namespace pxh
