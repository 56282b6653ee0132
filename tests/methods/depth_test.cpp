// The depth a method setting writes (docs/conventions.md section 11; methods/depth.h,
// harness/backends/written_depth.cpp, metrics/depth.cpp): closed forms on flat fields, the exact
// method's hit at rounding level on measured fields, every `ray` method's answer on its declared
// search line, the engines' formulas against literal transcriptions of their lines, and the GLSL
// twin's depth target against the CPU's.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/results/pictures.h"
#include "harness/run/runner.h"
#include "harness/run/view_writers.h"
#include "harness/scene/perspective_camera.h"
#include "methods/march/march.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::parse_error;
using test::run;

const std::string kFlat =
    "[[heightfields]]\nname = \"flat\"\ngenerator = \"flat\"\nlevel = 0.25\nwidth = 32\n"
    "height = 32\nscale = 0.08\nbias = 1.0\n";

const char* const kSome[] = {"parallax", "parallax_limited", "steep",    "pom",      "relief",
                             "qdm",      "godot_deep",       "hdrp_pom", "o3de_pom", "o3de_basic",
                             "jme_steep"};

// `engine` only on the engine presets (a method with no engine formula refuses it).
// The rows methods_with("[\"base\", \"hit\", \"engine\"]") gives per view.
int settings_with_engine() {
    int n = 0;
    for (const char* name : kSome) n += find_method(name)->engine_depth ? 3 : 2;
    return n;
}

std::string methods_with(const std::string& depth) {
    std::string m;
    for (const char* name : kSome) {
        std::string d = depth;
        if (!find_method(name)->engine_depth) {
            const size_t at = d.find(", \"engine\"");
            if (at != std::string::npos) d.erase(at, 10);
        }
        m += std::string("[[methods]]\nname = \"") + name + "\"\ndepth = " + d + "\n";
    }
    return m;
}

// On a flat field h = c every method writes, with depth = base, the polygon: its depth error
// is minus the true hit's depth, the distance along the ray from P to z = s (c - b) (times
// -V . f: 1 for parallel rays). A plane strictly above the relief always shows, one below the
// bottom never, in truth and for the method.
TEST(Depth, BaseOnAFlatFieldIsTheRaysDistanceToTheSurface) {
    const double zc = 0.08 * (0.25 - 1.0);
    const auto rows =
        run("samples = 16\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\n"
            "theta_deg = [0, 40, 75]\nphi_deg = [30]\ncut = [0.2, 0.26, 1.5]\n" +
            kFlat + methods_with("\"base\""));
    ASSERT_EQ(rows.size(), std::size(kSome) * 3 * 3);
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        const double t = -zc / std::cos(r.num("theta_deg") * M_PI / 180);
        EXPECT_NEAR(r.num("depth_bias_mean"), -t, 1e-12) << r.text("method");
        EXPECT_NEAR(r.num("depth_err_max"), t, 1e-12) << r.text("method");
        EXPECT_EQ(r.num("depth_toward_frac"), 0) << r.text("method");
        // Base writes the polygon, in front of all the relief: a plane below the surface (c =
        // 0.2) shows in neither; one between the surface and the polygon (0.26) shows in truth
        // and never for the method; one above the polygon (1.5) shows in both.
        EXPECT_EQ(r.num("cut_flip_frac"), r.num("cut") > 0.25 && r.num("cut") < 1 ? 1.0 : 0.0)
            << r.text("method") << " cut " << r.num("cut");
    }
}

