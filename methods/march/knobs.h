// The parametric marcher's knobs, declared once: one row per knob (what each does:
// methods/march/march.h). The rows generate MarchConfig's fields (and each choice's enum), the
// `march` method's parameters (march_knobs()[i].param), the GLSL twin's uniforms
// (march_uniforms: pm_MEMBER) and their declarations in methods/march/march.frag.glsl
// (march_glsl_declarations(), written in place of the shader's `// @pxh-declarations` line when
// its program is built). Adding a knob is one row here, plus its use in march() (march.h) and in
// the shader's pxh_method.
//
//   CHOICE(member, Enum, (Enumerators...), ("names"...), default enumerator, help)
//       int member, one of enum Enum; the names users type, in the enumerators' order; uniform
//       int pm_member = the index
//   REAL(member, default, lo, hi, help)      double member; uniform float pm_member
//   INTEGER(member, default, lo, hi, help)   int member; uniform int pm_member
//   BOOLEAN(member, default, help)           bool member; uniform bool pm_member
// The parameter is named as the member, with the row's default and range [lo, hi].
#pragma once
#include <initializer_list>
#include <string>
#include <vector>

#include "harness/core/params.h"

// clang-format off
#define PXH_MARCH_KNOBS(CHOICE, REAL, INTEGER, BOOLEAN)                                           \
    CHOICE(search, Search, (Offset, Layers), ("offset", "layers"), Layers,                         \
           "offset: one fetch, uv = P + z(P) d f; layers: the layered search")                     \
    CHOICE(offset_form, OffsetForm, (OffTan, OffSin, OffSoft, OffSinCos),                          \
           ("tan", "sin", "soft", "sincos"), OffTan,                                               \
           "offset search: f = 1/V.z (tan), 1 (sin), 1/(V.z + offset_soften) (soft), V.z "         \
           "(sincos)")                                                                             \
    REAL(offset_soften, 0.42, 0, 10, "soft offset: added to V.z")                                  \
    CHOICE(count, Count, (Fixed, Mix, MixTrunc, MixNegated, AngleScaled, MixScaled, Texels),       \
           ("fixed", "mix", "mix_trunc", "mix_negated", "angle_scaled", "mix_scaled", "texels"),   \
           Mix,                                                                                    \
           "layer count rule (methods/march/march.h): fixed, mix, mix_trunc, mix_negated, "        \
           "angle_scaled, mix_scaled, texels")                                                     \
    REAL(layers, 32, 1, 4096, "count = fixed: n")                                                  \
    REAL(layers_min, 8, 0, 4096, "the count rules' lower (head-on) value")                         \
    REAL(layers_max, 32, 0, 4096, "the count rules' upper (grazing) value (mix_scaled: times s)")  \
    CHOICE(step, Step, (StepTan, StepSin), ("tan", "sin"), StepTan,                                \
           "per-layer uv step: tan = V.xy/V.z dz (a ray), sin = V.xy dz")                          \
    BOOLEAN(mirror_v, false, "negate the v component of the march direction")                      \
    CHOICE(first, First, (FirstSample, FirstTop, FirstBottom), ("sample", "top", "bottom"),        \
           FirstSample,                                                                            \
           "layer 0: sample (fetched and tested), top / bottom (not fetched; taken as h = 1 / "    \
           "h = 0, the search starts at layer 1)")                                                 \
    CHOICE(compare, Compare, (Le, Lt), ("le", "lt"), Le, "a hit: g <= 0 (le) or g < 0 (lt)")       \
    BOOLEAN(lag, false, "compare layer k's sample with layer k-1's ray depth (OGRE)")              \
    INTEGER(max_steps, 0, 0, 4096, "cap on the layer index (0: none)")                             \
    INTEGER(extra_layers, 0, 0, 4, "layers searched beyond ceil(n)")                               \
    CHOICE(on_miss, OnMiss, (MissLast, MissNext, MissRefine), ("last", "next", "refine"),          \
           MissLast,                                                                               \
           "no hit by the last layer: its uv (last), the next layer's uv (next), or refine "       \
           "anyway (refine)")                                                                      \
    CHOICE(refine, Refine, (RefineNone, Lerp, Bisect, Secant, Contact),                            \
           ("none", "lerp", "bisect", "secant", "contact"), Lerp,                                  \
           "after the search: none, lerp (POM), bisect (relief), secant (regula falsi), contact "  \
           "(sub-layer search)")                                                                   \
    BOOLEAN(clamp_weight, true, "lerp: w clamped to [0, 1], uv_k when the bracket is degenerate")  \
    BOOLEAN(refetch, false, "lerp: fetch layer k-1 again (as engines do)")                         \
    BOOLEAN(refine_at_k0, false,                                                                   \
            "refine also when the search stops at layer 0 (layer -1 as the previous one)")         \
    INTEGER(iterations, 5, 0, 256, "bisect: probes after the first half step; secant: at most")    \
    BOOLEAN(probe_last, false, "bisect: one more (unused) probe at the end")                       \
    CHOICE(tie, Tie, (TieBack, TieStay), ("back", "stay"), TieBack,                                \
           "bisect at g = 0: step back, or stay")                                                  \
    REAL(tolerance, 0.01, 0, 1, "secant: stop when |delta| <= tolerance")                     \
    BOOLEAN(pad_fetches, false,                                                                    \
            "after the answer, fetch at its uv until the search made kmax + 1 fetches (first = "  \
            "sample; kmax otherwise): a loop that samples on every iteration, also after the "    \
            "hit (Babylon.js)")                                                                    \
    CHOICE(lod_fade, LodFade, (FadeNone, FadeHdrp, FadeDxsdk, FadeTexels),                         \
           ("none", "hdrp", "dxsdk", "texels"), FadeNone,                                          \
           "what the sample's level of detail L = max(lambda, 0) does (methods/march/march.h): "  \
           "none; hdrp: offset times 1 - saturate(L - lod_threshold); dxsdk: L > lod_threshold: " \
           "P, nothing fetched; L in (lod_threshold - 1, lod_threshold]: uv + (P - uv) frac(L); " \
           "texels: offset times saturate((t - fade_texels_min) / (fade_texels_max - "            \
           "fade_texels_min)), t the march's texels at L, P unfetched at 0")                      \
    REAL(lod_threshold, 0, 0, 16, "lod_fade hdrp / dxsdk: the level where the fade starts / ends") \
    REAL(texels_per_step, 2, 0.001, 1000, "count = texels: n = t / texels_per_step in [1, "        \
         "layers_max], t = |s d (W, H)| / 2^L the march's span in texels of level L")             \
    REAL(max_slope, 0, 0, 1000000,                                                                 \
         "layers: the march direction d (uv per unit of depth) capped at this length (0: none)")  \
    BOOLEAN(clamp_depth, false,                                                                    \
            "layers: the answer's layer clamped to [0, n] (not lerp's, which blends two layers)")  \
    REAL(fade_texels_min, 1, 0, 1000, "lod_fade = texels: t where the offset is gone")             \
    REAL(fade_texels_max, 3, 0, 1000, "lod_fade = texels: t where the offset is whole")          \
    CHOICE(depth_offset, DepthOffset,                                                              \
           (PdoNone, PdoHdrp, PdoO3de, PdoUnrealLegacy, PdoUnrealCamera),                          \
           ("none", "hdrp", "o3de", "unreal_legacy", "unreal_camera"), PdoNone,                    \
           "the depth the engine writes (depth = engine; methods/march/march.h): none (the "      \
           "polygon's), hdrp, o3de, unreal_legacy, unreal_camera")

