// The parametric marcher: one search whose knobs reproduce the parallax that engines ship (and
// pxh's own steep / pom / relief), in pxh's convention (docs/conventions.md): surface
// z = s (h - b), V toward the eye, P the sample. The knobs are declared once, in
// methods/march/knobs.h (MarchConfig, the parameters, the uniforms and their GLSL declarations).
// Engine presets (methods/march/presets/ENGINE.cpp, methods/march/preset.h) are named settings
// of it; the `march` method exposes every knob. Its GLSL twin is methods/march/march.frag.glsl
// (same operations in the same order; pm_* uniforms). What engines do around the search with
// the sample's level of detail (lod_fade) and pad_fetches: march(), below.
//
// search = offset (one fetch): uv = P + z(P) * d * f, d = V.xy (v mirrored with mirror_v),
//   f = 1 / V.z (tan), 1 (sin), 1 / (V.z + offset_soften) (soft), V.z (sincos).
// search = layers: n layers (count rule below), per-layer depth dz = s / n, direction
//   d = V.xy / V.z (step = tan) or V.xy (step = sin: the ray's horizontal travel over the slab is
//   s sin(theta), not s tan(theta)); layer x (real) at uv(x) = uv0 + duv x, ray z(x) = z0 - dz x,
//   z0 = z_top = s (1 - b), uv0 = P + d z0, duv = -d dz; g(x, zs) = z(x - lag) - zs.
//   first = sample: layer 0 is fetched and tested; top / bottom: layer 0 is not fetched, its
//   surface is taken as h = 1 / h = 0, and the search starts at layer 1.
//   k advances while g_k is not a hit (compare le: g <= 0, lt: g < 0) and k < kmax,
//   kmax = ceil(n) + extra_layers, capped by max_steps when > 0.
//   No hit at kmax: on_miss = last (uv_k), next (uv_{k+1}, not fetched) or refine (refine as if
//   hit; with lag the refinement uses unlagged ray depths, as OGRE's counter has moved on).
//   k = 0: uv_0 unless refine_at_k0 (then the layer before is -1).
//   refine = none: uv_k.  lerp: w = g_k / (g_k - g_{k-1}) on uv_{k-1} (clamp_weight: w in [0, 1]
//   and uv_k when g_k - g_{k-1} is not negative; refetch: layer k-1 fetched again).  bisect:
//   x = k, d = 1; iterations + 1 times: d /= 2, move by the sign of g (> 0 deeper, < 0 back,
//   0: back, or stay with tie = stay), then probe g at x (not after the last move unless
//   probe_last).  secant (regula falsi on normalised heights r = z / s + b): bracket
//   (k - 1, k); up to `iterations` times: ih = (r0 d1 - r1 d0) / (d1 - d0), probe h there,
//   delta = ih - h, stop when |delta| <= tolerance, else replace the end of the bracket with
//   delta's sign; uv of the last probe.  contact: from layer k - 1, sub-layers of 1 / n until a
//   hit (at most ceil(n) + 1), uv of that sub-layer.
// max_slope > 0: the direction d (after the step rule) is capped at that length, the start uv0
//   too (PlayCanvas' parallaxMaxSlope). clamp_depth: an answer that is a layer x (not lerp's)
//   is taken at clamp(x, 0, n).
// The count rules: texels: n = clamp(t / texels_per_step, 1, layers_max), t = march_texels (the
//   march's span s |d| in texels of the sample's level L = max(lambda, 0)).  fixed: n = layers.
//   mix: n = layers_max (1 - |V.z|) + layers_min |V.z|. mix_trunc: n = trunc(layers_max +
//   (layers_min - layers_max) V.z).  mix_negated: n = layers_max + (-V.z) (layers_min -
//   layers_max).  angle_scaled: a = fastacos(z of normalize(s V.xy, V.z)) 2 / pi clamped to [0, 1],
//   n = trunc(layers_min + (layers_max - layers_min) a).  mix_scaled: n = layers_min (1 - a) +
//   (layers_max s) a, a = 1 - V.z.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "methods/depth.h"
#include "methods/march/knobs.h"
#include "methods/method.h"

