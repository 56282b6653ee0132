// Literal re-expressions of the parallax loops shipped by the JavaScript engines (three.js,
// Babylon.js, PlayCanvas), for the engine preset tests. Each function keeps the
// engine's variable names, order of operations, loop structure and constants, in float as the GPU
// runs it, written from the public sources cited above it (read for facts, not pasted). Inputs are
// pxh's: hf (h, white = high), s (pxh scale), V (unit, toward the eye, x = +u, y = +v), P (sample
// point). Each function converts them to what the engine's shader sees and returns the engine's
// uv in pxh coordinates with its fetch count. Heights are fetched with
// HeightSampler<float>(hf, 1, 0).height(uv) (bilinear, wrapping, LOD 0; the engines use implicit
// or biased LOD, which pxh ignores). Sources, file by file and commit by commit:
// docs/guide/engines.md.
#pragma once
#include <algorithm>
#include <cmath>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "tests/engines/literal_common.h"

namespace pxh::literal {

namespace js_glsl {
using namespace gpu;
}  // namespace js_glsl

// ---- three.js ParallaxShader ---------------------------------------------------------------
// mrdoob/three.js examples/jsm/shaders/ParallaxShader.js @ 05578ec7204d317789959d28ce057ff8c1711d8e
// (fragment function parallaxMap(V), modes as #defines; the UMD copy examples/js/shaders/
// ParallaxShader.js @ 083b224036cd4102c8a9027190c370ca0894bcb0 has the same loop). Defaults from
// examples/webgl_materials_parallaxmap.html @ 76e37a6a21fe4267b82a21b01cd89c96dd0e8c66: minLayers
// 20, maxLayers 25 (the shader's uniforms default to null). Loop cap 30 and 5 relief searches are
// hard-coded in the shader.
// Convention used here: a positive parallaxScale with a DEPTH map, bumpMap.r = t = 1 - h, and
// parallaxScale = s (pxh b = 1). The example itself sets parallaxScale = -0.005 on a height map,
// which marches bottom-up from the slab floor; that variant is not transcribed.
// V: perturbUv builds vProjVtex with xy = the uv change of the view vector's tangential part and
// z = N.V (not normalised); with one world unit per uv tile it is pxh's V.
enum class ThreeMode { basic, steep, occlusion, relief };

inline EngineResult threejs_parallaxMap(const HeightField& hf, float s, Vec3<float> V,
                                        Vec2<float> P, ThreeMode mode,
                                        float parallaxMinLayers = 20.0f,
                                        float parallaxMaxLayers = 25.0f) {
    using namespace js_glsl;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    auto bumpMap_r = [&](Vec2<float> uv) { return 1.0f - hs.height(uv); };  // depth map t = 1 - h
    const float parallaxScale = s;
    const Vec2<float> vUv = P;

    if (mode == ThreeMode::basic) {  // USE_BASIC_PARALLAX: offset limiting, no / V.z
        const float initialHeight = bumpMap_r(vUv);
        const Vec2<float> texCoordOffset = V.xy() * parallaxScale * initialHeight;
        return {vUv - texCoordOffset, hs.fetches};
    }

    const float numLayers =
        mix(parallaxMaxLayers, parallaxMinLayers, std::abs(dot(Vec3<float>(0.0f, 0.0f, 1.0f), V)));
    const float layerHeight = 1.0f / numLayers;
    float currentLayerHeight = 0.0f;
    const Vec2<float> dtex = div(div(V.xy() * parallaxScale, V.z), numLayers);
    Vec2<float> currentTextureCoords = vUv;
    float heightFromTexture = bumpMap_r(currentTextureCoords);
    for (int i = 0; i < 30; i += 1) {
        if (heightFromTexture <= currentLayerHeight) break;
        currentLayerHeight += layerHeight;
        currentTextureCoords = currentTextureCoords - dtex;
        heightFromTexture = bumpMap_r(currentTextureCoords);
    }

    if (mode == ThreeMode::steep) return {currentTextureCoords, hs.fetches};

    if (mode == ThreeMode::relief) {
        Vec2<float> deltaTexCoord = div(dtex, 2.0f);
        float deltaHeight = layerHeight / 2.0f;
        currentTextureCoords = currentTextureCoords + deltaTexCoord;
        currentLayerHeight -= deltaHeight;
        const int numSearches = 5;
        for (int i = 0; i < numSearches; i += 1) {
            deltaTexCoord = div(deltaTexCoord, 2.0f);
            deltaHeight /= 2.0f;
            heightFromTexture = bumpMap_r(currentTextureCoords);
            if (heightFromTexture >
                currentLayerHeight) {  // the shader's comment: "Below the surface"
                currentTextureCoords = currentTextureCoords - deltaTexCoord;
                currentLayerHeight += deltaHeight;
            } else {
                currentTextureCoords = currentTextureCoords + deltaTexCoord;
                currentLayerHeight -= deltaHeight;
            }
        }
        return {currentTextureCoords, hs.fetches};
    }

    // USE_OCLUSION_PARALLAX (sic): re-fetches the previous layer, no clamp, no k = 0 guard.
    const Vec2<float> prevTCoords = currentTextureCoords + dtex;
    const float nextH = heightFromTexture - currentLayerHeight;
    const float prevH = bumpMap_r(prevTCoords) - currentLayerHeight + layerHeight;
    const float weight = nextH / (nextH - prevH);
    return {prevTCoords * weight + currentTextureCoords * (1.0f - weight), hs.fetches};
}

inline EngineResult threejs_basic(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
    return threejs_parallaxMap(hf, s, V, P, ThreeMode::basic);
}
inline EngineResult threejs_steep(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                  float parallaxMinLayers = 20.0f,
                                  float parallaxMaxLayers = 25.0f) {
    return threejs_parallaxMap(hf, s, V, P, ThreeMode::steep, parallaxMinLayers, parallaxMaxLayers);
}
inline EngineResult threejs_occlusion(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                      float parallaxMinLayers = 20.0f,
                                      float parallaxMaxLayers = 25.0f) {
    return threejs_parallaxMap(hf, s, V, P, ThreeMode::occlusion, parallaxMinLayers,
                               parallaxMaxLayers);
}
inline EngineResult threejs_relief(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                   float parallaxMinLayers = 20.0f,
                                   float parallaxMaxLayers = 25.0f) {
    return threejs_parallaxMap(hf, s, V, P, ThreeMode::relief, parallaxMinLayers,
                               parallaxMaxLayers);
}

// ---- Babylon.js StandardMaterial / PBRMaterial --------------------------------------------
// BabylonJS/Babylon.js packages/dev/core/src/Shaders/ShadersInclude/bumpFragmentFunctions.fx
// @ 769119fa3fc4361674f90c61d97435b2b95c1aac (parallaxOcclusion, parallaxOffset; the keepWorking
// form with PARALLAX_RHS), called from ShadersInclude/bumpFragment.fx
// @ 1af75dc439cf808c93e33cecf15dd7f78c688148 with invTBN = transpose(TBN), TBN from cotangent_frame
// (bumpFragmentMainFunctions.fx @ 1f1b9593ab0e8d0bc9fbf131b99db4edacdcad5c).
// parallaxScaleBias (default 0.05, standardMaterial.ts @ 045c2287d92a5104e8c52d1bcd7d3f38de036d4b)
// arrives as vBumpInfos.z: s = parallaxScaleBias. Height = bumpSampler.w (normal-map alpha,
// white = high).
// Frame: the derivative frame is (T, B, N) = (-u, -v, N) in Babylon's default left-handed world
// and (+u, +v, N) with scene.useRightHandedSystem, which also sets PARALLAX_RHS; invTBN * w =
// (T.w, B.w, N.w). viewDirectionW = normalize(eye - pos) = pxh V.
namespace js_glsl {
inline Vec3<float> babylon_invTBN_times(Vec3<float> w, bool PARALLAX_RHS) {
    const float t = PARALLAX_RHS ? 1.0f : -1.0f;  // T = t u, B = t v
    return {t * w.x, t * w.y, w.z};
}
}  // namespace js_glsl

// babylon_parallax: parallaxOffset(invTBN * viewDirectionW, vBumpInfos.z); uv = vBumpUV + uvOffset.
inline EngineResult babylon_parallax(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                     bool PARALLAX_RHS = false) {
    using namespace js_glsl;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    const Vec2<float> vBumpUV = P;
    const Vec3<float> viewDir = babylon_invTBN_times(V, PARALLAX_RHS);
    const float heightScale = s;
    // parallaxOffset
    const float height = hs.height(vBumpUV);  // texture2D(bumpSampler, vBumpUV).w
    const Vec2<float> texCoordOffset = viewDir.xy() * heightScale * height;
    const Vec2<float> uvOffset = PARALLAX_RHS ? texCoordOffset : texCoordOffset * -1.0f;
    return {vBumpUV + uvOffset, hs.fetches};
}

// babylon_pom: parallaxOcclusion(invTBN * -viewDirectionW, invTBN * normalW, vBumpUV,
// vBumpInfos.z); uv = vBumpUV + uvOffset. Always 15 fetches (the loop fetches after the hit too).
inline EngineResult babylon_pom(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                                bool PARALLAX_RHS = false) {
    using namespace js_glsl;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    const Vec2<float> vBumpUV = P;
    const Vec3<float> vViewDirCoT =
        babylon_invTBN_times(Vec3<float>(-V.x, -V.y, -V.z), PARALLAX_RHS);
    const Vec3<float> vNormalCoT =
        babylon_invTBN_times(Vec3<float>(0.0f, 0.0f, 1.0f), PARALLAX_RHS);
    const Vec2<float> texCoord = vBumpUV;
    const float parallaxScale = s;

    const float minSamples = 4.0f;
    const float maxSamples = 15.0f;
    const int iMaxSamples = 15;

    float parallaxLimit = length(vViewDirCoT.xy()) / vViewDirCoT.z;
    parallaxLimit *= parallaxScale;
    const Vec2<float> vOffsetDir = normalize(vViewDirCoT.xy());
    const Vec2<float> vMaxOffset = vOffsetDir * parallaxLimit;
    const float numSamples =
        maxSamples + (dot(vViewDirCoT, vNormalCoT) * (minSamples - maxSamples));
    const float stepSize = 1.0f / numSamples;

    float currRayHeight = 1.0f;
    Vec2<float> vCurrOffset(0.0f, 0.0f);
    Vec2<float> vLastOffset(0.0f, 0.0f);
    float lastSampledHeight = 1.0f;
    float currSampledHeight = 1.0f;
    bool keepWorking = true;
    for (int i = 0; i < iMaxSamples; i++) {
        currSampledHeight = hs.height(texCoord + vCurrOffset);  // texture2D(bumpSampler, ...).w
        if (!keepWorking) {
            // do nothing
        } else if (currSampledHeight > currRayHeight) {
            const float delta1 = currSampledHeight - currRayHeight;
            const float delta2 = (currRayHeight + stepSize) - lastSampledHeight;
            const float ratio = delta1 / (delta1 + delta2);
            vCurrOffset = vLastOffset * ratio + vCurrOffset * (1.0f - ratio);
            keepWorking = false;
        } else {
            currRayHeight -= stepSize;
            vLastOffset = vCurrOffset;
            if (PARALLAX_RHS) vCurrOffset = vCurrOffset - vMaxOffset * stepSize;
            else vCurrOffset = vCurrOffset + vMaxOffset * stepSize;
            lastSampledHeight = currSampledHeight;
        }
    }
    const Vec2<float> uvOffset = vCurrOffset;
    return {vBumpUV + uvOffset, hs.fetches};
}

// ---- PlayCanvas StandardMaterial (stable) --------------------------------------------------
// playcanvas/engine @ e287e0c67f3c20c689a52b7c53d2b7fedbe887da (tag v2.21.4):
// src/scene/shader-lib/glsl/chunks/standard/frag/parallax.js (getParallax); the uniform
// material_heightMapFactor = heightMapFactor * 0.025 (src/scene/materials/standard-material.js,
// heightMapFactor default 1), so s = 0.025 * heightMapFactor; height channel heightMapChannel
// (default 'g'), white = high. dUvOffset is added to the uv of the other maps
// (src/scene/shader-lib/programs/standard.js). dViewDirW = normalize(camera - pos) = pxh V;
// dTBN from vertex tangents with B along +v (engine-generated tangents), so viewDirT = pxh V.
// (The derivative frame used without tangents has y = -v; not transcribed.) v2.21.4 has no
// occlusion mode; the later one is playcanvas_occlusion below. Preset: playcanvas_basic_v2_21.
inline EngineResult playcanvas_basic_v2_21(const HeightField& hf, float s, Vec3<float> V,
                                           Vec2<float> P) {
    using namespace js_glsl;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    const float material_heightMapFactor = s;
    const Vec2<float> uv0 = P;
    Vec2<float> dUvOffset;
    {  // getParallax()
        const float parallaxScale = material_heightMapFactor;
        float height = hs.height(uv0);  // texture2DBias(heightMap, uv, textureBias).g
        height = height * parallaxScale - parallaxScale * 0.5f;
        Vec3<float> viewDirT = V;  // dViewDirW * dTBN
        viewDirT.z += 0.42f;
        dUvOffset = div(viewDirT.xy(), viewDirT.z) * height;
    }
    return {uv0 + dUvOffset, hs.fetches};
}

// ---- PlayCanvas StandardMaterial 2.22.0+, parallaxMode PARALLAX_OFFSET (the default) --------
// npm playcanvas@2.22.0 and @2.23.3, build/playcanvas.mjs: the chunk parallaxPS (getParallax,
// the #else branch of STD_PARALLAX == OCCLUSION) and convertHeightMapFactor
// (material_heightMapFactor = 0.1 heightMapFactor = s); material_heightMapBase = base (pxh's b,
// default 0.5). viewDirT = normalize(dViewDirW * dTBN), viewDirUv = (viewDirT.x, -viewDirT.y)
// in a frame whose y runs along -v: pxh's V.xy. Preset: playcanvas_basic.
inline EngineResult playcanvas_offset(const HeightField& hf, float s, float base, Vec3<float> V,
                                      Vec2<float> P) {
    using namespace js_glsl;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    const float material_heightMapFactor = s, material_heightMapBase = base;
    Vec2<float> dUvOffset;
    {  // getParallax()
        const float parallaxScale = material_heightMapFactor;
        const Vec2<float> viewDirUv = V.xy();
        float height = hs.height(P);  // texture2DBias(heightMap, uv, bias).g
        height = (height - material_heightMapBase) * parallaxScale;
        dUvOffset = viewDirUv * height;
    }
    return {P + dUvOffset, hs.fetches};
}

// ---- PlayCanvas StandardMaterial, parallaxMode PARALLAX_OCCLUSION ---------------------------
// playcanvas/engine src/scene/shader-lib/glsl/chunks/standard/frag/parallax.js @
// 1c1a0230c3974c084281cd33c15bf2f25165f186 (getParallax, STD_PARALLAX == OCCLUSION; PRs 9213,
// 9219, 9245). material_heightMapFactor = s; material_heightMapBase = base (pxh's b);
// material_parallaxSamples = samples (default 16). viewDirUv = (viewDirT.x, -viewDirT.y) of a
// frame whose y runs along -v: pxh's V.xy. `lod` is the level the shader derives before the loop,
// max(0, 0.5 log2(max(|dFdx|^2, |dFdy|^2))) of the texel coordinates: pxh's max(lambda, 0); the
// taps are texture2DLod at it, here level 0 (what the rule does with the level is what this
// transcribes, not the filtering).
inline EngineResult playcanvas_occlusion(const HeightField& hf, float s, float base, Vec3<float> V,
                                         Vec2<float> P, float lod, float samples = 16.0f) {
    using namespace js_glsl;
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    auto tap = [&](Vec2<float> uv) { return 1.0f - hs.height(uv); };  // 1 - texture2DLod(..)
    const float material_heightMapFactor = s, material_heightMapBase = base;
    const float material_parallaxSamples = samples;
    const float parallaxMaxSlope = 5.0f, parallaxTexelsPerStep = 2.0f;
    const float parallaxFadeMin = 1.0f, parallaxFadeMax = 3.0f;
    const int parallaxRefineSteps = 5;

    const float parallaxScale = material_heightMapFactor;
    const Vec3<float> viewDirT = V;
    const Vec2<float> viewDirUv = viewDirT.xy();
    const Vec2<float> march = div(viewDirUv * -parallaxScale, std::max(viewDirT.z, 0.0001f));
    const float marchLength = length(march);
    const float maxMarchLength = parallaxScale * parallaxMaxSlope;
    const Vec2<float> uvSpan =
        marchLength > maxMarchLength ? march * (maxMarchLength / marchLength) : march;
    const float geomDepth = 1.0f - material_heightMapBase;
    const Vec2<float> entryUv = P - uvSpan * geomDepth;
    const Vec2<float> heightMapSize(float(hf.width), float(hf.height));
    const float marchTexels =
        length(Vec2<float>(uvSpan.x * heightMapSize.x, uvSpan.y * heightMapSize.y)) /
        std::exp2(lod);
    const float fade = std::clamp(
        (marchTexels - parallaxFadeMin) / (parallaxFadeMax - parallaxFadeMin), 0.0f, 1.0f);
    Vec2<float> dUvOffset(0.0f, 0.0f);
    if (fade > 0.0f) {
        const float steps =
            std::clamp(marchTexels / parallaxTexelsPerStep, 1.0f, material_parallaxSamples);
        const float stepSize = 1.0f / steps;
        float rayDepth = 0.0f;
        float surfaceDepth = tap(entryUv);
        float prevRayDepth = rayDepth;
        for (float i = 0.0f; i < steps; i += 1.0f) {
            if (rayDepth >= surfaceDepth) break;
            prevRayDepth = rayDepth;
            rayDepth += stepSize;
            surfaceDepth = tap(entryUv + uvSpan * rayDepth);
        }
        float hitDepth = rayDepth;
        if (rayDepth >= surfaceDepth) {
            float interval = (rayDepth - prevRayDepth) * 0.5f;
            hitDepth = rayDepth - interval;
            for (int i = 0; i < parallaxRefineSteps; i++) {
                interval *= 0.5f;
                const float refineDepth = tap(entryUv + uvSpan * hitDepth);
                hitDepth += hitDepth >= refineDepth ? -interval : interval;
            }
        }
        const float hitBelowTop = std::clamp(hitDepth, 0.0f, 1.0f);
        dUvOffset = uvSpan * ((hitBelowTop - geomDepth) * fade);
    }
    return {P + dUvOffset, hs.fetches};
}

}  // namespace pxh::literal
