// Cone maps for `cone` and `relaxed_cone` (methods/cone/cone.md, methods/relaxed_cone/
// relaxed_cone.md). Sources, read for their algorithms only:
//   Dummer, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection Algorithm", 2006
//     (conservative cones through texel centres);
//   Policarpo, Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007
//     (relaxed cones: a ray from above the source through each higher texel, followed until it
//     leaves the surface);
//   Ban, Valasek, Balint, Vad, "Robust Cone Step Mapping", EGSR 2024 (Symposium track),
//     doi:10.2312/sr.20241146, as implemented in github.com/Bundas102/robust-cone-map, commit
//     2dbc39b (Conemap.cs.slang: the brute-force cones, the book's generation adapted to
//     heights, the corrected relaxed cones from "falling edges", the 3 x 3 minimum post-process).
// pxh's own: `bilinear`, cones provably free of the bilinear surface for every apex a linearly
// filtered ratio can stand for (methods/cone/cone.md, "The bilinear map").
//
// Units: a ratio is horizontal uv per unit of height h (h in [0, 1]), independent of s and b;
// the shaders divide by s for uv per unit of z = s (h - b). Distances are Euclidean in uv (a
// non-square field's texels are 1/W by 1/H). Ratios are capped at 1 (Dummer's storage range)
// and rounded toward zero to float. The field tiles: every periodic image counts.
//
// The accelerated builders ("quick cone map generation": Valasek and Ban, Eurographics 2022
// short paper, cited by Ban et al. 2024) prune whole blocks of a max pyramid whose bound cannot
// lower the ratio found so far; each `*_brute` evaluates every candidate. Both compute each
// candidate with the same function and take the minimum, so they agree bit for bit (tested).
// Rows in parallel, one texel per task: the same bytes for any thread count.
#pragma once
#include <cstddef>
#include <vector>

#include "harness/scene/heightfield.h"

namespace pxh::cone_maps {

// Dummer: min over texel centres q higher than the source p of |q - p| / (h(q) - h(p)), cap 1.
std::vector<float> dummer(const HeightField& hf);
std::vector<float> dummer_brute(const HeightField& hf);

// Ban et al.'s post-process: each texel's ratio becomes the minimum over its 3 x 3
// neighbourhood (wrapping here; the source clamps at the border of its non-tiling texture).
std::vector<float> min3x3(const std::vector<float>& ratio, int W, int H);

// pxh: per bilinear cell Q (between texel centres), a ratio c_Q with c_Q <= |x - q| /
// (h(x) - h(q)) for every q in Q and every x of the bilinear surface; per texel the minimum of
// its four cells, times (1 - 2^-20) before rounding down (rounding headroom).
std::vector<float> bilinear(const HeightField& hf);
std::vector<float> bilinear_brute(const HeightField& hf);

// The book's relaxed cones (generation listing, as adapted to heights by Ban et al.): for each
// destination texel, the ray from (p, kBookSourceHeight) through (q, h(q)), marched onward in
// kBookSearchSteps equal steps down to h = 0 while the surface is at or above it; the ratio
// of the point where it stopped (1 if that point is not above the source's height).
constexpr int kBookSearchSteps = 64;         // Ban et al.'s default relaxedConeSearchSteps
constexpr double kBookSourceHeight = 1.001;  // Ban et al.'s src.z: finite rays at h = 1
std::vector<float> relaxed_book(const HeightField& hf);
std::vector<float> relaxed_book_brute(const HeightField& hf);

// Ban et al.'s corrected relaxed cones: min over texels q higher than p that are "limiting
// vertices" (the cell beyond q, away from p, has a falling edge) of |q - p| / (h(q) - h(p)).
std::vector<float> relaxed_ban(const HeightField& hf);
std::vector<float> relaxed_ban_brute(const HeightField& hf);

// The largest field (texels) relaxed_cone builds its maps for: the book's generation marches
// a ray for every destination inside the cone found so far (methods/relaxed_cone/
// relaxed_cone.md gives the measured times).
constexpr size_t kRelaxedTexelLimit = size_t(256) * 256;

// Round toward zero to float (Ban et al. truncate for the same reason: never a larger cone).
float round_down(double v);

}  // namespace pxh::cone_maps
