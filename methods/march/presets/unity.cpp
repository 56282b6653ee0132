// Unity's parallax as presets of the parametric marcher (methods/march/preset.h): built-in/URP
// ParallaxOffset and HDRP's PerPixelDisplacement. The engine's height scale is the experiment's
// scale s (conversions in README); each fixes the reference plane, so each requires its bias.
// HDRP's LOD fade (_PPDLodThreshold) is left off: the orthographic scene defines no screen
// footprint. Literal transcriptions and the comparison: tests/engines/literal_unity_jme_ogre_dx.h,
// tests/methods/engines_unity_jme_ogre_dx_test.cpp.
#include "methods/march/preset.h"

namespace pxh {
namespace {

using M = MarchConfig;

// ParallaxOffset: h = h _Parallax - _Parallax / 2; v = normalize(viewDir); v.z += 0.42;
// offset = h v.xy / v.z.  In pxh terms uv = P + s (h - 0.5) V.xy / (V.z + 0.42).
const MarchPresetRow kUnityParallaxOffset{
    .name = "unity_parallax_offset",
    .citation =
        "Unity built-in/URP ParallaxOffset: TwoTailsGames/Unity-Built-in-Shaders "
        "CGIncludes/UnityStandardUtils.cginc ParallaxOffset1Step, UnityCG.cginc "
        "ParallaxOffset, UnityStandardInput.cginc Parallax @ 6a63f93bc1f2 (Unity "
        "2019.4.1); URP Unity-Technologies/Graphics universal/Shaders/LitInput.hlsl "
        "@ 3b0efc39f87e; s = _Parallax (0.02 built-in, 0.005 URP)",
    .summary = "one fetch: uv = P + s (h - 0.5) V.xy / (V.z + 0.42) (softened offset)",
    .knobs = {.search = M::Offset, .offset_form = M::OffSoft, .offset_soften = 0.42},
    .order = 360,
    .required_bias = 0.5,
    .bias_reason = "ParallaxOffset centres heights on 0.5 (h _Parallax - _Parallax / 2)",
};
PXH_REGISTER_PRESET(kUnityParallaxOffset);

// ParallaxOcclusionMapping (secant branch): numSteps = int(lerp(_PPDMinSamples, _PPDMaxSamples,
// saturate(FastACosPos(normalize(s V.xy, V.z).z) 2/pi))); layer 0 fetched, layers 1.. tested
// (height > rayHeight), one layer fetched past the bottom; regula falsi, at most 3 probes,
// tolerance 0.01, the last probe's offset returned.
const MarchPresetRow kHdrpPom{
    .name = "hdrp_pom",
    .citation =
        "Unity HDRP Lit pixel displacement: Unity-Technologies/Graphics "
        "render-pipelines.core/ShaderLibrary/PerPixelDisplacement.hlsl @ c8df1d81db96 "
        "(ParallaxOcclusionMapping), high-definition/Runtime/Material/Lit/"
        "LitDataDisplacement.hlsl @ d679af29c7a2 (ApplyPerPixelDisplacement), Lit.shader "
        "@ ba62a5986427 (defaults); s = _HeightPoMAmplitude / 100 (2 cm: 0.02) for a 1 m "
        "primitive at tiling 1",
    .summary =
        "POM with an angle-of-the-scaled-ray layer count, regula falsi (3 probes, "
        "tolerance 0.01) returning the last probe; LOD fade off",
    .knobs = {.count = M::AngleScaled,
              .first = M::FirstSample,  // prevHeight at offset 0 (never a hit: h <= 1)
              .compare = M::Lt,         // currHeight > rayHeight
              .extra_layers = 1,        // layer numSteps + 1 is fetched, below the slab
              .on_miss = M::MissRefine,
              .refine = M::Secant,
              .iterations = 3,
              .tolerance = 0.01},
    .params = {{ParamSpec::integer("_PPDMinSamples", 5, 1, 64, "layers head-on (Lit.shader: 5)"),
                MarchKnob::layers_min},
               {ParamSpec::integer("_PPDMaxSamples", 15, 1, 64,
                                   "layers when the s-scaled ray is grazing (Lit.shader: 15)"),
                MarchKnob::layers_max}},
    .exact_on_flat = true,
    .order = 361,
    .required_bias = 1.0,
    .bias_reason = "HDRP pixel displacement goes inward only (height 1 at the polygon)",
};
PXH_REGISTER_PRESET(kHdrpPom);

}  // namespace
}  // namespace pxh
