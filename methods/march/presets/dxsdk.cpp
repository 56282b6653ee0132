// The DirectX SDK ParallaxOcclusionMapping sample (Tatarchuk 2006) as a preset of the parametric
// marcher (methods/march/preset.h). s = g_fHeightMapScale; heights go inward from the polygon,
// so b = 1. The LOD fade (g_nLODThreshold) is left off: the orthographic scene defines no screen
// footprint. Literal transcription and the comparison: tests/engines/literal_unity_jme_ogre_dx.h,
// tests/methods/engines_unity_jme_ogre_dx_test.cpp.
#include "methods/march/preset.h"

namespace pxh {
namespace {

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
        "s = g_fHeightMapScale (0.02, Stones)",
    .summary =
        "POM with n = int(lerp(50, 8, V.z)) layers and height 1 as the previous sample of "
        "layer 1 (P is never sampled); LOD fade off",
    .knobs = {.count = M::MixTrunc,
              .first = M::FirstTop,
              .compare = M::Lt,
              .on_miss = M::MissLast,
              .refine = M::Lerp,
              .clamp_weight = false},
    .params = {{ParamSpec::integer("g_nMinSamples", 8, 1, 130, "layers head-on (sample: 8)"),
                MarchKnob::layers_min},
               {ParamSpec::integer("g_nMaxSamples", 50, 1, 130, "layers at grazing (Stones: 50)"),
                MarchKnob::layers_max}},
    .order = 366,
    .required_bias = 1.0,
    .bias_reason = "the sample's bound 1.0 is the polygon, heights go inward",
};
PXH_REGISTER_PRESET(kDxsdkPom);

}  // namespace
}  // namespace pxh