// The same through the perspective camera: per pixel t (-V . f), averaged over the inside.
TEST(Depth, BaseOnAFlatFieldThroughThePerspectiveCamera) {
    const double zc = 0.08 * (0.25 - 1.0);
    const auto rows =
        run("samples = 16\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\ntheta_deg = [60]\n"
            "phi_deg = [10]\ncamera = \"perspective\"\ndistance = 1.5\nfov_deg = 60\n" +
            kFlat + "[[methods]]\nname = \"pom\"\n");
    ASSERT_EQ(rows.size(), 1u);
    ASSERT_TRUE(rows[0].ok()) << rows[0].text("error");
    const ParamDict views = ParamDict::parse("distance = 1.5\nfov_deg = 60", "v", "v");
    const auto settings = Camera::settings("perspective", views, "v", 16);
    const View v = Camera::create("perspective", settings[0], {60, 10, 16})->view();
    double sum = 0, n = 0;
    for (size_t k = 0; k < v.size(); ++k) {
        if (!v.is_inside(k)) continue;
        const Vec3d V = v.dir(k), f = v.depth_axis();
        sum += -zc / V.z * -(V.x * f.x + V.y * f.y + V.z * f.z);
        ++n;
    }
    EXPECT_NEAR(rows[0].num("depth_bias_mean"), -sum / n, 1e-12);
}

// maxmip returns the exact hit: with depth = hit, in double, its written depth is the truth's to
// rounding on measured and procedural fields, and the cut planes flip no sample.
TEST(Depth, TheExactMethodsHitIsTheTruthsDepth) {
    const auto rows =
        run("samples = 32\ntiming_repeats = 0\nbackends = [\"cpu\"]\nprecision = \"double\"\n"
            "[views]\ntheta_deg = [20, 60, 80]\nphi_deg = [35]\ncut = [0.25, 0.5, 0.75]\n"
            "[[heightfields]]\nscan = \"luxembourg\"\nscale = 0.05\nbias = 1.0\n"
            "[[heightfields]]\ngenerator = \"bricks\"\nsize = 64\nscale = 0.05\nbias = 1.0\n"
            "[[methods]]\nname = \"maxmip\"\ndepth = \"hit\"\n");
    ASSERT_EQ(rows.size(), 2u * 3 * 3);
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        EXPECT_LT(r.num("depth_err_max"), 1e-9) << r.text("heightfield") << r.num("theta_deg");
        EXPECT_EQ(r.num("cut_flip_frac"), 0) << r.text("heightfield") << r.num("theta_deg");
    }
}

// Every registered method with a C++ twin (no skip list: resources built, every engine preset)
// hands back the height z_m of its own answer (docs/conventions.md section 8): a search's point
// (uv_m, z_m) lies on its own line uv = P + d z (hit_direction, else V.xy / V.z), checked in uv
// so that nothing is divided by tan(theta) (at theta = 0 uv_m = P whatever z_m); a single-step
// method's z_m is the surface's at uv_m. Float and double, theta 0, 1e-4, 30 and 80 degrees.
TEST(Depth, EveryMethodWritesAPointOfItsOwnRay) {
    const HeightField hf = test::random_field(32, 32, 7);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    int searches = 0, single = 0;
    for (const MethodInfo& m : all_methods()) {
        if (!m.run_double) continue;  // a plug-in: pxh_write_hit, tested on the GL side
        const ParamValues p = test::params_for(m);
        const double b = std::isnan(m.required_bias) ? 1.0 : m.required_bias;
        const bool ray = m.hit_height_of(p) == HitHeight::ray;
        for (double theta : {0.0, 1e-4, 30.0, 80.0}) {
            const Scene<double> sc = test::make_scene(hf, 0.06, b, theta, 360 * u(rng));
            const std::vector<Vec2d> P = test::random_points(48, 5);
            for (int prec = 0; prec < 2; ++prec) {
                std::vector<double> z;
                const std::vector<Vec2d> uv =
                    prec ? test::run_method<double>(m, p, sc, hf, P, nullptr, nullptr, &z)
                         : test::run_method<float>(m, p, sc, hf, P, nullptr, nullptr, &z);
                const Vec2d d =
                    m.hit_direction ? m.hit_direction(p, sc.V, sc.scale) : eye_ray_direction(sc.V);
                // float: P is rounded to float, the line followed in float (a few steps of |uv|)
                const double tol = prec ? 1e-9 : 2e-5;
                for (size_t k = 0; k < P.size(); ++k) {
                    const std::string at = m.name + (prec ? " double" : " float") + " theta " +
                                           std::to_string(theta) + " sample " + std::to_string(k);
                    if (!std::isfinite(uv[k].x)) {
                        EXPECT_TRUE(m.may_discard) << at;
                        EXPECT_TRUE(std::isnan(z[k])) << at;
                        continue;
                    }
                    ASSERT_TRUE(std::isfinite(z[k])) << at;
                    if (ray) {
                        const Vec2d Pk = prec ? P[k] : Vec2d(Vec2<float>(P[k]));
                        const double scale = 1 + std::abs(z[k]) * std::hypot(d.x, d.y);
                        EXPECT_NEAR(uv[k].x, Pk.x + d.x * z[k], tol * scale) << at;
                        EXPECT_NEAR(uv[k].y, Pk.y + d.y * z[k], tol * scale) << at;
                    } else {
                        HeightSampler<double> hs(hf, sc.scale, sc.bias);
                        EXPECT_NEAR(z[k], hs.z(uv[k]), prec ? 1e-12 : 1e-6) << at;
                    }
                }
            }
        }
        ++(ray ? searches : single);
    }
    EXPECT_GE(searches, 30);
    EXPECT_GE(single, 5);
}

