// pxh's side of the HDRP-style chunks: the sample point P is the uv, pxh_V the tangent-space view
// vector, and the level is HDRP's ComputeTextureLOD(uv * _HeightMap_TexelSize.zw) =
// max(0.5 log2(max(|ddx|^2, |ddy|^2)), 0) of the texel coordinates, which is pxh's max(lambda, 0).
#include "LitDisplacement.hlsl"

float2 pxh_method(float2 P)
{
    return ApplyPerPixelDisplacementUV(pxh_V, P, max(pxh_lod(), 0.0));
}
