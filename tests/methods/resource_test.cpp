// Method resources (methods/resource.h): the CPU sampler against GLSL textureLod semantics on
// hand-made textures, the checks on what a builder returns, the cache (built once per field,
// per (s, b) only when declared), the pyramid reduction, and sizes.
#include "methods/resource.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>

#include "tests/test_util.h"

namespace pxh {
namespace {

// A 4 x 2 single-channel texture with texel (i, j) = 10 j + i.
ResourceImage grid4x2() {
    ResourceLevel lv{4, 2, {}};
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) lv.texels.push_back(float(10 * j + i));
    return {{lv}};
}

TEST(ResourceSampler, NearestRepeatAndClamp) {
    const ResourceImage img = grid4x2();
    ResourceSpec rep{"r_t", TexelFormat::R32F, TexFilter::Nearest, TexWrap::Repeat};
    ResourceSpec clamp{"r_t", TexelFormat::R32F, TexFilter::Nearest, TexWrap::Clamp};
    TextureSampler<double> a(rep, img), b(clamp, img);
    EXPECT_EQ(a.fetch_r({0.30, 0.70}), 11);   // texel (1, 1)
    EXPECT_EQ(a.fetch_r({1.30, -0.30}), 11);  // wrapped both ways
    EXPECT_EQ(a.fetch_r({-0.01, 0.2}), 3);    // i = -1 -> 3
    EXPECT_EQ(b.fetch_r({-0.01, 0.2}), 0);    // clamped to 0
    EXPECT_EQ(b.fetch_r({1.7, 1.2}), 13);     // clamped to (3, 1)
    const auto t = a.fetch({0.1, 0.1});
    EXPECT_EQ(t[1], 0);  // r32f reads as (r, 0, 0, 1)
    EXPECT_EQ(t[3], 1);
    EXPECT_EQ(a.fetches, 4);
    EXPECT_EQ(b.fetches, 2);
}

TEST(ResourceSampler, LinearBlendsTheFourTexelsAroundTheSample) {
    const ResourceImage img = grid4x2();
    ResourceSpec rep{"r_t", TexelFormat::R32F, TexFilter::Linear, TexWrap::Repeat};
    ResourceSpec clamp{"r_t", TexelFormat::R32F, TexFilter::Linear, TexWrap::Clamp};
    TextureSampler<double> a(rep, img), b(clamp, img);
    // Texel centres at ((i + 0.5) / 4, (j + 0.5) / 2): midway between (1, 0) and (2, 1).
    EXPECT_DOUBLE_EQ(a.fetch_r({0.5, 0.5}), (1 + 2 + 11 + 12) / 4.0);
    // u = 0: halfway between texel 3 (wrapped) and 0 in repeat; clamped: texel 0.
    EXPECT_DOUBLE_EQ(a.fetch_r({0.0, 0.25}), 1.5);
    EXPECT_DOUBLE_EQ(b.fetch_r({0.0, 0.25}), 0.0);
    // v = 1: between rows 1 and 0 (repeat), row 1 only (clamp).
    EXPECT_DOUBLE_EQ(a.fetch_r({0.125, 1.0}), 5.0);
    EXPECT_DOUBLE_EQ(b.fetch_r({0.125, 1.0}), 10.0);
}

TEST(ResourceSampler, RgbaChannelsAndLevels) {
    ResourceImage img;
    img.levels.push_back({2, 2, {}});
    for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 4; ++c) img.levels[0].texels.push_back(float(10 * k + c));
    img.levels.push_back({1, 1, {100, 101, 102, 103}});
    ResourceSpec s{"r_t", TexelFormat::RGBA32F, TexFilter::Nearest, TexWrap::Repeat};
    TextureSampler<float> t(s, img);
    EXPECT_EQ(t.fetch({0.75, 0.25})[2], 12.0f);      // texel 1, channel b
    EXPECT_EQ(t.fetch({0.75, 0.25}, 1)[3], 103.0f);  // level 1
    EXPECT_EQ(t.fetch({0.75, 0.25}, 7)[0], 100.0f);  // beyond the last level: the last
    EXPECT_EQ(t.fetch({0.75, 0.75}, -1)[0], 30.0f);  // below 0: level 0
}