// Steep at theta = 0 writes its layer height (not the surface's): on a flat field at h = 0.3,
// s 0.08, b 1 the surface is at -0.056 and 32 layers of 0.0025 stop at layer 23, -0.0575, so
// every sample's depth is 0.0015 tiles behind the truth; pom interpolates to the surface itself.
// (Before z_m was handed back, every one of these wrote the surface here: 0 for all.)
// A flat field at h = 0.3 (s 0.08, b 1) seen head-on, CPU float and double; `views` adds to
// [views], `methods` are the entries.
std::vector<ResultRow> run_flat_head_on(const std::string& views, const std::string& methods) {
    return run(
        "samples = 16\ntiming_repeats = 0\nbackends = [\"cpu\"]\n"
        "precision = [\"float\", \"double\"]\n[views]\ntheta_deg = [0]\nphi_deg = [0]\n" +
        views +
        "[[heightfields]]\nname = \"flat\"\ngenerator = \"flat\"\nlevel = 0.3\n"
        "width = 32\nheight = 32\nscale = 0.08\nbias = 1.0\n" +
        methods);
}

TEST(Depth, SteepAtTheNormalWritesItsLayer) {
    const std::vector<ResultRow> rows =
        run_flat_head_on("",
                         "[[methods]]\nname = \"steep\"\ndepth = \"hit\"\n"
                         "[[methods]]\nname = \"pom\"\ndepth = \"hit\"\n"
                         "[[methods]]\nname = \"o3de_steep\"\ndepth = [\"hit\", \"engine\"]\n");
    ASSERT_EQ(rows.size(), 8u);
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        // O3DE's steep (quality Low: 16 layers of 0.005) stops at layer 12, -0.06: 0.004 behind;
        // its engine writes that marched depth (CalcPixelDepthOffset), at the normal too
        const std::string m = r.text("method");
        const double want = m == "steep" ? 0.0015 : m == "o3de_steep" ? 0.004 : 0.0;
        EXPECT_NEAR(r.num("depth_err_mean"), want, 2e-8) << m << " " << r.text("depth");
        EXPECT_NEAR(r.num("depth_bias_mean"), want, 2e-8) << m << " " << r.text("depth");
    }
}

