// Engine presets of the parametric marcher (methods/march/march.h): Godot 4 BaseMaterial3D,
// Bevy StandardMaterial and O3DE Atom StandardPBR parallax, as named settings with the engines'
// parameter names and defaults. The engine's height scale is the experiment's scale s (Godot:
// s = 0.01 heightmap_scale; Bevy: s = parallax_depth_scale; O3DE: s = factor); every one of these
// engines marches from the polygon down through a depth 1 - h, so the reference plane is b = 1.
// Literal transcriptions and the comparisons: tests/engines/literal_godot_bevy_o3de.h,
// tests/methods/engines_godot_bevy_o3de_test.cpp. Research: the README section on engine presets.
#include <string>

#include "harness/core/error.h"
#include "methods/march/march.h"

namespace pxh {
namespace {

MethodInfo with_bias_one(MethodInfo m, const char* engine) {
    m.required_bias = 1.0;
    m.bias_reason = std::string(engine) +
                    " marches from the polygon down through depth 1 - h: the top of the height "
                    "map stays put";
    return m;
}

// ---- Godot 4 ---------------------------------------------------------------------------------
const char* kGodotSource =
    "Godot 4 BaseMaterial3D height mapping: godotengine/godot scene/resources/material.cpp "
    "@ 0059d788b03b559846087c2a1b86a0e19cbdc4ce (BaseMaterial3D::_update_shader, "
    "FEATURE_HEIGHT_MAPPING); defaults from the constructor and doc/classes/BaseMaterial3D.xml "
    "@ 004b2aacb7e87503a583f23e7cf6435aa74b4edf. s = 0.01 heightmap_scale (default 5 -> 0.05)";

ParamSpec godot_flip_binormal() {
    return ParamSpec::boolean("heightmap_flip_binormal", false,
                              "Godot's heightmap_flip_binormal: march with v mirrored");
}

struct GodotParallax {
    static MethodInfo info() {
        return with_bias_one(
            {"godot_parallax",
             kGodotSource,
             "Godot 4 height mapping, deep parallax off: one fetch, uv = P + s (h(P) - 1) V.xy "
             "(offset limiting, no / V.z); heightmap_flip_tangent is not offered",
             {godot_flip_binormal()},
             false,
             301},
            "Godot");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffSin;
        c.mirror_v = p.get_bool("heightmap_flip_binormal");
        return c;
    }
};
PXH_REGISTER_PRESET(GodotParallax);

struct GodotDeep {
    static MethodInfo info() {
        return with_bias_one(
            {"godot_deep",
             kGodotSource,
             "Godot 4 deep parallax: n = mix(heightmap_max_layers, heightmap_min_layers, V.z) "
             "layers stepped by (s/n) V.xy (no / V.z: a relief of depth s V.z), POM lerp with "
             "layer k-1 fetched again, also at k = 0; heightmap_flip_tangent is not offered",
             {ParamSpec::integer("heightmap_min_layers", 8, 1, 64,
                                 "Godot's heightmap_min_layers: layers head-on"),
              ParamSpec::integer("heightmap_max_layers", 32, 1, 64,
                                 "Godot's heightmap_max_layers: layers at grazing views"),
              godot_flip_binormal()},
             false,
             302},
            "Godot");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c;
        c.count = MarchConfig::Mix;
        c.layers_min = p.get_int("heightmap_min_layers");
        c.layers_max = p.get_int("heightmap_max_layers");
        c.step = MarchConfig::StepSin;
        c.mirror_v = p.get_bool("heightmap_flip_binormal");
        c.compare = MarchConfig::Le;
        c.on_miss = MarchConfig::MissRefine;
        c.refine = MarchConfig::Lerp;
        c.refetch = true;
        c.clamp_weight = false;
        c.refine_at_k0 = true;
        return c;
    }
};
PXH_REGISTER_PRESET(GodotDeep);

// ---- Bevy ------------------------------------------------------------------------------------
const char* kBevySource =
    "Bevy StandardMaterial parallax: bevyengine/bevy crates/bevy_pbr/src/render/"
    "parallax_mapping.wgsl @ 1cb1d0dc0fd5f4b3bd9c80ea3ec895c8955a4158 (parallaxed_uv; "
    "parallax_mapping.wesl @ 4805ca792c3e94eef07afd6fa9a2712f388c9a67, same loop); defaults from "
    "crates/bevy_pbr/src/pbr_material.rs and parallax.rs. s = parallax_depth_scale (default 0.1); "
    "depth map D = 1 - h";

std::vector<ParamSpec> bevy_params(bool relief) {
    std::vector<ParamSpec> p = {
        ParamSpec::real("max_parallax_layer_count", 16, 1, 4096,
                        "Bevy's max_parallax_layer_count: layers at grazing views (1 head-on)"),
        ParamSpec::boolean("mirror_v", false,
                           "march with v mirrored: Bevy's literal (1, -1) step on a mikktspace "
                           "frame (B = +dP/dv); false: tangents with B = -dP/dv, where the flip "
                           "cancels")};
    if (relief)
        p.push_back(ParamSpec::integer("max_steps", 5, 0, 256,
                                       "Bevy's ParallaxMappingMethod::Relief max_steps: "
                                       "bisection probes after the midpoint start"));
    return p;
}

MarchConfig bevy_config(const ParamValues& p) {
    MarchConfig c;
    c.count = MarchConfig::Mix;
    c.layers_min = 1;
    c.layers_max = p.get("max_parallax_layer_count");
    c.step = MarchConfig::StepTan;
    c.mirror_v = p.get_bool("mirror_v");
    c.compare = MarchConfig::Le;
    c.on_miss = MarchConfig::MissRefine;
    c.refine_at_k0 = true;
    return c;
}

struct BevyOcclusion {
    static MethodInfo info() {
        return with_bias_one(
            {"bevy_occlusion", kBevySource,
             "Bevy parallax occlusion mapping: n = mix(max_parallax_layer_count, 1, V.z) layers, "
             "POM lerp with layer k-1 fetched again, run also at k = 0 and at the cap",
             bevy_params(false), true, 311},
            "Bevy");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = bevy_config(p);
        c.refine = MarchConfig::Lerp;
        c.refetch = true;
        c.clamp_weight = false;
        return c;
    }
};
PXH_REGISTER_PRESET(BevyOcclusion);

struct BevyRelief {
    static MethodInfo info() {
        return with_bias_one(
            {"bevy_relief", kBevySource,
             "Bevy relief mapping: the occlusion search, then bisection from the midpoint of "
             "layers k-1 and k with max_steps probes (also at k = 0: ends above the polygon)",
             bevy_params(true), false, 312},
            "Bevy");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = bevy_config(p);
        c.refine = MarchConfig::Bisect;
        c.iterations = p.get_int("max_steps");
        c.tie = MarchConfig::TieBack;
        return c;
    }
};
PXH_REGISTER_PRESET(BevyRelief);

// ---- O3DE ------------------------------------------------------------------------------------
const char* kO3deSource =
    "O3DE Atom StandardPBR parallax: o3de/o3de Gems/Atom/Feature/Common/Assets/ShaderLib/Atom/"
    "Features/ParallaxMapping.azsli @ 354a2accd2a21779bbd68812bd69e7e957262cc7 "
    "(AdvancedParallaxMapping, BasicParallaxMapping, CalculateParallaxOffset); defaults from "
    "Materials/Types/MaterialInputs/ParallaxPropertyGroup.json. s = factor (default 0.05); "
    "offset 0 (b = 1)";

ParamSpec o3de_quality() {
    return ParamSpec::choice("quality", {"Low", "Medium", "High", "Ultra"}, "Low",
                             "O3DE's parallax quality: 16 / 32 / 64 / 128 layers");
}

MarchConfig o3de_config(const ParamValues& p) {
    MarchConfig c;
    const std::string q = p.get_name("quality");
    c.count = MarchConfig::Fixed;
    c.layers = q == "Ultra" ? 128 : q == "High" ? 64 : q == "Medium" ? 32 : 16;
    c.step = MarchConfig::StepTan;
    c.compare = MarchConfig::Le;
    c.on_miss = MarchConfig::MissLast;
    return c;
}

struct O3deBasic {
    static MethodInfo info() {
        return with_bias_one({"o3de_basic",
                              kO3deSource,
                              "O3DE Basic parallax: one fetch, uv = P + s (h(P) - 1) V.xy "
                              "(no / V.z)",
                              {},
                              false,
                              321},
                             "O3DE");
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffSin;
        return c;
    }
};
PXH_REGISTER_PRESET(O3deBasic);

struct O3deSteep {
    static MethodInfo info() {
        return with_bias_one({"o3de_steep",
                              kO3deSource,
                              "O3DE Steep: fixed layers (quality), the first layer at or below "
                              "the surface, no refinement",
                              {o3de_quality()},
                              false,
                              322},
                             "O3DE");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = o3de_config(p);
        c.refine = MarchConfig::RefineNone;
        return c;
    }
};
PXH_REGISTER_PRESET(O3deSteep);

struct O3dePom {
    static MethodInfo info() {
        return with_bias_one({"o3de_pom",
                              kO3deSource,
                              "O3DE POM (the default algorithm): fixed layers, lerp between "
                              "layers k-1 and k with the loop's previous sample (no re-fetch)",
                              {o3de_quality()},
                              true,
                              323},
                             "O3DE");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = o3de_config(p);
        c.refine = MarchConfig::Lerp;
        c.clamp_weight = false;
        return c;
    }
};
PXH_REGISTER_PRESET(O3dePom);

struct O3deRelief {
    static MethodInfo info() {
        return with_bias_one({"o3de_relief",
                              kO3deSource,
                              "O3DE Relief: fixed layers, then n sign-steps of halving size "
                              "(sign 0 stays), each followed by a fetch (the last one unused)",
                              {o3de_quality()},
                              false,
                              324},
                             "O3DE");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = o3de_config(p);
        c.refine = MarchConfig::Bisect;
        c.iterations = int(c.layers) - 1;
        c.probe_last = true;
        c.tie = MarchConfig::TieStay;
        return c;
    }
};
PXH_REGISTER_PRESET(O3deRelief);

struct O3deContact {
    static MethodInfo info() {
        return with_bias_one({"o3de_contact",
                              kO3deSource,
                              "O3DE ContactRefinement: fixed layers, then from layer k-1 a "
                              "linear search in sub-layers of 1/n layer, no interpolation",
                              {o3de_quality()},
                              false,
                              325},
                             "O3DE");
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = o3de_config(p);
        c.refine = MarchConfig::Contact;
        return c;
    }
};
PXH_REGISTER_PRESET(O3deContact);

}  // namespace
}  // namespace pxh
