// The shading every method's image and the truth's share (docs/conventions.md section 13.1):
// an albedo texture and the height field's own normal, both read at the pixel's texture level,
// lit by one directional light, encoded to sRGB. The CPU twin; the GLSL twin is
// harness/backends/shade_gl.cpp (the same formulas in a fragment shader).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/texture_levels.h"

namespace pxh {

// An RGB image, linear, row-major, 3 floats a texel; row j = 0 is v near 0 (as a height field).
struct RgbImage {
    int width = 0, height = 0;
    std::vector<float> rgb;
};

inline constexpr float kShadeAmbient = 0.2f;     // k_a
inline constexpr float kShadeDiffuse = 0.8f;     // k_d
inline constexpr float kShadeBackground = 0.5f;  // sRGB value of a pixel a side does not cover

float srgb_encode(float linear);
float srgb_decode(float encoded);

// The unit light vector (tangent frame) of an elevation and azimuth in degrees.
Vec3d light_direction(double elevation_deg, double azimuth_deg);

// Box levels of each albedo channel (built as a height field's: build_texture_levels).
struct AlbedoLevels {
    std::array<TextureLevels, 3> channel;
    int width = 0, height = 0;
};
AlbedoLevels build_albedo_levels(const RgbImage& albedo);

// [shading] of an experiment: the material and the light, and the viewing set-up of FLIP.
struct ShadingSpec {
    std::string albedo = "checker";              // "checker" or the image file as written
    int albedo_size = 512;                       // the checker's texels per side
    double elevation_deg = 45;                   // the light above the tangent plane
    double azimuth_deg = 135;                    // ... from +u towards +v
    double ppd = 67.02;                          // FLIP's pixels per degree (kFlipDefaultPpd)
    std::shared_ptr<const RgbImage> image;       // the albedo's texels (linear), read with the file
    std::shared_ptr<const AlbedoLevels> levels;  // ... and their box levels
};

// What one field's pixels are shaded with. `heights` and `albedo` must outlive it.
struct Material {
    const TextureLevels* heights = nullptr;
    const AlbedoLevels* albedo = nullptr;
    double scale = 0;       // s: the surface z = s (h - b)
    Vec3d light;            // unit, tangent frame
    double albedo_lod = 0;  // log2(max(Wa, Ha) / max(W, H)): the albedo's lambda - the field's
};

// dh/du, dh/dv (per tile) at level lambda: central differences one texel of level L apart
// (wrapped) on levels floor(lambda) and the next, blended as the trilinear fetch blends them
// (level_fetch's rule: lambda <= 0 or NaN level 0; past the last level the last).
Vec2d height_gradient(const TextureLevels& tl, Vec2d uv, double lambda);

// The linear colour A (k_a + k_d max(0, n . L)) at uv, lambda (the field's level of detail).
std::array<float, 3> shade_linear(const Material& m, Vec2d uv, double lambda);

// The sRGB image (3 floats a pixel, in [0, 1]) of per-pixel uv at per-pixel lambda; a pixel
// whose `covered` entry is 0 (when given), or whose uv is not finite, is the background.
std::vector<float> shaded_image(const Material& m, const std::vector<Vec2d>& uv,
                                const std::vector<double>& lambda,
                                const std::vector<uint8_t>& covered);

// Values rounded to 8 bits and back (what a PNG holds and a display shows): round(255 v) / 255.
void quantize_8bit(std::vector<float>& rgb);

}  // namespace pxh
