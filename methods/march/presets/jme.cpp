// jMonkeyEngine's Parallax.glsllib (classic and steep) as presets of the parametric marcher
// (methods/march/preset.h). The engine's height scale is the experiment's scale s (conversions
// in docs/findings/engines.md); each fixes the reference plane, so each requires its bias. Literal
// transcriptions and the comparison: tests/engines/literal_unity_jme_ogre_dx.h,
// tests/methods/engines_unity_jme_ogre_dx_test.cpp.
//
// Texture levels: both read texture2D(parallaxMap, ...), in steep's loop too (`lod =
// "implicit"` on the GLSL backend). No fade.
#include "methods/march/preset.h"

namespace pxh {
namespace {

// The release the presets of this file follow (`pxh list methods`: "follows").
const char* const kJmeVersion = "jMonkeyEngine @ 7277b5d8 (git; no release checked)";

using M = MarchConfig;

// classicParallaxOffset: h = (h s - 0.6 s) normView.z; uv = P + h normView.xy.
const MarchPresetRow kJmeParallax{
    .name = "jme_parallax",
    .citation =
        "jMonkeyEngine classic parallax: jMonkeyEngine/jmonkeyengine "
        "jme3-core/src/main/resources/Common/ShaderLib/Parallax.glsllib @ "
        "7277b5d8013f (classicParallaxOffset), Lighting.j3md @ 68c082c13ded; "
        "s = ParallaxHeight (0.05)",
    .summary = "one fetch: uv = P + s (h - 0.6) V.z V.xy (offset times V.z, largest at 45 degrees)",
    .knobs = {.search = M::Offset, .offset_form = M::OffSinCos},
    .order = 362,
    .required_bias = 0.6,
    .bias_reason = "classicParallaxOffset adds heightBias = -0.6 ParallaxHeight",
    .engine_version = kJmeVersion,
};
PXH_REGISTER_PRESET(kJmeParallax);

// steepParallaxOffset: n = mix(6, 1000 s, 1 - V.z) (real), layers 1 .. ceil(n), stop after the
// first height > bound; the previous height of layer 1 is 0 (fPrevHeight takes the initial
// fCurrHeight = 0.0); line intersection of the last two (bound, height) pairs, no guard.
const MarchPresetRow kJmeSteep{
    .name = "jme_steep",
    .citation =
        "jMonkeyEngine steep parallax: jMonkeyEngine/jmonkeyengine "
        "jme3-core/src/main/resources/Common/ShaderLib/Parallax.glsllib @ "
        "7277b5d8013f (steepParallaxOffset, SteepParallax true); s = 0.3 "
        "ParallaxHeight (0.015)",
    .summary =
        "POM with n = mix(6, 1000 s, 1 - V.z) layers and height 0 as the previous sample of "
        "layer 1 (P is never sampled)",
    .knobs = {.count = M::MixScaled,
              .layers_min = 6,
              .layers_max = 1000,
              .first = M::FirstBottom,
              .compare = M::Lt,
              .on_miss = M::MissRefine,
              .refine = M::Lerp,
              .clamp_weight = false},
    .order = 363,
    .required_bias = 1.0,
    .bias_reason = "steepParallaxOffset starts at bound 1.0 at the polygon",
    .engine_version = kJmeVersion,
};
PXH_REGISTER_PRESET(kJmeSteep);

}  // namespace
}  // namespace pxh