namespace pxh {

// Hastings-style polynomial arccos on [0, 1] as HDRP's FastACosPos: p(x) sqrt(1 - x).
template <typename T>
T fast_acos_pos(T x) {
    const T p = (T(0.0468878) * x - T(0.203471)) * x + T(1.570796);
    return p * std::sqrt(T(1) - x);
}

// `texels`: the march's span in texels of the sample's level (march_texels; count = texels).
template <typename T>
T march_layer_count(const MarchConfig& c, const Scene<T>& sc, T texels = T(0)) {
    const T vz = sc.V.z, lo = T(c.layers_min), hi = T(c.layers_max);
    switch (c.count) {
        case MarchConfig::Fixed:
            return T(c.layers);
        case MarchConfig::Texels:
            return std::clamp(texels / T(c.texels_per_step), T(1), hi);
        case MarchConfig::MixTrunc:
            return std::trunc(hi + (lo - hi) * vz);
        case MarchConfig::MixNegated:
            return hi + (-vz) * (lo - hi);
        case MarchConfig::AngleScaled: {
            const Vec2<T> xy = sc.V.xy() * sc.scale;
            const T zn = vz / std::sqrt(xy.x * xy.x + xy.y * xy.y + vz * vz);
            const T a = std::clamp(fast_acos_pos(std::abs(zn)) * T(0.636619772), T(0), T(1));
            return std::trunc(lo + (hi - lo) * a);
        }
        case MarchConfig::MixScaled: {
            const T a = T(1) - vz;
            return lo * (T(1) - a) + (hi * sc.scale) * a;
        }
        default: {
            const T a = std::abs(vz);
            return hi * (T(1) - a) + lo * a;
        }
    }
}

// The layered search's direction, uv per unit of surface depth: V.xy (v mirrored with
// mirror_v), divided by V.z with step = tan, its length capped at max_slope when that is > 0.
template <typename T>
Vec2<T> march_direction(const MarchConfig& c, const Scene<T>& sc) {
    Vec2<T> d = sc.V.xy();
    if (c.mirror_v) d.y = -d.y;
    if (c.step == MarchConfig::StepTan) d = d * (T(1) / sc.V.z);
    if (c.max_slope > 0) {
        const T len = std::sqrt(d.x * d.x + d.y * d.y), cap = T(c.max_slope);
        if (len > cap) d = d * (cap / len);
    }
    return d;
}

// The march's span over the whole depth s, in texels of level L of a W x H field:
// |(s d.x W, s d.y H)| / 2^L (PlayCanvas' marchTexels).
template <typename T>
T march_texels(const Scene<T>& sc, Vec2<T> d, int W, int H, T L) {
    const T x = sc.scale * d.x * T(W), y = sc.scale * d.y * T(H);
    return std::sqrt(x * x + y * y) / std::exp2(L);
}

// The last layer index the search may reach for this view (kmax).
template <typename T>
int march_kmax(const MarchConfig& c, T n) {
    double kmax = std::ceil(double(n)) + c.extra_layers;
    if (!(kmax < 1e6)) kmax = 1e6;  // n from a degenerate view: the loop stays bounded
    int k = int(std::max(kmax, 0.0));
    if (c.max_steps > 0) k = std::min(k, c.max_steps);
    return c.first == MarchConfig::FirstSample ? k : std::max(k, 1);
}

// The offset search: one fetch at P (z_m: the surface at uv, MethodHit::z NaN).
template <typename T>
MethodHit<T> march_offset(const MarchConfig& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P,
                          Vec2<T> d) {
    const T z = hs.z(P);
    switch (c.offset_form) {
        case MarchConfig::OffSin:
            return {P + d * z};
        case MarchConfig::OffSoft:
            return {P + d * (z / (sc.V.z + T(c.offset_soften)))};
        case MarchConfig::OffSinCos:
            return {P + d * (z * sc.V.z)};
        default:
            return {P + d * (z / sc.V.z)};
    }
}

// The layered search's line: layer position x lies at uv0 + duv x, on the ray at depth
// z0 - dz x; the sign test g against the surface sample zs, `lag` layers behind.
template <typename T>
struct MarchLine {
    const MarchConfig& c;
    Vec2<T> uv0, duv;
    T z0, dz, n, s, b, lag;
    Vec2<T> uv_at(T x) const { return uv0 + duv * x; }
    T ray_z(T x) const { return z0 - dz * x; }
    // An answer that is a layer position (clamp_depth: inside the slab).
    MethodHit<T> answer(T x) const {
        const T xc = c.clamp_depth ? std::clamp(x, T(0), n) : x;
        return MethodHit<T>{uv_at(xc), ray_z(xc)};
    }
    T g_of(T x, T zs) const { return ray_z(x - lag) - zs; }
    bool hit(T g) const { return c.compare == MarchConfig::Lt ? g < T(0) : g <= T(0); }
};

// Where the search stopped: layer k, its sample zs and the layer before's (if fetched).
template <typename T>
struct MarchStop {
    int k = 0;
    T zs = T(0), zs_prev = T(0);
    bool has_prev = false;
};

template <typename T>
MethodHit<T> march_lerp(const MarchLine<T>& L, HeightSampler<T>& hs, MarchStop<T> st, T gk) {
    const int k = st.k;
    if (!st.has_prev || L.c.refetch) st.zs_prev = hs.z(L.uv_at(T(k - 1)));
    const T gp = L.g_of(T(k - 1), st.zs_prev);
    const T denom = gk - gp;
    T w = gk / denom;
    if (L.c.clamp_weight) {
        if (!(denom < T(0))) return {L.uv_at(T(k)), L.ray_z(T(k))};
        w = std::clamp(w, T(0), T(1));
    }
    return {L.uv_at(T(k - 1)) * w + L.uv_at(T(k)) * (T(1) - w),
            L.ray_z(T(k - 1)) * w + L.ray_z(T(k)) * (T(1) - w)};
}

template <typename T>
MethodHit<T> march_bisect(const MarchLine<T>& L, HeightSampler<T>& hs, int k, T gk) {
    T x = T(k), step = T(1), g = gk;
    for (int i = 0; i <= L.c.iterations; ++i) {
        step = step * T(0.5);
        if (g > T(0)) x = x + step;
        else if (g < T(0) || L.c.tie == MarchConfig::TieBack) x = x - step;
        if (i < L.c.iterations) g = L.g_of(x, hs.z(L.uv_at(x)));
    }
    if (L.c.probe_last) (void)hs.z(L.uv_at(x));
    return L.answer(x);
}

template <typename T>
MethodHit<T> march_secant(const MarchLine<T>& L, HeightSampler<T>& hs, MarchStop<T> st, T gk) {
    const int k = st.k;
    const T s = L.s, b = L.b;
    if (!st.has_prev) st.zs_prev = hs.z(L.uv_at(T(k - 1)));
    const T xp = T(k - 1) - L.lag, xk = T(k) - L.lag;  // the ray depths the search compared
    T r0 = L.ray_z(xp) / s + b, d0 = L.g_of(T(k - 1), st.zs_prev) / s;
    T r1 = L.ray_z(xk) / s + b, d1 = gk / s;
    T x = T(k);
    for (int i = 0; i < L.c.iterations; ++i) {
        const T ih = (r0 * d1 - r1 * d0) / (d1 - d0);
        x = (L.z0 - s * (ih - b)) / L.dz;
        const T delta = ih - hs.height(L.uv_at(x));
        if (std::abs(delta) <= T(L.c.tolerance)) break;
        if (delta < T(0)) {
            r1 = ih;
            d1 = delta;
        } else {
            r0 = ih;
            d0 = delta;
        }
    }
    return L.answer(x);
}

template <typename T>
MethodHit<T> march_contact(const MarchLine<T>& L, HeightSampler<T>& hs, MarchStop<T> st) {
    const T base = T(st.k - 1), sub = T(1) / L.n;
    if (!st.has_prev) st.zs_prev = hs.z(L.uv_at(base));
    T x = base, g = L.g_of(base, st.zs_prev);
    const int jmax = march_kmax(MarchConfig{}, L.n) + 1;
    for (int j = 1; !L.hit(g) && j <= jmax; ++j) {
        x = base + sub * T(j);
        g = L.g_of(x, hs.z(L.uv_at(x)));
    }
    return L.answer(x);
}

// The search and its refinement (the knobs up to tolerance); march() below adds what the
// engines do around it. The layered search hands back its answer's height on its own line
// (z = z0 - dz x at the answer's layer position x: the layer's, or the refined one's); the
// offset search is one fetch (march_offset).
template <typename T>
MethodHit<T> march_search(const MarchConfig& c, const Scene<T>& sc, HeightSampler<T>& hs,
                          Vec2<T> P) {
    Vec2<T> d = sc.V.xy();
    if (c.mirror_v) d.y = -d.y;
    if (c.search == MarchConfig::Offset) return march_offset(c, sc, hs, P, d);
    const T s = sc.scale, b = sc.bias;
    d = march_direction(c, sc);
    const T texels =
        c.count == MarchConfig::Texels
            ? march_texels(sc, d, hs.field().width, hs.field().height, std::max(hs.lod(), T(0)))
            : T(0);
    const T n = march_layer_count(c, sc, texels);
    const T dz = s / n;
    const T z0 = sc.z_top();
    MarchLine<T> L{c, P + d * z0, d * (-dz), z0, dz, n, s, b, c.lag ? T(1) : T(0)};
    const int kmax = march_kmax(c, n);

    MarchStop<T> st;
    if (c.first == MarchConfig::FirstSample) {
        st.zs = hs.z(L.uv0);
    } else {
        st.zs_prev = s * ((c.first == MarchConfig::FirstTop ? T(1) : T(0)) - b);
        st.has_prev = true;
        st.k = 1;
        st.zs = hs.z(L.uv_at(T(1)));
    }
    while (!L.hit(L.g_of(T(st.k), st.zs)) && st.k < kmax) {
        ++st.k;
        st.zs_prev = st.zs;
        st.has_prev = true;
        st.zs = hs.z(L.uv_at(T(st.k)));
    }
    if (!L.hit(L.g_of(T(st.k), st.zs))) {
        if (c.on_miss == MarchConfig::MissLast) return L.answer(T(st.k));
        if (c.on_miss == MarchConfig::MissNext) return L.answer(T(st.k + 1));
        L.lag = T(0);
    }
    if (c.refine == MarchConfig::RefineNone) return L.answer(T(st.k));
    if (st.k == 0 && !c.refine_at_k0) return L.answer(T(0));
    const T gk = L.g_of(T(st.k), st.zs);
    switch (c.refine) {
        case MarchConfig::Lerp:
            return march_lerp(L, hs, st, gk);
        case MarchConfig::Bisect:
            return march_bisect(L, hs, st.k, gk);
        case MarchConfig::Secant:
            return march_secant(L, hs, st, gk);
        case MarchConfig::Contact:
            return march_contact(L, hs, st);
        default:
            return L.answer(T(st.k));
    }
}

// The fetches a search that runs to kmax makes: what pad_fetches fills up to.
template <typename T>
int march_full_fetches(const MarchConfig& c, const Scene<T>& sc, T texels) {
    if (c.search == MarchConfig::Offset) return 1;
    const int kmax = march_kmax(c, march_layer_count(c, sc, texels));
    return (c.first == MarchConfig::FirstSample ? 1 : 0) + kmax;
}

// The marcher: the search (march_search), then pad_fetches and the level-of-detail rule
// (lod_fade) on the sample's level of detail L = max(lambda, 0) (HeightSampler::lod(); the
// engines clamp their level at 0 before using it), with t = lod_threshold:
//   hdrp (HDRP's ParallaxOcclusionMapping: offset *= 1 - saturate(lod - lodThreshold)):
//     f = 1 - clamp(L - t, 0, 1); uv = P + (uv - P) f, applied only when f < 1, so that below
//     the threshold the uv is the search's own, bit for bit. The search runs at every L.
//   dxsdk (the DirectX SDK sample's RenderScenePS): L > t: P (bump mapping: the search is not
//     run, nothing is fetched); t - 1 < L <= t: uv = uv + (P - uv) frac(L) (HLSL's
//     lerp(texSampleBase, texCoord, frac)); L <= t - 1: the search's uv.
//   texels (PlayCanvas' occlusion mode): f = clamp((m - fade_texels_min) / (fade_texels_max -
//     fade_texels_min), 0, 1), m = march_texels at L; f = 0: P, the search not run; else
//     uv = P + (uv - P) f, applied only when f < 1.
//
// The hit's height z_m moves with the uv (the faded point on its own line: z_m f, z_m (1 - frac);
// P itself: 0); the offset search's stays the surface's at the final uv. engine_z (HDRP's depth
// offset reads it): the last probe's surface height at the unfaded uv, as HDRP's
// ParallaxOcclusionMapping sets outHeight = currHeight before its fade scales the offset.
template <typename T>
MethodHit<T> march(const MarchConfig& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
    const T L = std::max(hs.lod(), T(0));
    const T t = T(c.lod_threshold);
    const bool layered = c.search != MarchConfig::Offset;
    // P itself, the search not run: a layered search's line is at 0 there
    const MethodHit<T> at_P{P, layered ? T(0) : std::numeric_limits<T>::quiet_NaN()};
    if (c.lod_fade == MarchConfig::FadeDxsdk && L > t) return at_P;
    T f = T(1);
    if (c.lod_fade == MarchConfig::FadeTexels) {
        const T m =
            march_texels(sc, march_direction(c, sc), hs.field().width, hs.field().height, L);
        const T lo = T(c.fade_texels_min), hi = T(c.fade_texels_max);
        f = std::clamp((m - lo) / (hi - lo), T(0), T(1));
        if (!(f > T(0))) return at_P;
    }
    const int fetched_before = hs.fetches;
    MethodHit<T> r = march_search(c, sc, hs, P);
    Vec2<T>& uv = r.uv;
    if (c.pad_fetches) {
        const T texels =
            c.count == MarchConfig::Texels
                ? march_texels(sc, march_direction(c, sc), hs.field().width, hs.field().height, L)
                : T(0);
        const int full = march_full_fetches(c, sc, texels);
        while (hs.fetches - fetched_before < full) (void)hs.height(uv);
    }
    if (c.lod_fade == MarchConfig::FadeHdrp) f = T(1) - std::clamp(L - t, T(0), T(1));
    if (c.lod_fade == MarchConfig::FadeHdrp || c.lod_fade == MarchConfig::FadeTexels) {
        if (f < T(1)) {
            if (c.depth_offset == MarchConfig::PdoHdrp) {
                const int before = hs.fetches;  // the engine's last probe (already counted)
                r.engine_z = hs.z(uv);
                hs.fetches = before;
            }
            uv = P + (uv - P) * f;
            if (layered) r.z = r.z * f;
        }
    } else if (c.lod_fade == MarchConfig::FadeDxsdk && L > t - T(1)) {
        const T frac = L - std::floor(L);
        uv = uv + (P - uv) * frac;
        if (layered) r.z = r.z - r.z * frac;
    }
    return r;
}

// The depth the engine writes (depth = engine; docs/conventions.md section 11), as depth(X_w)
// along the view's depth axis f from P, by depth_offset:
//   none: the polygon's (0).
//   hdrp (Unity HDRP: ApplyPerPixelDisplacement returns depthOffset = (maxHeight - h maxHeight) /
//     ClampNdotV(NdotV), h the last probe's height; ApplyDepthOffsetPositionInput moves the
//     position by depthOffset (-V) and reprojects it): X_w = P - V (z_top - z_s) / max(V.z,
//     1e-4), z_s = s (h - b) with h the last probe's, at the unfaded uv
//     (PerPixelDisplacement.hlsl @ c8df1d81db96, ParallaxOcclusionMapping: outHeight =
//     currHeight, then offset *= 1 - saturate(lod - lodThreshold); MethodHit::engine_z).
//   o3de (O3DE CalcPixelDepthOffset: the tangent-space offset, its z the marched depth,
//     reprojected through viewProj; an offset whose z ends above the polygon is zeroed): the
//     layered search: X_w = (uv_m, z_line), P where z_line > 0; the offset search (Basic, whose
//     offset has z = 0): X_w = (uv_m, 0).
//   unreal_legacy, unreal_camera (Unreal's MaterialTemplate.ush, PIXEL_DEPTH_OFFSET_MODE legacy /
//     camera vector; the material's pixel depth offset PDO taken as the ray's length from P to
//     the search's hit, -z_line / V.z, as Epic's ParallaxOcclusionMapping function is described
//     to output it: its graph is a binary asset, not read): legacy: view depth + max(PDO, 0)
//     (along f); camera vector: view depth + max(PDO cos a, 0), cos a = -V . f (the point on the
//     ray at length PDO).
inline double march_engine_depth(const MarchConfig& c, const EngineDepthInput& in) {
    const Vec3d V = in.V, f = in.f;
    const double vf = V.x * f.x + V.y * f.y + V.z * f.z;  // V . f (< 0: V points back)
    switch (c.depth_offset) {
        case MarchConfig::PdoHdrp: {
            const double z_top = in.scale * (1 - in.bias);
            return -vf * (z_top - in.z_engine) / std::max(V.z, 1e-4);
        }
        case MarchConfig::PdoO3de: {
            if (c.search == MarchConfig::Offset) return depth_offset(in.P, f, in.uv, 0.0);
            if (in.z_line > 0) return 0;
            return depth_offset(in.P, f, in.uv, in.z_line);
        }
        case MarchConfig::PdoUnrealLegacy:
            return std::max(-in.z_line / V.z, 0.0);
        case MarchConfig::PdoUnrealCamera:
            return std::max(-in.z_line / V.z * -vf, 0.0);
        default:
            return 0;
    }
}

// Declared bound on fetches per sample for this view, in float and double alike.
inline int march_max_fetches(const MarchConfig& c, const Scene<double>& sc) {
    if (c.search == MarchConfig::Offset) return 1;
    // count = texels: its largest count, layers_max
    const double nd = march_layer_count(c, sc, std::numeric_limits<double>::infinity());
    const float nf =
        march_layer_count(c, scene_cast<float>(sc), std::numeric_limits<float>::infinity());
    const int kmax = std::max(march_kmax(c, nd), march_kmax(c, nf));
    const int n_ceil = int(std::min(std::max(std::ceil(nd), double(std::ceil(nf))), 1e6));
    int f = (c.first == MarchConfig::FirstSample ? 1 : 0) + kmax;
    switch (c.refine) {
        case MarchConfig::Lerp:
            f += 1;
            break;
        case MarchConfig::Bisect:
            f += c.iterations + (c.probe_last ? 1 : 0);
            break;
        case MarchConfig::Secant:
            f += c.iterations + 1;
            break;
        case MarchConfig::Contact:
            f += n_ceil + 3;
            break;
        default:
            break;
    }
    return f;
}

// The GLSL twin's uniforms (methods/march/march.frag.glsl): every knob, by its pm_ name, in the
// table's order (methods/march/knobs.h; implemented in knobs.cpp).
GlUniforms march_uniforms(const MarchConfig& c);

}  // namespace pxh
