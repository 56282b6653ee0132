// OGRE's RTSS normal_map parallax and parallax_occlusion as presets of the parametric marcher
// (methods/march/preset.h). s = height_scale; OGRE reads depth = 1 - alpha below the polygon,
// so b = 1. Literal transcriptions and the comparison: tests/engines/literal_unity_jme_ogre_dx.h,
// tests/methods/engines_unity_jme_ogre_dx_test.cpp.
//
// Texture levels: SGX_Generate_Parallax_Texcoord reads texture2D(normalHeightMap, ...), in the
// loop too (`lod = "implicit"` on the GLSL backend). No fade.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kOgreVersion = "OGRE @ 3e955a16 (git; no release checked)";

using M = MarchConfig;

const char* const kOgreBias = "OGRE reads depth = 1 - alpha below the polygon";

// SGX_Generate_Parallax_Texcoord without POM_LAYER_COUNT: uv = P - eyeVec.xy / eyeVec.z
// (1 - a) heightScale: pxh parallax with b = 1.
const MarchPresetRow kOgreParallax{
    .name = "ogre_parallax",
    .citation =
        "OGRE RTSS normal_map parallax: OGRECave/ogre "
        "Media/RTShaderLib/SGXLib_NormalMap.glsl (SGX_Generate_Parallax_Texcoord), "
        "Components/RTShaderSystem/src/OgreShaderExNormalMapLighting.cpp @ "
        "3e955a168617; s = height_scale (0.04)",
    .summary = "one fetch: uv = P + s (h - 1) V.xy / V.z (depth = 1 - normal map alpha)",
    .knobs = {.search = M::Offset, .offset_form = M::OffTan},
    .exact_on_flat = true,
    .order = 364,
    .required_bias = 1.0,
    .bias_reason = kOgreBias,
    .engine_version = kOgreVersion,
};
PXH_REGISTER_PRESET(kOgreParallax);

// SGX_Generate_Parallax_Texcoord with POM_LAYER_COUNT=32: step eyeVec.xy s / 32 (no division by
// eyeVec.z); a dead fetch at P; the sample at P - k delta compared with layer depth (k - 1)/32;
// the interpolation re-fetches the previous layer; after 32 layers without a break it
// interpolates with the counter's final (unlagged) depths; no guard on 0/0.
const MarchPresetRow kOgrePom{
    .name = "ogre_pom",
    .citation =
        "OGRE RTSS normal_map parallax_occlusion: OGRECave/ogre "
        "Media/RTShaderLib/SGXLib_NormalMap.glsl (SGX_Generate_Parallax_Texcoord, "
        "POM_LAYER_COUNT), OgreShaderExNormalMapLighting.cpp @ 3e955a168617; "
        "s = height_scale (0.04)",
    .summary = "POM with 32 layers, a sin(theta) step and a one-step lag in the comparison",
    .knobs = {.count = M::Fixed,
              .layers = 32,  // POM_LAYER_COUNT
              .step = M::StepSin,
              .first = M::FirstSample,  // the dead fetch at P (never a hit with the lag)
              .compare = M::Lt,         // currentLayerDepth > currentDepthMapValue
              .lag = true,
              .on_miss = M::MissRefine,
              .refine = M::Lerp,
              .clamp_weight = false,
              .refetch = true},
    .order = 365,
    .required_bias = 1.0,
    .bias_reason = kOgreBias,
    .engine_version = kOgreVersion,
};
PXH_REGISTER_PRESET(kOgrePom);

}  // namespace
}  // namespace pxh
