// What every literal engine transcription shares (tests/engines/literal_*.h): the result type
// and the few GLSL / WGSL / HLSL operations the shaders use, on pxh's vector types, as the
// shading languages define them.
#pragma once
#include <cmath>

#include "harness/core/vec.h"

namespace pxh::literal {

struct EngineResult {
    Vec2<float> uv;
    int fetches;
};

namespace gpu {
inline float mix(float x, float y, float a) { return x * (1.0f - a) + y * a; }
inline Vec2<float> mix(Vec2<float> x, Vec2<float> y, float a) { return x * (1.0f - a) + y * a; }
// float3 arithmetic (pxh's Vec3 has none).
inline Vec3<float> add(Vec3<float> a, Vec3<float> b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3<float> sub(Vec3<float> a, Vec3<float> b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3<float> scale(Vec3<float> a, float k) { return {a.x * k, a.y * k, a.z * k}; }
// HLSL lerp(x, y, a) = x + a (y - x).
inline Vec3<float> lerp(Vec3<float> x, Vec3<float> y, float a) {
    return add(x, scale(sub(y, x), a));
}
inline float dot(Vec3<float> a, Vec3<float> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float length(Vec2<float> a) { return std::sqrt(a.x * a.x + a.y * a.y); }
// normalize: x * inversesqrt(dot(x, x)); the zero vector gives 0 * inf = NaN, as on GPUs.
inline Vec3<float> normalize(Vec3<float> a) { return scale(a, 1.0f / std::sqrt(dot(a, a))); }
inline Vec2<float> normalize(Vec2<float> a) {
    return a * (1.0f / std::sqrt(a.x * a.x + a.y * a.y));
}
inline Vec2<float> div(Vec2<float> a, float k) { return {a.x / k, a.y / k}; }
inline Vec2<float> mul(Vec2<float> a, Vec2<float> b) { return {a.x * b.x, a.y * b.y}; }
inline float sign(float x) { return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f); }
}  // namespace gpu

}  // namespace pxh::literal