// Cut ties (docs/conventions.md section 8): steep at theta = 0 on the flat field above writes
// layer 23, h = 1 - 23 / 32 = 0.28125 in height-map units; a cut there is its layer height, so
// every sample ties (cut_tie_frac 1, no flip fraction: nothing decides); a cut at 0.29 lies
// between the truth (h 0.3) and the layer: the plane shows for the method only, every sample
// flips, none ties.
TEST(Depth, CutAtALayerHeightTies) {
    const std::vector<ResultRow> rows = run_flat_head_on(
        "cut = [0.28125, 0.29]\n", "[[methods]]\nname = \"steep\"\nlayers = 32\ndepth = \"hit\"\n");
    ASSERT_EQ(rows.size(), 4u);
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        if (r.num("cut") < 0.285) {
            EXPECT_EQ(r.num("cut_tie_frac"), 1.0) << r.text("precision");
            EXPECT_TRUE(std::isnan(r.num("cut_flip_frac"))) << r.text("precision");
        } else {
            EXPECT_EQ(r.num("cut_tie_frac"), 0.0) << r.text("precision");
            EXPECT_EQ(r.num("cut_flip_frac"), 1.0) << r.text("precision");
        }
    }
}

// The engines' lines, transcribed: HDRP LitDataDisplacement.hlsl 193-194 and Common.hlsl
// 1268 (needle-mirror/com.unity.render-pipelines.high-definition @ a645acdd,
// com.unity.render-pipelines.core @ 0088895f); O3DE ParallaxMapping.azsli 171, 188, 284-286,
// CalcPixelDepthOffset 445-450 (o3de/o3de @ 354a2acc), here with an orthographic viewProj
// (depth along f).
TEST(Depth, EngineFormulasMatchTheirLines) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 200; ++i) {
        const double theta = 80 * u(rng), phi = 360 * u(rng), s = 0.02 + 0.1 * u(rng);
        const Vec3d V = view_vector(theta, phi);
        const Vec3d f = {-V.x + 0.1 * u(rng), -V.y, -V.z};  // any depth axis
        const Vec2d P{u(rng), u(rng)};
        const double h = u(rng);  // the last probe's height
        EngineDepthInput in{P, V, f, {0, 0}, 0, s * (h - 1), s, 1.0};
        // HDRP: verticalDisplacement = maxHeight - height * maxHeight; depthOffset =
        // verticalDisplacement / max(NdotV, 0.0001); positionWS += depthOffset * (-V).
        const double maxHeight = s, height = h;
        const double verticalDisplacement = maxHeight - height * maxHeight;
        const double depthOffset = verticalDisplacement / std::max(V.z, 0.0001);
        const Vec3d pos{P.x - depthOffset * V.x, P.y - depthOffset * V.y, -depthOffset * V.z};
        MarchConfig c;
        c.depth_offset = MarchConfig::PdoHdrp;
        const double hdrp = (pos.x - P.x) * f.x + (pos.y - P.y) * f.y + pos.z * f.z;
        EXPECT_NEAR(march_engine_depth(c, in), hdrp, 1e-12);
        // O3DE (POM): parallaxOffset = -dirToCameraTS.xyz * (1 / V.z) * depth at the marched
        // depth; zeroed where its z > 0; worldOffsetPosition = posWS + offset.
        const double marched = s * (2 * u(rng) - 0.2);  // some searches end above (< 0)
        Vec3d off{-V.x / V.z * marched, -V.y / V.z * marched, -V.z / V.z * marched};
        if (off.z > 0) off = {0, 0, 0};
        in.uv = {P.x - V.x / V.z * marched, P.y - V.y / V.z * marched};
        in.z_line = -marched;
        c.depth_offset = MarchConfig::PdoO3de;
        c.search = MarchConfig::Layers;
        EXPECT_NEAR(march_engine_depth(c, in), off.x * f.x + off.y * f.y + off.z * f.z, 1e-12);
    }
}

