// Every registered method that declares precomputed textures (methods/resource.h), automatically
// (a new method is covered without editing this file):
// - its resources are the same bytes built with one thread and with eight (odd field sizes, so
//   uneven splits and odd pyramid levels are exercised), and so are the method's results;
// - they wrap: level 0 built from the field shifted cyclically by (dx, dy) texels is level 0 of
//   the unshifted field shifted by the same amount (for a level stacked from several field-sized
//   blocks, such as an atlas of slices, each block shifted), so a tiling field stays tiling;
// - building them at (s, b) depends on s and b only when the resource says so.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "tests/test_util.h"

namespace pxh {
namespace {

class EveryResourceMethod : public ::testing::TestWithParam<std::string> {
  protected:
    const MethodInfo& m() const { return test::method(GetParam()); }
};

// Every level of every resource of the method, built now with `threads` threads.
std::vector<ResourceLevel> build_all(const MethodInfo& m, const HeightField& hf, double s, double b,
                                     int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    std::vector<ResourceLevel> out;
    for (const ResourceSpec& spec : m.resources) {
        const BuiltResource r = build_resource(spec, hf, s, b);
        for (const ResourceLevel& lv : r.image->levels) out.push_back(lv);
    }
    return out;
}

bool same_bytes(const ResourceLevel& a, const ResourceLevel& b) {
    return a.width == b.width && a.height == b.height && a.texels.size() == b.texels.size() &&
           std::memcmp(a.texels.data(), b.texels.data(), a.texels.size() * sizeof(float)) == 0;
}

TEST_P(EveryResourceMethod, SameBytesAndResultsForOneAndEightThreads) {
    const HeightField hf = test::random_field(37, 29, 71);
    const auto one = build_all(m(), hf, 0.08, 0.7, 1), many = build_all(m(), hf, 0.08, 0.7, 8);
    ASSERT_EQ(one.size(), many.size());
    for (size_t k = 0; k < one.size(); ++k) EXPECT_TRUE(same_bytes(one[k], many[k])) << k;

    const ParamValues p = test::params_for(m());
    const auto sc = test::make_scene(hf, 0.08, 0.7, 60, 25);
    const auto P = test::random_points(200, 5);
    auto results = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        std::vector<int> f;
        auto uv = test::run_method<double>(m(), p, sc, hf, P, &f);
        return std::make_pair(uv, f);
    };
    const auto r1 = results(1), r8 = results(8);
    for (size_t i = 0; i < P.size(); ++i) {
        EXPECT_EQ(r1.first[i].x, r8.first[i].x) << i;
        EXPECT_EQ(r1.first[i].y, r8.first[i].y) << i;
        EXPECT_EQ(r1.second[i], r8.second[i]) << i;
    }
}

// A cyclic shift of the field by (dx, dy) texels.
HeightField shifted(const HeightField& hf, int dx, int dy) {
    HeightField out = hf;
    for (int j = 0; j < hf.height; ++j)
        for (int i = 0; i < hf.width; ++i)
            out.texels[size_t(j) * size_t(hf.width) + size_t(i)] =
                hf.at((i - dx + hf.width) % hf.width, (j - dy + hf.height) % hf.height);
    return out;
}

TEST_P(EveryResourceMethod, Level0WrapsWithTheField) {
    const HeightField hf = test::random_field(24, 20, 72);
    const int dx = 5, dy = 7;
    for (const ResourceSpec& spec : m().resources) {
        const BuiltResource a = build_resource(spec, hf, 0.1, 1.0);
        const BuiltResource b = build_resource(spec, shifted(hf, dx, dy), 0.1, 1.0);
        const ResourceLevel &la = a.image->levels[0], &lb = b.image->levels[0];
        ASSERT_EQ(la.width, lb.width);
        ASSERT_EQ(la.height, lb.height);
        if (la.width % hf.width != 0 || la.height % hf.height != 0) {
            ADD_FAILURE() << m().name << " " << spec.name << ": level 0 is " << la.width << " x "
                          << la.height << ", not made of " << hf.width << " x " << hf.height
                          << " blocks";
            continue;
        }
        const int ch = channels(spec.format);
        int differ = 0;
        for (int j = 0; j < la.height; ++j)
            for (int i = 0; i < la.width; ++i) {
                // Texel (i, j) lies in block (bi, bj); within it the shift moves it.
                const int bi = i / hf.width * hf.width, bj = j / hf.height * hf.height;
                const int si = bi + (i - bi + dx) % hf.width, sj = bj + (j - bj + dy) % hf.height;
                for (int c = 0; c < ch; ++c)
                    differ += la.texels[(size_t(j) * la.width + i) * ch + c] !=
                              lb.texels[(size_t(sj) * lb.width + si) * ch + c];
            }
        EXPECT_EQ(differ, 0) << m().name << " " << spec.name << ": level 0 does not wrap";
    }
}

TEST_P(EveryResourceMethod, DependsOnScaleAndBiasOnlyWhenDeclared) {
    const HeightField hf = test::random_field(16, 16, 73);
    for (const ResourceSpec& spec : m().resources) {
        if (spec.depends_on_scale_bias) continue;  // built per (s, b): nothing to check
        const BuiltResource a = build_resource(spec, hf, 0.05, 1.0);
        const BuiltResource b = build_resource(spec, hf, 0.3, 0.25);
        ASSERT_EQ(a.image->levels.size(), b.image->levels.size());
        for (size_t k = 0; k < a.image->levels.size(); ++k)
            EXPECT_TRUE(same_bytes(a.image->levels[k], b.image->levels[k]))
                << m().name << " " << spec.name << " level " << k
                << " changes with s and b but does not declare depends_on_scale_bias";
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryResourceMethod,
                         ::testing::ValuesIn(test::method_names([](const MethodInfo& m) {
                             return !m.resources.empty();
                         })),
                         test::MethodName());

}  // namespace
}  // namespace pxh
