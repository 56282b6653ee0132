// three.js' ParallaxShader (its four modes) as presets of the parametric marcher
// (methods/march/preset.h). Fed a depth map (bumpMap.r = 1 - h) with a positive parallaxScale = s:
// b = 1. The example's negative scale on a height map (a bottom-up march from the slab floor) is
// not reproduced. Literal transcription and the comparison: tests/engines/literal_js.h,
// tests/methods/engines_js_test.cpp.
//
// Texture levels: every mode reads texture2D(bumpMap, ...), in the loop too: the hardware's
// derivatives of the offset uv (`lod = "implicit"` on the GLSL backend). No fade.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kThreeVersion =
    "three.js r131 (npm three@0.131.3, checked: the last release whose package ships "
    "examples/jsm/shaders/ParallaxShader.js; three.js now ships the TSL node parallaxUV)";

using M = MarchConfig;

#define PXH_THREEJS_SOURCE                                                                   \
    "three.js ParallaxShader: mrdoob/three.js examples/jsm/shaders/ParallaxShader.js @ "     \
    "05578ec7204d317789959d28ce057ff8c1711d8e; defaults from "                               \
    "examples/webgl_materials_parallaxmap.html @ 76e37a6a21fe4267b82a21b01cd89c96dd0e8c66; " \
    "parallaxScale = s on the depth map 1 - h (b = 1)"

const char* const kThreeBias =
    "three.js is fed the depth map 1 - h with a positive parallaxScale: the top of the map stays "
    "at the polygon";

std::vector<PresetParam> layer_params(double max_layers) {
    return {{ParamSpec::real("parallaxMinLayers", 20, 1, max_layers,
                             "uniform parallaxMinLayers: layers head-on (the example's 20)"),
             MarchKnob::layers_min},
            {ParamSpec::real("parallaxMaxLayers", 25, 1, max_layers,
                             "uniform parallaxMaxLayers: layers at grazing (the example's 25); the "
                             "loop stops after 30 steps whatever the count"),
             MarchKnob::layers_max}};
}

const MarchPresetRow kThreeJsBasic{
    .name = "threejs_basic",
    .citation = PXH_THREEJS_SOURCE " (USE_BASIC_PARALLAX)",
    .summary =
        "three.js basic: offset limiting, uv = P - parallaxScale V.xy t(P), no division by "
        "V.z (one fetch)",
    .knobs = {.search = M::Offset, .offset_form = M::OffSin},
    .order = 340,
    .required_bias = 1.0,
    .bias_reason = kThreeBias,
    .engine_version = kThreeVersion,
};
PXH_REGISTER_PRESET(kThreeJsBasic);

// steep / occlusion / relief share the loop: n = mix(parallaxMaxLayers, parallaxMinLayers,
// |V.z|), layer 0 sampled at P, stop at the first t <= layer (le), at most 30 steps.
const MarchPresetRow kThreeJsSteep{
    .name = "threejs_steep",
    .citation = PXH_THREEJS_SOURCE " (USE_STEEP_PARALLAX)",
    .summary =
        "three.js steep: layers mix(25, 20, |V.z|), first layer with t <= depth, at most 30 "
        "steps; returns that layer's uv",
    .knobs = {.count = M::Mix,
              .step = M::StepTan,
              .first = M::FirstSample,
              .compare = M::Le,
              .max_steps = 30,
              .refine = M::RefineNone},
    .params = layer_params(4096),
    .order = 341,
    .required_bias = 1.0,
    .bias_reason = kThreeBias,
    .engine_version = kThreeVersion,
};
PXH_REGISTER_PRESET(kThreeJsSteep);

const MarchPresetRow kThreeJsOcclusion{
    .name = "threejs_occlusion",
    .citation = PXH_THREEJS_SOURCE " (USE_OCLUSION_PARALLAX)",
    .summary =
        "three.js occlusion (POM): the steep search, then the previous layer fetched again "
        "and the uv interpolated, weight unclamped, also at layer 0 and past the 30-step "
        "cap",
    .knobs = {.count = M::Mix,
              .step = M::StepTan,
              .first = M::FirstSample,
              .compare = M::Le,
              .max_steps = 30,
              .on_miss = M::MissRefine,
              .refine = M::Lerp,
              .clamp_weight = false,
              .refetch = true,
              .refine_at_k0 = true},
    .params = layer_params(4096),
    .exact_on_flat = true,
    .order = 342,
    .required_bias = 1.0,
    .bias_reason = kThreeBias,
    .engine_version = kThreeVersion,
};
PXH_REGISTER_PRESET(kThreeJsOcclusion);

// parallaxMaxLayers <= 30 (the example's GUI range): beyond, the 30-step cap ends the search
// uncrossed, where the shader still steps half a layer back before bisecting and the marcher
// steps forward; no knob reproduces that.
const MarchPresetRow kThreeJsRelief{
    .name = "threejs_relief",
    .citation = PXH_THREEJS_SOURCE " (USE_RELIEF_PARALLAX)",
    .summary =
        "three.js relief: the steep search, then 5 bisection probes from half a layer back; "
        "returns the never-sampled bracket centre (also at layer 0, above the slab)",
    .knobs = {.count = M::Mix,
              .step = M::StepTan,
              .first = M::FirstSample,
              .compare = M::Le,
              .max_steps = 30,
              .on_miss = M::MissRefine,
              .refine = M::Bisect,
              .refine_at_k0 = true,
              .iterations = 5,  // const int numSearches = 5
              .tie = M::TieBack},
    .params = layer_params(30),
    .order = 343,
    .required_bias = 1.0,
    .bias_reason = kThreeBias,
    .engine_version = kThreeVersion,
};
PXH_REGISTER_PRESET(kThreeJsRelief);

}  // namespace
}  // namespace pxh
