#include "harness/metrics/image_metrics.h"

#include <array>
#include <cmath>

#include "harness/metrics/column_groups.h"
#include "harness/metrics/flip.h"

namespace pxh {

double psnr_db(const std::vector<float>& a, const std::vector<float>& b) {
    if (a.empty() || a.size() != b.size()) return NAN;
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        const double d = double(a[i]) - double(b[i]);
        sum += d * d;
    }
    const double mse = sum / double(a.size());
    return mse == 0 ? INFINITY : 10 * std::log10(1 / mse);
}

std::vector<double> luma(const std::vector<float>& rgb) {
    std::vector<double> y(rgb.size() / 3);
    for (size_t i = 0; i < y.size(); ++i)
        y[i] = 0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2];
    return y;
}

namespace {

constexpr int kWin = 11;

// The normalised 1-D Gaussian (sigma 1.5): the 2-D window is its outer product.
std::array<double, kWin> gaussian() {
    std::array<double, kWin> g{};
    double sum = 0;
    for (int i = 0; i < kWin; ++i) {
        const double d = i - kWin / 2;
        g[size_t(i)] = std::exp(-d * d / (2 * 1.5 * 1.5));
        sum += g[size_t(i)];
    }
    for (double& v : g) v /= sum;
    return g;
}

// 'valid' filtering by the separable window: (w - 10) x (h - 10) outputs.
std::vector<double> filter_valid(const std::vector<double>& img, int w, int h) {
    static const std::array<double, kWin> g = gaussian();
    const int ow = w - kWin + 1, oh = h - kWin + 1;
    std::vector<double> rows(size_t(ow) * size_t(h)), out(size_t(ow) * size_t(oh));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < ow; ++i) {
            double s = 0;
            for (int k = 0; k < kWin; ++k) s += g[size_t(k)] * img[size_t(j) * w + size_t(i + k)];
            rows[size_t(j) * ow + size_t(i)] = s;
        }
    for (int j = 0; j < oh; ++j)
        for (int i = 0; i < ow; ++i) {
            double s = 0;
            for (int k = 0; k < kWin; ++k) s += g[size_t(k)] * rows[size_t(j + k) * ow + size_t(i)];
            out[size_t(j) * ow + size_t(i)] = s;
        }
    return out;
}

}  // namespace

double ssim(const std::vector<double>& x, const std::vector<double>& y, int w, int h) {
    if (w < kWin || h < kWin || x.size() != size_t(w) * size_t(h) || y.size() != x.size())
        return NAN;
    const double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
    std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    const auto mx = filter_valid(x, w, h), my = filter_valid(y, w, h);
    const auto sxx = filter_valid(xx, w, h), syy = filter_valid(yy, w, h),
               sxy = filter_valid(xy, w, h);
    double sum = 0;
    for (size_t i = 0; i < mx.size(); ++i) {
        const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i],
                     cxy = sxy[i] - mx[i] * my[i];
        sum += (2 * mx[i] * my[i] + C1) * (2 * cxy + C2) /
               ((mx[i] * mx[i] + my[i] * my[i] + C1) * (vx + vy + C2));
    }
    return sum / double(mx.size());
}

void add_psnr(const ImageMetricInput& in, ResultRow& row) {
    row.set("img_psnr_db", psnr_db(in.picture, in.truth));
}

void add_ssim(const ImageMetricInput& in, ResultRow& row) {
    row.set("img_ssim", ssim(luma(in.picture), luma(in.truth), in.n, in.n));
}

const std::vector<ImageMetric>& image_metrics() {
    static const std::vector<ImageMetric> metrics = {
        {"psnr", &add_psnr},
        {"ssim", &add_ssim},
    };
    return metrics;
}

void apply_image_metrics(const ImageMetricInput& in, ResultRow& row) {
    for (const ImageMetric& m : image_metrics()) m.add(in, row);
}

void add_flip(const FlipInput& in, ResultRow& row, std::vector<float>* map) {
    const FlipResult f = flip_ldr({in.truth, in.n, in.n, FlipEncoding::srgb},
                                  {in.shaded, in.n, in.n, FlipEncoding::srgb}, in.ppd,
                                  in.mask.empty() ? nullptr : &in.mask, map);
    row.set("flip_mean", f.counted ? f.mean : NAN);
    row.set("flip_p95", f.counted ? f.p95 : NAN);
    row.set("flip_max", f.counted ? f.max : NAN);
}

// The [render] pictures' image quality.
// Declared here, by the code that fills them; harness/metrics/columns.cpp places them in
// results.csv's order.
std::vector<ColumnSpec> image_columns() {
    using namespace column_decl;
    return {
        ColumnSpec{"img_psnr_db", kNum, kMeasured,
                   "[render]: PSNR of its picture vs the truth's (dB; inf: =)"}
            .in("image", "dB", Better::larger)
            .lead(),
        ColumnSpec{"img_ssim", kNum, kMeasured,
                   "[render]: mean SSIM (Wang et al. 2004) of the pictures"}
            .in("image", "", Better::larger)
            .lead(),
        // [shading]: what a viewer sees (docs/conventions.md section 13)
        ColumnSpec{"flip_mean", kNum, kMeasured,
                   "[shading]: mean LDR-FLIP of its shaded image vs the truth's (0: alike)"}
            .in("image", "FLIP")
            .lead(),
        ColumnSpec{"flip_p95", kNum, kMeasured,
                   "[shading]: 95th-percentile LDR-FLIP over the covered pixels"}
            .in("image", "FLIP")
            .lead(),
        ColumnSpec{"flip_max", kNum, kMeasured,
                   "[shading]: largest LDR-FLIP over the covered pixels"}
            .in("image", "FLIP"),
    };
}

}  // namespace pxh
