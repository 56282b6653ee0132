// The vector per-ray paths' shared pieces (internal to harness/truth): the rays' columns, the
// square tables' layout, the scene the passes read, and the AVX2 kernels' entry points. The
// passes themselves are described in ray_walk_simd.cpp (AVX-512, 8 rays to a vector, and the
// driver, trace_rays_simd); ray_walk_avx2.cpp is the same two passes at 4 rays to a vector
// (its square walk in float at 8 rays to a vector: ray_walk_avx2_f32.cpp).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "harness/scene/view.h"

namespace pxh::vector_walk {

// The first square of a walk: 2^kSquareStart cells on a side (2 to 4 measured alike).
constexpr int kSquareStart = 3;
// The DDA's cells per ray in one pass B (4 to 16 measured alike).
constexpr int kDdaCells = 8;

// A chunk's rays still to resolve, one array per parameter (ExactTracer::Ray's, for the
// vectors' loads; ivz = 1 / vz), and per ray its place in the chunk (id), the cells walked so
// far (cells) and the exit time of the last one counted (counted, dda_pass). 8 entries of
// padding after the last ray: pass A loads 8 (AVX-512) or 4 (AVX2) at a time.
struct RayColumns {
    std::vector<double> X0, Y0, dX, dY, iX, iY, vz, ivz, tm, counted;
    std::vector<int> id, cells;
    static constexpr std::vector<double> RayColumns::*kReals[] = {
        &RayColumns::X0, &RayColumns::Y0, &RayColumns::dX,  &RayColumns::dY, &RayColumns::iX,
        &RayColumns::iY, &RayColumns::vz, &RayColumns::ivz, &RayColumns::tm, &RayColumns::counted};
    static constexpr std::vector<int> RayColumns::*kInts[] = {&RayColumns::id, &RayColumns::cells};
    void resize(size_t n) {
        for (auto col : kReals) (this->*col).resize(n + 8);
        for (auto col : kInts) (this->*col).resize(n + 8);
    }
    // Ray `from` of `src` to place `to`.
    void copy(int to, const RayColumns& src, int from) {
        for (auto col : kReals) (this->*col)[to] = (src.*col)[from];
        for (auto col : kInts) (this->*col)[to] = (src.*col)[from];
    }
};

// Where level k (1 .. K <= 7) of the square tables lies in square_code_: entry (I, J) of its
// cols[k] x rows[k] grid, at base[k] + J cols[k] + I, bounds the squares of 2^k cells on a side
// whose first cell (i, j) lies in [I d, I d + d) x [J d, J d + d), d = spacing[k] =
// 2^max(0, k - 2) (so it bounds the square of 2^k + d - 1 cells from (I d, J d), wrapped): the
// larger levels are stored at a coarser spacing, smaller tables for slightly larger squares.
struct SquareLayout {
    int spacing[8] = {}, cols[8] = {}, rows[8] = {};
    size_t base[8] = {}, total = 0;
    SquareLayout(int W, int H, int K) {
        for (int k = 1; k <= K; ++k) {
            spacing[k] = 1 << std::max(0, k - 2);
            cols[k] = (W + spacing[k] - 1) / spacing[k];
            rows[k] = (H + spacing[k] - 1) / spacing[k];
            base[k] = total;
            total += size_t(cols[k]) * size_t(rows[k]);
        }
    }
};

// What the passes read of the tracer.
struct SquareScene {
    const float* texels;  // texels_, rows of `up` floats
    int up;
    const uint8_t* squares;  // square_code_, laid out as SquareLayout
    size_t entries;          // SquareLayout's total
    // SquareLayout's by level k (index k; 0 unused), for the vectors' lookups.
    alignas(64) double inv_spacing[8], cols[8], base[8];
    double lo, step;  // code c: the bound lo + c step
    int levels;       // K
    int W, H;
    double s, b, zt;
};

// The AVX-512 path's pass B (ray_walk_simd.cpp), for the band tracer's vector DDA.
namespace avx512 {
void dda_pass(const SquareScene& sc, RayColumns& rays, const int* list, const double* t_safe, int n,
              double* out_t, uint8_t* resolved);
}  // namespace avx512

// The AVX2 (+FMA) kernels (ray_walk_avx2.cpp), the AVX-512 ones' contracts
// (ray_walk_simd.cpp): make_rays, square_pass (pass A) and dda_pass (pass B).
namespace avx2 {
void make_rays(const View& view, size_t k0, const int* where, int n, const SquareScene& sc,
               RayColumns& c, double* ex_out, double* ey_out);
void square_pass(const SquareScene& sc, const RayColumns& rays, const double* t0, int n,
                 double* t_safe, uint8_t* bottom);
// square_pass in double, 4 rays to a vector (ray_walk_avx2.cpp): square_pass's rays beyond the
// float walk's bounds (ray_walk_avx2_f32.cpp) take it.
void square_pass_f64(const SquareScene& sc, const RayColumns& rays, const double* t0, int n,
                     double* t_safe, uint8_t* bottom);
void dda_pass(const SquareScene& sc, RayColumns& rays, const int* list, const double* t_safe, int n,
              double* out_t, uint8_t* resolved);
}  // namespace avx2

}  // namespace pxh::vector_walk
