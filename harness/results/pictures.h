// Pictures of what a method shows: a real albedo texture (a numbered checkerboard) sampled
// through the true uv and through a method's uv, and their difference, as PNG files (through
// OpenImageIO). The run writes them for the experiment's [render] views (harness/commands/
// cmd_run.cpp), and pxh report assembles them into montages and strips.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/shading.h"

namespace pxh {

// The albedo at uv (tile units, wrapping): 8 x 8 cells per tile, each numbered 0..63 (row-major,
// two digits of a 3 x 5 pixel font), columns tinted from Paul Tol's muted palette, alternate
// cells lighter and darker, a dark border line around each cell. Deterministic; linear RGB in
// [0, 1]. Non-finite uv gives magenta (1, 0, 1).
void albedo(Vec2d uv, float rgb[3]);

// The checkerboard above as a size x size texture (each texel the albedo at its centre): the
// `checker` albedo of [shading] (harness/scene/shading.h).
RgbImage checker_albedo(int size);

// An albedo image file read through OpenImageIO (any format it reads): 8- and 16-bit integer
// values are sRGB-encoded and decoded to linear, float formats taken as linear; one channel is
// grey, a fourth (alpha) is ignored. Row 0 of the file is v near 0. std::runtime_error saying
// why when the file cannot be read or holds no pixels.
RgbImage read_albedo_image(const std::string& path);

// The n x n picture seen through per-sample uv (sample j * n + i is pixel (i, j)): 3 floats a
// pixel. `inside` (empty: every sample): a sample it marks 0 is outside the view and neutral
// grey (0.5, 0.5, 0.5) in every picture, the truth's too.
std::vector<float> picture(const std::vector<Vec2d>& uv, int n,
                           const std::vector<uint8_t>& inside = {});

// A method's uv from the truth's and the per-sample texel error (e = uv_method - uv_true,
// wrapped into a tile, in texels of a width x height field): the albedo repeats every tile, so
// the picture through these is the method's picture. NaN errors (failed or left-out samples)
// give NaN uv (magenta).
std::vector<Vec2d> uv_from_errors(const std::vector<Vec2d>& truth_uv,
                                  const std::vector<Vec2d>& errors, int width, int height);

// The opaque plane of a depth test ([views] cut; docs/conventions.md section 11) painted over a
// picture: a flat blue (kPlaneRgb, no colour the albedo uses) at the samples whose `shows`
// has bit `bit` set (add_cut_flips: bit 1 the truth shows the plane, bit 2 the method).
inline constexpr float kPlaneRgb[3] = {0.12f, 0.35f, 0.95f};
void paint_plane(std::vector<float>& rgb, const std::vector<uint8_t>& shows, uint8_t bit);

// |a - b| per channel: black where the pictures agree.
std::vector<float> difference(const std::vector<float>& a, const std::vector<float>& b);

// Writes an n x n RGB picture as an 8-bit PNG (values clamped to [0, 1], rounded), a new
// file (harness/results/image_file.h: never through a link, never over a file). Pixel row j is
// file row j (texture space, as error maps: v grows downwards), or with `as_seen` file row
// n - 1 - j (a camera's image as the viewer sees it: gl_FragCoord's row 0 at the bottom).
void write_picture(const std::vector<float>& rgb, int n, const std::string& path,
                   bool as_seen = false);

}  // namespace pxh
