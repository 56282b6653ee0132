// PSNR and SSIM (harness/metrics/image_metrics.h) against closed forms and an independent,
// direct transcription of Wang et al.'s ssim_index.m (2-D window sums, no separable filter);
// the albedo of the pictures (harness/results/pictures.h) against its definition.
#include "harness/metrics/image_metrics.h"

#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "harness/results/pictures.h"

namespace {

std::vector<double> random_image(int w, int h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(0, 1);
    std::vector<double> v(size_t(w) * size_t(h));
    for (auto& x : v) x = d(rng);
    return v;
}

// ssim_index.m (Wang 2004), written out directly: window = fspecial('gaussian', 11, 1.5)
// (2-D, normalised over the 121 weights); for every valid window position the weighted
// means, variances and covariance; the SSIM map's mean.
double ssim_direct(const std::vector<double>& x, const std::vector<double>& y, int w, int h) {
    double win[11][11], total = 0;
    for (int a = 0; a < 11; ++a)
        for (int b = 0; b < 11; ++b)
            total += win[a][b] = std::exp(-((a - 5) * (a - 5) + (b - 5) * (b - 5)) / 4.5);
    const double C1 = 1e-4, C2 = 9e-4;
    double sum = 0;
    int count = 0;
    for (int j = 0; j + 11 <= h; ++j)
        for (int i = 0; i + 11 <= w; ++i) {
            double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
            for (int a = 0; a < 11; ++a)
                for (int b = 0; b < 11; ++b) {
                    const double g = win[a][b] / total;
                    const double p = x[size_t(j + a) * w + size_t(i + b)];
                    const double q = y[size_t(j + a) * w + size_t(i + b)];
                    mx += g * p, my += g * q, xx += g * p * p, yy += g * q * q, xy += g * p * q;
                }
            const double vx = xx - mx * mx, vy = yy - my * my, c = xy - mx * my;
            sum += (2 * mx * my + C1) * (2 * c + C2) / ((mx * mx + my * my + C1) * (vx + vy + C2));
            ++count;
        }
    return sum / count;
}

TEST(ImageMetrics, PsnrClosedForms) {
    const std::vector<float> zero(300, 0.0f), tenth(300, 0.1f);
    EXPECT_NEAR(pxh::psnr_db(zero, tenth), 20.0, 1e-5);  // MSE 0.01
    std::vector<float> half = zero;
    for (size_t i = 0; i < half.size(); i += 2) half[i] = 1;  // MSE 0.5: 10 log10 2
    EXPECT_NEAR(pxh::psnr_db(zero, half), 10 * std::log10(2.0), 1e-12);
    EXPECT_EQ(pxh::psnr_db(half, half), INFINITY);
    EXPECT_TRUE(std::isnan(pxh::psnr_db(zero, std::vector<float>(3, 0.0f))));
}

TEST(ImageMetrics, SsimClosedForms) {
    const int w = 23, h = 17;
    const auto x = random_image(w, h, 1);
    EXPECT_NEAR(pxh::ssim(x, x, w, h), 1.0, 1e-12);
    // Constant images a, b: no variance, so each window gives (2ab + C1) / (a^2 + b^2 + C1).
    const double a = 0.3, b = 0.7, C1 = 1e-4;
    const std::vector<double> ca(size_t(w) * h, a), cb(size_t(w) * h, b);
    EXPECT_NEAR(pxh::ssim(ca, cb, w, h), (2 * a * b + C1) / (a * a + b * b + C1), 1e-12);
    // A constant image against one with structure: luminance term times C2 / (var + C2) per
    // window, which the direct transcription computes; symmetric in its arguments.
    const auto y = random_image(w, h, 2);
    EXPECT_NEAR(pxh::ssim(x, y, w, h), pxh::ssim(y, x, w, h), 1e-12);
    // Images below the window are not measured.
    EXPECT_TRUE(std::isnan(pxh::ssim(random_image(10, 30, 3), random_image(10, 30, 4), 10, 30)));
}

TEST(ImageMetrics, SsimMatchesTheDirectTranscription) {
    const int w = 31, h = 26;
    const auto x = random_image(w, h, 5), noise = random_image(w, h, 6);
    std::vector<double> y(x.size()), z(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        y[i] = 0.8 * x[i] + 0.2 * noise[i];  // related: SSIM well inside (0, 1)
        z[i] = 0.5;
    }
    using Pair = std::pair<const std::vector<double>*, const std::vector<double>*>;
    for (const Pair& pq : {Pair{&x, &y}, Pair{&x, &noise}, Pair{&z, &x}}) {
        const double want = ssim_direct(*pq.first, *pq.second, w, h);
        EXPECT_NEAR(pxh::ssim(*pq.first, *pq.second, w, h), want, 1e-12) << want;
    }
    EXPECT_GT(pxh::ssim(x, y, w, h), 0.5);
    EXPECT_LT(pxh::ssim(x, noise, w, h), 0.2);
}

TEST(ImageMetrics, LumaIsBt601) {
    const auto y = pxh::luma({1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
    ASSERT_EQ(y.size(), 4u);
    EXPECT_NEAR(y[0], 0.299, 1e-7);
    EXPECT_NEAR(y[1], 0.587, 1e-7);
    EXPECT_NEAR(y[2], 0.114, 1e-7);
    EXPECT_NEAR(y[3], 1.0, 1e-6);
}

// The albedo repeats every tile, numbers its 8 x 8 cells, and the picture through a method's uv
// rebuilt from the truth's and the wrapped texel errors is the picture through that uv.
TEST(Pictures, AlbedoTilesAndUvFromErrors) {
    float a[3], b[3];
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-3, 3);
    for (int k = 0; k < 200; ++k) {
        const pxh::Vec2d uv{d(rng), d(rng)};
        pxh::albedo(uv, a);
        pxh::albedo({uv.x + 2, uv.y - 1}, b);
        EXPECT_EQ(std::vector<float>(a, a + 3), std::vector<float>(b, b + 3))
            << uv.x << "," << uv.y;
    }
    // Cell 27 (row 3, column 3): its two digits' strokes are ink, in the cell's ink colour;
    // the cell's border is the dark line.
    pxh::albedo({(3 + 0.5 / 11 + 0.5 * 0.08) / 8, (3 + 3.5 / 11) / 8}, a);  // left margin
    pxh::albedo({(3 + 2.5 / 11) / 8, (3 + 3.5 / 11) / 8}, b);  // top-left of the '2': ink
    EXPECT_NE(std::vector<float>(a, a + 3), std::vector<float>(b, b + 3));
    EXPECT_TRUE((b[0] == 0 && b[1] == 0 && b[2] == 0) || (b[0] == 1 && b[1] == 1 && b[2] == 1));
    pxh::albedo({(3 + 0.01) / 8, (3 + 0.5) / 8}, a);
    EXPECT_FLOAT_EQ(a[0], 0.1f);
    pxh::albedo({NAN, 0.5}, a);
    EXPECT_EQ(std::vector<float>(a, a + 3), (std::vector<float>{1, 0, 1}));
    // uv_from_errors: truth + wrapped error / size is the method's uv modulo a tile.
    const int n = 16, W = 64, H = 32;
    std::vector<pxh::Vec2d> truth, method, errors;
    for (int k = 0; k < n * n; ++k) {
        truth.push_back({d(rng), d(rng)});
        method.push_back({truth.back().x + d(rng) * 0.1 + 1, truth.back().y - d(rng) * 0.1});
        double ex = method.back().x - truth.back().x, ey = method.back().y - truth.back().y;
        ex -= std::round(ex), ey -= std::round(ey);  // wrapped into a tile, as texel_error
        errors.push_back({ex * W, ey * H});
    }
    const auto rebuilt = pxh::uv_from_errors(truth, errors, W, H);
    const auto p = pxh::picture(rebuilt, n), q = pxh::picture(method, n);
    size_t differ = 0;
    for (size_t i = 0; i < p.size(); ++i) differ += p[i] != q[i];
    EXPECT_LE(differ, 3u);  // a sample exactly on a cell edge may round the other way
    EXPECT_EQ(pxh::psnr_db(pxh::picture(truth, n), pxh::picture(truth, n)), INFINITY);
}

}  // namespace

// A camera's picture: outside pixels neutral grey whatever their uv; written as the viewer sees
// it, pixel row 0 (the bottom, as gl_FragCoord) is the file's last row.
TEST(Pictures, OutsideIsGreyAndCameraPicturesAreUpright) {
    const int n = 4;
    std::vector<pxh::Vec2d> uv(n * n);
    for (int k = 0; k < n * n; ++k) uv[k] = {(k % n + 0.5) / n, (k / n + 0.5) / n};
    std::vector<uint8_t> inside(n * n, 1);
    inside[13] = 0;
    const auto masked = pxh::picture(uv, n, inside), plain = pxh::picture(uv, n);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(masked[3 * 13 + c], 0.5f);
    for (int k = 0; k < n * n; ++k) {
        if (k == 13) continue;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(masked[3 * k + c], plain[3 * k + c]) << k;
    }
    std::vector<float> rgb(n * n * 3, 0.0f);
    for (int c = 0; c < 3; ++c) rgb[c] = 1.0f;  // pixel (0, 0) white, the rest black
    const std::string dir = ::testing::TempDir() + "/pxh_pictures_upright";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    pxh::write_picture(rgb, n, dir + "/seen.png", true);
    pxh::write_picture(rgb, n, dir + "/texture.png", false);
    for (const auto& [file, row] : {std::pair{"seen.png", n - 1}, std::pair{"texture.png", 0}}) {
        OIIO::ImageBuf img(dir + "/" + file);
        float px[3];
        img.getpixel(0, row, px);
        EXPECT_EQ(px[0], 1.0f) << file;
        img.getpixel(0, n - 1 - row, px);
        EXPECT_EQ(px[0], 0.0f) << file;
    }
    std::filesystem::remove_all(dir);
}
