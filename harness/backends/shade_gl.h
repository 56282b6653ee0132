// The GLSL twin of the shading (harness/scene/shading.h, docs/conventions.md section 13.1): the
// same material, light and sRGB encoding in a fragment shader, drawn over an n x n RGBA8 target
// and read back. The height field's levels and the albedo's levels are uploaded as mip chains
// (R32F, RGB32F), each pixel's uv, lambda and coverage as an RGBA32F texture; the shader reads
// every level texel by texel (texelFetch) with section 1's bilinear rule and repeat wrapping,
// and blends two levels as level_fetch does, so the twins differ by float against double only.
// A level's size is computed from level 0's (textureSize with a level that differs between
// the pixels of a SIMD group gave some pixels another level's size on llvmpipe).
#pragma once
#include <cstdint>
#include <vector>

#include "harness/gl/context.h"
#include "harness/scene/shading.h"

namespace pxh {

struct ShadeGlInput {
    const Material& material;
    const std::vector<Vec2d>& uv;         // n x n, pixel (i, j) = sample j n + i
    const std::vector<double>& lambda;    // per pixel (NaN: level 0, as the CPU twin)
    const std::vector<uint8_t>& covered;  // empty: all; 0: the background
    int n = 0;
};

// GlslBackend::shade calls it in the GL process after a [shading] run's draw, on the uv the
// draw read back.
// The sRGB image (3 floats a pixel, each an 8-bit value / 255), as shaded_image() followed by
// quantize_8bit() computes it on the CPU. Makes `ctx` current; std::runtime_error when the
// shader does not compile or a GL call fails.
std::vector<float> shade_gl(GlContext& ctx, const ShadeGlInput& in);

}  // namespace pxh
