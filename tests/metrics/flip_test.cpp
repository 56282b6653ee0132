// LDR-FLIP (harness/metrics/flip.h): zero on identical images; a flat colour against another
// equal to the paper's formulas worked by hand (in double, here); the authors' values on the
// pairs of flip_pairs.h.
//
// The authors' values: NVlabs/flip at commit 1eb247cabcf2862c2c8207ab15314304394132b9 (version
// 1.6), its src/cpp/FLIP.h, built with g++ 12 -std=c++17 -O2 -march=x86-64-v2 (no OpenMP) into a
// driver (kept outside pxh, like scripts/flip_bench_authors.cpp) that fills a
// FLIP::image<FLIP::color3> from each pair's bytes (color3(const unsigned char*), i.e. / 255),
// calls sRGBToLinearRGB() on both (as the authors' tool does after loading a PNG) and
// FLIP::evaluate(reference, test, false, parameters, errorMap) with parameters.PPD = 67.02f;
// the mean is the map's mean in double, the pixels the map's values. Cross-checked with the
// authors' own tool on the pairs written as PNG: `flip -r REF.png -t TEST.png -ppd 67.02`
// printed Mean 0.273859 / 0.003360 / 0.143162 / 0.142443 and Max 0.968360 / 0.378682 /
// 0.272755 / 0.628552 (edge, point, ramp, checker). pxh's maps were bit-identical to the
// driver's on all four pairs when recorded.
#include "harness/metrics/flip.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <random>

#include "tests/metrics/flip_pairs.h"

