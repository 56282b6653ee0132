// The parametric marcher as a method of its own (`march`: every knob a typed parameter), and
// preset rows as methods. The search itself is methods/march/march.h, the knobs
// methods/march/knobs.h; engine presets are data rows (methods/march/presets/).
#include "methods/march/march.h"

#include <algorithm>

#include "harness/core/error.h"
#include "methods/march/preset.h"

namespace pxh {

MarchConfig preset_config(const MarchPresetRow& row, const ParamValues& p,
                          const std::string& where) {
    MarchConfig c = row.knobs;
    for (const PresetParam& pp : row.params) {
        const ParamValue& v = p.value(pp.spec.name);
        double x = 0;
        if (pp.spec.type == ParamType::Choice) {
            const auto& n = pp.spec.names;
            const size_t i = size_t(std::find(n.begin(), n.end(), v.name()) - n.begin());
            x = pp.values.empty() ? double(i) : pp.values.at(i);
        } else if (pp.spec.type == ParamType::Bool) {
            x = v.boolean() ? 1 : 0;
        } else {
            x = v.number();
        }
        march_knob(pp.knob).set(c, x);
    }
    if (row.derive) row.derive(c);
    if (row.check) row.check(c, where);
    return c;
}

MethodInfo preset_info(const MarchPresetRow& row) {
    MethodInfo m{row.name, row.citation, row.summary, {}, row.exact_on_flat, row.order};
    for (const PresetParam& pp : row.params) m.params.push_back(pp.spec);
    m.required_bias = row.required_bias;
    m.bias_reason = row.bias_reason;
    m.engine_version = row.engine_version;
    m.shader_path = "methods/march/march.frag.glsl";
    m.shader_declarations = march_glsl_declarations();
    return m;
}

namespace {

std::vector<PresetParam> every_knob() {
    std::vector<PresetParam> p;
    for (const MarchKnobSpec& k : march_knobs()) p.push_back({k.param, k.id});
    return p;
}

void check_layer_counts(const MarchConfig& c, const std::string& where) {
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
}

// The `march` method: the marcher with every knob given in the experiment (defaults: pxh's
// view-adaptive POM, methods/pom).
const MarchPresetRow kMarch{
    .name = "march",
    .citation =
        "pxh's parametric marcher (methods/march/march.h): the knobs of the engines' "
        "layered searches; defaults = pom with layers_min 8, layers_max 32",
    .summary =
        "a layered (or one-fetch offset) search with typed knobs; engine presets are "
        "named settings of it",
    .params = every_knob(),
    .exact_on_flat = true,
    .order = 200,
    .check = check_layer_counts,
};

}  // namespace

PXH_REGISTER_PRESET(kMarch);

}  // namespace pxh
