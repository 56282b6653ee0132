// Exact ground truth (docs/conventions.md section 4): the first hit of each eye ray with the bilinear surface
// z = s (h - b), coming from the eye, traced per cell with the exact quadratic in double.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "harness/scene/heightfield.h"
#include "harness/core/vec.h"

namespace pxh {

// The longest horizontal path, in tiles, an eye or light ray may travel through the relief:
// s tan(theta) (the ray drops through the slab's height s and moves tan(theta) sideways per
// unit of drop). Near 90 degrees it grows without bound, and with it the work of both ground
// truths whenever a ray skims the relief and meets it late (at worst only at the slab bottom):
// Embree walks the path one tile per packet call, the exact tracer keeps bounds per band of
// rays along it, and the true-shadow walk steps through its cells. 6000 tiles keeps every
// shipped view (hard_cases.toml: s = 1 at 89.99 degrees, 5730 tiles). Measured at the limit
// (pxh run, s = 1, 256 x 256 samples, 2 cores; fbm, a single spike, flat at the slab bottom;
// azimuths 0 and 20): at most 13 s and 184 MB on a 32 x 32 field, 20 s and 1.09 GB on a
// 4096 x 4096 one (whose run takes 8 s and 1.01 GB at any angle). It also keeps every grid
// index the tracers convert from a double in range (6000 tiles x 16384 texels < 2^27). Views
// beyond it are refused when an experiment is read and by pxh bench and, as a last line of
// defence, by the tracers' entry points.
inline constexpr double kMaxRayTravelTiles = 6000;

// "" when rays of scale s at polar angle theta (degrees) stay within kMaxRayTravelTiles, else
// a one-line reason naming the value and the limit (also for a scale that is not a finite
// positive number, or theta outside [0, 90)).
std::string ray_travel_problem(double scale, double theta_deg);
// The same for a ray direction D (unit; D.z > 0 points from the surface toward the eye or
// light), as the tracers see it; a rounding margin over the limit is let through, so that
// every view ray_travel_problem(scale, theta) accepts is accepted here too.
std::string ray_travel_problem(double scale, Vec3d D);

// Sample points of an N x N grid over one tile: ((i + 0.5) / N, (j + 0.5) / N), row-major.
std::vector<Vec2d> sample_grid(int n);

// Unit vector toward the eye for polar angle theta and azimuth phi (degrees).
Vec3d view_vector(double theta_deg, double phi_deg);

struct TruthHit {
    Vec2d uv;       // unwrapped texture coordinate of the visible point
    double z = 0;   // its height z = s (h - b)
    int cells = 0;  // cells handed to the exact cell solver (cost)
};

class ExactTracer {
  public:
    // Throws std::invalid_argument unless the scale is finite and positive. Every entry point
    // taking a direction throws std::invalid_argument (ray_travel_problem's reason) for a
    // direction beyond the travel limit or not above the surface, before any work.
    ExactTracer(const HeightField& hf, double scale, double bias);
    // First hit from the eye, accelerated by a maximum mipmap over cell corners (Tevs, Ihrke
    // and Seidel, I3D 2008: a bilinear patch's maximum lies at its corners, so block maxima
    // bound the surface exactly). Same answer as trace_naive to rounding (tested: within
    // 1e-9 texel on every ray): both solve the same cells with the same closed-form cell
    // parameters; the hierarchy only skips cells whose maximum lies below the ray.
    TruthHit trace(Vec2d P, Vec3d V) const;
    // The reference: a per-cell 2D DDA testing every cell the ray crosses.
    TruthHit trace_naive(Vec2d P, Vec3d V) const;
    // Every ray of one view at once: the rays through the N x N sample grid (sample_grid(n),
    // out[j * n + i]), all parallel to V. Rays are grouped in narrow lateral bands; each band
    // keeps, per run of grid columns along the view direction, an exact upper bound (from the
    // maximum mipmap) of the surface its rays can meet there (built 256 runs at a time where
    // a coarser bound does not already rule the rays out, so grazing rays that skim low ground
    // cost little), so a ray skips to the first run where it could hit and solves there only
    // the cells trace_naive would solve: the same cells, the same closed forms, hence the same
    // hits (tested bit for bit). Runs in parallel
    // (TBB); the result does not depend on the thread count. `out` is resized and reused.
    // The ground truth of every run and of pxh bench.
    void trace_grid(int n, Vec3d V, std::vector<TruthHit>& out) const;
    // True hard shadow: does the ray from the surface point (uv, z) toward L (unit, L.z > 0)
    // pass strictly below the surface before leaving the slab at z_top? L.z <= 0: shadowed.
    bool occluded(Vec2d uv, double z, Vec3d L) const;
    double z_top() const { return s_ * (1 - b_); }
    double scale() const { return s_; }
    double z_bot() const { return -s_ * b_; }

  private:
    struct Ray;
    Ray make_ray(Vec2d P, Vec3d V) const;
    Ray make_ray(Vec2d P, const Ray& like) const;  // same direction as `like`, new start
    friend class ViewTracer;  // trace_grid's machinery (ground_truth.cpp)
    // Solves cell (ci, cj) on [tau_in, tau_out]; returns the hit parameter or -1.
    double solve_cell(const Ray& r, int64_t ci, int64_t cj, double tau_out) const;
    // The same, given the cell's index wrapped into the tile (wi, wj).
    double solve_cell(const Ray& r, int64_t ci, int64_t cj, int64_t wi, int64_t wj, double tau_out) const;
    TruthHit hit_at(const Ray& r, double tau, int cells) const;

    const HeightField& hf_;
    double s_, b_;
    // level_max_[l]: the maximum of cell corners over tile-local blocks of 2^l x 2^l cells,
    // row-major (level 0: cells, each the max of its 4 corners); blocks at the tile's right/top
    // edges are partial. The last level is one block. level_max_t_[l]: the same, column-major,
    // for the levels trace_grid builds its bounds from.
    std::vector<std::vector<float>> level_max_, level_max_t_;
    // Texel (i, j) and (i, j + 1) side by side, row by row: a cell's four corners in 16
    // consecutive bytes (one cache line, mostly), as the solver reads them.
    std::vector<float> column_pairs_;
    static constexpr size_t kBandLevels = 4;
    std::vector<int> level_w_, level_h_;
};

struct GroundTruth {
    std::vector<Vec2d> uv;  // per sample, unwrapped
    std::vector<double> z;
    std::vector<uint8_t> lit;  // per sample, when a light was given: true hard shadow state
    double cells_mean = 0;
};

// Traces every sample of the N x N grid (in parallel; the result does not depend on threads).
// With a light L, also the true shadow state of every visible point.
GroundTruth trace_ground_truth(const HeightField& hf, double scale, double bias, Vec3d V, int n,
                               const Vec3d* L = nullptr);
// The same with a tracer built once for the field (and s, b), shared by its views.
GroundTruth trace_ground_truth(const ExactTracer& tracer, Vec3d V, int n, const Vec3d* L = nullptr);

}  // namespace pxh
