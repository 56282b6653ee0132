// Image-space comparison of a method's picture with the truth's picture (harness/results/
// pictures.h), so that pxh's numbers can be set beside the image-based comparisons of the
// literature. Images are linear RGB floats in [0, 1], row-major, 3 per pixel.
//
// Registered like the per-output metrics (metric.h): image_metrics() lists them, and the
// pictures writer (harness/run/view_writers.cpp) applies each to every row of a [render] view.
// A new one: a function `void add_NAME(const ImageMetricInput&, ResultRow&)`, its columns in
// columns.cpp, one line in image_metrics() (image_metrics.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "harness/metrics/row.h"

namespace pxh {

// Peak signal-to-noise ratio, peak 1: 10 log10(1 / MSE), the MSE over every pixel and channel.
// +inf for identical images; NaN for images of different sizes or empty ones.
double psnr_db(const std::vector<float>& a, const std::vector<float>& b);

// Luma of an RGB image: Y = 0.299 R + 0.587 G + 0.114 B (ITU-R BT.601, as MATLAB's rgb2gray,
// which the SSIM reference code is run on).
std::vector<double> luma(const std::vector<float>& rgb);

// Mean SSIM (Wang, Bovik, Sheikh, Simoncelli, "Image quality assessment: from error
// visibility to structural similarity", IEEE TIP 13(4):600-612, 2004, doi:10.1109/TIP.2003.819861)
// of two w x h single-channel images with values in [0, 1] (L = 1): an 11 x 11 circular-symmetric
// Gaussian window, sigma 1.5, normalised to sum 1; K1 = 0.01, K2 = 0.03 (C1 = (K1 L)^2,
// C2 = (K2 L)^2); the SSIM map over every window that lies wholly inside the image ('valid',
// as the authors' ssim_index.m), and its mean. No down-sampling (the authors' later ssim.m
// scales images above 256 px down first; pxh's pictures are compared at full size). NaN when
// w or h is below 11 or the sizes do not match.
double ssim(const std::vector<double>& x, const std::vector<double>& y, int w, int h);

// A row's picture of its view beside the truth's (n x n, linear RGB floats).
struct ImageMetricInput {
    const std::vector<float>& picture;
    const std::vector<float>& truth;
    int n = 0;
};
struct ImageMetric {
    const char* name;
    void (*add)(const ImageMetricInput&, ResultRow&);
};
void add_psnr(const ImageMetricInput& in, ResultRow& row);  // img_psnr_db
void add_ssim(const ImageMetricInput& in, ResultRow& row);  // img_ssim (on luma)
const std::vector<ImageMetric>& image_metrics();            // psnr, ssim
void apply_image_metrics(const ImageMetricInput& in, ResultRow& row);

// [shading]: LDR-FLIP (flip.h) of a row's shaded image against the truth's (n x n, sRGB values
// in [0, 1]) at `ppd`, counted over the pixels `mask` marks (either side covers them): the
// columns flip_mean, flip_p95, flip_max (NaN when the mask counts none). `map`, when given,
// receives the per-pixel FLIP.
struct FlipInput {
    const std::vector<float>& shaded;
    const std::vector<float>& truth;
    int n = 0;
    double ppd = 0;
    const std::vector<uint8_t>& mask;
};
void add_flip(const FlipInput& in, ResultRow& row, std::vector<float>* map = nullptr);

}  // namespace pxh
