// The exact tracer (docs/conventions.md section 4): the first hit of each eye ray with the
// bilinear surface z = s (h - b), coming from the eye, traced per cell with the exact
// quadratic in double. Its pieces, one file each:
//   exact_tracer.cpp  the maximum mipmap (construction) and the Tracer interface
//   cell_solver.h     the ray and the closed-form ray / bilinear-patch cell solver
//   ray_walk.cpp      one ray at a time: trace_naive (DDA) and trace (over the mipmap)
//   ray_walk_exact.cpp  one ray at a time, fast and bit for bit trace_naive: trace_ray
//   ray_walk_simd.cpp   a view's rays 8 to a vector (AVX-512), bit for bit trace_naive
//   ray_walk_avx2.cpp   the same at 4 to a vector (AVX2 and FMA)
//   ray_walk_avx2_f32.cpp  the AVX2 path's square walk in float, 8 to a vector
//   band_tracer.cpp   every ray of an orthographic grid view at once: trace_grid
//   true_shadow.cpp   the true hard shadow query: occluded
#pragma once
#include <algorithm>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "harness/core/huge_pages.h"
#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "harness/truth/tracer.h"

namespace pxh {

namespace vector_walk {
struct SquareScene;
}

class ExactTracer final : public Tracer {
  public:
    // Throws std::invalid_argument unless the scale is finite and positive. Every entry point
    // taking a direction throws std::invalid_argument (ray_travel_problem's reason) for a
    // direction beyond the travel limit or not above the surface, before any work.
    ExactTracer(const HeightField& hf, double scale, double bias);
    // Not copied: the walk keeps pointers into the tracer's own levels (level_ptr_).
    ExactTracer(const ExactTracer&) = delete;
    ExactTracer& operator=(const ExactTracer&) = delete;

    // The Tracer interface ("exact"): an orthographic view on the sample grid takes
    // trace_grid unless grid_takes_rays; any other view (a perspective one) is traced ray by ray
    // with trace_ray's walk, in packets of neighbouring pixels that first descend through the slab
    // together (trace_rays, ray_walk_exact.cpp). Both equal trace_naive bit for bit, so a view's
    // hits do not depend on the path that traced them.
    std::string name() const override { return "exact"; }
    void trace(const View& view, Hits& out) const override;
    // Whether an orthographic grid view along V takes the per-ray vector path (trace_rays) rather
    // than the band tracer (trace_grid): on a vector path (ray_path()) for theta up to
    // kGridRaysMaxThetaDeg. Both give trace_naive's hits bit for bit; the choice is speed alone.
    // Measured (thread CPU time, one thread, 512 x 512 rays at phi 20 on fbm, bricks and bumps
    // fields of 512 and 2048 texels; docs/internals/tracers.md): the per-ray walk 1.0-1.75 times
    // as fast as the scalar band tracer up to 75 degrees on the AVX2 path, about even at 80,
    // 0.74-1.09 at 85 (grazing rays cross many squares; a band's bounds follow the ray); against
    // the band tracer with the vector DDA (fbm, AVX2): ahead up to 70 degrees, behind from 78.
    static constexpr double kGridRaysMaxThetaDeg = 78;
    bool grid_takes_rays(Vec3d V) const;
    bool has_shadow_query() const override { return true; }