namespace {

constexpr double kStep = 1.0 / 255;  // the 8-bit step: the tolerance of a pixel's value

std::vector<uint8_t> random_bytes(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(0, 255);
    std::vector<uint8_t> v(n);
    for (auto& x : v) x = uint8_t(d(rng));
    return v;
}

TEST(Flip, IdenticalImagesGiveZeroEverywhere) {
    const int w = 37, h = 23;
    const auto im = random_bytes(size_t(3 * w * h), 7);
    std::vector<float> map;
    const auto r = pxh::flip_ldr(im, im, w, h, pxh::kFlipDefaultPpd, nullptr, &map);
    ASSERT_EQ(map.size(), size_t(w * h));
    for (float v : map) ASSERT_EQ(v, 0.0f);
    EXPECT_EQ(r.mean, 0.0);
    EXPECT_EQ(r.p95, 0.0);
    EXPECT_EQ(r.max, 0.0);
    EXPECT_EQ(r.counted, long(w * h));
}

// --- The paper's colour pipeline by hand, in double (Andersson et al. 2020, section 4.1). ----
struct C3 {
    double x, y, z;
};
double lin(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
// Linear sRGB (D65) to XYZ, then CIELab against the D65 white, then the Hunt adjustment.
C3 lab_hunt(C3 rgb) {
    const C3 xyz{(10135552.0 * rgb.x + 8788810.0 * rgb.y + 4435075.0 * rgb.z) / 24577794.0,
                 (2613072.0 * rgb.x + 8788810.0 * rgb.y + 887015.0 * rgb.z) / 12288897.0,
                 (1425312.0 * rgb.x + 8788810.0 * rgb.y + 70074185.0 * rgb.z) / 73733382.0};
    const double d = 6.0 / 29;
    auto f = [&](double t) { return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29; };
    const double fx = f(xyz.x / 0.950428545), fy = f(xyz.y), fz = f(xyz.z / 1.088900371);
    const double L = 116 * fy - 16, a = 500 * (fx - fy), b = 200 * (fy - fz);
    return {L, 0.01 * L * a, 0.01 * L * b};
}
double hyab(C3 p, C3 q) { return std::abs(p.x - q.x) + std::hypot(p.y - q.y, p.z - q.z); }

// FLIP of two flat colours (8-bit sRGB): the filters (each normalised) leave a flat image as it
// is and the feature filters see no edge and no point, so FLIP is the remapped colour
// difference: e = HyAB(Hunt(Lab(A)), Hunt(Lab(B)))^q_c, q_c = 0.7; c_max the same of pure
// green and pure blue; e p_t / (p_c c_max) below p_c c_max, else p_t + (e - p_c c_max) /
// (c_max - p_c c_max) (1 - p_t), p_c = 0.4, p_t = 0.95.
double flat_by_hand(C3 a8, C3 b8) {
    const C3 a = lab_hunt({lin(a8.x / 255), lin(a8.y / 255), lin(a8.z / 255)});
    const C3 b = lab_hunt({lin(b8.x / 255), lin(b8.y / 255), lin(b8.z / 255)});
    const double cmax = std::pow(hyab(lab_hunt({0, 1, 0}), lab_hunt({0, 0, 1})), 0.7);
    const double pc = 0.4 * cmax, e = std::pow(hyab(a, b), 0.7);
    return e < pc ? e * 0.95 / pc : 0.95 + (e - pc) / (cmax - pc) * 0.05;
}

double flat_flip(C3 a8, C3 b8, std::vector<float>* map) {
    const int w = 30, h = 20;
    std::vector<uint8_t> a(size_t(3 * w * h)), b(a.size());
    for (size_t i = 0; i < a.size(); i += 3) {
        a[i] = uint8_t(a8.x), a[i + 1] = uint8_t(a8.y), a[i + 2] = uint8_t(a8.z);
        b[i] = uint8_t(b8.x), b[i + 1] = uint8_t(b8.y), b[i + 2] = uint8_t(b8.z);
    }
    return pxh::flip_ldr(a, b, w, h, pxh::kFlipDefaultPpd, nullptr, map).mean;
}

TEST(Flip, FlatColoursEqualTheColourTermByHand) {
    // A small difference (below p_c c_max), black against white (above it), a chromatic one.
    const C3 pairs[][2] = {{{200, 120, 60}, {190, 130, 70}},
                           {{0, 0, 0}, {255, 255, 255}},
                           {{40, 160, 40}, {40, 40, 200}}};
    // The one thing the hand value leaves out: the derivative filters' weights sum to +1 and -1
    // only to float rounding, so on a flat image they leave an edge of order 1e-7, which the
    // feature term's square root (q_f = 0.5) turns into f of order 1e-4; FLIP = colour^(1 - f)
    // is then the colour term raised a little (colour < 1). So: FLIP within 1e-5 of the hand
    // value, or above it by at most what f <= 1e-3 gives (the authors' float code alike).
    for (const auto& p : pairs) {
        const double hand = flat_by_hand(p[0], p[1]);
        const double tol = 1e-5 + hand * std::abs(std::log(hand)) * 1e-3;
        std::vector<float> map;
        const double flip = flat_flip(p[0], p[1], &map);
        EXPECT_GE(flip, hand - 1e-5);
        EXPECT_NEAR(flip, hand, tol);
        for (float v : map) ASSERT_NEAR(v, hand, tol);  // the same everywhere, borders too
    }
    EXPECT_NEAR(pxh::flip_cmax(), std::pow(hyab(lab_hunt({0, 1, 0}), lab_hunt({0, 0, 1})), 0.7),
                1e-4);
    EXPECT_LT(flat_by_hand({200, 120, 60}, {190, 130, 70}), 0.95);  // the lower branch
    EXPECT_GT(flat_by_hand({0, 0, 0}, {255, 255, 255}), 0.95);      // the upper branch
}

// --- The authors' values (see the head of this file for how they were made). ---------------
struct Px {
    int x, y;
    float v;
};
void expect_authors(const flip_pairs::Pair& p, double mean, double max, std::vector<Px> px) {
    SCOPED_TRACE(p.name);
    std::vector<float> map;
    const auto r = pxh::flip_ldr(p.reference, p.test, p.w, p.h, 67.02, nullptr, &map);
    EXPECT_NEAR(r.mean, mean, 1e-4);
    EXPECT_NEAR(r.max, max, kStep);
    for (const Px& q : px)
        EXPECT_NEAR(map[size_t(q.y) * size_t(p.w) + size_t(q.x)], q.v, kStep)
            << "pixel (" << q.x << ", " << q.y << ")";
}

TEST(Flip, AuthorsValuesOnAnEdge) {
    expect_authors(flip_pairs::edge(), 0.2738613, 0.9683600,
                   {{31, 24, 0.895599f},
                    {32, 24, 0.968360f},
                    {33, 24, 0.846772f},
                    {34, 24, 0.693508f},
                    {10, 24, 0.000000f},
                    {60, 24, 0.413599f},
                    {32, 0, 0.968360f}});
}

TEST(Flip, AuthorsValuesOnAPoint) {
    expect_authors(flip_pairs::point(), 0.0033601, 0.3786823,
                   {{20, 15, 0.378682f},
                    {21, 15, 0.293298f},
                    {20, 17, 0.126409f},
                    {25, 20, 0.000000f},
                    {0, 0, 0.000000f}});
}

TEST(Flip, AuthorsValuesOnARamp) {
    expect_authors(flip_pairs::ramp(), 0.1431617, 0.2727545,
                   {{0, 12, 0.176722f},
                    {15, 12, 0.007254f},
                    {16, 12, 0.099283f},
                    {40, 12, 0.154436f},
                    {79, 0, 0.272755f}});
}

TEST(Flip, AuthorsValuesOnACheckerboardShiftedAPixel) {
    expect_authors(flip_pairs::checker_shift(), 0.1424432, 0.6285522,
                   {{0, 0, 0.628552f},
                    {4, 8, 0.145558f},
                    {5, 8, 0.111828f},
                    {23, 20, 0.104217f},
                    {44, 36, 0.313522f},
                    {43, 36, 0.218855f},
                    {44, 35, 0.263522f}});
}

// --- Pooling, encodings, threads, errors. ----------------------------------------------------
TEST(Flip, MaskCountsOnlyItsPixels) {
    const auto p = flip_pairs::edge();
    std::vector<float> map;
    const auto all = pxh::flip_ldr(p.reference, p.test, p.w, p.h, 67.02, nullptr, &map);
    std::vector<uint8_t> mask(map.size(), 0);
    double sum = 0, mx = 0;
    long n = 0;
    for (int y = 0; y < p.h; ++y)
        for (int x = 40; x < p.w; ++x) {  // the light side only
            const size_t i = size_t(y) * size_t(p.w) + size_t(x);
            mask[i] = 1, sum += map[i], mx = std::max(mx, double(map[i])), ++n;
        }
    const auto r = pxh::flip_ldr(p.reference, p.test, p.w, p.h, 67.02, &mask);
    EXPECT_EQ(r.counted, n);
    EXPECT_NEAR(r.mean, sum / double(n), 1e-12);
    EXPECT_EQ(r.max, mx);
    EXPECT_LE(r.p95, r.max);
    EXPECT_NE(r.mean, all.mean);
    const std::vector<uint8_t> none(map.size(), 0);
    const auto empty = pxh::flip_ldr(p.reference, p.test, p.w, p.h, 67.02, &none);
    EXPECT_EQ(empty.counted, 0);
    EXPECT_TRUE(std::isnan(empty.mean) && std::isnan(empty.p95) && std::isnan(empty.max));
}

TEST(Flip, LinearInputMatchesItsSrgbEncoding) {
    const auto p = flip_pairs::checker_shift();
    std::vector<float> sa(p.reference.size()), sb(sa.size()), la(sa.size()), lb(sa.size());
    for (size_t i = 0; i < sa.size(); ++i) {
        sa[i] = float(p.reference[i]) / 255.0f, sb[i] = float(p.test[i]) / 255.0f;
        const auto l = [](double c) {
            return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        };
        la[i] = float(l(sa[i])), lb[i] = float(l(sb[i]));
    }
    using pxh::FlipEncoding;
    const auto s =
        pxh::flip_ldr({sa, p.w, p.h, FlipEncoding::srgb}, {sb, p.w, p.h, FlipEncoding::srgb});
    const auto l =
        pxh::flip_ldr({la, p.w, p.h, FlipEncoding::linear}, {lb, p.w, p.h, FlipEncoding::linear});
    EXPECT_NEAR(s.mean, l.mean, 1e-5);
    EXPECT_NEAR(s.max, l.max, 1e-4);
}

TEST(Flip, SameMapForAnyThreadCount) {
    const auto p = flip_pairs::bench512();
    std::vector<float> one, many;
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
        pxh::flip_ldr(p.reference, p.test, p.w, p.h, 67.02, nullptr, &one);
    }
    pxh::flip_ldr(p.reference, p.test, p.w, p.h, 67.02, nullptr, &many);
    ASSERT_EQ(one.size(), many.size());
    for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], many[i]) << i;
}