// The GLSL twin writes gl_FragDepth into a 32-bit float target; read back, it is the CPU float
// twin's depth within 1e-4 tile, in every mode, through both cameras.
TEST(Depth, GlslDepthTargetIsTheCpuTwinsDepth) {
    for (const std::string& cam :
         {std::string(""), std::string("camera = \"perspective\"\ndistance = 2\nfov_deg = 50\n")}) {
        const auto rows = run(
            "samples = 24\ntiming_repeats = 0\nbackends = [\"cpu\", \"glsl\"]\n"
            "[views]\ntheta_deg = [0, 50, 80]\nphi_deg = [20]\n" +
            cam + "[[heightfields]]\ngenerator = \"fbm\"\nsize = 64\nscale = 0.05\nbias = 1.0\n" +
            methods_with("[\"base\", \"hit\", \"engine\"]") +
            "[[methods]]\nname = \"march\"\ndepth_offset = [\"unreal_legacy\", "
            "\"unreal_camera\"]\ndepth = \"engine\"\n");
        int glsl = 0;
        for (const ResultRow& r : rows) {
            ASSERT_TRUE(r.ok()) << r.text("method") << ": " << r.text("error");
            if (r.text("backend") != "glsl") continue;
            ++glsl;
            EXPECT_LE(r.num("depth_cpu_diff_p999"), 1e-4)
                << r.text("method") << " " << r.text("depth") << " theta " << r.num("theta_deg");
        }
        EXPECT_EQ(glsl, settings_with_engine() * 3 + 2 * 3);
    }
}

// On a curved base each pixel has its own depth axis in its tangent frame (View::axes): the GLSL
// twin reads it from a per-pixel map and writes the C++ twin's depth.
TEST(Depth, GlslDepthOnACurvedBaseIsTheCpuTwins) {
    const auto rows = run(
        "samples = 24\ntiming_repeats = 0\nbackends = [\"cpu\", \"glsl\"]\n"
        "[views]\ntheta_deg = [30, 70]\nphi_deg = [20]\ncamera = \"perspective\"\ndistance = 2\n"
        "fov_deg = 40\ncut = 0.5\n[[heightfields]]\ngenerator = \"fbm\"\nsize = 64\nscale = 0.05\n"
        "bias = 1.0\nbase = \"sphere\"\nradius = 0.4\n" +
        methods_with("[\"base\", \"hit\", \"engine\"]"));
    int glsl = 0;
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("method") << ": " << r.text("error");
        EXPECT_FALSE(std::isnan(r.num("depth_err_mean"))) << r.text("method");
        EXPECT_FALSE(std::isnan(r.num("cut_flip_frac"))) << r.text("method");
        if (r.text("backend") != "glsl") continue;
        ++glsl;
        EXPECT_LE(r.num("depth_cpu_diff_p999"), 1e-4)
            << r.text("method") << " " << r.text("depth") << " theta " << r.num("theta_deg");
    }
    EXPECT_EQ(glsl, settings_with_engine() * 2);
}

// A plug-in writes its hit through pxh_write_hit(z) (methods/common.glsl): returning P and
// writing z = -0.02, its depth along the ray (-V) is 0.02 V.z: its bias differs from the same
// shader's without the call (which writes the polygon, as base) by exactly that, up to float.
TEST(Depth, PluginWritesItsHitThroughPxhWriteHit) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("pxh_depth_plugin_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const char* const body = "vec2 pxh_method(vec2 P) {\n    pxh_height(P);\n%s    return P;\n}\n";
    char with[256], without[256];
    std::snprintf(with, sizeof with, body, "    pxh_write_hit(-0.02);\n");
    std::snprintf(without, sizeof without, body, "");
    std::ofstream(dir / "with.frag.glsl") << with;
    std::ofstream(dir / "without.frag.glsl") << without;
    const std::string toml =
        "samples = 8\ntiming_repeats = 0\nbackends = [\"glsl\"]\n[views]\ntheta_deg = [50]\n"
        "phi_deg = [15]\n" +
        kFlat +
        "[[methods]]\nname = \"with\"\nshader = \"with.frag.glsl\"\nmax_fetches = 1\n"
        "depth = \"hit\"\n[[methods]]\nname = \"without\"\nshader = \"without.frag.glsl\"\n"
        "max_fetches = 1\ndepth = \"hit\"\n";
    const auto rows = run_experiment(parse_experiment(toml, (dir / "e.toml").string()), {});
    std::filesystem::remove_all(dir);
    ASSERT_EQ(rows.size(), 2u);
    ASSERT_TRUE(rows[0].ok() && rows[1].ok()) << rows[0].text("error") << rows[1].text("error");
    const double vz = std::cos(50 * M_PI / 180);
    EXPECT_NEAR(rows[0].num("depth_bias_mean") - rows[1].num("depth_bias_mean"), 0.02 * vz, 1e-6);
    EXPECT_NEAR(rows[1].num("depth_bias_mean"), -0.08 * 0.75 / vz, 1e-6);  // the polygon's
}

