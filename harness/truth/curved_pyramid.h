// The accelerated exact curved truth (issue 62, item 1; docs/internals/tracers.md, "Curved
// bases: the pyramid tracer"): the first hit of a ray with the displaced surface
// X = B + s (h - b) N of a cylinder or sphere base, found with the same first-hit rule as the
// curved walk (harness/truth/curved_tracer.h: the first t where
//   g(t) = height(o + t d) - s (h(uv(o + t d)) - b)
// is <= 0, bisected to the last bit of t), but without walking the relief in quarter texels:
// - a min/max pyramid of the height field: per node of 2^k x 2^k cells, the largest corner
//   height over the node dilated by one cell on each side (a bilinear patch's maximum is at its
//   corners), so the node's relief lies under the shell of the base at offset s (max - b);
// - an ordered traversal along the ray: at the current point the node of level k holding its
//   (u, v) is cleared when the ray does not come down to that shell before it leaves the node's
//   sector (a wedge between two planes through the axis in u, a slab in v on the cylinder and
//   two latitude cones on the sphere, all met in closed form), then the walk moves to the exit
//   and up a level; otherwise it moves to where the ray meets the shell and down a level;
// - in a cell (level 0) still in question, steps that never pass a crossing: each is the
//   larger of g / L (L bounds |g'| over the cell) and the first root of the quadratic lower
//   bound g + g' dt - K dt^2 / 2 (K bounds |g''|): a Newton step taken from the safe side, so a
//   transversal crossing is approached quadratically. Once the safe step is under 8 ulp of t,
//   a step of 8 ulp is taken as it is and bisected where it ends at or below the surface.
// The dilation by one cell absorbs rounding in (u, v) at node borders; the shells carry a
// margin of a few ulp of R. The traversal and the safe steps take a table-reduced atan2 (a few
// ulp); the bisection and the residual take the bases' own expressions, the walk's g to the bit.
// Per ray, so the result does not depend on the thread count. trace_many takes rays 8 (AVX-512)
// or 4 (AVX2) to a vector (curved_pyramid_lanes.h), each ray's result trace_one's bit for bit.
#pragma once
#include <atomic>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/scene/base_surface.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/view.h"

// The vector paths are compiled with GCC on x86-64 (curved_pyramid_avx512.cpp and
// curved_pyramid_avx2.cpp, each after its `#pragma GCC target`); elsewhere trace_many is scalar.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PXH_PYRAMID_LANES 1
#else
#define PXH_PYRAMID_LANES 0
#endif

namespace pxh {

class CurvedPyramid {
  public:
    // The bases it knows in closed form: "cylinder", "sphere" and "plane".
    static bool supports(const BaseSurface& base);
    // The vector paths of trace_many: the widest this CPU has, or PXH_TRACER_PATH's (scalar,
    // avx2, avx512: ExactTracer::default_path), and its name in words (pxh bench prints it).
    enum class Path { scalar, avx2, avx512 };
    static Path default_path();
    static Path cpu_path();  // the widest this CPU has, whatever PXH_TRACER_PATH says
    static std::string path_name(Path p = default_path());
    CurvedPyramid(const HeightField& hf, double scale, double bias, const BaseSurface& base);

    struct One {
        bool hit = false;
        double t = 0, residual = 0;
        long long steps = 0;  // node visits and cell evaluations
        // a hit's texture coordinates: BaseSurface::coords(o + t d).uv, the same expressions
        // (the bisection's own evaluation there, kept)
        double u = 0, v = 0;
    };
    // One ray; it stops (no hit) once it has taken more than `max_steps` steps (the caller's
    // budget left).
    One trace_one(const WorldRay& r, long long max_steps) const;
    // rays[0 .. n) into out[0 .. n), each trace_one's result on the ray, bit for bit, taken on
    // `path` (never above what the CPU has; the scalar path: trace_one itself). Each ray may
    // take what was left of `max_steps` (over the n rays) when it began, plus 4096; once the
    // rays' steps pass max_steps + 4096, or `stop` is set, the rays under way end over budget
    // (hit false, their steps) and the others are left unstarted (One{}): the caller's budget
    // is spent, and it throws.
    void trace_many(const WorldRay* rays, size_t n, One* out, long long max_steps,
                    Path path = default_path(), const std::atomic<bool>* stop = nullptr) const;
    int levels() const { return int(nx_.size()); }

    // Deliberate breakage, for the tests only: every node bound lowered by `shrink_ulps` float
    // steps, and nodes of level `skip_level` whose indices (i + j) % 5 == 0 taken as cleared
    // without a test.
    struct Breakage {
        int shrink_ulps = 0;
        int skip_level = -1;
    };
    void break_for_test(const Breakage& b);

