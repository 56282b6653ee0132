// The qdm method's traversal and refinement (methods/qdm/qdm.cpp; its GLSL twin qdm.frag.glsl
// does the same operations in the same order). Generic over float and double.
//
// In the source's terms (depth d in [0, 1] from the slab top, depth map 1 - h): the ray enters
// the slab top at p = P + (V.xy / V.z) z_top (depth 0) and is at p + v d at depth d, with
// v = -(V.xy / V.z) s (uv per unit of depth). Node depth D = 1 - M, M the node's max height.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/scene.h"
#include "methods/depth.h"
#include "methods/resource.h"

namespace pxh::qdm {

inline int nodes_at(int n, int L) { return std::max(1, n >> L); }
inline int top_level(int W, int H) { return int(std::bit_width(unsigned(std::max(W, H)))) - 1; }

// The traversal: returns the ray point where it stopped, as (uv, depth). tex: r_qdm.
template <typename T>
struct Stop {
    Vec2<T> uv;
    T depth;
    int iterations;
};

template <typename T>
Stop<T> traverse(const Scene<T>& sc, TextureSampler<T>& tex, Vec2<T> p, Vec2<T> v, int cap) {
    const int W = sc.width, H = sc.height;
    const T inf = std::numeric_limits<T>::infinity();
    // fDeltaNC = TEXEL_SPAN_HALF * depth_factor: the nudge past a node border, in depth units.
    const T delta = T(1) / T(2 * W) * sc.scale;
    const T sgx = v.x > T(0) ? T(1) : T(0), sgy = v.y > T(0) ? T(1) : T(0);  // dirSign
    Vec2<T> p2 = p;
    T z2 = T(0);
    int level = top_level(W, H), it = 0;
    while (level >= 0 && it < cap) {
        const T nodes_x = T(nodes_at(W, level)), nodes_y = T(nodes_at(H, level));
        const T d = T(1) - tex.fetch_r(p2, level);  // the node's min depth
        if (d > z2) {
            const Vec2<T> q = p + v * d;  // the predictive point at the node's depth
            const T nx = std::floor(p2.x * nodes_x), ny = std::floor(p2.y * nodes_y);
            T dn = d;
            if (nx != std::floor(q.x * nodes_x) || ny != std::floor(q.y * nodes_y)) {
                // The ray leaves the node first: the depth at the nearest border (the source's
                // b p2.z / a, with a = p2 - p = v p2.z, written b / v so that it holds at p2 = p
                // too), nudged past it; the level stays.
                const T bx = v.x != T(0) ? ((nx + sgx) / nodes_x - p.x) / v.x : inf;
                const T by = v.y != T(0) ? ((ny + sgy) / nodes_y - p.y) / v.y : inf;
                dn = std::min(d, std::min(bx, by)) + delta;
                ++level;
            }
            p2 = p + v * dn;
            z2 = dn;
        }
        --level;
        ++it;
    }
    return {p2, z2, it};
}

// The source's refinement ("manual bilinear filtering"): the ray points one texel (of uv length)
// before and after the stop, their distances to the bilinear surface as weights. Two fetches.
// Returns the refined uv and the ray's height there (z = z_top - s depth on the line p + v depth).
template <typename T>
MethodHit<T> refine(const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> p, Vec2<T> v, Stop<T> st) {
    const T half = T(1) / T(2 * sc.width);  // TEXEL_SPAN_HALF
    const T delta = half * sc.scale;        // fDeltaNC, added to the length as in the source
    const Vec2<T> a = st.uv - p;
    const T len = std::sqrt(a.x * a.x + a.y * a.y) + delta;
    const T dA = st.depth * (len - T(2) * half) / len;  // BILINEAR_SMOOTH_FACTOR = 2
    const T dB = st.depth * (len + T(2) * half) / len;
    const Vec2<T> pa = p + v * dA, pb = p + v * dB;
    const T ea = std::abs(dA - (T(1) - hs.height(pa)));
    const T eb = std::abs(dB - (T(1) - hs.height(pb)));
    // Both on the surface (the source divides 0 by 0 here): the stop itself.
    if (!(ea + eb > T(0))) return {st.uv, sc.z_top() - sc.scale * st.depth};
    const T w = ea / (ea + eb);
    return {pa * (T(1) - w) + pb * w, sc.z_top() - sc.scale * (dA * (T(1) - w) + dB * w)};
}

template <typename T>
MethodHit<T> trace(const Scene<T>& sc, HeightSampler<T>& hs, TextureSampler<T>& tex, Vec2<T> P,
                   int cap, bool with_refinement, int* iterations) {
    const Vec2<T> dir = sc.V.xy() * (T(1) / sc.V.z);
    const Vec2<T> p = P + dir * sc.z_top();
    const Vec2<T> v = dir * (-sc.scale);
    const Stop<T> st = traverse(sc, tex, p, v, cap);
    if (iterations) *iterations = st.iterations;
    if (with_refinement) return refine(sc, hs, p, v, st);
    return {st.uv, sc.z_top() - sc.scale * st.depth};
}

}  // namespace pxh::qdm
