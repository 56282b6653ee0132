// Embree as an independent second ground truth: the same height samples as a GRID geometry
// (vertices at texel centres, two triangles per cell), the periodic tiling handled by walking
// each ray tile by tile, each segment traced in the base tile with packets of 16 rays.
#pragma once
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "harness/truth/tracer.h"

namespace pxh {

class EmbreeTracer final : public Tracer {
  public:
    // Throws std::invalid_argument unless the scale is finite and positive.
    EmbreeTracer(const HeightField& hf, double scale, double bias);
    ~EmbreeTracer();
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    // The Tracer interface ("embree"): every ray P_k along V_k (uv only: no heights, no cell
    // counts, no shadow query).
    std::string name() const override { return "embree"; }
    double scale() const override { return s_; }
    void trace(const View& view, Hits& out) const override;

    // First hits of the eye rays of points P (coming down along -V from the slab top),
    // unwrapped uv; in parallel (TBB), 16 rays per packet. Throws std::invalid_argument
    // (ray_travel_problem's reason) for a V beyond the travel limit, before any work.
    std::vector<Vec2d> trace(const std::vector<Vec2d>& P, Vec3d V) const;
    void trace(const std::vector<Vec2d>& P, Vec3d V, std::vector<Vec2d>& out) const;  // reuses out
    double build_ms() const { return build_ms_; }
    // The device's configuration: "max_isa=avx2" where the environment's PXH_TRACER_PATH is
    // avx2, "max_isa=sse4.2" where it is scalar (the build's x86-64-v2 baseline), else empty
    // (Embree takes the widest of its kernels the CPU runs), so that a run capped to a path
    // caps both tracers as a CPU without the wider instructions would.
    static std::string device_config();
    // The kernels Embree runs: "avx512", "avx2", "avx" or "sse4.2" (the widest the CPU has,
    // as Embree tests them, within device_config's cap; Embree's packets of 16 rays run as one
    // vector of 16 lanes only with avx512).
    static std::string isa();

  private:
    // n <= 16 rays: P[k] along V[k * v_step] (v_step 0: one direction for all).
    void trace_packet(const Vec2d* P, const Vec3d* V, size_t v_step, int n, Vec2d* out) const;
    void trace_all(const std::vector<Vec2d>& P, const Vec3d* V, size_t v_step,
                   std::vector<Vec2d>& out) const;
    int W_, H_;
    double s_, b_;
    double zs_ = 1;  // heights in units of zs_ (1 up to s = 2^32; see the constructor)
    void* device_ = nullptr;
    void* scene_ = nullptr;       // 3 x 3 instances of the tile
    void* tile_scene_ = nullptr;  // the GRID geometry of one tile
    double build_ms_ = 0;
};

}  // namespace pxh