  private:
    template <class L>
    friend struct PyramidLanes;  // the vector paths (curved_pyramid_lanes.h)
    void trace_avx512(const WorldRay* rays, size_t n, One* out, long long max_steps,
                      const std::atomic<bool>* stop) const;
    void trace_avx2(const WorldRay* rays, size_t n, One* out, long long max_steps,
                    const std::atomic<bool>* stop) const;
    static const double* atan_table();  // atan(i / 64), i = 0 .. 64: fast_atan2's
    enum class Kind { plane, cylinder, sphere };
    struct Eval {
        double g, dg;  // g and dg/dt at t
    };
    struct Geo {  // a point in the base's coordinates
        double u, v, height;
    };
    Geo geo(Vec3d p, bool fast = false) const;
    double height_exact(Vec3d p) const;  // geo(p).height, without the coordinates
    // g and dg/dt at t; (ci, cj) the cell whose bilinear patch gave them
    Eval eval(const WorldRay& r, double t, int64_t& ci, int64_t& cj) const;
    // g at t (the bases' own expressions); with c, the point's coordinates there
    double g_at(const WorldRay& r, double t, Geo* c = nullptr) const;
    // from p (with its coordinates c), how far along the ray it leaves the node of unwrapped
    // cells [c0, c1) x [d0, d1) (inf: never)
    double node_exit(const WorldRay& r, Vec3d p, const Geo& c, int64_t c0, int64_t c1, int64_t d0,
                     int64_t d1) const;
    // the sphere's latitude e of the border below cell row d (v = (d + 0.5) / H), its cos^2 and
    // sin^2, and cell_bounds' least cos(latitude) over row d dilated by a cell: from a table
    // made once (make_latitude, the same expressions) within 4 tiles of the field
    struct Latitude {
        double e, c2, s2, cos_cell;
    };
    Latitude latitude(int64_t d) const;
    Latitude make_latitude(int64_t d) const;
    // from p, how far along the ray it first is at or below `offset` over the base (inf: never)
    double shell_entry(const WorldRay& r, Vec3d p, double height_now, double offset) const;
    double angle_exit(double x, double z, double dx, double dz, double L, double delta) const;
    double cone_exit(Vec3d q, Vec3d d, const Latitude& lat, bool upward) const;
    struct CellBounds {
        double L, K;  // bounds of |g'| and |g''| over the cell dilated by one cell
    };
    // cell_bounds' bounds over the segment above the bottom shell, for cells of row cj: the
    // speeds |u'|, |v'|, the second derivatives |u''|, |v''| and |height''| (per row on the
    // sphere, from a table made once with the same expressions; one set on the other bases)
    struct Speeds {
        double su = 1, sv = 1, uu = 0, vv = 0, hh = 0;
    };
    Speeds speeds(int64_t cj) const;
    Speeds make_speeds(int64_t cj) const;
    CellBounds cell_bounds(int64_t ci, int64_t cj) const;
    // the bounds from the cell's largest differences of the field (|h_u|, |h_v| and |h_uv| over
    // a texel, over the dilated cell) on row cj
    CellBounds bounds_of(int64_t cj, double gx, double gy, double gxy) const;
    double bisect(const WorldRay& r, double lo, double hi, double& g_hi, Geo& c_hi) const;
    // the walk's chord through the shell: [t0, t_end]; ok: the ray enters it
    struct Chord {
        double t0 = 0, t_end = 0;
        bool ok = false, floor_ends = false;
    };
    Chord chord(const WorldRay& r) const;
    // a hit bisected in [lo, hi] (g(lo) > 0 or lo the start, g(hi) <= 0) into out; g_hi and
    // c_hi: g_at's values at hi where the caller has them (else NaN, null)
    void finish(const WorldRay& r, double lo, double hi, One& out, double g_hi = NAN,
                const Geo* c_hi = nullptr) const;
    // the walk's last step on the bottom shell, at t_end: a hit there (bisected from t_safe
    // where g <= 0 at t_end)
    void floor_end(const WorldRay& r, double t_safe, double t_end, One& out) const;
    // a cell (ci, cj) still in question, its exit tb, the chord's end, 1e-10 texel past t
    struct CellWalk {
        int64_t ci, cj;
        double tb, t_end, tiny;
    };
    enum class CellEnd { hit, left, chord_end, over_budget };
    // certified steps from tt through the cell: a hit (in out), past its exit, the chord's end
    // (tt there) or the budget spent
    CellEnd cell_steps(const WorldRay& r, const CellWalk& w, double& tt, double& t_safe, One& out,
                       long long max_steps) const;
    float node_max(int k, int64_t ni, int64_t nj) const {
        return max_[size_t(off_[size_t(k)]) + size_t(nj) * size_t(nx_[size_t(k)]) + size_t(ni)];
    }

    const HeightField& hf_;
    double s_, b_;
    const BaseSurface& base_;
    Kind kind_;
    double R_;
    int W_, H_;
    double margin_;  // tiles: the shells' rounding margin
    double tiny_;    // tiles: past a node's exit (1e-10 texel)
    double rmin_;    // R + s (0 - b): no point of the segments is nearer
    // per level (from off_[k], nx_[k] x ny_[k] nodes, row by row), per node: the largest corner
    // height, dilated
    std::vector<float> max_;
    std::vector<int64_t> off_;
    std::vector<int> nx_, ny_;
    std::vector<Latitude> lat_;       // the sphere's rows from lat_lo_
    std::vector<Speeds> row_speeds_;  // the sphere's rows from lat_lo_, as lat_
    Speeds speeds_;                   // the cylinder's and the plane's
    int64_t lat_lo_ = 0;
    Breakage breakage_;
};

}  // namespace pxh
