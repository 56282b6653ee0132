// Unity's parallax as presets of the parametric marcher (methods/march/preset.h): built-in/URP
// ParallaxOffset and HDRP's PerPixelDisplacement. The engine's height scale is the experiment's
// scale s (conversions in docs/findings/engines.md); each fixes the reference plane, so each
// requires its bias. Literal transcriptions and the comparison:
// tests/engines/literal_unity_jme_ogre_dx.h, tests/methods/engines_unity_jme_ogre_dx_test.cpp.
//
// Texture levels. Built-in/URP ParallaxOffset reads tex2D (the hardware's derivatives: `lod =
// "implicit"` on the GLSL backend). HDRP computes one level before the loop,
// lod = ComputeTextureLOD(uv * _HeightMap_TexelSize.zw) = max(0.5 log2(max(|ddx|^2, |ddy|^2)), 0)
// of the texel coordinates (LitDataDisplacement.hlsl, ApplyPerPixelDisplacement; Common.hlsl),
// which is pxh's max(lambda, 0) (docs/conventions.md section 10.2), and every fetch of the march
// is SAMPLE_TEXTURE2D_LOD at it (ComputePerPixelHeightDisplacement): `lod = "level"` reproduces
// the sampling on both twins. After the march ParallaxOcclusionMapping fades the offset,
// offset *= 1 - saturate(lod - lodThreshold) (PerPixelDisplacement.hlsl): full up to
// _PPDLodThreshold (Lit.shader: 5), gone one level past it; the march runs (and fetches) at every
// level. That is lod_fade = hdrp; the level is the sample's own lambda in every lod mode.
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
    .engine_version =
        "Unity built-in render pipeline shaders @ 6a63f93b (TwoTailsGames/Unity-Built-in-Shaders) "
        "and URP @ 3b0efc39 (git; no release checked)",
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
        "(ParallaxOcclusionMapping; the LOD fade also @ "
        "50e45ca435f942aabed02e45c76bf8dd8ef0c1a0), high-definition/Runtime/Material/Lit/"
        "LitDataDisplacement.hlsl @ d679af29c7a2 (ApplyPerPixelDisplacement; the level before "
        "the loop also @ 155cdbc4789454bf0bc92c8918aae1f3126c0cf2), Lit.shader @ ba62a5986427 "
        "(defaults, _PPDLodThreshold 5); s = _HeightPoMAmplitude / 100 (2 cm: 0.02) for a 1 m "
        "primitive at tiling 1",
    .summary =
        "POM with an angle-of-the-scaled-ray layer count, regula falsi (3 probes, "
        "tolerance 0.01) returning the last probe; offset faded out over the level after "
        "_PPDLodThreshold (5)",
    .knobs = {.count = M::AngleScaled,
              .first = M::FirstSample,  // prevHeight at offset 0 (never a hit: h <= 1)
              .compare = M::Lt,         // currHeight > rayHeight
              .extra_layers = 1,        // layer numSteps + 1 is fetched, below the slab
              .on_miss = M::MissRefine,
              .refine = M::Secant,
              .iterations = 3,
              .tolerance = 0.01,
              .lod_fade = M::FadeHdrp,
              .lod_threshold = 5,
              .depth_offset = M::PdoHdrp},
    .params = {{ParamSpec::integer("_PPDMinSamples", 5, 1, 64, "layers head-on (Lit.shader: 5)"),
                MarchKnob::layers_min},
               {ParamSpec::integer("_PPDMaxSamples", 15, 1, 64,
                                   "layers when the s-scaled ray is grazing (Lit.shader: 15)"),
                MarchKnob::layers_max},
               {ParamSpec::real("_PPDLodThreshold", 5, 0, 16,
                                "level of detail where the offset starts fading out (gone one "
                                "level later; Lit.shader: 5)"),
                MarchKnob::lod_threshold}},
    .exact_on_flat = true,
    .order = 361,
    .required_bias = 1.0,
    .bias_reason = "HDRP pixel displacement goes inward only (height 1 at the polygon)",
    .engine_version =
        "HDRP (Unity-Technologies/Graphics) @ c8df1d81, d679af29, ba62a598 (git; no release "
        "checked)",
};
PXH_REGISTER_PRESET(kHdrpPom);

}  // namespace
}  // namespace pxh
