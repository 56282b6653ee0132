// Pixel footprints (docs/conventions.md section 10), for every camera: a pixel's footprint J is
// the uv change per pixel step; from it the texels per pixel rho, the level of detail lambda a
// texture sampler picks, and the pixel error, the screen distance a uv error makes.
#pragma once
#include <vector>

#include "harness/core/vec.h"

namespace pxh {

// A pixel's footprint: the uv change per pixel step, dP/di (one column to the right) and dP/dj
// (one row up).
struct Footprint {
    Vec2d dPdi, dPdj;
};

// rho = max(|(W dPdi.x, H dPdi.y)|, |(W dPdj.x, H dPdj.y)|): level-0 texels per pixel.
double footprint_scale(const Footprint& J, int width, int height);
// lambda = log2(rho): the isotropic level of detail of GL's scale-factor formula.
double footprint_lod(const Footprint& J, int width, int height);

// lambda of every sample: footprint_lod of each footprint, in sample order.
std::vector<double> sample_lods(const std::vector<Footprint>& J, int width, int height);

// The pixel error |J^-1 e_uv| (e_uv the uv error, wrapped per tile): screen pixels between the
// shown and the true point. NaN for a singular J or a non-finite error.
double pixel_error(const Footprint& J, Vec2d e_uv);

}  // namespace pxh