    // First hit from the eye, accelerated by a maximum mipmap over cell corners (Tevs, Ihrke
    // and Seidel, I3D 2008: a bilinear patch's maximum lies at its corners, so block maxima
    // bound the surface exactly). Same answer as trace_naive to rounding (tested: within
    // 1e-9 texel on every ray): both solve the same cells with the same closed-form cell
    // parameters; the hierarchy only skips cells whose maximum lies below the ray.
    TruthHit trace(Vec2d P, Vec3d V) const;
    // The reference: a per-cell 2D DDA testing every cell the ray crosses.
    TruthHit trace_naive(Vec2d P, Vec3d V) const;
    // The per-ray fast path: trace_naive's hits bit for bit (uv and z; `cells` counts the
    // cells solved, a subset of trace_naive's), over the maximum mipmap. Where trace steps between
    // blocks in tile-local coordinates (hence its 1e-9 texel), this walk keeps trace_naive's DDA
    // cell exactly, found from the same line-crossing times, skips a block only when the ray leaves
    // it above the block's maximum (so every skipped cell is one trace_naive's solver rejects by
    // the same test) and solves the others with trace_naive's exit times.
    // Rays of a short horizontal travel (kDdaTravelCells, ray_walk_exact.cpp) take the DDA
    // itself, faster there; trace_walk is the walk for every ray (tested bit for bit too).
    TruthHit trace_ray(Vec2d P, Vec3d V) const;
    TruthHit trace_walk(Vec2d P, Vec3d V) const;
    // Every ray of one view at once: the rays through the N x N sample grid (sample_grid(n),
    // out[j * n + i]), all parallel to V. Rays are grouped in narrow lateral bands; each band
    // keeps, per run of grid columns along the view direction, an exact upper bound (from the
    // maximum mipmap) of the surface its rays can meet there (built 256 runs at a time where
    // a coarser bound does not already rule the rays out, so grazing rays that skim low ground
    // cost little), so a ray skips to the first run where it could hit and solves there only
    // the cells trace_naive would solve: the same cells, the same closed forms, hence the same
    // hits (tested bit for bit). On a vector path (ray_path()) the candidates' cells are walked
    // by that path's DDA, rays of a band side by side in vector lanes (band_tracer.cpp's
    // BandDdaRun), the same hits again. Runs in parallel
    // (TBB); the result does not depend on the thread count. `out` is resized and reused.
    void trace_grid(int n, Vec3d V, Hits& out) const;
    void trace_grid(int n, Vec3d V, std::vector<TruthHit>& out) const;
    // True hard shadow: does the ray from the surface point (uv, z) toward L (unit, L.z > 0)
    // pass strictly below the surface before leaving the slab at z_top? L.z <= 0: shadowed.
    bool occluded(Vec2d uv, double z, Vec3d L) const override;
    // The per-ray path's kernels (ray_path): the square walk and DDA 8 rays to a vector
    // (avx512, ray_walk_simd.cpp) where the CPU has avx512f and avx512dq, 4 to a vector (avx2,
    // ray_walk_avx2.cpp; its square walk 8 to a vector in float, ray_walk_avx2_f32.cpp) where it
    // has avx2 and fma, else the scalar walk (scalar, ray_walk_exact.cpp); the vector paths need a
    // field of at least 2 x 2 cells. All give trace_naive's hits bit for bit. The default is the
    // CPU's best (cpu_best_path) capped by the environment's PXH_TRACER_PATH (scalar, avx2 or
    // avx512: to take a path as a CPU without the wider ones would; default_path throws
    // std::invalid_argument for another value). set_path picks this tracer's (tests, benchmarks),
    // capped by what the CPU has; set_simd(on) is set_path(on ? default_path() : scalar). Not to be
    // called while another thread traces with this tracer.
    enum class RayPath { scalar, avx2, avx512 };
    static const char* path_name(RayPath p);
    static RayPath cpu_best_path();
    static RayPath default_path();
    static bool cpu_has_simd_path() { return default_path() != RayPath::scalar; }
    RayPath ray_path() const { return square_levels_ > 0 ? path_ : RayPath::scalar; }
    bool simd_path() const { return ray_path() != RayPath::scalar; }
    void set_path(RayPath p) { path_ = std::min(p, cpu_best_path()); }
    void set_simd(bool on) { set_path(on ? default_path() : RayPath::scalar); }
    // Builds the vector path's tables now where simd_path() (they are built on the first
    // per-ray trace otherwise; orthographic grid views never need them). Thread-safe.
    void prepare_rays() const;
    double z_top() const { return s_ * (1 - b_); }
    double scale() const override { return s_; }
    double z_bot() const { return -s_ * b_; }

