// The DirectX SDK ParallaxOcclusionMapping sample (Tatarchuk 2006) as a preset of the parametric
// marcher (methods/march/preset.h). s = g_fHeightMapScale; heights go inward from the polygon,
// so b = 1. Literal transcription and the comparison: tests/engines/literal_unity_jme_ogre_dx.h,
// tests/methods/engines_unity_jme_ogre_dx_test.cpp.
//
// Texture levels (RenderScenePS). Before the loop it takes dx, dy = ddx, ddy of the uv and of
// the texel coordinates uv * g_vTextureDims, and its level
// fMipLevel = max(0.5 log2(max(dxSize.x^2 + dySize.x^2, dxSize.y^2 + dySize.y^2)), 0); every
// fetch of the march is tex2Dgrad(.., dx, dy): `lod = "grad"` reproduces the sampling on the
// GLSL backend. fMipLevel <= g_nLODThreshold (3): the POM offset; above: bump mapping, texSample
// = the input uv, the march not run (no fetch); in the band (g_nLODThreshold - 1, threshold] the
// uv is lerp(texSampleBase, texCoord, frac(fMipLevel)). That is lod_fade = dxsdk, applied to
// pxh's L = max(lambda, 0): the sample's per-axis sums (|du|^2 over both screen axes, then
// |dv|^2) equal GL's per-axis lengths when the footprint is axis-aligned (the orthographic grid),
// and differ by at most half a level otherwise. As shipped the application never sets
// g_vTextureDims (ParallaxOcclusionMapping.cpp sets every other parameter; an effect parameter
// starts at 0), so the sample's fMipLevel is max(log2(0), 0) = 0 and it always runs the full POM;
// g_nLODThreshold = 16 reproduces that for any field up to 2^16 texels.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kDxsdkVersion =
    "DirectX SDK (June 2010) sample, as in walbourn/directx-sdk-legacy-samples @ f35ea763";

using M = MarchConfig;

// RenderScenePS: nNumSteps = (int)lerp(g_nMaxSamples, g_nMinSamples, V.z); layers 1 .. n,
// fPrevHeight = 1.0 before layer 1; stop at the first height > bound; line intersection, and
// fParallaxAmount = 0 (the bottom point) when no layer was crossed.
const MarchPresetRow kDxsdkPom{
    .name = "dxsdk_pom",
    .citation =
        "DirectX SDK ParallaxOcclusionMapping sample (Tatarchuk 2006): "
        "walbourn/directx-sdk-legacy-samples Direct3D/ParallaxOcclusionMapping/"
        "ParallaxOcclusionMapping.fx (RenderSceneVS, RenderScenePS) and .cpp @ f35ea7637d51; "
        "s = g_fHeightMapScale (0.02, Stones); g_nLODThreshold 3",
    .summary =
        "POM with n = int(lerp(50, 8, V.z)) layers and height 1 as the previous sample of "
        "layer 1 (P is never sampled); past level g_nLODThreshold (3) bump mapping (P), "
        "blended over the level before",
    .knobs = {.count = M::MixTrunc,
              .first = M::FirstTop,
              .compare = M::Lt,
              .on_miss = M::MissLast,
              .refine = M::Lerp,
              .clamp_weight = false,
              .lod_fade = M::FadeDxsdk,
              .lod_threshold = 3},
    .params = {{ParamSpec::integer("g_nMinSamples", 8, 1, 130, "layers head-on (sample: 8)"),
                MarchKnob::layers_min},
               {ParamSpec::integer("g_nMaxSamples", 50, 1, 130, "layers at grazing (Stones: 50)"),
                MarchKnob::layers_max},
               {ParamSpec::integer("g_nLODThreshold", 3, 0, 16,
                                   "level of detail past which it bump-maps (P), blended over "
                                   "the level before (sample: 3)"),
                MarchKnob::lod_threshold}},
    .order = 366,
    .required_bias = 1.0,
    .bias_reason = "the sample's bound 1.0 is the polygon, heights go inward",
    .engine_version = kDxsdkVersion,
};
PXH_REGISTER_PRESET(kDxsdkPom);

}  // namespace
}  // namespace pxh
