// A Lit material's pixel displacement in the style of HDRP's Runtime/Material/Lit/
// LitDataDisplacement.hlsl (Unity-Technologies/Graphics @ 155cdbc4789454bf0bc92c8918aae1f3126c0cf2)
// and its material properties (Lit.shader: _PPDMinSamples 5, _PPDMaxSamples 15,
// _PPDLodThreshold 5), written for pxh: UV mapping, tiling 1, a 1 m primitive, so the uv-space
// scale is the height amplitude; the height map's red channel, sampled at the level the caller
// gives; the step count from the angle of the scaled view ray.
#include "core_macros.hlsl"

TEXTURE2D(_HeightMap);
SAMPLER(sampler_HeightMap);

cbuffer UnityPerMaterial
{
    float _HeightAmplitude;
    float _PPDMinSamples;
    float _PPDMaxSamples;
    float _PPDLodThreshold;
};

struct PerPixelHeightDisplacementParam
{
    float2 uv;
};

float ComputePerPixelHeightDisplacement(float2 texOffsetCurrent, float lod,
                                        PerPixelHeightDisplacementParam param)
{
    return SAMPLE_TEXTURE2D_LOD(_HeightMap, sampler_HeightMap, param.uv + texOffsetCurrent, lod).r;
}

#include "Packages/com.unity.render-pipelines.core/ShaderLibrary/PerPixelDisplacement.hlsl"

// The uv after pixel displacement of `uv` seen along viewDirTS (tangent space, toward the eye)
// at texture level `lod`.
float2 ApplyPerPixelDisplacementUV(float3 viewDirTS, float2 uv, float lod)
{
    float maxHeight = abs(_HeightAmplitude);
    float2 uvSpaceScale = float2(1.0, 1.0) * maxHeight;

    PerPixelHeightDisplacementParam ppdParam;
    ppdParam.uv = uv;
    float height = 0;

    float3 viewDirUV = normalize(float3(viewDirTS.xy * uvSpaceScale, viewDirTS.z));
    float unitAngle = saturate(FastACosPos(viewDirUV.z) * INV_HALF_PI);
    int numSteps = (int)lerp(_PPDMinSamples, _PPDMaxSamples, unitAngle);
    float2 offset = ParallaxOcclusionMapping(lod, _PPDLodThreshold, numSteps, viewDirUV,
                                             ppdParam, height);
    return uv + offset;
}
