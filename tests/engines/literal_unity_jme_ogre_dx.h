// Literal transcriptions of the parallax loops shipped by Unity (built-in/URP ParallaxOffset, HDRP
// PerPixelDisplacement), jMonkeyEngine (Parallax.glsllib), OGRE (RTSS SGXLib_NormalMap.glsl) and
// the DirectX SDK ParallaxOcclusionMapping sample. Each function re-expresses the
// engine's shader code with its own variable names, order of operations, loop structure and
// constants, in float as the GPU runs it; it was written from the engine's public source (cited
// above each function, read for facts only) and from /work/research/unity_jme_ogre_dx.md.
//
// Common interface: hf is pxh's height field (h, white = high), s pxh's scale, V pxh's V (unit,
// toward the eye, x = +u, y = +v), P the sample point. Each function converts these to what the
// engine's shader sees and returns the engine's uv in pxh coordinates, with the number of height
// fetches the engine's code makes (dead fetches included). LOD fades are left out (pxh samples at
// LOD 0 and the orthographic scene defines no screen footprint).
#pragma once
#include <cmath>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "tests/engines/literal_common.h"

namespace pxh::literal {

namespace detail {
// GLSL/HLSL helpers, as the shading languages define them.
inline float length3(Vec3<float> v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }
inline Vec3<float> normalize3(Vec3<float> v) {
    const float l = length3(v);
    return {v.x / l, v.y / l, v.z / l};
}
inline Vec2<float> normalize2(Vec2<float> v) {
    const float l = std::sqrt(v.x * v.x + v.y * v.y);
    return {v.x / l, v.y / l};  // (0, 0) gives NaN, as GPUs do for normalize(vec2(0))
}
inline float saturate(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }
// GLSL mix(x, y, a) = x (1 - a) + y a (GLSL 4.60 section 8.3).
inline float glsl_mix(float x, float y, float a) { return x * (1.0f - a) + y * a; }
inline Vec2<float> glsl_mix(Vec2<float> x, Vec2<float> y, float a) {
    return {glsl_mix(x.x, y.x, a), glsl_mix(x.y, y.y, a)};
}
// HLSL lerp(x, y, s) = x + s (y - x).
inline float hlsl_lerp(float x, float y, float s) { return x + s * (y - x); }
}  // namespace detail

// ---- unity_parallax_offset -------------------------------------------------------------------
// TwoTailsGames/Unity-Built-in-Shaders @ 6a63f93bc1f20ce6cd47f981c7494e8328915621 (Unity 2019.4.1):
// CGIncludes/UnityStandardUtils.cginc ParallaxOffset1Step (the same formula as UnityCG.cginc
// ParallaxOffset, in half), called by CGIncludes/UnityStandardInput.cginc Parallax with
// h = tex2D(_ParallaxMap, texcoords.xy).g. URP: Unity-Technologies/Graphics
// Packages/com.unity.render-pipelines.universal/Shaders/LitInput.hlsl @ 3b0efc39f87e... uses the
// same ParallaxOffset1Step. _Parallax = s (default 0.02 built-in, 0.005 URP), b = 0.5.
// Computed in float here (desktop compilers promote half to float).
inline EngineResult unity_parallax_offset(const HeightField& hf, float s, Vec3<float> V,
                                          Vec2<float> P) {
    HeightSampler<float> tex(hf, 1.0f, 0.0f);
    const float _Parallax = s;
    const Vec3<float> viewDir = V;  // tangent-space vector toward the eye, v along +v
    const Vec2<float> texcoords = P;
    // Parallax():
    float h = tex.height(texcoords);  // _ParallaxMap.g
    // ParallaxOffset1Step(h, _Parallax, viewDir):
    const float height = _Parallax;
    h = h * height - height / 2.0f;
    Vec3<float> v = detail::normalize3(viewDir);
    v.z += 0.42f;
    const Vec2<float> offset = Vec2<float>(v.x / v.z, v.y / v.z) * h;
    return {texcoords + offset, tex.fetches};
}

// ---- hdrp_pom --------------------------------------------------------------------------------
// Unity-Technologies/Graphics:
//  Packages/com.unity.render-pipelines.core/ShaderLibrary/PerPixelDisplacement.hlsl
//    @ c8df1d81db96da3d951b102d792852e6712a1a10, ParallaxOcclusionMapping (secant branch,
//    POM_SECANT_METHOD 1);
//  Packages/com.unity.render-pipelines.high-definition/Runtime/Material/Lit/LitDataDisplacement.hlsl
//    @ d679af29c7a23623f5eb60130df7ec9df8386637, ApplyPerPixelDisplacement (UV mapping branch) and
//    ComputePerPixelHeightDisplacement (_HeightMap.r at param.uv + texOffsetCurrent);
//  core ShaderLibrary/Common.hlsl FastACosPos; Macros.hlsl INV_HALF_PI 0.636619772367.
// Defaults (Lit.shader @ ba62a59864270b82f88d9396878da2926f69b353): _PPDMinSamples 5,
// _PPDMaxSamples 15, _HeightPoMAmplitude 2 cm. uvSpaceScale = _InvPrimScale * _BaseColorMap_ST.xy *
// (worldScale * maxHeight) with maxHeight = _HeightPoMAmplitude * 0.01 (BaseLitAPI.cs) for a 1 m
// primitive, tiling 1 and UV mapping: that is pxh s (0.02 by default), passed here directly.
// Height map, 1 = top: b = 1. The LOD fade (offset *= 1 - saturate(lod - lodThreshold)) acts
// where lod > lodThreshold (default lod 0: off; the fetches stay at level 0 here); outHeight:
// what ParallaxOcclusionMapping hands back (outHeight = currHeight, the last probe's height at the
// unfaded offset, set before the fade), what ApplyPerPixelDisplacement's depth offset reads.
inline EngineResult hdrp_pom(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                             int _PPDMinSamples = 5, int _PPDMaxSamples = 15, float lod = 0.0f,
                             float lodThreshold = 5.0f, float* outHeight = nullptr) {
    HeightSampler<float> tex(hf, 1.0f, 0.0f);
    const Vec2<float> param_uv = P;
    auto ComputePerPixelHeightDisplacement = [&](Vec2<float> texOffsetCurrent) {
        return tex.height(param_uv + texOffsetCurrent);  // _HeightMap.r
    };
    auto FastACosPos = [](float inX) {
        const float x = std::abs(inX);
        float res = (0.0468878f * x + -0.203471f) * x + 1.570796f;  // p(x)
        res *= std::sqrt(1.0f - x);
        return res;
    };
    const float INV_HALF_PI = 0.636619772367f;
    // ApplyPerPixelDisplacement, UV mapping:
    const float uvSpaceScale =
        s;  // both components: _InvPrimScale (1, 1), _BaseColorMap_ST.xy (1, 1)
    const Vec3<float> viewDirTS = V;  // TransformWorldToTangent(V, tangentToWorld) * objectScale(1)
    const Vec3<float> viewDirUV =
        detail::normalize3({viewDirTS.x * uvSpaceScale, viewDirTS.y * uvSpaceScale, viewDirTS.z});
    const float unitAngle = detail::saturate(FastACosPos(viewDirUV.z) * INV_HALF_PI);
    const int numSteps =
        int(detail::hlsl_lerp(float(_PPDMinSamples), float(_PPDMaxSamples), unitAngle));

    // ParallaxOcclusionMapping(lod, lodThreshold, numSteps, viewDirUV, ppdParam, outHeight):
    const float stepSize = 1.0f / float(numSteps);
    const Vec2<float> parallaxMaxOffsetTS = {viewDirUV.x / -viewDirUV.z,
                                             viewDirUV.y / -viewDirUV.z};
    const Vec2<float> texOffsetPerStep = parallaxMaxOffsetTS * stepSize;

    Vec2<float> texOffsetCurrent = {0.0f, 0.0f};
    float prevHeight = ComputePerPixelHeightDisplacement(texOffsetCurrent);
    texOffsetCurrent += texOffsetPerStep;
    float currHeight = ComputePerPixelHeightDisplacement(texOffsetCurrent);
    float rayHeight = 1.0f - stepSize;

    for (int stepIndex = 0; stepIndex < numSteps; ++stepIndex) {
        if (currHeight > rayHeight) break;
        prevHeight = currHeight;
        rayHeight -= stepSize;
        texOffsetCurrent += texOffsetPerStep;
        currHeight = ComputePerPixelHeightDisplacement(texOffsetCurrent);
    }

    float pt0 = rayHeight + stepSize;
    float pt1 = rayHeight;
    float delta0 = pt0 - prevHeight;
    float delta1 = pt1 - currHeight;

    float delta;
    Vec2<float> offset;
    for (int i = 0; i < 3; ++i) {
        const float intersectionHeight = (pt0 * delta1 - pt1 * delta0) / (delta1 - delta0);
        // offset = (1 - intersectionHeight) * texOffsetPerStep * numSteps, left to right
        offset = texOffsetPerStep * (1.0f - intersectionHeight) * float(numSteps);
        currHeight = ComputePerPixelHeightDisplacement(offset);
        delta = intersectionHeight - currHeight;
        if ((delta >= -0.01f) && (delta <= 0.01f)) break;
        if (delta < 0.0f) {
            delta1 = delta;
            pt1 = intersectionHeight;
        } else {
            delta0 = delta;
            pt0 = intersectionHeight;
        }
    }
    if (outHeight) *outHeight = currHeight;  // outHeight = currHeight;
    offset = offset * (1.0f - detail::saturate(lod - lodThreshold));
    // layerTexCoord.base.uv += offset
    return {param_uv + offset, tex.fetches};
}

// ApplyPerPixelDisplacement's depth offset (LitDataDisplacement.hlsl @ d679af29c7a2,
// _DEPTHOFFSET): verticalDisplacement = maxHeight - height * maxHeight; return
// verticalDisplacement / ClampNdotV(NdotV), ClampNdotV = max(NdotV, 0.0001); then
// ApplyDepthOffsetPositionInput moves positionWS by depthOffset * -V. Here: that offset along f.
inline double hdrp_depth_offset(float maxHeight, float height, Vec3d V, Vec3d f) {
    const float verticalDisplacement = maxHeight - height * maxHeight;
    const double depthOffset = verticalDisplacement / std::max(V.z, 0.0001);
    return -depthOffset * (V.x * f.x + V.y * f.y + V.z * f.z);
}

// ---- jme_parallax ----------------------------------------------------------------------------
// jMonkeyEngine/jmonkeyengine jme3-core/src/main/resources/Common/ShaderLib/Parallax.glsllib
// @ 7277b5d8013f1052989410af017c1f8d432547ce, classicParallaxOffset (ParallaxMap.r); default
// ParallaxHeight 0.05 (Common/MatDefs/Light/Lighting.j3md @
// 68c082c13ded1ceaed63a8e1047e8a4d59366b44). parallaxScale = ParallaxHeight = s, heightBias = -0.6
// s: b = 0.6. vViewDir is the tangent-space eye vector (TBN = (T, cross(N, T) w, N), v along +v),
// normalised inside.
inline EngineResult jme_parallax(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
    HeightSampler<float> parallaxMap(hf, 1.0f, 0.0f);
    const Vec3<float> vViewDir = V;
    const Vec2<float> texCoord = P;
    const float parallaxScale = s;
    float h = parallaxMap.height(texCoord);  // texture2D(parallaxMap, texCoord).r
    const float heightScale = parallaxScale;
    const float heightBias = heightScale * -0.6f;
    const Vec3<float> normView = detail::normalize3(vViewDir);
    h = (h * heightScale + heightBias) * normView.z;
    return {texCoord + Vec2<float>(h * normView.x, h * normView.y), parallaxMap.fetches};
}

// ---- jme_steep -------------------------------------------------------------------------------
// Same file and commit, steepParallaxOffset (selected by SteepParallax). The function receives
// parallaxScale = ParallaxHeight and does parallaxScale *= 0.3; pxh s is that product
// (s = 0.3 ParallaxHeight = 0.015 by default), so the argument here is s with the multiply folded
// into the conversion (keeping the float values exact). Top at the polygon: b = 1.
// Kept as shipped: nNumSamples is real (not rounded); the first iteration sets fPrevHeight from
// fCurrHeight = 0.0 (the 1.0 initialisation is dead); no guard on fDenominator == 0;
// normalize(vViewDir.xy) is NaN at theta = 0.
inline EngineResult jme_steep(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
    HeightSampler<float> parallaxMap(hf, 1.0f, 0.0f);
    const Vec3<float> vViewDir = V;
    const Vec2<float> texCoord = P;
    const Vec2<float> vParallaxDirection = detail::normalize2(vViewDir.xy());
    const float fLength = detail::length3(vViewDir);
    const float fParallaxLength =
        std::sqrt(fLength * fLength - vViewDir.z * vViewDir.z) / vViewDir.z;
    Vec2<float> vParallaxOffsetTS = vParallaxDirection * fParallaxLength;
    const float parallaxScale = s;  // ParallaxHeight after "parallaxScale *= 0.3"
    vParallaxOffsetTS = vParallaxOffsetTS * parallaxScale;

    const Vec3<float> eyeDir = detail::normalize3(vViewDir);
    const float nMinSamples = 6.0f;
    const float nMaxSamples = 1000.0f * parallaxScale;
    const float nNumSamples = detail::glsl_mix(nMinSamples, nMaxSamples, 1.0f - eyeDir.z);
    const float fStepSize = 1.0f / nNumSamples;
    float fCurrHeight = 0.0f;
    float fPrevHeight = 1.0f;
    float nStepIndex = 0.0f;
    const Vec2<float> vTexOffsetPerStep = vParallaxOffsetTS * fStepSize;
    Vec2<float> vTexCurrentOffset = texCoord;
    float fCurrentBound = 1.0f;
    float fParallaxAmount = 0.0f;

    while (nStepIndex < nNumSamples && fCurrHeight <= fCurrentBound) {
        vTexCurrentOffset = vTexCurrentOffset - vTexOffsetPerStep;
        fPrevHeight = fCurrHeight;
        fCurrHeight = parallaxMap.height(vTexCurrentOffset);  // .r
        fCurrentBound -= fStepSize;
        nStepIndex += 1.0f;
    }
    const Vec2<float> pt1 = {fCurrentBound, fCurrHeight};
    const Vec2<float> pt2 = {fCurrentBound + fStepSize, fPrevHeight};
    const float fDelta2 = pt2.x - pt2.y;
    const float fDelta1 = pt1.x - pt1.y;
    const float fDenominator = fDelta2 - fDelta1;
    fParallaxAmount = (pt1.x * fDelta2 - pt2.x * fDelta1) / fDenominator;
    const Vec2<float> vParallaxOffset = vParallaxOffsetTS * (1.0f - fParallaxAmount);
    return {texCoord - vParallaxOffset, parallaxMap.fetches};
}

// ---- OGRE: eyeVec as SGX_Generate_Parallax_Texcoord sees it -----------------------------------
// eyeVec = normalize(mul(-viewPos, TBN)) with TBN = (T, cross(N, T) w, N). OGRE's tangent
// generator (OgreMain/src/OgreTangentSpaceCalc.cpp calculateParity) makes that binormal point
// toward -v for its usual meshes, so before "eyeVec.y = -eyeVec.y; //Inverse y" the vector is
// (V.x, -V.y, V.z) in pxh terms, and pxh V after it.
namespace detail {
inline Vec3<float> ogre_eye_vec_before_inverse_y(Vec3<float> V) { return {V.x, -V.y, V.z}; }
}  // namespace detail

// ---- ogre_parallax ---------------------------------------------------------------------------
// OGRECave/ogre @ 3e955a168617aa13edd418c8a2e4a9a72b6a0247, Media/RTShaderLib/SGXLib_NormalMap.glsl
// SGX_Generate_Parallax_Texcoord without POM_LAYER_COUNT and without TERRAIN_PARALLAX_MAPPING;
// heightScale = mParallaxHeightScale, 0.04 by default
// (Components/RTShaderSystem/src/OgreShaderExNormalMapLighting.cpp). Normal map alpha = height,
// read as depth 1 - a: b = 1.
inline EngineResult ogre_parallax(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
    HeightSampler<float> normalHeightMap(hf, 1.0f, 0.0f);
    const Vec2<float> texCoord = P;
    const float heightScale = s;
    Vec3<float> eyeVec = detail::ogre_eye_vec_before_inverse_y(V);
    eyeVec = detail::normalize3(eyeVec);
    eyeVec.y = -eyeVec.y;  // Inverse y
    Vec2<float> newTexCoord = texCoord;
    const float height = 1.0f - normalHeightMap.height(newTexCoord);  // .a
    const Vec2<float> p =
        Vec2<float>(eyeVec.x / eyeVec.z, eyeVec.y / eyeVec.z) * (height * heightScale);
    newTexCoord = newTexCoord - p;
    return {newTexCoord, normalHeightMap.fetches};
}

// ---- ogre_pom --------------------------------------------------------------------------------
// Same file and commit, SGX_Generate_Parallax_Texcoord with POM_LAYER_COUNT (the RTSS adds
// POM_LAYER_COUNT=32 for parallax_occlusion; POM_MAX_DISTANCE is terrain-only). Kept as shipped:
// the step has no division by eyeVec.z (sin theta step); the fetch before the loop is dead; the
// sample at newTexCoord_k = P - k delta is compared with layer depth (k - 1)/32 (one-step lag);
// no guard on afterDepth - beforeDepth = 0.
inline EngineResult ogre_pom(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
    HeightSampler<float> normalHeightMap(hf, 1.0f, 0.0f);
    const int POM_LAYER_COUNT = 32;
    const Vec2<float> texCoord = P;
    const float heightScale = s;
    Vec3<float> eyeVec = detail::ogre_eye_vec_before_inverse_y(V);
    eyeVec = detail::normalize3(eyeVec);
    eyeVec.y = -eyeVec.y;  // Inverse y
    Vec2<float> newTexCoord = texCoord;

    const float layerDepth = 1.0f / float(POM_LAYER_COUNT);
    float currentLayerDepth = 0.0f;
    const Vec2<float> parallaxShift = eyeVec.xy() * heightScale;
    const Vec2<float> deltaTexCoords = {parallaxShift.x / float(POM_LAYER_COUNT),
                                        parallaxShift.y / float(POM_LAYER_COUNT)};

    float currentDepthMapValue = 1.0f - normalHeightMap.height(newTexCoord);
    for (int currentLayerId = 0; currentLayerId < POM_LAYER_COUNT; currentLayerId++) {
        newTexCoord = newTexCoord - deltaTexCoords;
        currentDepthMapValue = 1.0f - normalHeightMap.height(newTexCoord);
        if (currentLayerDepth > currentDepthMapValue) break;
        currentLayerDepth += layerDepth;
    }
    const Vec2<float> prevTexCoords = newTexCoord + deltaTexCoords;
    const float afterDepth = currentDepthMapValue - currentLayerDepth;
    const float beforeDepth =
        (1.0f - normalHeightMap.height(prevTexCoords)) - currentLayerDepth + layerDepth;
    const float weight = afterDepth / (afterDepth - beforeDepth);
    newTexCoord = detail::glsl_mix(newTexCoord, prevTexCoords, weight);
    return {newTexCoord, normalHeightMap.fetches};
}

// ---- dxsdk_pom -------------------------------------------------------------------------------
// walbourn/directx-sdk-legacy-samples @ f35ea7637d512508cc937baa2dd50bf86eb2731d,
// Direct3D/ParallaxOcclusionMapping/ParallaxOcclusionMapping.fx: RenderSceneVS (vParallaxOffsetTS)
// and RenderScenePS (the POM branch). Defaults (ParallaxOcclusionMapping.cpp, SetPOMTextures
// (POM_STONES)): g_fHeightMapScale 0.02 = s, g_nMinSamples 8, g_nMaxSamples 50. Normal map alpha
// = height, bound 1 at the polygon: b = 1. The LOD branch (fMipLevel vs g_nLODThreshold) is off.
// Kept as shipped: fPrevHeight starts at 1.0; the zero-denominator guard gives
// fParallaxAmount = 0; normalize(vViewTS.xy) is NaN at theta = 0.
inline EngineResult dxsdk_pom(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P,
                              int g_nMinSamples = 8, int g_nMaxSamples = 50) {
    HeightSampler<float> tNormalHeightMap(hf, 1.0f, 0.0f);
    const float g_fHeightMapScale = s;
    // RenderSceneVS (orthographic, flat polygon: the interpolated values are the vertex values).
    const Vec3<float> vViewTS = V;  // mul(mWorldToTangent, vViewWS) = (T.E, B.E, N.E)
    const Vec2<float> vParallaxDirection = detail::normalize2(vViewTS.xy());
    const float fLength = detail::length3(vViewTS);
    const float fParallaxLength = std::sqrt(fLength * fLength - vViewTS.z * vViewTS.z) / vViewTS.z;
    Vec2<float> vParallaxOffsetTS = vParallaxDirection * fParallaxLength;
    vParallaxOffsetTS = vParallaxOffsetTS * g_fHeightMapScale;
    const Vec2<float> texCoord = P;

    // RenderScenePS: dot(normalize(vViewWS), normalize(vNormalWS)) = V.z.
    const Vec3<float> vViewWS = detail::normalize3(V);
    const Vec3<float> vNormalWS = {0.0f, 0.0f, 1.0f};
    const float NdotV = vViewWS.x * vNormalWS.x + vViewWS.y * vNormalWS.y + vViewWS.z * vNormalWS.z;
    const int nNumSteps = int(detail::hlsl_lerp(float(g_nMaxSamples), float(g_nMinSamples), NdotV));

    float fCurrHeight = 0.0f;
    const float fStepSize = 1.0f / float(nNumSteps);
    float fPrevHeight = 1.0f;
    int nStepIndex = 0;
    const Vec2<float> vTexOffsetPerStep = vParallaxOffsetTS * fStepSize;
    Vec2<float> vTexCurrentOffset = texCoord;
    float fCurrentBound = 1.0f;
    float fParallaxAmount = 0.0f;
    Vec2<float> pt1 = {0.0f, 0.0f};
    Vec2<float> pt2 = {0.0f, 0.0f};

    while (nStepIndex < nNumSteps) {
        vTexCurrentOffset = vTexCurrentOffset - vTexOffsetPerStep;
        fCurrHeight = tNormalHeightMap.height(vTexCurrentOffset);  // tex2Dgrad(...).a
        fCurrentBound -= fStepSize;
        if (fCurrHeight > fCurrentBound) {
            pt1 = {fCurrentBound, fCurrHeight};
            pt2 = {fCurrentBound + fStepSize, fPrevHeight};
            nStepIndex = nNumSteps + 1;
            fPrevHeight = fCurrHeight;
        } else {
            nStepIndex++;
            fPrevHeight = fCurrHeight;
        }
    }
    const float fDelta2 = pt2.x - pt2.y;
    const float fDelta1 = pt1.x - pt1.y;
    const float fDenominator = fDelta2 - fDelta1;
    if (fDenominator == 0.0f) {
        fParallaxAmount = 0.0f;
    } else {
        fParallaxAmount = (pt1.x * fDelta2 - pt2.x * fDelta1) / fDenominator;
    }
    const Vec2<float> vParallaxOffset = vParallaxOffsetTS * (1.0f - fParallaxAmount);
    const Vec2<float> texSampleBase = texCoord - vParallaxOffset;
    return {texSampleBase, tNormalHeightMap.fetches};
}

}  // namespace pxh::literal
