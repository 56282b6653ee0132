// PlayCanvas StandardMaterial parallax as presets of the parametric marcher
// (methods/march/preset.h), following the current stable release (2.22.0 and later: its offset
// mode, playcanvas_basic, and its occlusion mode, playcanvas_occlusion), with the offset mode of
// 2.21 and earlier kept as playcanvas_basic_v2_21. Literal transcriptions and the comparison:
// tests/engines/literal_js.h, tests/methods/engines_js_test.cpp.
//
// Sources read for 2.22+: npm playcanvas@2.22.0 and playcanvas@2.23.3, build/playcanvas.mjs,
// the GLSL chunk parallaxPS (`parallax_default`: getParallax, the same text in both but for
// the texture bias's spelling) and convertHeightMapFactor (material_heightMapFactor =
// 0.1 heightMapFactor; registerProp heightMapBase 0.5, parallaxSamples 16). 2.22 reworked the
// offset mode: uv = P + s (h - heightMapBase) viewDirUv, no division by V.z, no 0.42, and
// the plane at heightMapBase (any b); viewDirUv = (viewDirT.x, -viewDirT.y) in a frame whose y
// runs along -v, pxh's V.xy.
//
// Texture levels. playcanvas_basic reads texture2DBias(.., textureBias), the hardware's level
// plus the material's bias (`lod = "implicit"` on the GLSL backend at bias 0). The occlusion mode
// computes one level before the loop, lod = max(0, 0.5 log2(max(|dFdx|^2, |dFdy|^2))) of the
// height map's texel coordinates (pxh's max(lambda, 0)), reads every tap with texture2DLod at it
// (`lod = "level"` reproduces the sampling on both twins), and lets it drive the step count
// (count = texels: marchTexels / parallaxTexelsPerStep, capped by parallaxSamples) and a fade
// (lod_fade = texels: the offset scaled by saturate((marchTexels - 1) / (3 - 1)), the march
// skipped at 0). The level is the sample's own lambda in every lod mode.
#include "methods/march/preset.h"

namespace pxh {
namespace {

using M = MarchConfig;

// getParallax, STD_PARALLAX == OFFSET (2.22.0+): height = (h - heightMapBase) s; dUvOffset =
// height viewDirUv: the offset search with f = 1 (sin), one fetch, any plane b.
const MarchPresetRow kPlayCanvasBasic{
    .name = "playcanvas_basic",
    .citation =
        "PlayCanvas StandardMaterial getParallax (parallaxMode PARALLAX_OFFSET, the default): "
        "npm playcanvas@2.22.0 and @2.23.3 build/playcanvas.mjs, chunk parallaxPS and "
        "convertHeightMapFactor (playcanvas/engine src/scene/shader-lib/glsl/chunks/standard/"
        "frag/parallax.js, src/scene/materials/standard-material.js); s = 0.1 heightMapFactor "
        "(default 1), b = heightMapBase (default 0.5), heightMapChannel g",
    .summary =
        "PlayCanvas parallax offset: uv = P + s (h(P) - b) V.xy (one fetch, no division by "
        "V.z)",
    .knobs = {.search = M::Offset, .offset_form = M::OffSin},
    .order = 346,
    .engine_version = "PlayCanvas 2.22.0 and later (checked: npm 2.22.0, 2.23.3)",
};
PXH_REGISTER_PRESET(kPlayCanvasBasic);

const MarchPresetRow kPlayCanvasBasicV221{
    .name = "playcanvas_basic_v2_21",
    .citation =
        "PlayCanvas StandardMaterial getParallax: playcanvas/engine "
        "src/scene/shader-lib/glsl/chunks/standard/frag/parallax.js and "
        "src/scene/materials/standard-material.js @ "
        "e287e0c67f3c20c689a52b7c53d2b7fedbe887da (v2.21.4); s = 0.025 heightMapFactor "
        "(default 1), heightMapChannel g",
    .summary =
        "PlayCanvas 2.21 parallax: uv = P + s (h(P) - 0.5) V.xy / (V.z + 0.42) (one fetch); "
        "that release has no occlusion mode",
    .knobs = {.search = M::Offset, .offset_form = M::OffSoft, .offset_soften = 0.42},
    .order = 348,
    .required_bias = 0.5,
    .bias_reason =
        "PlayCanvas offsets by height * s - s * 0.5: the map's mid-grey stays at the polygon",
    .engine_version =
        "PlayCanvas 2.21.4 (tag v2.21.4; checked: npm playcanvas@2.21.4); "
        "replaced in 2.22.0 (playcanvas_basic)",
};
PXH_REGISTER_PRESET(kPlayCanvasBasicV221);

// getParallax, STD_PARALLAX == OCCLUSION: march = -s V.xy / V.z limited to length
// parallaxMaxSlope s (5 s); the volume entered at depth 0, extrapolated back from the geometry
// plane at depth 1 - heightMapBase (= b); steps = clamp(marchTexels / 2, 1, parallaxSamples),
// not rounded; the entry tap, then taps at depth i / steps while the ray is above the field (at
// most ceil(steps)); crossed: from the middle of the last step, five halvings each with a tap
// (below the field: back); not crossed: the last step; the depth clamped to [0, 1]; the offset
// from the geometry plane times the fade.
const MarchPresetRow kPlayCanvasOcclusion{
    .name = "playcanvas_occlusion",
    .citation =
        "PlayCanvas StandardMaterial parallax occlusion (parallaxMode PARALLAX_OCCLUSION): "
        "playcanvas/engine src/scene/shader-lib/glsl/chunks/standard/frag/parallax.js @ "
        "1c1a0230c3974c084281cd33c15bf2f25165f186 (getParallax); defaults from PRs 9213 "
        "(parallaxSamples 16), 9245 (heightMapBase 0.5 = b) and standard-material.js @ "
        "0aaef5e432c4797ed23c1f966e2cc43232ec0613 (material_heightMapFactor = 0.1 "
        "heightMapFactor = s)",
    .summary =
        "PlayCanvas POM: slope limited to 5, steps from the march's span in texels of the "
        "pixel's level (2 texels a step, at most parallaxSamples), five bisection taps from "
        "the middle of the last step, the offset faded out below 3 texels",
    .knobs = {.count = M::Texels,
              .layers_max = 16,  // parallaxSamples
              .step = M::StepTan,
              .first = M::FirstSample,
              .compare = M::Le,  // rayDepth >= surfaceDepth
              .on_miss = M::MissLast,
              .refine = M::Bisect,
              .iterations = 5,  // parallaxRefineSteps
              .tie = M::TieBack,
              .lod_fade = M::FadeTexels,
              .texels_per_step = 2,   // parallaxTexelsPerStep
              .max_slope = 5,         // parallaxMaxSlope
              .clamp_depth = true,    // hitBelowTop = clamp(hitDepth, 0, 1)
              .fade_texels_min = 1,   // parallaxFadeMin
              .fade_texels_max = 3},  // parallaxFadeMax
    .params = {{ParamSpec::real("parallaxSamples", 16, 1, 4096,
                                "StandardMaterial#parallaxSamples: the cap on the march's steps"),
                MarchKnob::layers_max}},
    .order = 347,
    .engine_version =
        "PlayCanvas 2.22.0 and later (checked: npm 2.22.0, 2.23.3, chunk "
        "parallaxPS, the same loop as the commit cited)",
};
PXH_REGISTER_PRESET(kPlayCanvasOcclusion);

}  // namespace
}  // namespace pxh
