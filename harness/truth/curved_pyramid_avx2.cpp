// The pyramid tracer's avx2 path: curved_pyramid_lanes.h's kernel, 4 rays to a vector
// (CurvedPyramid::trace_many picks it where the CPU has avx2). Every header this file takes
// from the library and the standard library is included before the target pragma, so their
// inline functions stay compiled for every CPU; only the kernel and the lane type after it
// are compiled for avx2. GCC 12's gathers start from _mm256_undefined_pd(), which its
// -Wmaybe-uninitialized reports once inlined (a known false positive, as in ray_walk_simd.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

#include "harness/scene/heightfield.h"
#include "harness/truth/cell_solver.h"
#include "harness/truth/curved_pyramid.h"

#if PXH_PYRAMID_LANES
#pragma GCC push_options
#pragma GCC target("avx2")
#define PXH_LANES_AVX2 1
#include "harness/truth/curved_pyramid_lanes.h"

namespace pxh {

void CurvedPyramid::trace_avx2(const WorldRay* rays, size_t n, One* out, long long max_steps,
                               const std::atomic<bool>* stop) const {
    PyramidLanes<Lanes4> lanes(*this, atan_table());
    lanes.run(rays, n, out, max_steps, stop);
}

}  // namespace pxh

#pragma GCC pop_options
#endif