#define PXH_KNOB_UNPAREN(...) __VA_ARGS__
#define PXH_KNOB_NONE(...)
// clang-format on

namespace pxh {

// The knobs' values: a plain aggregate, so a preset writes the ones it fixes as designated
// initialisers (in the table's order) and the rest keep the table's defaults.
struct MarchConfig {
#define PXH_KNOB_ENUM(member, Enum, enumerators, names, def, help) \
    enum Enum { PXH_KNOB_UNPAREN enumerators };
    PXH_MARCH_KNOBS(PXH_KNOB_ENUM, PXH_KNOB_NONE, PXH_KNOB_NONE, PXH_KNOB_NONE)
#undef PXH_KNOB_ENUM
#define PXH_KNOB_NAMES_CHECK(member, Enum, enumerators, names, def, help)                \
    static_assert(std::initializer_list<int>{PXH_KNOB_UNPAREN enumerators}.size() ==     \
                      std::initializer_list<const char*>{PXH_KNOB_UNPAREN names}.size(), \
                  "knob '" #member "': one name per enumerator");
    PXH_MARCH_KNOBS(PXH_KNOB_NAMES_CHECK, PXH_KNOB_NONE, PXH_KNOB_NONE, PXH_KNOB_NONE)
#undef PXH_KNOB_NAMES_CHECK

#define PXH_KNOB_CHOICE_FIELD(member, Enum, enumerators, names, def, help) int member = def;
#define PXH_KNOB_REAL_FIELD(member, def, lo, hi, help) double member = def;
#define PXH_KNOB_INTEGER_FIELD(member, def, lo, hi, help) int member = def;
#define PXH_KNOB_BOOLEAN_FIELD(member, def, help) bool member = def;
    PXH_MARCH_KNOBS(PXH_KNOB_CHOICE_FIELD, PXH_KNOB_REAL_FIELD, PXH_KNOB_INTEGER_FIELD,
                    PXH_KNOB_BOOLEAN_FIELD)
#undef PXH_KNOB_CHOICE_FIELD
#undef PXH_KNOB_REAL_FIELD
#undef PXH_KNOB_INTEGER_FIELD
#undef PXH_KNOB_BOOLEAN_FIELD
};

// A knob by its row (march_knobs()[int(k)]).
enum class MarchKnob {
#define PXH_KNOB_ID(member, ...) member,
    PXH_MARCH_KNOBS(PXH_KNOB_ID, PXH_KNOB_ID, PXH_KNOB_ID, PXH_KNOB_ID)
#undef PXH_KNOB_ID
};

// One row as data: the parameter (name, type, default, range or names, help), the uniform and
// access to the member (as a double: an int's value, a bool's 0 / 1).
struct MarchKnobSpec {
    MarchKnob id;
    ParamSpec param;
    std::string uniform;  // pm_MEMBER
    double (*get)(const MarchConfig&);
    void (*set)(MarchConfig&, double);
};

// Every knob, in the table's order.
const std::vector<MarchKnobSpec>& march_knobs();
const MarchKnobSpec& march_knob(MarchKnob k);

// The GLSL declarations of the knobs' uniforms, one line each (a choice's with its indices'
// names as a comment, consecutive comments aligned), as methods/march/march.frag.glsl gets them.
std::string march_glsl_declarations();

}  // namespace pxh
