// The few Core render pipeline definitions the chunks below use, written for pxh in the style of
// Unity's com.unity.render-pipelines.core ShaderLibrary (API macros, Common.hlsl, Macros.hlsl).
// Facts read at Unity-Technologies/Graphics @ 50e45ca435f942aabed02e45c76bf8dd8ef0c1a0:
// `real` is float at full precision; FastACosPos is a polynomial arccos on [0, 1].
#ifndef PXH_EXAMPLE_CORE_MACROS
#define PXH_EXAMPLE_CORE_MACROS

#define real float
#define real2 float2
#define real3 float3
#define real4 float4

#define INV_HALF_PI 0.636619772367

#define TEXTURE2D(textureName) Texture2D textureName
#define SAMPLER(samplerName) SamplerState samplerName
#define SAMPLE_TEXTURE2D_LOD(textureName, samplerName, coord2, lod) \
    textureName.SampleLevel(samplerName, coord2, lod)

// arccos of x in [0, 1], |error| below 1e-4 rad: (c2 x + c1) x + c0, times sqrt(1 - x).
real FastACosPos(real inX)
{
    real x = abs(inX);
    real res = (0.0468878 * x + -0.203471) * x + 1.570796;
    res *= sqrt(1.0 - x);
    return res;
}

#endif
