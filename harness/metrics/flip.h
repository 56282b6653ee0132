// LDR-FLIP, the perceptual difference of two low-dynamic-range images (docs/conventions.md
// section 10): Andersson, Nilsson, Akenine-Moeller, Oskarsson, Astroem, Fairchild, "FLIP: A
// Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2),
// article 15, 2020 (HPG 2020), doi:10.1145/3406183.
//
// Written in pxh from the paper. Where the paper leaves a choice open (the separated form of the
// blue-yellow filter, the filter radii and normalisations, float arithmetic, clamp-to-edge
// borders) pxh follows the authors' implementation, NVlabs/flip, src/cpp/FLIP.h at commit
// 1eb247cabcf2862c2c8207ab15314304394132b9 (version 1.6), which was read for its constants and
// run to produce the expected values of tests/metrics/flip_test.cpp; none of its code is in pxh.
// flip.cpp names, for each constant, the line of FLIP.h it agrees with.
//
// Pipeline (reference and test alike): sRGB -> linear RGB (clamped to [0, 1]) -> XYZ (D65) ->
// YCxCz; the colour pipeline filters Y, Cx, Cz with the contrast sensitivity functions (Gaussians
// in degrees of visual angle, at `ppd` pixels per degree), goes back to linear RGB (clamped),
// to CIELab, applies the Hunt adjustment (a, b scaled by 0.01 L), takes the HyAB distance,
// raises it to q_c = 0.7 and maps it to [0, 1] (p_c = 0.4, p_t = 0.95). The feature pipeline
// filters the unfiltered Y, normalised to [0, 1], with the first and second derivatives of a
// Gaussian (sigma 0.5 w ppd, w = 0.082 degrees) for edges and points; the feature difference
// (max of the edge and point differences over sqrt 2, to the q_f = 0.5) gives the final
// per-pixel error: colour difference ^ (1 - feature difference).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace pxh {

// The paper's viewing set-up: 0.7 m from a 0.7 m wide 3840-pixel monitor, 3840 pi / 180 pixels
// per degree (67.0206...), rounded as docs/conventions.md section 10 writes it.
inline constexpr double kFlipDefaultPpd = 67.02;

// How an image's values encode colour: sRGB-encoded (as an 8-bit PNG's values / 255: the
// authors' tool's LDR input) or linear RGB (pxh's pictures, harness/results/pictures.h).
enum class FlipEncoding { srgb, linear };

// A w x h RGB image, row-major, 3 floats a pixel, values in [0, 1] (clamped after decoding).
struct FlipImage {
    const std::vector<float>& rgb;
    int w = 0, h = 0;
    FlipEncoding encoding = FlipEncoding::srgb;
};

struct FlipResult {
    double mean = 0;  // over the counted pixels (all, or the mask's)
    double p95 = 0;   // 95th percentile, linear interpolation between ranks (percentile_sorted)
    double max = 0;
    long counted = 0;  // pixels counted; 0 (mean, p95, max NaN) when the mask counts none
};

// LDR-FLIP of `test` against `reference` (the same size, at least 1 x 1), at `ppd` pixels per
// degree. `mask`, when given (w * h entries), counts the pixels whose entry is non-zero in mean,
// p95 and max; the filters still see the whole image. `map`, when given, receives the per-pixel
// FLIP values (w * h, row-major, in [0, 1]). Float arithmetic as the authors'; each pixel
// independent of the order of work, so the result is the same for any thread count.
// std::invalid_argument when the sizes disagree, an image is empty, or ppd is not a finite
// number from about 1.7 up (below it FLIP's feature filters vanish in float).
FlipResult flip_ldr(const FlipImage& reference, const FlipImage& test, double ppd = kFlipDefaultPpd,
                    const std::vector<uint8_t>* mask = nullptr, std::vector<float>* map = nullptr);

// 8-bit sRGB images (3 bytes a pixel, row-major): the values / 255, as the authors' tool reads
// a PNG.
FlipResult flip_ldr(const std::vector<uint8_t>& reference, const std::vector<uint8_t>& test, int w,
                    int h, double ppd = kFlipDefaultPpd, const std::vector<uint8_t>* mask = nullptr,
                    std::vector<float>* map = nullptr);

// The FLIP map's colours (flip_magma.cpp): the magma colour map of the paper and the authors'
// tool, 8-bit sRGB, entry int(v 255 + 0.5) of 256 (v clamped to [0, 1]; NaN as 0); the image
// of a whole map (3 bytes a pixel, row-major) for a PNG beside the pictures.
std::array<uint8_t, 3> flip_magma(float v);
std::vector<uint8_t> flip_magma_image(const std::vector<float>& map);

// Pieces of the colour pipeline (for tests that work the formulas by hand).
struct FlipColor {
    float x, y, z;
};
FlipColor flip_ycxcz_to_lab_hunt(FlipColor c);  // -> linear RGB (clamped) -> Lab, Hunt applied
float flip_hyab(FlipColor a, FlipColor b);      // |dL| + sqrt(da^2 + db^2)
float flip_color_remap(float hyab);             // ^q_c, then mapped to [0, 1] (p_c, p_t, c_max)
float flip_cmax();                              // HyAB(green, blue, Hunt-adjusted) ^ q_c

}  // namespace pxh
