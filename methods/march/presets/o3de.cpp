// O3DE Atom StandardPBR parallax as presets of the parametric marcher (methods/march/preset.h),
// with O3DE's parameter names and defaults. s = factor; offset 0: O3DE marches from the polygon
// down through a depth 1 - h, so b = 1. Literal transcription and the comparison:
// tests/engines/literal_godot_bevy_o3de.h, tests/engines_godot_bevy_o3de_test.cpp.
//
// Texture levels: SampleDepthFromHeightmap reads map.SampleGrad(.., uv_ddx, uv_ddy) with
// ddx_fine / ddy_fine of the unoffset uv taken before the loop (`lod = "grad"` on the GLSL
// backend is O3DE's sampling; `level` is its isotropic equivalent on both twins). No fade.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kO3deVersion = "O3DE @ 354a2acc (git; no release checked)";

using M = MarchConfig;

const char* const kO3deSource =
    "O3DE Atom StandardPBR parallax: o3de/o3de Gems/Atom/Feature/Common/Assets/ShaderLib/Atom/"
    "Features/ParallaxMapping.azsli @ 354a2accd2a21779bbd68812bd69e7e957262cc7 "
    "(AdvancedParallaxMapping, BasicParallaxMapping, CalculateParallaxOffset); defaults from "
    "Materials/Types/MaterialInputs/ParallaxPropertyGroup.json. s = factor (default 0.05); "
    "offset 0 (b = 1)";
const char* const kO3deBias =
    "O3DE marches from the polygon down through depth 1 - h: the top of the height map stays put";

// The layered algorithms: quality Low / Medium / High / Ultra = 16 / 32 / 64 / 128 fixed layers,
// stepped along the ray, the first layer at or below the surface; no hit: the last layer.
PresetParam quality() {
    return {ParamSpec::choice("quality", {"Low", "Medium", "High", "Ultra"}, "Low",
                              "O3DE's parallax quality: 16 / 32 / 64 / 128 layers"),
            MarchKnob::layers,
            {16, 32, 64, 128}};
}

const MarchPresetRow kO3deBasic{
    .name = "o3de_basic",
    .citation = kO3deSource,
    .summary = "O3DE Basic parallax: one fetch, uv = P + s (h(P) - 1) V.xy (no / V.z)",
    .knobs = {.search = M::Offset, .offset_form = M::OffSin, .depth_offset = M::PdoO3de},
    .order = 321,
    .required_bias = 1.0,
    .bias_reason = kO3deBias,
    .engine_version = kO3deVersion,
};
PXH_REGISTER_PRESET(kO3deBasic);

const MarchPresetRow kO3deSteep{
    .name = "o3de_steep",
    .citation = kO3deSource,
    .summary =
        "O3DE Steep: fixed layers (quality), the first layer at or below the surface, no "
        "refinement",
    .knobs = {.count = M::Fixed,
              .step = M::StepTan,
              .compare = M::Le,
              .on_miss = M::MissLast,
              .refine = M::RefineNone,
              .depth_offset = M::PdoO3de},
    .params = {quality()},
    .order = 322,
    .required_bias = 1.0,
    .bias_reason = kO3deBias,
    .engine_version = kO3deVersion,
};
PXH_REGISTER_PRESET(kO3deSteep);

const MarchPresetRow kO3dePom{
    .name = "o3de_pom",
    .citation = kO3deSource,
    .summary =
        "O3DE POM (the default algorithm): fixed layers, lerp between layers k-1 and k with "
        "the loop's previous sample (no re-fetch)",
    .knobs = {.count = M::Fixed,
              .step = M::StepTan,
              .compare = M::Le,
              .on_miss = M::MissLast,
              .refine = M::Lerp,
              .clamp_weight = false,
              .depth_offset = M::PdoO3de},
    .params = {quality()},
    .exact_on_flat = true,
    .order = 323,
    .required_bias = 1.0,
    .bias_reason = kO3deBias,
    .engine_version = kO3deVersion,
};
PXH_REGISTER_PRESET(kO3dePom);

const MarchPresetRow kO3deRelief{
    .name = "o3de_relief",
    .citation = kO3deSource,
    .summary =
        "O3DE Relief: fixed layers, then n sign-steps of halving size (sign 0 stays), each "
        "followed by a fetch (the last one unused)",
    .knobs = {.count = M::Fixed,
              .step = M::StepTan,
              .compare = M::Le,
              .on_miss = M::MissLast,
              .refine = M::Bisect,
              .probe_last = true,
              .tie = M::TieStay,
              .depth_offset = M::PdoO3de},
    .params = {quality()},
    .order = 324,
    .required_bias = 1.0,
    .bias_reason = kO3deBias,
    .derive = [](MarchConfig& c) { c.iterations = int(c.layers) - 1; },
    .engine_version = kO3deVersion,
};
PXH_REGISTER_PRESET(kO3deRelief);

const MarchPresetRow kO3deContact{
    .name = "o3de_contact",
    .citation = kO3deSource,
    .summary =
        "O3DE ContactRefinement: fixed layers, then from layer k-1 a linear search in "
        "sub-layers of 1/n layer, no interpolation",
    .knobs = {.count = M::Fixed,
              .step = M::StepTan,
              .compare = M::Le,
              .on_miss = M::MissLast,
              .refine = M::Contact,
              .depth_offset = M::PdoO3de},
    .params = {quality()},
    .order = 325,
    .required_bias = 1.0,
    .bias_reason = kO3deBias,
    .engine_version = kO3deVersion,
};
PXH_REGISTER_PRESET(kO3deContact);

}  // namespace
}  // namespace pxh
