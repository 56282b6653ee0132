// PlayCanvas StandardMaterial parallax as a preset of the parametric marcher
// (methods/march/preset.h). PlayCanvas has no occlusion mode: there is no playcanvas_occlusion.
// Literal transcription and the comparison: tests/engines/literal_js.h,
// tests/methods/engines_js_test.cpp.
#include "methods/march/preset.h"

namespace pxh {
namespace {

using M = MarchConfig;

const MarchPresetRow kPlayCanvasBasic{
    .name = "playcanvas_basic",
    .citation =
        "PlayCanvas StandardMaterial getParallax: playcanvas/engine "
        "src/scene/shader-lib/glsl/chunks/standard/frag/parallax.js and "
        "src/scene/materials/standard-material.js @ "
        "e287e0c67f3c20c689a52b7c53d2b7fedbe887da (v2.21.4); s = 0.025 heightMapFactor "
        "(default 1), heightMapChannel g",
    .summary =
        "PlayCanvas parallax: uv = P + s (h(P) - 0.5) V.xy / (V.z + 0.42) (one fetch); "
        "there is no occlusion mode",
    .knobs = {.search = M::Offset, .offset_form = M::OffSoft, .offset_soften = 0.42},
    .order = 346,
    .required_bias = 0.5,
    .bias_reason =
        "PlayCanvas offsets by height * s - s * 0.5: the map's mid-grey stays at the polygon",
};
PXH_REGISTER_PRESET(kPlayCanvasBasic);

}  // namespace
}  // namespace pxh