// A written depth the GL target cannot hold is counted, never clamped into a number
// (docs/conventions.md section 8): z = 10 or 1e30 lies far beyond the span (depth_clamped, scored
// with the value written: depth_err_mean about z cos 50 deg); 1 / 0 and 0 / 0 are not finite
// (depth_nonfinite, not scored, no depth statistics at all). Before, the target's clamp made 2.13
// of the first three and a finite number of NaN.
TEST(Depth, HostileWrittenDepthsAreCountedNotClamped) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("pxh_depth_hostile_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    // zero at run time (not folded by the compiler)
    const char* const writes[] = {"10.0", "1e30", "1.0 / zero", "zero / zero"};
    for (int i = 0; i < 4; ++i) {
        const std::string name = "w" + std::to_string(i);
        std::ofstream(dir / (name + ".frag.glsl"))
            << "vec2 pxh_method(vec2 P) {\n    float zero = pxh_height(P) * 0.0;\n"
            << "    pxh_write_hit(" << writes[i] << ");\n    return P;\n}\n";
    }
    std::string toml =
        "samples = 8\ntiming_repeats = 0\nbackends = [\"glsl\"]\n[views]\ntheta_deg = [50]\n"
        "phi_deg = [15]\n" +
        kFlat;
    for (int i = 0; i < 4; ++i) {
        const std::string name = "w" + std::to_string(i);
        toml += "[[methods]]\nname = \"" + name + "\"\nshader = \"" + name +
                ".frag.glsl\"\nmax_fetches = 1\ndepth = \"hit\"\n";
    }
    const auto rows = run_experiment(parse_experiment(toml, (dir / "e.toml").string()), {});
    std::filesystem::remove_all(dir);
    ASSERT_EQ(rows.size(), 4u);
    const double vz = std::cos(50 * M_PI / 180);
    for (int i = 0; i < 4; ++i) {
        const ResultRow& r = rows[size_t(i)];
        ASSERT_TRUE(r.ok()) << r.text("error");
        if (i < 2) {
            EXPECT_EQ(r.num("depth_clamped"), 64) << writes[i];
            EXPECT_EQ(r.num("depth_nonfinite"), 0) << writes[i];
            const double z = i == 0 ? 10.0 : 1e30;
            EXPECT_NEAR(r.num("depth_err_mean") / (z * vz), 1.0, 0.03) << writes[i];
        } else {
            EXPECT_EQ(r.num("depth_nonfinite"), 64) << writes[i];
            EXPECT_EQ(r.num("depth_clamped"), 0) << writes[i];
            EXPECT_TRUE(std::isnan(r.num("depth_err_mean"))) << writes[i];
        }
    }
}

