// The shading of docs/conventions.md section 13.1: a flat field shades the method's and the
// truth's images alike wherever their uv agree (the normal is the tangent frame's up, A times
// k_a + k_d L.z), the gradient on a field that is linear along u, and the GLSL twin's images
// within one 8-bit step of the CPU twin's on a field with relief, across levels.
#include "harness/scene/shading.h"

#include <gtest/gtest.h>

#include <cmath>

#include "harness/backends/shade_gl.h"
#include "harness/gl/context.h"
#include "harness/results/pictures.h"

namespace pxh {
namespace {

HeightField flat(int n, float h) {
    HeightField f(n, n);
    std::fill(f.texels.begin(), f.texels.end(), h);
    return f;
}

// A relief with edges and slopes: bricks-like plateaus and a ramp.
HeightField relief(int n) {
    HeightField f(n, n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const bool groove = (i % 16) < 2 || (j % 8) < 1;
            f.at(i, j) = groove ? 0.1f : 0.6f + 0.3f * float(std::sin(0.2 * i + 0.1 * j));
        }
    return f;
}

struct World {
    TextureLevels heights;
    AlbedoLevels albedo;
    Material material;
    World(const HeightField& f, double s, int albedo_size)
        : heights(build_texture_levels(f)),
          albedo(build_albedo_levels(checker_albedo(albedo_size))) {
        material = {&heights, &albedo, s, light_direction(45, 135),
                    std::log2(double(albedo_size) / f.width)};
    }
};

TEST(Shading, FlatFieldMethodAndTruthAgreeWhereTheirUvAgree) {
    const World w(flat(32, 0.7f), 0.2, 128);
    const int n = 24;
    std::vector<Vec2d> truth(n * n), method(n * n);
    std::vector<double> lambda(n * n);
    for (int k = 0; k < n * n; ++k) {
        truth[size_t(k)] = {0.05 + 0.037 * (k % n), 0.11 + 0.029 * (k / n)};
        // every third pixel of the method's points elsewhere (a quarter tile off)
        method[size_t(k)] = truth[size_t(k)] + Vec2d{k % 3 == 0 ? 0.25 : 0.0, 0.0};
        lambda[size_t(k)] = -1 + 0.01 * k;
    }
    const auto a = shaded_image(w.material, truth, lambda, {});
    const auto b = shaded_image(w.material, method, lambda, {});
    int differ_where_apart = 0;
    for (int k = 0; k < n * n; ++k) {
        for (int c = 0; c < 3; ++c) {
            const size_t i = size_t(3 * k + c);
            if (k % 3 != 0) {
                EXPECT_EQ(a[i], b[i]) << "pixel " << k;
            }
            differ_where_apart += k % 3 == 0 && a[i] != b[i];
        }
        // flat: n = (0, 0, 1), so the light is k_a + k_d sin(45 degrees) on the albedo
        const auto lin = shade_linear(w.material, truth[size_t(k)], lambda[size_t(k)]);
        const double la = lambda[size_t(k)] + w.material.albedo_lod;
        for (size_t c = 0; c < 3; ++c)
            EXPECT_NEAR(lin[c],
                        level_fetch(w.albedo.channel[c], truth[size_t(k)], la) *
                            (0.2 + 0.8 * std::sqrt(0.5)),
                        1e-6);
    }
    EXPECT_GT(differ_where_apart, 0);  // the test's shifted pixels do show another colour
}

TEST(Shading, GradientOfALinearRampAndTheUncoveredBackground) {
    HeightField f(64, 64);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) f.at(i, j) = 0.2f + 0.01f * float(i);  // dh/du = 0.64/tile
    const TextureLevels tl = build_texture_levels(f);
    // Away from the wrap seam every level's central difference is the ramp's slope.
    const Vec2d g = height_gradient(tl, {0.5, 0.5}, 0.0), g2 = height_gradient(tl, {0.5, 0.5}, 2.5);
    EXPECT_NEAR(g.x, 0.64, 1e-5);
    EXPECT_NEAR(g.y, 0.0, 1e-6);
    EXPECT_NEAR(g2.x, 0.64, 1e-4);
    const World w(f, 0.1, 64);
    const auto img =
        shaded_image(w.material, {{0.5, 0.5}, {NAN, 0.5}, {0.5, 0.5}}, {0, 0, 0}, {1, 1, 0});
    for (size_t i = 3; i < 9; ++i) EXPECT_EQ(img[i], kShadeBackground) << i;
}

TEST(ShadingGl, GlslTwinWithinOne8BitStepOfTheCpuTwin) {
    std::unique_ptr<GlContext> ctx;
    try {
        ctx = make_gl_context("osmesa");
    } catch (const std::exception& e) {
        GTEST_SKIP() << "no GL context: " << e.what();
    }
    const World w(relief(128), 0.08, 256);
    const int n = 96;
    std::vector<Vec2d> uv(n * n);
    std::vector<double> lambda(n * n);
    std::vector<uint8_t> covered(n * n, 1);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const size_t k = size_t(j * n + i);
            // a perspective-like mapping: rows further away cover more of the tile
            const double depth = 1 + 3.0 * j / n;
            uv[k] = {0.13 + (i - n / 2) * 0.004 * depth, 0.37 + 0.6 * std::pow(double(j) / n, 1.5)};
            // levels 0 .. 6 blended, differing between neighbouring pixels (a level that
            // differs within a SIMD group once gave llvmpipe's textureSize another's size)
            lambda[k] = -0.5 + 6.0 * j / n + 0.3 * std::sin(0.1 * i);
            covered[k] = (i * 7 + j * 3) % 23 != 0;
        }
    auto cpu = shaded_image(w.material, uv, lambda, covered);
    quantize_8bit(cpu);
    const auto gl = shade_gl(*ctx, {w.material, uv, lambda, covered, n});
    ASSERT_EQ(gl.size(), cpu.size());
    double worst = 0;
    long equal = 0;
    long over = 0;
    for (size_t i = 0; i < cpu.size(); ++i) {
        const double d = std::fabs(double(gl[i]) - double(cpu[i])) * 255;
        worst = std::max(worst, d);
        equal += gl[i] == cpu[i];
        if (d > 1.5 && over++ < 8)
            ADD_FAILURE() << "pixel " << i / 3 << " channel " << i % 3 << ": GL " << gl[i] * 255
                          << " CPU " << cpu[i] * 255 << " uv " << uv[i / 3].x << " " << uv[i / 3].y
                          << " lambda " << lambda[i / 3];
    }
    EXPECT_LE(worst, 1.0 + 1e-6);
    EXPECT_GT(double(equal) / double(cpu.size()), 0.9);  // most values identical
    std::printf("GLSL vs CPU shading: largest difference %.0f 8-bit step(s), %.2f%% equal\n", worst,
                100.0 * double(equal) / double(cpu.size()));
}

}  // namespace
}  // namespace pxh