// The colour map: entries of BIDS/colormap's _magma_data (CC0) worked by hand, entry
// int(v 255 + 0.5), each channel round(255 c). pxh's magma images of the five pairs of
// flip_pairs.h were byte-identical to the PNGs the authors' tool wrote (flip -r REF.png
// -t TEST.png -ppd 67.02) when this was recorded.
TEST(Flip, MagmaColourMap) {
    using A = std::array<uint8_t, 3>;
    EXPECT_EQ(pxh::flip_magma(0.0f), (A{0, 0, 4}));       // entry 0: 0.001462 0.000466 0.013866
    EXPECT_EQ(pxh::flip_magma(0.5f), (A{183, 55, 121}));  // entry 128: 0.716387 0.214982 0.475290
    EXPECT_EQ(pxh::flip_magma(0.96836f), (A{252, 238, 176}));  // entry 247
    EXPECT_EQ(pxh::flip_magma(1.0f), (A{252, 253, 191}));  // entry 255: 0.987053 0.991438 0.749504
    EXPECT_EQ(pxh::flip_magma(2.0f), pxh::flip_magma(1.0f));
    EXPECT_EQ(pxh::flip_magma(-1.0f), pxh::flip_magma(0.0f));
    EXPECT_EQ(pxh::flip_magma(NAN), pxh::flip_magma(0.0f));
    const auto img = pxh::flip_magma_image({0.0f, 1.0f});
    EXPECT_EQ(img, (std::vector<uint8_t>{0, 0, 4, 252, 253, 191}));
}

