// Babylon.js StandardMaterial/PBRMaterial parallax and parallax occlusion as presets of the
// parametric marcher (methods/march/preset.h); parallaxScaleBias = s. Literal transcription and
// the comparison: tests/engines/literal_js.h, tests/methods/engines_js_test.cpp.
//
// Texture levels: both read the height with texture2D(bumpSampler, ...), the hardware's own
// derivatives (`lod = "implicit"` reproduces it on the GLSL backend; `base` is level 0, pxh's
// default). parallaxOcclusion's loop has no break: it samples on every one of its iMaxSamples =
// 15 iterations, also after the hit (at the interpolated offset, the value unused), so every
// sample costs 15 fetches (pad_fetches); the uv is the search's.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kBabylonVersion = "Babylon.js @ 769119fa (git; no release checked)";

using M = MarchConfig;

#define PXH_BABYLON_SOURCE                                                                      \
    "Babylon.js StandardMaterial/PBRMaterial: BabylonJS/Babylon.js "                            \
    "packages/dev/core/src/Shaders/ShadersInclude/bumpFragmentFunctions.fx @ "                  \
    "769119fa3fc4361674f90c61d97435b2b95c1aac, bumpFragment.fx @ "                              \
    "1af75dc439cf808c93e33cecf15dd7f78c688148; parallaxScaleBias (default 0.05) = s, height = " \
    "normal-map alpha"

const MarchPresetRow kBabylonParallax{
    .name = "babylon_parallax",
    .citation = PXH_BABYLON_SOURCE " (parallaxOffset, useParallax)",
    .summary =
        "Babylon.js parallax: offset limiting above the polygon, uv = P + s h(P) V.xy, no "
        "division by V.z (one fetch)",
    .knobs = {.search = M::Offset, .offset_form = M::OffSin},
    .order = 344,
    .required_bias = 0.0,
    .bias_reason =
        "Babylon.js' parallaxOffset moves uv by s h V.xy: the polygon is the bottom of the map",
    .engine_version = kBabylonVersion,
};
PXH_REGISTER_PRESET(kBabylonParallax);

const MarchPresetRow kBabylonPom{
    .name = "babylon_pom",
    .citation = PXH_BABYLON_SOURCE " (parallaxOcclusion, useParallaxOcclusion)",
    .summary =
        "Babylon.js POM: n = 15 + 11 V.z layers (the count from dot(N, -V), inverted), only "
        "layers 0..14 tested (iMaxSamples 15), hit h > ray, interpolated; no hit: uv of "
        "layer 15, untested; 15 fetches on every sample (the loop samples on, after the hit)",
    .knobs = {.count = M::MixNegated,
              .layers_min = 4,   // minSamples
              .layers_max = 15,  // maxSamples
              .step = M::StepTan,
              .first = M::FirstSample,
              .compare = M::Lt,
              .max_steps = 14,  // iMaxSamples = 15 samples: layers 0..14
              .on_miss = M::MissNext,
              .refine = M::Lerp,
              .clamp_weight = false,
              .pad_fetches = true},  // the loop fetches on all 15 iterations, also after the hit
    .order = 345,
    .required_bias = 1.0,
    .bias_reason = "Babylon.js' parallaxOcclusion starts the ray at height 1 at the polygon",
    .engine_version = kBabylonVersion,
};
PXH_REGISTER_PRESET(kBabylonPom);

}  // namespace
}  // namespace pxh
