// The parametric marcher as a method of its own (`march`: every knob a typed parameter) and
// the knobs' uniforms. The search itself is methods/march/march.h; engine presets are named
// settings of it (methods/march/presets_*.cpp).
#include "methods/march/march.h"

#include <algorithm>

#include "harness/core/error.h"

namespace pxh {
namespace {

// Choice names, in the order of MarchConfig's enums (the uniform gets the index).
const std::vector<std::string> kSearch = {"offset", "layers"};
const std::vector<std::string> kOffsetForm = {"tan", "sin", "soft", "sincos"};
const std::vector<std::string> kCount = {"fixed",       "mix",          "mix_trunc",
                                         "mix_negated", "angle_scaled", "mix_scaled"};
const std::vector<std::string> kStep = {"tan", "sin"};
const std::vector<std::string> kFirst = {"sample", "top", "bottom"};
const std::vector<std::string> kCompare = {"le", "lt"};
const std::vector<std::string> kOnMiss = {"last", "next", "refine"};
const std::vector<std::string> kRefine = {"none", "lerp", "bisect", "secant", "contact"};
const std::vector<std::string> kTie = {"back", "stay"};

int index_of(const std::vector<std::string>& names, const std::string& n) {
    return int(std::find(names.begin(), names.end(), n) - names.begin());
}

}  // namespace

std::vector<ParamSpec> march_params() {
    return {
        ParamSpec::choice("search", kSearch, "layers",
                          "offset: one fetch, uv = P + z(P) d f; layers: the layered search"),
        ParamSpec::choice("offset_form", kOffsetForm, "tan",
                          "offset search: f = 1/V.z (tan), 1 (sin), 1/(V.z + offset_soften) "
                          "(soft), V.z (sincos)"),
        ParamSpec::real("offset_soften", 0.42, 0, 10, "soft offset: added to V.z"),
        ParamSpec::choice("count", kCount, "mix",
                          "layer count rule (methods/march/march.h): fixed, mix, mix_trunc, "
                          "mix_negated, angle_scaled, mix_scaled"),
        ParamSpec::real("layers", 32, 1, 4096, "count = fixed: n"),
        ParamSpec::real("layers_min", 8, 0, 4096, "the count rules' lower (head-on) value"),
        ParamSpec::real("layers_max", 32, 0, 4096,
                        "the count rules' upper (grazing) value (mix_scaled: times s)"),
        ParamSpec::choice("step", kStep, "tan",
                          "per-layer uv step: tan = V.xy/V.z dz (a ray), sin = V.xy dz"),
        ParamSpec::boolean("mirror_v", false, "negate the v component of the march direction"),
        ParamSpec::choice("first", kFirst, "sample",
                          "layer 0: sample (fetched and tested), top / bottom (not fetched; "
                          "taken as h = 1 / h = 0, the search starts at layer 1)"),
        ParamSpec::choice("compare", kCompare, "le", "a hit: g <= 0 (le) or g < 0 (lt)"),
        ParamSpec::boolean("lag", false,
                           "compare layer k's sample with layer k-1's ray depth (OGRE)"),
        ParamSpec::integer("max_steps", 0, 0, 4096, "cap on the layer index (0: none)"),
        ParamSpec::integer("extra_layers", 0, 0, 4, "layers searched beyond ceil(n)"),
        ParamSpec::choice("on_miss", kOnMiss, "last",
                          "no hit by the last layer: its uv (last), the next layer's uv (next), "
                          "or refine anyway (refine)"),
        ParamSpec::choice("refine", kRefine, "lerp",
                          "after the search: none, lerp (POM), bisect (relief), secant "
                          "(regula falsi), contact (sub-layer search)"),
        ParamSpec::boolean("clamp_weight", true,
                           "lerp: w clamped to [0, 1], uv_k when the bracket is degenerate"),
        ParamSpec::boolean("refetch", false, "lerp: fetch layer k-1 again (as engines do)"),
        ParamSpec::boolean("refine_at_k0", false,
                           "refine also when the search stops at layer 0 (layer -1 as the "
                           "previous one)"),
        ParamSpec::integer("iterations", 5, 0, 256,
                           "bisect: probes after the first half step; secant: at most"),
        ParamSpec::boolean("probe_last", false, "bisect: one more (unused) probe at the end"),
        ParamSpec::choice("tie", kTie, "back", "bisect at g = 0: step back, or stay"),
        ParamSpec::real("tolerance", 0.01, 0, 1, "secant: stop when |delta| <= tolerance"),
    };
}

MarchConfig march_config(const ParamValues& p, const std::string& where) {
    MarchConfig c;
    c.search = index_of(kSearch, p.get_name("search"));
    c.offset_form = index_of(kOffsetForm, p.get_name("offset_form"));
    c.offset_soften = p.get("offset_soften");
    c.count = index_of(kCount, p.get_name("count"));
    c.layers = p.get("layers");
    c.layers_min = p.get("layers_min");
    c.layers_max = p.get("layers_max");
    c.step = index_of(kStep, p.get_name("step"));
    c.mirror_v = p.get_bool("mirror_v");
    c.first = index_of(kFirst, p.get_name("first"));
    c.compare = index_of(kCompare, p.get_name("compare"));
    c.lag = p.get_bool("lag");
    c.max_steps = p.get_int("max_steps");
    c.extra_layers = p.get_int("extra_layers");
    c.on_miss = index_of(kOnMiss, p.get_name("on_miss"));
    c.refine = index_of(kRefine, p.get_name("refine"));
    c.clamp_weight = p.get_bool("clamp_weight");
    c.refetch = p.get_bool("refetch");
    c.refine_at_k0 = p.get_bool("refine_at_k0");
    c.iterations = p.get_int("iterations");
    c.probe_last = p.get_bool("probe_last");
    c.tie = index_of(kTie, p.get_name("tie"));
    c.tolerance = p.get("tolerance");
    if (c.count != MarchConfig::Fixed && c.count != MarchConfig::MixScaled &&
        !(c.layers_min >= 1 && c.layers_max >= 1))
        throw InputError(where, "layers_min and layers_max must be at least 1");
    // mix_scaled: n = layers_min V.z + layers_max s (1 - V.z) is layers_min head-on, so
    // layers_min = 0 gives n = 0 layers there (dz = s / 0: every sample NaN).
    if (c.count == MarchConfig::MixScaled && !(c.layers_min >= 1))
        throw InputError(where,
                         "count = \"mix_scaled\" needs layers_min >= 1 (got " +
                             format_number(c.layers_min) +
                             "): its layer count is layers_min at theta = 0, and 0 layers give "
                             "no answer");
    return c;
}

GlUniforms march_uniforms(const MarchConfig& c) {
    return {GlUniform::integer("pm_search", c.search),
            GlUniform::integer("pm_offset_form", c.offset_form),
            GlUniform::real("pm_offset_soften", c.offset_soften),
            GlUniform::integer("pm_count", c.count),
            GlUniform::real("pm_layers", c.layers),
            GlUniform::real("pm_layers_min", c.layers_min),
            GlUniform::real("pm_layers_max", c.layers_max),
            GlUniform::integer("pm_step", c.step),
            GlUniform::boolean("pm_mirror_v", c.mirror_v),
            GlUniform::integer("pm_first", c.first),
            GlUniform::integer("pm_compare", c.compare),
            GlUniform::boolean("pm_lag", c.lag),
            GlUniform::integer("pm_max_steps", c.max_steps),
            GlUniform::integer("pm_extra_layers", c.extra_layers),
            GlUniform::integer("pm_on_miss", c.on_miss),
            GlUniform::integer("pm_refine", c.refine),
            GlUniform::boolean("pm_clamp_weight", c.clamp_weight),
            GlUniform::boolean("pm_refetch", c.refetch),
            GlUniform::boolean("pm_refine_at_k0", c.refine_at_k0),
            GlUniform::integer("pm_iterations", c.iterations),
            GlUniform::boolean("pm_probe_last", c.probe_last),
            GlUniform::integer("pm_tie", c.tie),
            GlUniform::real("pm_tolerance", c.tolerance)};
}

namespace {

// The `march` method: the marcher with every knob given in the experiment (defaults: pxh's
// view-adaptive POM, methods/pom).
struct MarchDef {
    static MethodInfo info() {
        return {"march",
                "pxh's parametric marcher (methods/march/march.h): the knobs of the engines' "
                "layered searches; defaults = pom with layers_min 8, layers_max 32",
                "a layered (or one-fetch offset) search with typed knobs; engine presets are "
                "named settings of it",
                march_params(),
                true,
                200};
    }
    static MarchConfig config(const ParamValues& p, const std::string& where) {
        return march_config(p, where);
    }
};

}  // namespace

PXH_REGISTER_PRESET(MarchDef);

}  // namespace pxh