TEST(ResourcePyramid, MaxReductionCoversOddSizes) {
    ResourceLevel base{5, 3, {}};
    for (int k = 0; k < 15; ++k) base.texels.push_back(float(k == 14 ? 99 : k));  // (4, 2) largest
    const ResourceImage img = reduce_pyramid(base, [](float a, float b) { return std::max(a, b); });
    ASSERT_EQ(img.levels.size(), 3u);  // 5x3, 2x1, 1x1
    EXPECT_EQ(img.levels[1].width, 2);
    EXPECT_EQ(img.levels[1].height, 1);
    // Level 1 texel 0 covers columns 0..1, rows 0..2; texel 1 columns 2..4 (the odd one).
    EXPECT_EQ(img.levels[1].texels[0], 11.0f);
    EXPECT_EQ(img.levels[1].texels[1], 99.0f);
    EXPECT_EQ(img.levels[2].texels[0], 99.0f);
}

std::atomic<int> g_builds{0};
ResourceImage count_and_fill(const HeightField& hf, double s, double b) {
    ++g_builds;
    ResourceLevel lv{hf.width, hf.height, {}};
    for (float h : hf.texels) lv.texels.push_back(float(s * (h - b)));
    return {{lv}};
}

TEST(ResourceCache, BuiltOncePerFieldAndPerScaleBiasOnlyWhenDeclared) {
    const HeightField hf = test::random_field(8, 4, 5);
    const std::vector<ResourceSpec> specs = {
        {"r_once", TexelFormat::R32F, TexFilter::Nearest, TexWrap::Repeat, false, count_and_fill},
        {"r_per_sb", TexelFormat::R32F, TexFilter::Nearest, TexWrap::Repeat, true, count_and_fill}};
    ResourceCache cache(hf);
    g_builds = 0;
    const MethodResources a = cache.get("m", specs, 0.05, 1.0);
    const MethodResources b = cache.get("m", specs, 0.05, 1.0);  // another view
    EXPECT_EQ(g_builds, 2);
    EXPECT_EQ(a.items[0].image, b.items[0].image);  // shared, not copied
    const MethodResources c = cache.get("m", specs, 0.10, 1.0);
    EXPECT_EQ(g_builds, 3);  // only r_per_sb again
    EXPECT_EQ(cache.builds(), 3);
    EXPECT_EQ(c.items[0].image, a.items[0].image);
    EXPECT_NE(c.items[1].image, a.items[1].image);
    EXPECT_EQ(c.items[1].image->levels[0].texels[3], float(0.10 * (hf.texels[3] - 1.0)));
    // Sizes: 8 x 4 floats each.
    EXPECT_EQ(a.aux_bytes(), 2u * 8 * 4 * 4);
    EXPECT_GE(a.precompute_ms(), 0.0);
}

ResourceImage bad_levels(const HeightField&, double, double) {
    return {
        {ResourceLevel{4, 4, std::vector<float>(16)}, ResourceLevel{3, 2, std::vector<float>(6)}}};
}
ResourceImage bad_count(const HeightField&, double, double) {
    return {{ResourceLevel{4, 4, std::vector<float>(15)}}};
}
ResourceImage non_finite(const HeightField&, double, double) {
    return {{ResourceLevel{1, 1, {NAN}}}};
}

TEST(ResourceCache, WhatABuilderReturnsIsChecked) {
    const HeightField hf = test::flat_field(4, 4, 0.5f);
    auto problem = [&](ResourceImage (*build)(const HeightField&, double, double)) {
        try {
            build_resource(
                {"r_x", TexelFormat::R32F, TexFilter::Nearest, TexWrap::Repeat, false, build}, hf,
                1, 0);
        } catch (const std::logic_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(problem(bad_levels), "resource 'r_x': level 1 is 3 x 2, a mip chain needs 2 x 2");
    EXPECT_EQ(problem(bad_count),
              "resource 'r_x': level 0 holds 15 floats, not width x height x 1");
    EXPECT_EQ(problem(non_finite), "resource 'r_x': level 0 has a non-finite texel");
}

}  // namespace
}  // namespace pxh
