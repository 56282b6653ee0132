// Bevy StandardMaterial parallax as presets of the parametric marcher (methods/march/preset.h),
// with Bevy's parameter names and defaults. s = parallax_depth_scale; Bevy marches from the
// polygon down through the depth map D = 1 - h, so b = 1. Literal transcription and the
// comparison: tests/engines/literal_godot_bevy_o3de.h, tests/engines_godot_bevy_o3de_test.cpp.
//
// Texture levels: sample_depth_map reads textureSampleLevel(.., 0.0), level 0 on purpose (`lod =
// "base"`, pxh's default, is Bevy's sampling). No fade.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kBevyVersion = "Bevy @ 1cb1d0dc and 4805ca79 (git; no release checked)";

using M = MarchConfig;

const char* const kBevySource =
    "Bevy StandardMaterial parallax: bevyengine/bevy crates/bevy_pbr/src/render/"
    "parallax_mapping.wgsl @ 1cb1d0dc0fd5f4b3bd9c80ea3ec895c8955a4158 (parallaxed_uv; "
    "parallax_mapping.wesl @ 4805ca792c3e94eef07afd6fa9a2712f388c9a67, same loop); defaults from "
    "crates/bevy_pbr/src/pbr_material.rs and parallax.rs. s = parallax_depth_scale (default 0.1); "
    "depth map D = 1 - h";
const char* const kBevyBias =
    "Bevy marches from the polygon down through depth 1 - h: the top of the height map stays put";

PresetParam max_layer_count() {
    return {ParamSpec::real("max_parallax_layer_count", 16, 1, 4096,
                            "Bevy's max_parallax_layer_count: layers at grazing views (1 head-on)"),
            MarchKnob::layers_max};
}
PresetParam mirror_v() {
    return {
        ParamSpec::boolean("mirror_v", false,
                           "march with v mirrored: Bevy's literal (1, -1) step on a mikktspace "
                           "frame (B = +dP/dv); false: tangents with B = -dP/dv, where the flip "
                           "cancels"),
        MarchKnob::mirror_v};
}

// Both: n = mix(max_parallax_layer_count, 1, V.z), the first layer at or below the surface, the
// refinement also at k = 0 and at the cap.
const MarchPresetRow kBevyOcclusion{
    .name = "bevy_occlusion",
    .citation = kBevySource,
    .summary =
        "Bevy parallax occlusion mapping: n = mix(max_parallax_layer_count, 1, V.z) layers, "
        "POM lerp with layer k-1 fetched again, run also at k = 0 and at the cap",
    .knobs = {.count = M::Mix,
              .layers_min = 1,
              .step = M::StepTan,
              .compare = M::Le,
              .on_miss = M::MissRefine,
              .refine = M::Lerp,
              .clamp_weight = false,
              .refetch = true,
              .refine_at_k0 = true},
    .params = {max_layer_count(), mirror_v()},
    .exact_on_flat = true,
    .order = 311,
    .required_bias = 1.0,
    .bias_reason = kBevyBias,
    .engine_version = kBevyVersion,
};
PXH_REGISTER_PRESET(kBevyOcclusion);

const MarchPresetRow kBevyRelief{
    .name = "bevy_relief",
    .citation = kBevySource,
    .summary =
        "Bevy relief mapping: the occlusion search, then bisection from the midpoint of "
        "layers k-1 and k with max_steps probes (also at k = 0: ends above the polygon)",
    .knobs = {.count = M::Mix,
              .layers_min = 1,
              .step = M::StepTan,
              .compare = M::Le,
              .on_miss = M::MissRefine,
              .refine = M::Bisect,
              .refine_at_k0 = true,
              .tie = M::TieBack},
    .params = {max_layer_count(),
               mirror_v(),
               {ParamSpec::integer("max_steps", 5, 0, 256,
                                   "Bevy's ParallaxMappingMethod::Relief max_steps: "
                                   "bisection probes after the midpoint start"),
                MarchKnob::iterations}},
    .order = 312,
    .required_bias = 1.0,
    .bias_reason = kBevyBias,
    .engine_version = kBevyVersion,
};
PXH_REGISTER_PRESET(kBevyRelief);

}  // namespace
}  // namespace pxh
