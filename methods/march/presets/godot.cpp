// Godot 4 BaseMaterial3D height mapping as presets of the parametric marcher
// (methods/march/preset.h), with Godot's parameter names and defaults. s = 0.01 heightmap_scale;
// Godot marches from the polygon down through a depth 1 - h, so b = 1. Literal transcription and
// the comparison: tests/engines/literal_godot_bevy_o3de.h, tests/engines_godot_bevy_o3de_test.cpp.
//
// Texture levels: the generated shader reads texture(texture_heightmap, ...) in the loop, the
// hardware's derivatives of the offset uv (`lod = "implicit"` on the GLSL backend); the stray
// pixels of godotengine/godot PR 101551 come from there. No fade.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kGodotVersion = "Godot 4 @ 0059d788 (git; no release checked)";

using M = MarchConfig;

const char* const kGodotSource =
    "Godot 4 BaseMaterial3D height mapping: godotengine/godot scene/resources/material.cpp "
    "@ 0059d788b03b559846087c2a1b86a0e19cbdc4ce (BaseMaterial3D::_update_shader, "
    "FEATURE_HEIGHT_MAPPING); defaults from the constructor and doc/classes/BaseMaterial3D.xml "
    "@ 004b2aacb7e87503a583f23e7cf6435aa74b4edf. s = 0.01 heightmap_scale (default 5 -> 0.05)";
const char* const kGodotBias =
    "Godot marches from the polygon down through depth 1 - h: the top of the height map stays put";

PresetParam flip_binormal() {
    return {ParamSpec::boolean("heightmap_flip_binormal", false,
                               "Godot's heightmap_flip_binormal: march with v mirrored"),
            MarchKnob::mirror_v};
}

const MarchPresetRow kGodotParallax{
    .name = "godot_parallax",
    .citation = kGodotSource,
    .summary =
        "Godot 4 height mapping, deep parallax off: one fetch, uv = P + s (h(P) - 1) V.xy "
        "(offset limiting, no / V.z); heightmap_flip_tangent is not offered",
    .knobs = {.search = M::Offset, .offset_form = M::OffSin},
    .params = {flip_binormal()},
    .order = 301,
    .required_bias = 1.0,
    .bias_reason = kGodotBias,
    .engine_version = kGodotVersion,
};
PXH_REGISTER_PRESET(kGodotParallax);

const MarchPresetRow kGodotDeep{
    .name = "godot_deep",
    .citation = kGodotSource,
    .summary =
        "Godot 4 deep parallax: n = mix(heightmap_max_layers, heightmap_min_layers, V.z) "
        "layers stepped by (s/n) V.xy (no / V.z: a relief of depth s V.z), POM lerp with "
        "layer k-1 fetched again, also at k = 0; heightmap_flip_tangent is not offered",
    .knobs = {.count = M::Mix,
              .step = M::StepSin,
              .compare = M::Le,
              .on_miss = M::MissRefine,
              .refine = M::Lerp,
              .clamp_weight = false,
              .refetch = true,
              .refine_at_k0 = true},
    .params = {{ParamSpec::integer("heightmap_min_layers", 8, 1, 64,
                                   "Godot's heightmap_min_layers: layers head-on"),
                MarchKnob::layers_min},
               {ParamSpec::integer("heightmap_max_layers", 32, 1, 64,
                                   "Godot's heightmap_max_layers: layers at grazing views"),
                MarchKnob::layers_max},
               flip_binormal()},
    .order = 302,
    .required_bias = 1.0,
    .bias_reason = kGodotBias,
    .engine_version = kGodotVersion,
};
PXH_REGISTER_PRESET(kGodotDeep);

}  // namespace
}  // namespace pxh
