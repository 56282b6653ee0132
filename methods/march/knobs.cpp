// The knob table (methods/march/knobs.h) as data, and what it generates for the GLSL twin: the
// uniforms' values and their declarations.
#include "methods/march/knobs.h"

#include <algorithm>

#include "methods/march/march.h"

namespace pxh {
namespace {

std::vector<MarchKnobSpec> make_knobs() {
    std::vector<MarchKnobSpec> k;
#define PXH_KNOB_ACCESS(member)                            \
    [](const MarchConfig& c) { return double(c.member); }, \
        [](MarchConfig& c, double v) { c.member = decltype(c.member)(v); }
#define PXH_KNOB_CHOICE_SPEC(member, Enum, enumerators, names, def, help)                         \
    {                                                                                             \
        const std::vector<std::string> n = {PXH_KNOB_UNPAREN names};                              \
        k.push_back({MarchKnob::member, ParamSpec::choice(#member, n, n[MarchConfig::def], help), \
                     "pm_" #member, PXH_KNOB_ACCESS(member)});                                    \
    }
#define PXH_KNOB_REAL_SPEC(member, def, lo, hi, help)                                           \
    k.push_back({MarchKnob::member, ParamSpec::real(#member, def, lo, hi, help), "pm_" #member, \
                 PXH_KNOB_ACCESS(member)});
#define PXH_KNOB_INTEGER_SPEC(member, def, lo, hi, help)                                           \
    k.push_back({MarchKnob::member, ParamSpec::integer(#member, def, lo, hi, help), "pm_" #member, \
                 PXH_KNOB_ACCESS(member)});
#define PXH_KNOB_BOOLEAN_SPEC(member, def, help)                                           \
    k.push_back({MarchKnob::member, ParamSpec::boolean(#member, def, help), "pm_" #member, \
                 PXH_KNOB_ACCESS(member)});
    PXH_MARCH_KNOBS(PXH_KNOB_CHOICE_SPEC, PXH_KNOB_REAL_SPEC, PXH_KNOB_INTEGER_SPEC,
                    PXH_KNOB_BOOLEAN_SPEC)
#undef PXH_KNOB_ACCESS
#undef PXH_KNOB_CHOICE_SPEC
#undef PXH_KNOB_REAL_SPEC
#undef PXH_KNOB_INTEGER_SPEC
#undef PXH_KNOB_BOOLEAN_SPEC
    return k;
}

GlslType glsl_type_of(const ParamSpec& p) {
    switch (p.type) {
        case ParamType::Real:
            return GlslType::Float;
        case ParamType::Bool:
            return GlslType::Bool;
        default:
            return GlslType::Int;  // integer, and a choice's index
    }
}

}  // namespace

const std::vector<MarchKnobSpec>& march_knobs() {
    static const std::vector<MarchKnobSpec> k = make_knobs();
    return k;
}

const MarchKnobSpec& march_knob(MarchKnob k) { return march_knobs()[size_t(k)]; }

GlUniforms march_uniforms(const MarchConfig& c) {
    GlUniforms u;
    for (const MarchKnobSpec& k : march_knobs())
        u.push_back({k.uniform, glsl_type_of(k.param), k.get(c)});
    return u;
}

std::string march_glsl_declarations() {
    struct Line {
        std::string code, comment;
    };
    std::vector<Line> lines;
    for (const MarchKnobSpec& k : march_knobs()) {
        Line l{
            "uniform " + std::string(glsl_type_name(glsl_type_of(k.param))) + " " + k.uniform + ";",
            ""};
        if (k.param.type == ParamType::Choice)
            for (size_t i = 0; i < k.param.names.size(); ++i)
                l.comment += (i ? ", " : "") + std::to_string(i) + " " + k.param.names[i];
        lines.push_back(l);
    }
    // A run of lines with comments has its comments aligned, two spaces after the longest
    // declaration (as clang-format writes trailing comments).
    std::string out;
    for (size_t i = 0; i < lines.size();) {
        size_t end = i, width = 0;
        while (end < lines.size() && !lines[end].comment.empty())
            width = std::max(width, lines[end++].code.size());
        if (end == i) {
            out += lines[i++].code + "\n";
            continue;
        }
        for (; i < end; ++i)
            out += lines[i].code + std::string(width + 2 - lines[i].code.size(), ' ') + "// " +
                   lines[i].comment + "\n";
    }
    return out;
}

}  // namespace pxh
