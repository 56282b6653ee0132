// [[methods]] entries: a built-in method's parameter sweeps, or a plug-in shader (its file,
// uniforms, fetch bound and CPU reference); each setting resolved and checked, a repeated one
// kept once.
#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <map>
#include <memory>
#include <optional>

#include "harness/backends/converted_shader.h"
#include "harness/backends/plugin_source.h"
#include "harness/backends/shaders.h"
#include "harness/core/error.h"
#include "harness/core/registry.h"
#include "harness/experiment/entries.h"

namespace pxh {

std::vector<GivenParams> expand(const Sweeps& sweeps) {
    std::vector<GivenParams> out{{}};
    for (const auto& [key, values] : sweeps) {
        std::vector<GivenParams> next;
        for (const auto& partial : out)
            for (const ParamValue& v : values) {
                auto m = partial;
                m[key] = v;
                next.push_back(std::move(m));
            }
        out = std::move(next);
    }
    return out;
}

std::vector<ParamValue> param_values(const ParamDict& entry, const std::string& key,
                                     const ParamSpec& spec, const std::string& owner) {
    std::vector<ParamValue> out;
    for (const auto& e : entry.elements(key)) {
        if (!e.value)
            throw InputError(e.where,
                             owner + " parameter '" + spec.name + "' must be " + spec.accepted());
        check_param_kind(spec, *e.value, e.where, owner);
        out.push_back(*e.value);
    }
    return out;
}

namespace {

// What parse_method needs of a plug-in entry besides its method: the tables its parameters are
// read from, its engine keys, its program per setting of its defines (the defines' values,
// joined) and where its text reads an explicit texture level.
struct PluginParts {
    ParamDict uniforms;
    PluginEngine engine;
    std::map<std::string, const MethodInfo*> variants;
    std::string explicit_level;
};

std::string define_key(const std::vector<std::pair<std::string, std::string>>& defines) {
    std::string key;
    for (const auto& [k, v] : defines) key += k + "=" + v + "\x1f";
    return key;
}

// The uniforms table's parameters (each p_NAME; a number, bool or a list sweeping them; an
// integer value makes an int uniform).
std::vector<ParamSpec> plugin_uniform_specs(const ParamDict& uniforms) {
    std::vector<ParamSpec> out;
    for (const std::string& key : uniforms.keys()) {
        bool ident = key.size() > 2 && key.rfind("p_", 0) == 0;
        for (char c : key)
            ident = ident && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
        if (!ident)
            throw InputError(uniforms.where(key),
                             "uniform '" + key +
                                 "': plug-in uniforms are named p_NAME (letters, digits, _); an "
                                 "engine's own uniform is bound instead: bind = { " +
                                 key + " = VALUE }");
        const ParamDict::Element first = uniforms.elements(key)[0];
        ParamSpec spec = first.value && first.value->is_bool()
                             ? ParamSpec::boolean(key, false, "plug-in uniform")
                         : first.integer
                             ? ParamSpec::integer(key, std::nullopt, -2147483647.0, 2147483647.0,
                                                  "plug-in uniform")
                             // What a GLSL float holds: 1e300 would reach the shader as inf.
                             : ParamSpec::real(key, std::nullopt, -double(FLT_MAX), double(FLT_MAX),
                                               "plug-in uniform (a GLSL float)");
        spec.default_value.reset();
        spec.to_uniform(key);
        out.push_back(spec);
    }
    return out;
}

// One program per setting of the entry's defines: `proto` with the adapted text of each (the
// engine's text as written: harness/backends/engine_shader.h), all in ex.plugins.
void plugin_variants(const MethodInfo& proto, const std::string& rel, const PluginSource& src,
                     Experiment& ex, PluginParts& parts, const std::string& where) {
    for (const GivenParams& setting : expand(parts.engine.define_sweeps)) {
        EngineAdapter a = parts.engine.base;
        a.defines = define_setting(parts.engine, setting, where);
        EngineShader sh;
        if (converted_language(rel)) {  // HLSL, WGSL: converted, then adapted as GLSL
            const ConvertedShader c = converted_to_glsl(ex.path, rel, src.text, src.display, a);
            EngineAdapter g = a;
            g.defines.clear();
            g.define_names.clear();
            sh = adapt_engine_shader(ex.path, rel, c.glsl, c.display, g, where);
            if (sh.explicit_level.empty()) sh.explicit_level = c.explicit_level;
        } else {
            sh = adapt_engine_shader(ex.path, rel, src.text, src.display, a, where);
        }
        auto info = std::make_shared<MethodInfo>(proto);
        info->plugin_source = sh.text;
        info->plugin_display = sh.files[0];  // a converted file's: "FILE (as GLSL)"
        info->plugin_files.assign(sh.files.begin() + 1, sh.files.end());
        if (converted_language(rel)) {
            info->plugin_original = src.text;
            info->plugin_original_display = src.display;
        }
        for (ParamSpec& spec : bound_value_specs(parts.engine, sh))
            info->params.push_back(std::move(spec));
        for (const ParamSpec& spec : parts.engine.define_specs) info->params.push_back(spec);
        if (parts.explicit_level.empty()) parts.explicit_level = sh.explicit_level;
        parts.variants[define_key(a.defines)] = info.get();
        ex.plugins.push_back(info);
    }
}

// A [[methods]] entry with `shader = FILE`: a GLSL-only method from the user's file (relative
// to the experiment), its uniforms (`uniforms`, `bind`), defines, includes and height sampler,
// its declared fetch bound; one program per setting of its defines (its first returned).
const MethodInfo* make_plugin(const ParamDict& t, const std::string& name, Experiment& ex,
                              PluginParts& parts) {
    const std::string where = t.where("shader");
    if (find_method(name))
        throw InputError(t.where("name"), "'" + name +
                                              "' is a built-in method; a plug-in shader needs a "
                                              "name of its own");
    for (const auto& p : ex.plugins)
        if (p->name == name)
            throw InputError(t.where("name"), "plug-in '" + name + "' is defined twice");
    check_safe_name(name, t.where("name"), "method name", false);
    const std::string rel = *t.string("shader");
    // Inside the experiment's folder, a regular UTF-8 text file under 1 MiB, read once here.
    PluginSource src = read_plugin_source(ex.path, rel, where);
    if (const auto problems = plugin_source_problems(src.display, src.text,
                                                     shader_source("methods/common.glsl", "").text);
        !problems.empty()) {
        const size_t colon = problems[0].find(": ");  // "FILE:LINE:COL: why"
        throw InputError(problems[0].substr(0, colon), problems[0].substr(colon + 2));
    }
    if (std::find(ex.backends.begin(), ex.backends.end(), "glsl") == ex.backends.end())
        throw InputError(t.where("name"), "plug-in '" + name +
                                              "' is a GLSL shader (it has no CPU rows) and the "
                                              "experiment's backends are " +
                                              join_names(ex.backends) +
                                              ": add \"glsl\" to backends");
    if (!t.has("max_fetches"))
        throw InputError(
            t.where("name"),
            "plug-in '" + name + "' needs max_fetches (its bound on texture fetches per sample)");
    MethodInfo info;
    info.name = name;
    info.citation = "plug-in shader " + rel + " (from " + ex.path + ")";
    info.summary = "GLSL only: " + rel;
    info.order = 1000;
    info.plugin_shader = src.resolved;
    info.shader_path = src.resolved;
    info.plugin_display = src.display;
    info.declared_max_fetches = *t.integer("max_fetches", 1, 1000000);
    if (auto u = t.table("uniforms", "'uniforms'", "'uniforms' must be a table")) {
        parts.uniforms = *u;
        info.params = plugin_uniform_specs(parts.uniforms);
    }
    parts.engine = read_plugin_engine(t);
    plugin_variants(info, rel, src, ex, parts, where);
    return parts.variants.begin()->second;
}

// A plug-in's CPU twin to compare with: `reference = "NAME"`, `reference_params = { ... }`
// (one value each).
void read_reference(const ParamDict& t, const std::string& where, MethodSpec& proto) {
    if (!t.has("reference")) {
        if (t.has("reference_params"))
            throw InputError(t.where("reference_params"), "'reference_params' without 'reference'");
        return;
    }
    const std::string rn = *t.string("reference");
    proto.reference = find_method(rn);
    if (!proto.reference || !proto.reference->run_float)
        throw InputError(t.where("reference"), "reference '" + rn + "' is not a built-in method");
    GivenParams given;
    if (auto rt = t.table("reference_params", "'reference_params'",
                          "'reference_params' must be a table")) {
        for (const std::string& k : rt->keys()) {
            const ParamSpec* spec = nullptr;
            for (const auto& p : proto.reference->params)
                if (p.name == k) spec = &p;
            if (!spec) continue;  // left unread: reported below
            const auto vals = param_values(*rt, k, *spec, "reference '" + rn + "'");
            if (vals.size() != 1)
                throw InputError(rt->where(k), "reference parameters take one value");
            given.emplace(k, vals[0]);
        }
        rt->report_unused([&](const std::string& key, const std::string&) {
            return "unknown parameter '" + key + "' for reference '" + rn + "'";
        });
    }
    proto.reference_params = resolve_method_params(*proto.reference, given, where);
}

// `lod`: the level modes (a value or a list, swept; default base). A method that reads
// precomputed maps keeps their own level semantics and takes base only; grad and implicit
// run on the GLSL backend only, so they need it among the experiment's backends.
std::vector<LodMode> read_lods(const ParamDict& t, const MethodInfo& m, const Experiment& ex) {
    if (!t.has("lod")) return {LodMode::base};
    const std::string where = t.where("lod");
    std::vector<LodMode> out;
    for (const std::string& name : t.strings("lod", {})) {
        std::optional<LodMode> mode;
        for (LodMode l : {LodMode::base, LodMode::level, LodMode::grad, LodMode::implicit})
            if (name == lod_name(l)) mode = l;
        if (!mode)
            throw InputError(where,
                             "unknown lod '" + name + "' (known: " + join_names(lod_names()) + ")");
        if (*mode != LodMode::base && !m.resources.empty())
            throw InputError(where, "method '" + m.name +
                                        "' reads precomputed maps that keep their own levels "
                                        "(docs/conventions.md section 10): its lod is 'base' only");
        if (lod_glsl_only(*mode) &&
            std::find(ex.backends.begin(), ex.backends.end(), "glsl") == ex.backends.end())
            throw InputError(where, "lod '" + name +
                                        "' samples through the GPU's own level selection and "
                                        "runs on the glsl backend only; the experiment's "
                                        "backends are " +
                                        join_names(ex.backends));
        if (std::find(out.begin(), out.end(), *mode) != out.end())
            throw InputError(where, "lod '" + name + "' is given twice");
        out.push_back(*mode);
    }
    return out;
}

// `depth`: the depth modes (methods/depth.h; a value or a list, swept; default base). `engine`
// on a preset whose engine writes no depth offset is `base`, said in the docs (its rows exist:
// a family's engine column stays comparable); on a method that is no engine preset (no engine
// formula at all: the seed and literature methods, plug-ins) it is refused.
std::vector<DepthMode> read_depths(const ParamDict& t, const MethodInfo& m) {
    if (!t.has("depth")) return {DepthMode::base};
    const std::string where = t.where("depth");
    std::vector<DepthMode> out;
    for (const std::string& name : t.strings("depth", {})) {
        std::optional<DepthMode> mode;
        for (DepthMode d : {DepthMode::base, DepthMode::hit, DepthMode::engine})
            if (name == depth_name(d)) mode = d;
        if (!mode)
            throw InputError(
                where, "unknown depth '" + name + "' (known: " + join_names(depth_names()) + ")");
        if (std::find(out.begin(), out.end(), *mode) != out.end())
            throw InputError(where, "depth '" + name + "' is given twice");
        if (*mode == DepthMode::engine && !m.engine_depth)
            throw InputError(where, "depth 'engine' needs an engine preset: method '" + m.name +
                                        "' has no engine formula (use base or hit)");
        out.push_back(*mode);
    }
    return out;
}

// `heightfields`: the entries the method runs on (empty: all), each one known and, when the
// method needs a bias, of that bias.
std::vector<std::string> read_method_fields(const ParamDict& t, const std::string& name,
                                            const MethodInfo& m, const Experiment& ex) {
    const std::vector<std::string> fields = t.strings("heightfields", {});
    for (const auto& f : fields) {
        bool known = false;
        for (const auto& h : ex.heightfields) known = known || h.name == f;
        if (!known)
            throw InputError(t.where("heightfields"),
                             "method '" + name + "': no heightfield named '" + f + "'");
    }
    if (!std::isnan(m.required_bias))
        for (const auto& h : ex.heightfields) {
            const bool runs =
                fields.empty() || std::find(fields.begin(), fields.end(), h.name) != fields.end();
            if (runs && h.bias != m.required_bias)
                throw InputError(t.where("name"), "method '" + name + "' needs bias = " +
                                                      format_number(m.required_bias) + " (" +
                                                      m.bias_reason + "); heightfield '" + h.name +
                                                      "' has bias = " + format_number(h.bias));
        }
    return fields;
}

// The entry's rows from its factors, before the sweep is expanded, checked against the limits.
void check_method_rows(const Sweeps& sweeps, const MethodSpec& proto,
                       const std::vector<LodMode>& lods, size_t depths, const Experiment& ex,
                       ParseState& state, const std::string& where) {
    const MethodInfo* m = proto.method;
    RowProduct rows;
    for (const auto& [key, values] : sweeps)
        if (values.size() > 1) rows.times(values.size(), key);
    size_t fields_run = 0;
    for (const auto& h : ex.heightfields) fields_run += proto.runs_on(h.name);
    rows.times(fields_run, "heightfield(s)");
    rows.times(ex.theta_deg.size(), "theta");
    rows.times(ex.phi_deg.size(), "phi");
    if (ex.camera_settings.size() > 1) rows.times(ex.camera_settings.size(), "camera settings");
    size_t variants = 0;  // per parameter setting, over its lod modes (grad, implicit: GLSL)
    for (LodMode lod : lods)
        variants +=
            variants_per_setting(ex, state.limits, !m->plugin_shader.empty() || lod_glsl_only(lod));
    rows.times(variants, lods.size() > 1 ? "lod mode x backend variant(s)" : "backend variant(s)");
    if (depths > 1) rows.times(depths, "depth modes");
    if (ex.cuts.size() > 1) rows.times(ex.cuts.size(), "cut planes ([views] cut)");
    check_entry_rows(state.method_rows, rows, where, "[[methods]]", state.limits);
}

// The parameters in the table's order (the sweep's order), each read by its spec: a built-in's
// from the entry, a plug-in's from its uniforms, then its bound values, then its defines.
Sweeps entry_sweeps(const ParamDict& t, const MethodInfo& m, const PluginParts* parts) {
    Sweeps sweeps;
    const std::string owner = "method '" + m.name + "'";
    if (!parts) {
        for (const std::string& key : t.keys())
            for (const auto& p : m.params)
                if (p.name == key) sweeps.emplace_back(key, param_values(t, key, p, owner));
        return sweeps;
    }
    std::vector<const ParamDict*> tables = {&parts->uniforms};
    if (parts->engine.binds) tables.push_back(&*parts->engine.binds);
    for (const ParamDict* pt : tables)
        for (const std::string& key : pt->keys())
            for (const auto& p : m.params)
                if (p.name == key && p.uniform == key)
                    sweeps.emplace_back(key, param_values(*pt, key, p, owner));
    for (const auto& d : parts->engine.define_sweeps) sweeps.push_back(d);
    return sweeps;
}

// An explicit texture level needs the field's levels: a plug-in that reads one is refused
// rows at lod = "base" (level 0 alone), where it reads it.
void check_explicit_level(const PluginParts& parts, const std::vector<LodMode>& lods) {
    if (parts.explicit_level.empty() ||
        std::find(lods.begin(), lods.end(), LodMode::base) == lods.end())
        return;
    const size_t colon = parts.explicit_level.rfind(": ");
    throw InputError(parts.explicit_level.substr(0, colon),
                     "'" + parts.explicit_level.substr(colon + 2) +
                         "' reads the height at an explicit texture level, and the entry's lod "
                         "\"base\" uploads level 0 alone: give it lod = \"level\" (or \"grad\", "
                         "\"implicit\"), which uploads the field's levels");
}

}  // namespace

void parse_method(const ParamDict& t, Experiment& ex, ParseState& state) {
    const std::string where = t.where();
    if (!t.has("name")) throw InputError(where, "a [[methods]] entry needs 'name'");
    const std::string name = *t.string("name");
    const bool plugin = t.has("shader");
    PluginParts parts;  // a plug-in's parameter tables (a built-in's are the entry's other keys)
    const MethodInfo* m = plugin ? make_plugin(t, name, ex, parts) : find_method(name);
    if (!m) {
        std::string names;
        std::vector<std::string> all;
        for (const auto& mi : all_methods()) {
            names += (names.empty() ? "" : ", ") + mi.name;
            all.push_back(mi.name);
        }
        throw InputError(t.where("name"), "unknown method '" + name + "'" +
                                              did_you_mean(name, all) + " (known: " + names + ")");
    }
    const std::vector<std::string> fields = read_method_fields(t, name, *m, ex);
    const Sweeps sweeps = entry_sweeps(t, *m, plugin ? &parts : nullptr);
    MethodSpec proto{m, {}, fields};
    const std::vector<LodMode> lods = read_lods(t, *m, ex);
    if (plugin) check_explicit_level(parts, lods);
    const std::vector<DepthMode> depths = read_depths(t, *m);
    const std::vector<double> cuts = ex.cuts.empty() ? std::vector<double>{NAN} : ex.cuts;
    if (plugin) {
        read_reference(t, where, proto);
        t.report_unused([](const std::string& key, const std::string& known) {
            return "unknown key '" + key + "' in a plug-in [[methods]] entry (known: " + known +
                   ")";
        });
    } else {
        t.report_unused([&](const std::string& key, const std::string& known) {
            std::string names;
            std::vector<std::string> all = split_names(known);  // the entry's own keys too
            for (const auto& p : m->params) {
                names += (names.empty() ? "" : ", ") + p.name;
                all.push_back(p.name);
            }
            return "unknown parameter '" + key + "'" + did_you_mean(key, all) + " for method '" +
                   name + "'" + (names.empty() ? " (it takes none)" : " (known: " + names + ")");
        });
    }
    check_method_rows(sweeps, proto, lods, depths.size(), ex, state, where);
    // A setting given twice (a repeated value, or two entries) is measured once: its rows
    // would repeat, and pxh compare refuses repeated rows.
    size_t repeats = 0;
    std::string first_repeat;
    for (const auto& given : expand(sweeps))
        for (size_t variant = 0; variant < lods.size() * depths.size() * cuts.size(); ++variant) {
            const LodMode lod = lods[variant / (depths.size() * cuts.size())];
            MethodSpec ms = proto;
            ms.params = resolve_method_params(*m, given, where);
            if (plugin)
                ms.method =
                    parts.variants.at(define_key(define_setting(parts.engine, given, where)));
            ms.lod = lod;
            ms.depth = depths[variant / cuts.size() % depths.size()];
            ms.cut = cuts[variant % cuts.size()];
            std::string key = m->name + "\x1f" + ms.params.canonical() + "\x1f" + lod_name(lod) +
                              "\x1f" + depth_name(ms.depth) + "\x1f" + format_number(ms.cut);
            if (ms.reference)
                key += "\x1f" + ms.reference->name + "\x1f" + ms.reference_params.canonical();
            const auto [it, fresh] =
                state.settings.emplace(key, std::make_pair(ex.methods.size(), where));
            if (fresh) {
                ex.methods.push_back(std::move(ms));
                continue;
            }
            // Measured on the union of both entries' fields (empty: every field); a repeat when
            // they share one (the same setting on other fields is no repeat).
            MethodSpec& kept = ex.methods[it->second.first];
            bool shared = kept.heightfields.empty() || ms.heightfields.empty();
            for (const auto& f : ms.heightfields) shared = shared || kept.runs_on(f);
            if (!kept.heightfields.empty()) {
                if (ms.heightfields.empty()) kept.heightfields.clear();
                else
                    for (const auto& f : ms.heightfields)
                        if (!kept.runs_on(f)) kept.heightfields.push_back(f);
            }
            if (shared && repeats++ == 0)
                first_repeat =
                    "[" + ms.params.canonical() +
                    (lods.size() > 1 ? std::string(", lod ") + lod_name(lod) : std::string()) +
                    "], as at " + it->second.second;
        }
    if (repeats)
        warn(ex, where + ": " + std::to_string(repeats) + " setting(s) of method '" + name +
                     "' repeat one given before (first: " + first_repeat +
                     "): each setting is measured once, one row per view");
}

ParamValues resolve_method_params(const MethodInfo& m, const GivenParams& given,
                                  const std::string& where) {
    ParamValues p = resolve_params(m.params, given, where, "method '" + m.name + "'");
    if (m.check) m.check(p, where);
    if (m.complete_params) {
        m.complete_params(p);
        m.check(p, where);
    }
    return p;
}

void check_plugin_backends(const Experiment& ex,
                           const std::vector<std::string>& backends_override) {
    const auto& names = backends_override.empty() ? ex.backends : backends_override;
    if (ex.plugins.empty() || std::find(names.begin(), names.end(), "glsl") != names.end()) return;
    std::string plugins;
    for (const auto& p : ex.plugins) plugins += (plugins.empty() ? "'" : ", '") + p->name + "'";
    throw InputError(backends_override.empty() ? "--only" : "--backend",
                     "the plug-in shader(s) " + plugins +
                         " run on the glsl backend only, and this run has backends " +
                         join_names(names) + ": add glsl (a plug-in has no CPU rows)");
}

std::vector<std::string> skipped_settings(const Experiment& ex,
                                          const std::vector<std::string>& backends_override) {
    const auto& names = backends_override.empty() ? ex.backends : backends_override;
    std::vector<std::string> out;
    for (const std::string& b : names) {
        // Per reason, the settings skipped (each named once).
        std::map<std::string, std::vector<std::string>> by_reason;
        for (const MethodSpec& m : ex.methods) {
            const std::string why = backend_skips(b, m);
            if (why.empty()) continue;
            std::string name = m.method->name;
            if (!m.params.canonical().empty()) name += " " + m.params.canonical();
            if (m.lod != LodMode::base) name += std::string(" lod=") + lod_name(m.lod);
            if (m.depth != DepthMode::base) name += std::string(" depth=") + depth_name(m.depth);
            auto& v = by_reason[why];
            if (std::find(v.begin(), v.end(), name) == v.end()) v.push_back(name);
        }
        for (const auto& [why, settings] : by_reason) {
            std::string listed;
            for (size_t i = 0; i < settings.size() && i < 6; ++i)
                listed += (i ? ", " : "") + settings[i];
            if (settings.size() > 6) listed += ", ... (" + std::to_string(settings.size()) + ")";
            out.push_back("backend " + b + " makes no rows of " + std::to_string(settings.size()) +
                          " method setting(s) (" + listed + "): " + why);
        }
    }
    return out;
}

}  // namespace pxh
