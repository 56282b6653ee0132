// Engine presets of the JavaScript engines: three.js' ParallaxShader (four modes),
// Babylon.js' StandardMaterial/PBRMaterial parallax and parallax occlusion, PlayCanvas'
// StandardMaterial parallax. Each is a named setting of the parametric marcher
// (methods/march/march.h); the engine's height scale is the experiment's `scale`. The literal
// transcriptions these presets are tested against are tests/engines/literal_js.h
// (tests/methods/engines_js_test.cpp). PlayCanvas has no occlusion mode: there is no
// playcanvas_occlusion.
#include "harness/core/error.h"
#include "methods/march/march.h"

namespace pxh {
namespace {

// ---- three.js -------------------------------------------------------------------------------
// Fed a depth map (bumpMap.r = 1 - h) with a positive parallaxScale = s: pxh b = 1. The example's
// negative scale on a height map (a bottom-up march from the slab floor) is not reproduced.
#define PXH_THREEJS_SOURCE                                                                   \
    "three.js ParallaxShader: mrdoob/three.js examples/jsm/shaders/ParallaxShader.js @ "     \
    "05578ec7204d317789959d28ce057ff8c1711d8e; defaults from "                               \
    "examples/webgl_materials_parallaxmap.html @ 76e37a6a21fe4267b82a21b01cd89c96dd0e8c66; " \
    "parallaxScale = s on the depth map 1 - h (b = 1)"

const char* const kThreeBias =
    "three.js is fed the depth map 1 - h with a positive parallaxScale: the top of the map stays "
    "at the polygon";

std::vector<ParamSpec> three_layer_params(double max_layers) {
    return {ParamSpec::real("parallaxMinLayers", 20, 1, max_layers,
                            "uniform parallaxMinLayers: layers head-on (the example's 20)"),
            ParamSpec::real("parallaxMaxLayers", 25, 1, max_layers,
                            "uniform parallaxMaxLayers: layers at grazing (the example's 25); the "
                            "loop stops after 30 steps whatever the count")};
}

// The shared loop of steep / occlusion / relief: n = mix(parallaxMaxLayers, parallaxMinLayers,
// |V.z|), layer 0 sampled at P, stop at the first t <= layer (le), at most 30 steps.
MarchConfig three_layers(const ParamValues& p) {
    MarchConfig c;
    c.count = MarchConfig::Mix;
    c.layers_min = p.get("parallaxMinLayers");
    c.layers_max = p.get("parallaxMaxLayers");
    c.step = MarchConfig::StepTan;
    c.first = MarchConfig::FirstSample;
    c.compare = MarchConfig::Le;
    c.max_steps = 30;
    return c;
}

struct ThreeJsBasic {
    static MethodInfo info() {
        MethodInfo m{"threejs_basic",
                     PXH_THREEJS_SOURCE " (USE_BASIC_PARALLAX)",
                     "three.js basic: offset limiting, uv = P - parallaxScale V.xy t(P), no "
                     "division by V.z (one fetch)",
                     {},
                     false,
                     340};
        m.required_bias = 1.0;
        m.bias_reason = kThreeBias;
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffSin;
        return c;
    }
};
PXH_REGISTER_PRESET(ThreeJsBasic);

struct ThreeJsSteep {
    static MethodInfo info() {
        MethodInfo m{"threejs_steep",
                     PXH_THREEJS_SOURCE " (USE_STEEP_PARALLAX)",
                     "three.js steep: layers mix(25, 20, |V.z|), first layer with t <= depth, at "
                     "most 30 steps; returns that layer's uv",
                     three_layer_params(4096),
                     false,
                     341};
        m.required_bias = 1.0;
        m.bias_reason = kThreeBias;
        return m;
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = three_layers(p);
        c.refine = MarchConfig::RefineNone;
        return c;
    }
};
PXH_REGISTER_PRESET(ThreeJsSteep);

struct ThreeJsOcclusion {
    static MethodInfo info() {
        MethodInfo m{"threejs_occlusion",
                     PXH_THREEJS_SOURCE " (USE_OCLUSION_PARALLAX)",
                     "three.js occlusion (POM): the steep search, then the previous layer fetched "
                     "again and the uv interpolated, weight unclamped, also at layer 0 and past "
                     "the 30-step cap",
                     three_layer_params(4096),
                     true,
                     342};
        m.required_bias = 1.0;
        m.bias_reason = kThreeBias;
        return m;
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = three_layers(p);
        c.refine = MarchConfig::Lerp;
        c.refetch = true;
        c.clamp_weight = false;
        c.refine_at_k0 = true;
        c.on_miss = MarchConfig::MissRefine;
        return c;
    }
};
PXH_REGISTER_PRESET(ThreeJsOcclusion);

struct ThreeJsRelief {
    static MethodInfo info() {
        // parallaxMaxLayers <= 30 (the example's GUI range): beyond, the 30-step cap ends the
        // search uncrossed, where the shader still steps half a layer back before bisecting
        // and the marcher steps forward; no knob reproduces that.
        MethodInfo m{"threejs_relief",
                     PXH_THREEJS_SOURCE " (USE_RELIEF_PARALLAX)",
                     "three.js relief: the steep search, then 5 bisection probes from half a "
                     "layer back; returns the never-sampled bracket centre (also at layer 0, "
                     "above the slab)",
                     three_layer_params(30),
                     false,
                     343};
        m.required_bias = 1.0;
        m.bias_reason = kThreeBias;
        return m;
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c = three_layers(p);
        c.refine = MarchConfig::Bisect;
        c.iterations = 5;  // const int numSearches = 5
        c.tie = MarchConfig::TieBack;
        c.refine_at_k0 = true;
        c.on_miss = MarchConfig::MissRefine;
        return c;
    }
};
PXH_REGISTER_PRESET(ThreeJsRelief);

// ---- Babylon.js -----------------------------------------------------------------------------
#define PXH_BABYLON_SOURCE                                                                      \
    "Babylon.js StandardMaterial/PBRMaterial: BabylonJS/Babylon.js "                            \
    "packages/dev/core/src/Shaders/ShadersInclude/bumpFragmentFunctions.fx @ "                  \
    "769119fa3fc4361674f90c61d97435b2b95c1aac, bumpFragment.fx @ "                              \
    "1af75dc439cf808c93e33cecf15dd7f78c688148; parallaxScaleBias (default 0.05) = s, height = " \
    "normal-map alpha"

struct BabylonParallax {
    static MethodInfo info() {
        MethodInfo m{"babylon_parallax",
                     PXH_BABYLON_SOURCE " (parallaxOffset, useParallax)",
                     "Babylon.js parallax: offset limiting above the polygon, uv = P + s h(P) "
                     "V.xy, no division by V.z (one fetch)",
                     {},
                     false,
                     344};
        m.required_bias = 0.0;
        m.bias_reason =
            "Babylon.js' parallaxOffset moves uv by s h V.xy: the polygon is the bottom of the map";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffSin;
        return c;
    }
};
PXH_REGISTER_PRESET(BabylonParallax);

struct BabylonPom {
    static MethodInfo info() {
        MethodInfo m{"babylon_pom",
                     PXH_BABYLON_SOURCE " (parallaxOcclusion, useParallaxOcclusion)",
                     "Babylon.js POM: n = 15 + 11 V.z layers (the count from dot(N, -V), "
                     "inverted), only layers 0..14 tested (iMaxSamples 15), hit h > ray, "
                     "interpolated; no hit: uv of layer 15, untested",
                     {},
                     false,
                     345};
        m.required_bias = 1.0;
        m.bias_reason = "Babylon.js' parallaxOcclusion starts the ray at height 1 at the polygon";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.count = MarchConfig::MixNegated;
        c.layers_min = 4;   // minSamples
        c.layers_max = 15;  // maxSamples
        c.step = MarchConfig::StepTan;
        c.first = MarchConfig::FirstSample;
        c.compare = MarchConfig::Lt;
        c.max_steps = 14;  // iMaxSamples = 15 samples: layers 0..14
        c.on_miss = MarchConfig::MissNext;
        c.refine = MarchConfig::Lerp;
        c.clamp_weight = false;
        return c;
    }
};
PXH_REGISTER_PRESET(BabylonPom);

// ---- PlayCanvas -----------------------------------------------------------------------------
struct PlayCanvasBasic {
    static MethodInfo info() {
        MethodInfo m{"playcanvas_basic",
                     "PlayCanvas StandardMaterial getParallax: playcanvas/engine "
                     "src/scene/shader-lib/glsl/chunks/standard/frag/parallax.js and "
                     "src/scene/materials/standard-material.js @ "
                     "e287e0c67f3c20c689a52b7c53d2b7fedbe887da (v2.21.4); s = 0.025 "
                     "heightMapFactor (default 1), heightMapChannel g",
                     "PlayCanvas parallax: uv = P + s (h(P) - 0.5) V.xy / (V.z + 0.42) (one "
                     "fetch); there is no occlusion mode",
                     {},
                     false,
                     346};
        m.required_bias = 0.5;
        m.bias_reason =
            "PlayCanvas offsets by height * s - s * 0.5: the map's mid-grey stays at the polygon";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffSoft;
        c.offset_soften = 0.42;
        return c;
    }
};
PXH_REGISTER_PRESET(PlayCanvasBasic);

}  // namespace
}  // namespace pxh
