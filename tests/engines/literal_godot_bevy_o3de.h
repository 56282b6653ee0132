// Literal re-expressions of the parallax loops shipped by Godot 4 (BaseMaterial3D), Bevy
// (StandardMaterial) and O3DE (Atom StandardPBR), for the engine preset tests. Each
// function keeps the engine's variable names, order of operations, loop structure and constants,
// in float as the GPU runs it, written from the public sources cited above it (read for facts,
// not pasted). Inputs are pxh's: hf (h, white = high), s (pxh scale), V (unit, toward the eye,
// x = +u, y = +v), P (sample point). Each function converts them to what the engine's shader sees
// (its depth texel, its height-scale setting, its view vector) and returns the engine's uv in pxh
// coordinates with its fetch count. Heights are fetched with HeightSampler<float>(hf, 1, 0)
// .height(uv) (bilinear, wrapping, LOD 0; Godot and O3DE use implicit / gradient LOD, which pxh
// ignores). Research notes: /work/research/godot_bevy_o3de.md.
#pragma once
#include <algorithm>
#include <cmath>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "tests/engines/literal_common.h"

namespace pxh::literal {

namespace gbo_shader {
using namespace gpu;
}  // namespace gbo_shader

// ---- Godot 4 BaseMaterial3D height mapping --------------------------------------------------
// godotengine/godot scene/resources/material.cpp @ 0059d788b03b559846087c2a1b86a0e19cbdc4ce,
// BaseMaterial3D::_update_shader, the FEATURE_HEIGHT_MAPPING block ("Height: Enabled", "Height
// Deep Parallax: Enabled"); defaults from the constructor (heightmap_scale 5, min / max layers 8 /
// 32, flips off) and doc/classes/BaseMaterial3D.xml @ 004b2aacb7e87503a583f23e7cf6435aa74b4edf.
// Convention: the texel is a height (white = high, FLAG_INVERT_HEIGHTMAP off) and the shader forms
// depth = 1 - texel; the march starts at depth 0 at P (pxh b = 1). heightmap_scale = s / 0.01
// (the shader multiplies it by 0.01). View: view_dir = normalize(V_view * mat3(TANGENT * flip.x,
// -BINORMAL * flip.y, NORMAL)); Godot's BINORMAL is the negated mikktspace bitangent
// (surface_tool.cpp), so -BINORMAL = +dP/dv and with default flips view_dir = pxh V; flip_tangent
// negates its x, flip_binormal its y.
inline Vec3<float> godot_view_dir(Vec3<float> V, bool heightmap_flip_tangent,
                                  bool heightmap_flip_binormal) {
    const float flip_x = heightmap_flip_tangent ? -1.0f : 1.0f;
    const float flip_y = heightmap_flip_binormal ? -1.0f : 1.0f;
    // Row vector times mat3(T flip.x, -B flip.y, N): (V.T flip.x, V.(-B) flip.y, V.N), and
    // V.(-B) = V.(+dP/dv) = pxh V.y.
    return gbo_shader::normalize(Vec3<float>(V.x * flip_x, V.y * flip_y, V.z));
}

// Deep parallax off: one fetch, "offset limiting" (no division by view_dir.z).
inline EngineResult godot_parallax(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                   bool heightmap_flip_tangent = false,
                                   bool heightmap_flip_binormal = false) {
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    auto texture_heightmap_r = [&](Vec2<float> uv) { return hs.height(uv); };
    const float heightmap_scale = s / 0.01f;
    const Vec2<float> base_uv = P;
    const Vec3<float> view_dir = godot_view_dir(V, heightmap_flip_tangent, heightmap_flip_binormal);
    const float depth = 1.0f - texture_heightmap_r(base_uv);
    const Vec2<float> ofs = base_uv - view_dir.xy() * depth * heightmap_scale * 0.01f;
    return {ofs, hs.fetches};
}

// Deep parallax on: view-adaptive layers, no division by view_dir.z, no loop cap, the previous
// layer fetched again for the interpolation (always executed, also when the loop did not run).
inline EngineResult godot_deep(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                               int heightmap_min_layers = 8, int heightmap_max_layers = 32,
                               bool heightmap_flip_tangent = false,
                               bool heightmap_flip_binormal = false) {
    using namespace gbo_shader;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    auto texture_heightmap_r = [&](Vec2<float> uv) { return hs.height(uv); };
    const float heightmap_scale = s / 0.01f;
    const Vec2<float> base_uv = P;
    const Vec3<float> view_dir = godot_view_dir(V, heightmap_flip_tangent, heightmap_flip_binormal);

    const float num_layers = mix(float(heightmap_max_layers), float(heightmap_min_layers),
                                 std::abs(dot(Vec3<float>(0.0f, 0.0f, 1.0f), view_dir)));
    const float layer_depth = 1.0f / num_layers;
    [[maybe_unused]] const float current_layer_depth = 0.0f;  // declared, unused by the shader
    const Vec2<float> p = view_dir.xy() * heightmap_scale * 0.01f;
    const Vec2<float> delta = div(p, num_layers);
    Vec2<float> ofs = base_uv;
    float depth = 1.0f - texture_heightmap_r(ofs);
    float current_depth = 0.0f;
    while (current_depth < depth) {
        ofs = ofs - delta;
        depth = 1.0f - texture_heightmap_r(ofs);
        current_depth += layer_depth;
    }
    const Vec2<float> prev_ofs = ofs + delta;
    const float after_depth = depth - current_depth;
    const float before_depth = (1.0f - texture_heightmap_r(prev_ofs)) - current_depth + layer_depth;
    const float weight = after_depth / (after_depth - before_depth);
    ofs = mix(ofs, prev_ofs, weight);
    return {ofs, hs.fetches};
}

// ---- Bevy StandardMaterial parallax mapping -------------------------------------------------
// bevyengine/bevy crates/bevy_pbr/src/render/parallax_mapping.wgsl @
// 1cb1d0dc0fd5f4b3bd9c80ea3ec895c8955a4158 (fn parallaxed_uv, fn sample_depth_map; the file is
// parallax_mapping.wesl at 4805ca792c3e94eef07afd6fa9a2712f388c9a67 with the same algorithm).
// Defaults: crates/bevy_pbr/src/pbr_material.rs (StandardMaterial::default: parallax_depth_scale
// 0.1, max_parallax_layer_count 16, method Occlusion) and crates/bevy_pbr/src/parallax.rs
// (ParallaxMappingMethod::DEFAULT_RELIEF_MAPPING: max_steps 5). Texture: a DEPTH map (white =
// bottom), sampled with textureSampleLevel(.., 0.0); to run a pxh height field through it the
// texel is D = 1 - h (pxh b = 1). depth_scale = s (uv units).
// View: the caller (pbr_fragment) passes Vt = -(V.T, V.B, V.N) with V toward the eye and the
// shader steps by Vt.xy * vec2(1, -1), so its v step has the opposite sign of its u step
// relative to B. mirror_v picks the frame:
//   mirror_v = false: B = -dP/dv (tangent.w following a "green up, v down" convention); the
//     engine's V.B is -pxh V.y, the flip cancels and the step equals pxh's -V.xy / V.z (the
//     preset's default).
//   mirror_v = true: B = +dP/dv (mikktspace on pxh's uv, what bevy_mikktspace computes); the
//     engine's V.B is +pxh V.y and the literal code marches with v mirrored.
inline EngineResult bevy_parallaxed_uv(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                       bool relief_mapping, float max_parallax_layer_count = 16.0f,
                                       unsigned max_relief_mapping_search_steps = 5,
                                       bool mirror_v = false) {
    using namespace gbo_shader;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    auto sample_depth_map = [&](Vec2<float> uv) { return 1.0f - hs.height(uv); };
    const float depth_scale = s;
    const float max_layer_count = max_parallax_layer_count;
    const unsigned max_steps = max_relief_mapping_search_steps;
    const Vec2<float> original_uv = P;
    const Vec3<float> V_engine(V.x, mirror_v ? V.y : -V.y, V.z);  // (V.T, V.B, V.N)
    const Vec3<float> Vt = gbo_shader::scale(V_engine, -1.0f);    // "to go toward the surface"

    if (max_layer_count < 1.0f) return {original_uv, hs.fetches};
    Vec2<float> uv = original_uv;

    const float view_steepness = std::abs(Vt.z);
    const float layer_count = mix(max_layer_count, 1.0f, view_steepness);
    const float layer_depth = 1.0f / layer_count;
    Vec2<float> delta_uv =
        div(mul(Vt.xy() * (depth_scale * layer_depth), Vec2<float>(1.0f, -1.0f)), view_steepness);

    float current_layer_depth = 0.0f;
    float texture_depth = sample_depth_map(uv);
    for (int i = 0; texture_depth > current_layer_depth && i <= int(layer_count); i++) {
        current_layer_depth += layer_depth;
        uv = uv + delta_uv;
        texture_depth = sample_depth_map(uv);
    }

    if (relief_mapping) {
        delta_uv = delta_uv * 0.5f;
        float delta_depth = 0.5f * layer_depth;
        uv = uv - delta_uv;
        current_layer_depth -= delta_depth;
        for (unsigned i = 0u; i < max_steps; i++) {
            texture_depth = sample_depth_map(uv);
            delta_uv = delta_uv * 0.5f;
            delta_depth *= 0.5f;
            if (texture_depth > current_layer_depth) {
                uv = uv + delta_uv;
                current_layer_depth += delta_depth;
            } else {
                uv = uv - delta_uv;
                current_layer_depth -= delta_depth;
            }
        }
    } else {
        const Vec2<float> previous_uv = uv - delta_uv;
        const float next_depth = texture_depth - current_layer_depth;
        const float previous_depth =
            sample_depth_map(previous_uv) - current_layer_depth + layer_depth;
        const float weight = next_depth / (next_depth - previous_depth);
        uv = mix(uv, previous_uv, weight);
    }
    return {uv, hs.fetches};
}

inline EngineResult bevy_occlusion(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                   float max_parallax_layer_count = 16.0f, bool mirror_v = false) {
    return bevy_parallaxed_uv(hf, s, V, P, false, max_parallax_layer_count, 0, mirror_v);
}
inline EngineResult bevy_relief(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                float max_parallax_layer_count = 16.0f, unsigned max_steps = 5,
                                bool mirror_v = false) {
    return bevy_parallaxed_uv(hf, s, V, P, true, max_parallax_layer_count, max_steps, mirror_v);
}

// ---- O3DE Atom StandardPBR parallax ---------------------------------------------------------
// o3de/o3de Gems/Atom/Feature/Common/Assets/ShaderLib/Atom/Features/ParallaxMapping.azsli @
// 0eeae056a6f1fad451407b5b127d5599e857d1bd (same text at 354a2accd2a21779bbd68812bd69e7e957262cc7):
// SampleDepthFromHeightmap, GetNormalizedDepth, BasicParallaxMapping, AdvancedParallaxMapping,
// CalculateParallaxOffset (quality Low / Medium / High / Ultra = 16 / 32 / 64 / 128 steps);
// ParallaxInput.azsli (GetParallaxInput: depthOffset = -offset, uv += offset.xy); defaults from
// Materials/Types/MaterialInputs/ParallaxPropertyGroup.json (factor 0.05, offset 0, algorithm
// POM, quality Low). Convention: height map (white = high), normalized depth 1 - texel;
// depthFactor = s in uv units; offset 0 is pxh b = 1 (offset > 0 is b = 1 - offset / s with the
// relief above the polygon clipped onto it, which pxh's truth does not model). View:
// dirToCameraTS = normalize(V.T, V.B, V.N) with B = +dP/dv (ConstructTBN, mikktspace) = pxh V.
// Self-shadowing, pixel depth offset and the clipping highlight do not change uv: left out.
enum class O3deAlgorithm { Steep, POM, Relief, Contact };
enum class O3deQuality { Low, Medium, High, Ultra };

namespace o3de_detail {
// GetNormalizedDepth(startDepth, stopDepth, inverseDepthRange, uv) with GetDepth =
// SampleDepthFromHeightmap (a Normalized result: 1 - texel).
inline float GetNormalizedDepth(HeightSampler<float>& hs, float startDepth, float stopDepth,
                                float inverseDepthRange, Vec2<float> uv) {
    float normalizedDepth = 0.0f;
    const float m_depth = 1.0f - hs.height(uv);
    if (stopDepth - startDepth > 0.0001f) {
        const float minNormalizedDepth = -startDepth * inverseDepthRange;
        normalizedDepth = std::max(m_depth, minNormalizedDepth);
    }
    return normalizedDepth;
}
}  // namespace o3de_detail

// BasicParallaxMapping: one fetch, no division by z, ignores the offset parameter, no clamp.
inline EngineResult o3de_basic(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    const float depthFactor = s;
    const Vec2<float> uv = P;
    const Vec3<float> dirToCameraTS = gbo_shader::normalize(V);
    // GetNormalizedDepth(0, depthFactor, uv): inverseDepthRange = 1 / (depthFactor - 0).
    const float inverseDepthRange = 1.0f / (depthFactor - 0.0f);
    const Vec2<float> delta =
        dirToCameraTS.xy() *
        o3de_detail::GetNormalizedDepth(hs, 0.0f, depthFactor, inverseDepthRange, uv) * depthFactor;
    Vec3<float> m_offsetTS(0.0f, 0.0f, 0.0f);
    m_offsetTS = Vec3<float>(m_offsetTS.x - delta.x, m_offsetTS.y - delta.y, m_offsetTS.z);
    return {uv + m_offsetTS.xy(), hs.fetches};
}

// AdvancedParallaxMapping (Steep, POM, Relief, Contact) through CalculateParallaxOffset's quality
// switch. offset is the material's "offset" (m_heightmapOffset; depthOffset = -offset).
inline EngineResult o3de_advanced(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                  O3deAlgorithm o_parallax_algorithm,
                                  O3deQuality o_parallax_quality = O3deQuality::Low,
                                  float offset = 0.0f) {
    using namespace gbo_shader;
    using o3de_detail::GetNormalizedDepth;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    const float depthFactor = s;
    const float depthOffset = -offset;
    const Vec2<float> uv = P;
    const Vec3<float> dirToCameraTS = gbo_shader::normalize(V);
    const int numSteps = o_parallax_quality == O3deQuality::Low      ? 16
                         : o_parallax_quality == O3deQuality::Medium ? 32
                         : o_parallax_quality == O3deQuality::High   ? 64
                                                                     : 128;

    const float dirToCameraZInverse = 1.0f / dirToCameraTS.z;
    const float step = float(1.0f / float(numSteps));
    float currentStep = 0.0f;
    const Vec3<float> delta =
        scale(scale(scale(scale(dirToCameraTS, -1.0f), depthFactor), dirToCameraZInverse), step);

    const float depthSearchStart = depthOffset;
    const float depthSearchEnd = depthSearchStart + depthFactor;
    const float inverseDepthFactor = 1.0f / depthFactor;

    Vec3<float> parallaxOffset =
        scale(scale(scale(dirToCameraTS, -1.0f), dirToCameraZInverse), depthOffset);
    auto depthAt = [&](Vec3<float> o) {
        return GetNormalizedDepth(hs, depthSearchStart, depthSearchEnd, inverseDepthFactor,
                                  uv + o.xy());
    };
    float currentSample = depthAt(parallaxOffset);
    float prevSample = 0.0f;  // uninitialised in the shader; only read after the loop ran

    while (currentSample > currentStep) {
        currentStep += step;
        parallaxOffset = add(parallaxOffset, delta);
        prevSample = currentSample;
        currentSample = depthAt(parallaxOffset);
    }

    switch (o_parallax_algorithm) {
        case O3deAlgorithm::Steep:
            break;
        case O3deAlgorithm::POM:
            if (currentStep > 0.0f) {
                const float prevStep = currentStep - step;
                const float currentDiff = currentStep - currentSample;
                const float prevDiff = prevSample - prevStep;
                const float ratio = prevDiff / (prevDiff + currentDiff);
                parallaxOffset = lerp(sub(parallaxOffset, delta), parallaxOffset, ratio);
            }
            break;
        case O3deAlgorithm::Relief:
            if (currentStep > 0.0f) {
                float depthSign = 1.0f;
                Vec3<float> reliefDelta = delta;
                float reliefStep = step;
                for (int i = 0; i < numSteps; i++) {
                    reliefDelta = scale(reliefDelta, 0.5f);
                    reliefStep *= 0.5f;
                    depthSign = float(sign(currentSample - currentStep));
                    parallaxOffset = add(parallaxOffset, scale(reliefDelta, depthSign));
                    currentStep += reliefStep * depthSign;
                    currentSample = depthAt(parallaxOffset);
                }
            }
            break;
        case O3deAlgorithm::Contact:
            if (currentStep > 0.0f) {
                parallaxOffset = sub(parallaxOffset, delta);
                currentStep -= step;
                currentSample = prevSample;
                const Vec3<float> adjustedDelta = scale(delta, step);
                const float adjustedStep = step * step;
                while (currentSample > currentStep) {
                    currentStep += adjustedStep;
                    parallaxOffset = add(parallaxOffset, adjustedDelta);
                    prevSample = currentSample;
                    currentSample = depthAt(parallaxOffset);
                }
            }
            break;
    }

    if (parallaxOffset.z > 0.0f) parallaxOffset = Vec3<float>(0.0f, 0.0f, 0.0f);
    return {uv + parallaxOffset.xy(), hs.fetches};
}

inline EngineResult o3de_steep(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                               O3deQuality quality = O3deQuality::Low) {
    return o3de_advanced(hf, s, V, P, O3deAlgorithm::Steep, quality);
}
inline EngineResult o3de_pom(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                             O3deQuality quality = O3deQuality::Low) {
    return o3de_advanced(hf, s, V, P, O3deAlgorithm::POM, quality);
}
inline EngineResult o3de_relief(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                O3deQuality quality = O3deQuality::Low) {
    return o3de_advanced(hf, s, V, P, O3deAlgorithm::Relief, quality);
}
inline EngineResult o3de_contact(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                 O3deQuality quality = O3deQuality::Low) {
    return o3de_advanced(hf, s, V, P, O3deAlgorithm::Contact, quality);
}

}  // namespace pxh::literal
