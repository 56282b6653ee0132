// Embree on a displaced triangle grid of a curved base (issue 62, item 3: pxh bench --base):
// vertices at the texel centres on X(u, v) = B + s (h - b) N, two triangles per cell (Embree's
// GRID geometry, Debian's Embree 3.13), over the box of (u, v) a view's rays can reach in the
// relief's shell. An approximation of the bilinear surface (facets), timed beside the exact
// curved tracers and measured against them.
#pragma once
#include <string>
#include <vector>

#include "harness/scene/base_surface.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/view.h"

namespace pxh {

class CurvedEmbreeGrid {
  public:
    // The grid over the (u, v) box the rays cross in the shell between s (1 - b) and -s b
    // (their chords' ends and midpoints, plus two texels), clipped to the base's coordinate
    // range (the cylinder's and sphere's seam at u' = +-pi R, the sphere's poles). Throws
    // std::runtime_error when the box would need more than `max_vertices` vertices.
    CurvedEmbreeGrid(const HeightField& hf, double scale, double bias, const BaseSurface& base,
                     const std::vector<WorldRay>& rays, double max_vertices = 6e7);
    ~CurvedEmbreeGrid();
    CurvedEmbreeGrid(const CurvedEmbreeGrid&) = delete;
    CurvedEmbreeGrid& operator=(const CurvedEmbreeGrid&) = delete;
    // The first hit's t along each ray (NaN: none), 16 rays a packet, in parallel (TBB).
    void trace(const std::vector<WorldRay>& rays, std::vector<double>& t) const;
    size_t vertices() const { return vertices_; }
    double build_ms() const { return build_ms_; }

  private:
    void* device_ = nullptr;
    void* scene_ = nullptr;
    size_t vertices_ = 0;
    double build_ms_ = 0;
};

}  // namespace pxh