// [render] with a cut: the pictures pxh run writes show the plane (the flat kPlaneRgb) where the
// depth test puts it in front. Counted from the PNG files, the pixels where the method's picture
// and the truth's differ in showing the plane are exactly cut_flip_frac of the inside pixels.
TEST(Depth, CutPicturesShowThePlaneWhereTheDepthTestDoes) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("pxh_depth_pictures_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const Experiment ex = parse_experiment(
        "samples = 48\ntiming_repeats = 0\nbackends = [\"cpu\"]\nprecision = \"double\"\n"
        "[views]\ntheta_deg = [70]\nphi_deg = [30]\ncamera = \"perspective\"\ndistance = 1.5\n"
        "fov_deg = 40\ncut = [0.3, 0.6]\n[render]\nheightfields = [\"bricks\"]\n"
        "theta_deg = [70]\n[[heightfields]]\ngenerator = \"bricks\"\nsize = 64\nscale = 0.08\n"
        "bias = 1.0\n[[methods]]\nname = \"parallax\"\ndepth = [\"base\", \"hit\"]\n"
        "[[methods]]\nname = \"pom\"\nlayers = 8\ndepth = \"hit\"\n",
        "e.toml");
    RunOptions opt;
    opt.on_view = view_writers_into(ex, dir);
    const auto rows = run_experiment(ex, opt);
    ASSERT_EQ(rows.size(), 6u);  // 3 settings x 2 cuts
    auto blue = [&](const std::string& rel) {
        OIIO::ImageBuf img((dir / rel).string());
        EXPECT_TRUE(img.read(0, 0, true, OIIO::TypeDesc::UINT8)) << rel;
        std::vector<uint8_t> px(size_t(48) * 48 * 3), out(size_t(48) * 48);
        img.get_pixels(img.roi(), OIIO::TypeDesc::UINT8, px.data());
        for (size_t k = 0; k < out.size(); ++k) {
            bool b = true;
            for (size_t c = 0; c < 3; ++c)
                b = b && px[3 * k + c] == uint8_t(std::lround(kPlaneRgb[c] * 255));
            out[k] = b;
        }
        return out;
    };
    double flips_seen = 0;
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        ASSERT_FALSE(r.text("picture").empty());
        EXPECT_NE(r.text("picture_truth").find("_cut"), std::string::npos);
        const auto truth = blue(r.text("picture_truth")), method = blue(r.text("picture"));
        double differ = 0, truth_blue = 0;
        for (size_t k = 0; k < truth.size(); ++k) {
            differ += truth[k] != method[k];
            truth_blue += truth[k];
        }
        const double inside = 48.0 * 48.0 - r.num("samples_outside");
        EXPECT_EQ(differ, std::round(r.num("cut_flip_frac") * inside))
            << r.text("method") << " " << r.text("depth") << " cut " << r.num("cut");
        EXPECT_GT(truth_blue, 0) << "cut " << r.num("cut");  // the plane shows somewhere
        flips_seen += differ;
    }
    EXPECT_GT(flips_seen, 0);  // base hides the plane where the truth shows it
    std::filesystem::remove_all(dir);
}

TEST(Depth, BadDepthAndCutAreRefused) {
    const std::string base =
        "samples = 8\nbackends = [\"cpu\"]\n[views]\ntheta_deg = [0]\n" + kFlat;
    EXPECT_EQ(parse_error(base + "[[methods]]\nname = \"pom\"\ndepth = \"deep\"\n"),
              "e.toml:15: unknown depth 'deep' (known: base, hit, engine)");
    EXPECT_EQ(parse_error(base + "[[methods]]\nname = \"pom\"\ndepth = [\"hit\", \"engine\"]\n"),
              "e.toml:15: depth 'engine' needs an engine preset: method 'pom' has no engine "
              "formula (use base or hit)");
    EXPECT_EQ(parse_error(base + "[[methods]]\nname = \"pom\"\ndepth = [\"hit\", \"hit\"]\n"),
              "e.toml:15: depth 'hit' is given twice");
    std::string twice = base;
    twice.replace(twice.find("theta_deg = [0]"), 15, "theta_deg = [0]\ncut = [0.5, 0.5]");
    EXPECT_EQ(parse_error(twice + "[[methods]]\nname = \"pom\"\n"),
              "e.toml:5: cut 0.5 is given twice");
}

}  // namespace
}  // namespace pxh