  private:
    struct Ray;
    Ray make_ray(Vec2d P, Vec3d V) const;
    Ray make_ray_unchecked(Vec2d P, Vec3d V) const;        // for directions checked already
    TruthHit walk(const Ray& r, double dda_travel) const;  // DDA below dda_travel cells
    TruthHit trace_ray_unchecked(Vec2d P, Vec3d V) const;  // a direction checked already
    TruthHit dda(const Ray& r) const;                      // trace_naive's DDA
    // trace_ray's walk (ray_walk_exact.cpp): its state (WalkState) set by a start, then walked
    // to the hit by walk_blocks (over the maximum mipmap) or walk_dda (level 0 throughout).
    struct WalkState;
    void walk_start(WalkState& w, const Ray& r, double dda_travel) const;
    void walk_start_ray(WalkState& w, const Ray& r, double dda_travel) const;  // cell untiled
    void walk_at_cell(WalkState& w, int64_t ci, int64_t cj) const;  // the cell and its tile
    // The same start, moved down to the DDA's cell where the ray comes down to z_floor, a
    // height above which the ray provably meets no cell (packet_floor); where rounding could
    // put a skipped cell below z_floor, the ray starts at its first cell.
    void walk_start_below(WalkState& w, const Ray& r, double z_floor) const;
    // A height z_floor such that every cell any of the m rays crosses while at or above
    // z_floor lies below the ray there (ray_walk_exact.cpp).
    double packet_floor(const Ray* rays, int m) const;
    // An upper bound (from the maximum mipmap) of the corner maxima of the global cells
    // [gx0, gx1] x [gy0, gy1], both ends included, tiles wrapped.
    float cells_max(int64_t gx0, int64_t gx1, int64_t gy0, int64_t gy1) const;
    TruthHit walk_blocks(const WalkState& w) const;
    TruthHit walk_dda(const WalkState& w) const;   // walk_blocks at level 0 throughout, faster
    TruthHit finish(WalkState& w) const;           // the rest of the walk: its hit
    void prefetch_cell(int li, int lj) const;      // requests tile-local cell (li, lj)'s texels
    Ray make_ray(Vec2d P, const Ray& like) const;  // same direction as `like`, new start
    friend class ViewTracer;                       // trace_grid's machinery (band_tracer.cpp)
    // Solves cell (ci, cj) on [tau_in, tau_out]; returns the hit parameter or -1.
    double solve_cell(const Ray& r, int64_t ci, int64_t cj, double tau_out) const;
    // The same, given the cell's index wrapped into the tile (wi, wj).
    double solve_cell(const Ray& r, int64_t ci, int64_t cj, int64_t wi, int64_t wj,
                      double tau_out) const;
    // The same from column_pairs_ (the band tracer's), and from the corners h(i, j) = f00,
    // h(i + 1, j) = f10, h(i, j + 1) = f01, h(i + 1, j + 1) = f11 however read.
    double solve_cell_pairs(const Ray& r, int64_t ci, int64_t cj, int64_t wi, int64_t wj,
                            double tau_out) const;
    double solve_corners(const Ray& r, int64_t ci, int64_t cj, float f00, float f10, float f01,
                         float f11, double tau_out) const;
    // solve_corners in two parts: its first test (the ray at tau_out above the corners'
    // maximum: no hit in the cell), and the closed form for a cell that passes it.
    bool cell_below(const Ray& r, float f00, float f10, float f01, float f11, double tau_out) const;
    double solve_patch(const Ray& r, int64_t ci, int64_t cj, float f00, float f10, float f01,
                       float f11, double tau_out) const;
    double solve_patch_inline(const Ray& r, int64_t ci, int64_t cj, float f00, float f10, float f01,
                              float f11, double tau_out) const;
    // The length of a row of texels_ (W + 1: a cell's corners at offsets 0, 1, stride and
    // stride + 1 from its first), and row wj of texels_ (tile-local, 0 <= wj <= height).
    size_t texel_stride() const { return size_t(hf_.width) + 1; }
    const float* texel_row(int64_t wj) const {
        return texels_.data() + size_t(wj) * texel_stride();
    }
    TruthHit hit_at(const Ray& r, double tau, int cells) const;
    // The per-ray path of the Tracer interface: trace_rays_simd where simd_path(), else
    // packets (packet_floor), then each ray's walk.
    void trace_rays(const View& view, Hits& out) const;
    void trace_rays_simd(const View& view, Hits& out) const;  // ray_walk_simd.cpp
    // What the vector kernels read of the tracer (ray_walk_simd.cpp; the square tables' fields
    // are valid once prepare_rays has built them, which the band tracer's DDA never reads).
    void fill_scene(vector_walk::SquareScene& sc) const;
    // The square walk's tables (square_code_), once (prepare_rays).
    void build_squares() const;
    // The maximum mipmap's levels (construction).
    void build_levels();

    const HeightField& hf_;
    double s_, b_;
    // level_max_[l]: the maximum of cell corners over tile-local blocks of 2^l x 2^l cells,
    // row-major (level 0: cells, each the max of its 4 corners); blocks at the tile's right/top
    // edges are partial. The last level is one block. level_max_t_[l]: the same, column-major,
    // for the levels trace_grid builds its bounds from.
    std::vector<HugePageVector<float>> level_max_, level_max_t_;
    // The texels, row-major, (W + 1) x (H + 1) (the height field's, its first column and row
    // repeated after the last; in huge pages), for the per-ray paths: a cell's four corners lie
    // in two rows, at fixed offsets from its first. column_pairs_: texel (i, j) and (i, j + 1)
    // side by side, row by row (a cell's corners in 16 consecutive bytes), for the band tracer.
    // Measured (pxh bench, single thread): the per-ray walk faster on texels_ (0-3% at
    // 512 x 512, 10% at 2048 x 2048: half the bytes, as many cache lines per cell), the band
    // tracer 8% slower at 512 x 512 (its cells' rows are not reused as a walk's are).
    HugePageVector<float> texels_, column_pairs_;
    static constexpr size_t kBandLevels = 4;
    std::vector<int> level_w_, level_h_;
    std::vector<const float*> level_ptr_;  // level_max_[l].data()
    int top_level_ = 0;                    // the last level (one block)
    // square_code_: for k = 1 .. square_levels_ (at most kSquareLevels), an upper bound of
    // level 0's maximum over the 2^k x 2^k cells from tile-local cell (i, j) on, wrapped
    // (ray_walk_simd.cpp's square walk), one entry per d x d first cells (d = 1 for k <= 2,
    // 2^(k - 2) above: the bound of their union; ray_walk_simd.cpp's SquareLayout): the code c
    // of the bound square_lo_ + c square_step_ (in double, as computed there), the smallest of
    // the 256 at or above the maximum. One byte per entry, 2.33 per texel in all (4 bytes of
    // padding after the last). Built only for a vector path (ray_path).
    static constexpr int kSquareLevels = 5;
    // Built on first use (prepare_rays, squares_built_); square_levels_ by the constructor.
    mutable HugePageVector<uint8_t> square_code_;
    mutable double square_lo_ = 0, square_step_ = 0;
    mutable std::once_flag squares_built_;
    int square_levels_ = 0;
    RayPath path_ = RayPath::scalar;  // the constructor's default_path()
};

}  // namespace pxh