TEST(Flip, RejectsMismatchedInput) {
    const std::vector<uint8_t> a(3 * 4 * 4, 0), b(3 * 4 * 5, 0);
    EXPECT_THROW(pxh::flip_ldr(a, b, 4, 4), std::invalid_argument);
    EXPECT_THROW(pxh::flip_ldr(a, a, 0, 0), std::invalid_argument);
    EXPECT_THROW(pxh::flip_ldr(a, a, 4, 4, 0.0), std::invalid_argument);
    EXPECT_THROW(pxh::flip_ldr(a, a, 4, 4, NAN), std::invalid_argument);
    EXPECT_THROW(pxh::flip_ldr(a, a, 4, 4, 0.5), std::invalid_argument);  // feature filters vanish
    EXPECT_TRUE(std::isfinite(pxh::flip_ldr(a, a, 4, 4, 2.0).mean));
    const std::vector<uint8_t> mask(3);
    EXPECT_THROW(pxh::flip_ldr(a, a, 4, 4, 67.02, &mask), std::invalid_argument);
    // A 1 x 1 image: the filters are clamped to its one pixel.
    const std::vector<uint8_t> p{10, 20, 30}, q{200, 100, 50};
    EXPECT_GT(pxh::flip_ldr(p, q, 1, 1).mean, 0.0);
}

}  // namespace
