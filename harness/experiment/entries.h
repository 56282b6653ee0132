// What the parts of the experiment parser share (parse.cpp, heightfield_entries.cpp,
// method_entries.cpp): the entry readers, names that become file names, warnings, and the row
// count of an entry checked before it is expanded. Internal to harness/experiment.
#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "harness/backends/engine_shader.h"
#include "harness/core/param_dict.h"
#include "harness/experiment/experiment.h"

namespace pxh {

// Names that become path components: the experiment's name is the default output folder
// (results/runs/NAME-DATE), a height field's name goes into map file names. Refused: empty,
// '/', '\\', control characters, over 100 characters, and for folders a leading '.' ('.', '..',
// hidden folders).
void check_safe_name(const std::string& name, const std::string& where, const std::string& what,
                     bool folder);

// A warning, "FILE:LINE: ..." on one line.
void warn(Experiment& ex, const std::string& text);

// A row count as a product of its factors, saturating (never wraps), with its text:
// "3000 p_a x 3000 p_b x 2 heightfields x ...".
struct RowProduct {
    size_t value = 1;
    std::string text;
    void times(size_t n, const std::string& what) {
        value = n != 0 && value > SIZE_MAX / n ? SIZE_MAX : value * n;
        text += (text.empty() ? "" : " x ") + std::to_string(n) + " " + what;
    }
};

// What parsing carries from entry to entry: the limits, the rows counted so far, and every
// method setting seen (method, canonical parameters, reference) with its index in ex.methods
// and the entry that gave it first.
struct ParseState {
    ParseLimits limits;
    size_t field_rows = 0, method_rows = 0;
    std::map<std::string, std::pair<size_t, std::string>> settings;
};

// Refuses an entry whose rows, counted from its factors before anything is expanded, take the
// total past --max-rows or its rows' memory past --max-memory.
void check_entry_rows(size_t& total, const RowProduct& rows, const std::string& where,
                      const std::string& entry, const ParseLimits& lim);

// Rows per method setting and view: the backends' variants (a plug-in: the glsl backend's
// only); at least 1, so that an entry's own size always counts.
size_t variants_per_setting(const Experiment& ex, const ParseLimits& lim, bool glsl_only);

// A parameter's sweep, one list of values per key, and its Cartesian product:
// {a: [1,2], b: [3]} -> [{a:1,b:3}, {a:2,b:3}].
using Sweeps = std::vector<std::pair<std::string, std::vector<ParamValue>>>;
std::vector<GivenParams> expand(const Sweeps& sweeps);

// A parameter's value or sweep (numbers, bools or strings) read from `entry`, each checked
// against the parameter's type where it is written (the accepted values in the message).
std::vector<ParamValue> param_values(const ParamDict& entry, const std::string& key,
                                     const ParamSpec& spec, const std::string& owner);

// Scales whose errors saturate, with the file:line of each entry that uses them (one
// warning per scale value, however many entries share it).
using LargeScales = std::map<double, std::vector<std::string>>;

// [[heightfields]] (heightfield_entries.cpp): one entry, expanded into ex.heightfields; the
// warning per large scale; one name, one field.
void parse_heightfield(const ParamDict& entry, Experiment& ex, LargeScales& large_scales,
                       ParseState& state);
void warn_large_scales(const LargeScales& large_scales, Experiment& ex);
void check_heightfield_names(const Experiment& ex);

// A plug-in entry's engine keys (plugin_entry.cpp): the adapter without its defines' values,
// each define's sweep (a parameter of the rows, not a uniform), the bind table and its keys
// bound to values (uniforms, typed as the shader declares them).
struct PluginEngine {
    EngineAdapter base;
    std::vector<ParamSpec> define_specs;
    Sweeps define_sweeps;
    std::optional<ParamDict> binds;
    std::vector<std::pair<std::string, std::string>> bound_values;  // name, its FILE:LINE
};
PluginEngine read_plugin_engine(const ParamDict& t);
// The parameters of the values bound (each typed as `shader` declares its uniform).
std::vector<ParamSpec> bound_value_specs(const PluginEngine& e, const EngineShader& shader);
// The defines of one setting, `given` holding a value for each.
std::vector<std::pair<std::string, std::string>> define_setting(const PluginEngine& e,
                                                                const GivenParams& given,
                                                                const std::string& where);

// [[methods]] (method_entries.cpp): one entry (a built-in method or a plug-in shader),
// expanded into ex.methods.
void parse_method(const ParamDict& entry, Experiment& ex, ParseState& state);

}  // namespace pxh
