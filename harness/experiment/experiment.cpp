#include "harness/experiment/experiment.h"

#include <OpenImageIO/imageio.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "harness/backends/backend.h"
#include "harness/backends/plugin_source.h"
#include "harness/backends/shaders.h"
#include "harness/core/error.h"
#include "harness/core/registry.h"
#include "harness/core/safe_files.h"
#include "harness/core/sha256.h"
#include "harness/gl/context.h"
#include "harness/scene/view.h"
#include "harness/truth/tracer.h"
#include "harness/truth/travel_limit.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

std::string where_of(const std::string& path, const toml::node& n) {
    const auto& src = n.source();
    if (src.begin.line == 0) return path;
    return path + ":" + std::to_string(src.begin.line);
}

void check_keys(const toml::table& t, const std::set<std::string>& allowed, const std::string& path,
                const std::string& context) {
    for (const auto& [k, v] : t) {
        const std::string key(k.str());
        if (!allowed.count(key)) {
            std::string names;
            for (const auto& a : allowed) names += (names.empty() ? "" : ", ") + a;
            throw InputError(where_of(path, v),
                             "unknown key '" + key + "' in " + context + " (known: " + names + ")");
        }
    }
}

double get_number(const toml::node& n, const std::string& path, const std::string& key) {
    if (auto v = n.value<double>(); v && (n.is_integer() || n.is_floating_point())) return *v;
    throw InputError(where_of(path, n), "'" + key + "' must be a number");
}

int get_int(const toml::node& n, const std::string& path, const std::string& key, int lo, int hi) {
    if (!n.is_integer()) throw InputError(where_of(path, n), "'" + key + "' must be an integer");
    const int64_t v = *n.value<int64_t>();
    if (v < lo || v > hi)
        throw InputError(where_of(path, n), "'" + key + "' = " + std::to_string(v) +
                                                " is outside [" + std::to_string(lo) + ", " +
                                                std::to_string(hi) + "]");
    return int(v);
}

std::string get_string(const toml::node& n, const std::string& path, const std::string& key) {
    if (auto v = n.value<std::string>(); v && n.is_string()) return *v;
    throw InputError(where_of(path, n), "'" + key + "' must be a string");
}

// A value or an array of values (a sweep), each read by `one`.
template <class T, class Get>
std::vector<T> get_list(const toml::node& n, const std::string& path, const std::string& key,
                        Get one) {
    std::vector<T> out;
    if (const auto* arr = n.as_array()) {
        if (arr->empty()) throw InputError(where_of(path, n), "'" + key + "' is an empty list");
        for (const auto& e : *arr) out.push_back(one(e, path, key));
    } else {
        out.push_back(one(n, path, key));
    }
    return out;
}

std::vector<double> get_numbers(const toml::node& n, const std::string& path,
                                const std::string& key) {
    return get_list<double>(n, path, key, get_number);
}

std::vector<std::string> get_strings(const toml::node& n, const std::string& path,
                                     const std::string& key) {
    return get_list<std::string>(n, path, key, get_string);
}

// Angles: a list, or { from, to, step } (inclusive of `to` within rounding).
std::vector<double> get_angles(const toml::node& n, const std::string& path,
                               const std::string& key) {
    if (const auto* t = n.as_table()) {
        check_keys(*t, {"from", "to", "step"}, path, "'" + key + "'");
        for (const char* k : {"from", "to", "step"})
            if (!t->contains(k))
                throw InputError(where_of(path, n), "'" + key + "' range needs '" + k + "'");
        const double from = get_number(*t->get("from"), path, "from");
        const double to = get_number(*t->get("to"), path, "to");
        const double step = get_number(*t->get("step"), path, "step");
        if (!std::isfinite(from) || !std::isfinite(to) || !std::isfinite(step))
            throw InputError(where_of(path, n),
                             "'" + key + "' range needs finite from, to and step");
        if (!(step > 0)) throw InputError(where_of(path, n), "'" + key + "' step must be > 0");
        if (!(to >= from)) throw InputError(where_of(path, n), "'" + key + "' needs to >= from");
        const double span = std::floor((to - from) / step + 1e-9) + 1;  // counted in double first
        if (!(span <= 100000))
            throw InputError(where_of(path, n), "'" + key + "' has too many angles");
        const long long count = (long long)span;
        std::vector<double> out;
        for (long long k = 0; k < count; ++k) out.push_back(from + double(k) * step);
        return out;
    }
    return get_numbers(n, path, key);
}

// Names that become path components: the experiment's name is the default output folder
// (results/runs/NAME-DATE), a height field's name goes into map file names. Refused: empty,
// '/', '\\', control characters, over 100 characters, and for folders a leading '.' ('.', '..',
// hidden folders).
void check_safe_name(const std::string& name, const std::string& where, const std::string& what,
                     bool folder) {
    std::string problem;
    if (name.empty()) problem = "is empty";
    else if (name.size() > 100) problem = "is longer than 100 characters";
    else if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
        problem = "contains '/' or '\\'";
    else if (std::any_of(name.begin(), name.end(),
                         [](unsigned char c) { return c < 0x20 || c == 0x7f; }))
        problem = "contains control characters";
    else if (folder && name[0] == '.') problem = "starts with '.'";
    if (!problem.empty())
        throw InputError(where, what + " '" + name + "' " + problem + ": it names " +
                                    (folder ? "the output folder" : "files") +
                                    ", so it must be a plain file name");
}

// The experiment's default name, from its file name: made safe rather than refused.
std::string safe_default_name(const std::string& stem) {
    std::string out;
    for (unsigned char c : stem) out += (c < 0x20 || c == 0x7f || c == '\\') ? '_' : char(c);
    while (!out.empty() && out[0] == '.') out[0] = '_';
    if (out.size() > 100) out.resize(100);
    return out.empty() ? "experiment" : out;
}

// "heightfield file 'PATH' (paths are relative to the experiment file): REASON", REASON being
// the loader's message without its leading "PATH: ".
std::string file_problem(const std::string& file, std::string reason) {
    if (reason.rfind(file + ": ", 0) == 0) reason = reason.substr(file.size() + 2);
    return "heightfield file '" + file + "' (paths are relative to the experiment file): " + reason;
}

// An identity without its hash, for messages: the part a reader tells fields apart by.
std::string describe_field(const HeightfieldSpec& h) {
    return h.identity.substr(0, h.identity.find(" sha256:"));
}

// A warning, "FILE:LINE: ..." on one line.
void warn(Experiment& ex, const std::string& text) { ex.warnings.push_back(one_line(text)); }

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

std::string count_text(size_t n) { return n == SIZE_MAX ? "more than 2^64" : std::to_string(n); }

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
                      const std::string& entry, const ParseLimits& lim) {
    const size_t before = total;
    total = rows.value > SIZE_MAX - before ? SIZE_MAX : before + rows.value;
    const std::string also =
        before ? " (" + std::to_string(before) + " more from the entries before it)" : "";
    if (total > lim.max_rows)
        throw InputError(where, "this " + entry + " entry would write " + count_text(rows.value) +
                                    " rows (" + rows.text + ")" + also + " > --max-rows " +
                                    std::to_string(lim.max_rows) +
                                    ": refused before expanding it (raise --max-rows N)");
    if (total > lim.max_memory / kBytesPerRow)
        throw InputError(
            where, "this " + entry + " entry would write " + count_text(rows.value) + " rows (" +
                       rows.text + ")" + also + ", whose " + std::to_string(kBytesPerRow) +
                       " bytes each need more than --max-memory " + format_bytes(lim.max_memory) +
                       ": refused before expanding it (raise --max-memory SIZE)");
}

// Rows per method setting and view: the backends' variants (a plug-in: the glsl backend's
// only); at least 1, so that an entry's own size always counts.
size_t variants_per_setting(const Experiment& ex, const ParseLimits& lim, bool glsl_only) {
    const auto& backends = lim.backends.empty() ? ex.backends : lim.backends;
    const BackendSettings settings = backend_settings(ex);
    size_t n = 0;
    for (const auto& b : backends)
        if (!glsl_only || b == "glsl") n += backend_variants(b, settings).size();
    return std::max<size_t>(n, 1);
}

// Cartesian product of parameter sweeps: {a: [1,2], b: [3]} -> [{a:1,b:3}, {a:2,b:3}].
std::vector<GivenParams> expand(
    const std::vector<std::pair<std::string, std::vector<ParamValue>>>& sweeps) {
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

// A parameter's value or sweep: numbers, bools or strings, each checked against the
// parameter's type where it is written (the accepted values in the message).
std::vector<ParamValue> get_param_values(const toml::node& n, const std::string& path,
                                         const ParamSpec& spec, const std::string& owner) {
    auto one = [&](const toml::node& e, const std::string&, const std::string&) {
        ParamValue v;
        if (e.is_integer()) v = ParamValue((long long)*e.value<int64_t>());
        else if (e.is_floating_point()) v = ParamValue(*e.value<double>());
        else if (e.is_boolean()) v = ParamValue(*e.value<bool>());
        else if (e.is_string()) v = ParamValue(*e.value<std::string>());
        else
            throw InputError(where_of(path, e),
                             owner + " parameter '" + spec.name + "' must be " + spec.accepted());
        check_param_kind(spec, v, where_of(path, e), owner);
        return v;
    };
    return get_list<ParamValue>(n, path, spec.name, one);
}

// The smallest scale accepted: at 1e-6 the parallax offset s tan(theta) is below 1/30 of a
// texel of the largest field (16384 texels) up to theta = 60 degrees.
constexpr double kMinScale = 1e-6;

// Scales whose errors saturate, with the file:line of each entry that uses them (one
// warning per scale value, however many entries share it).
using LargeScales = std::map<double, std::vector<std::string>>;

// Where a [[heightfields]] entry's field comes from (generator, scan or file): fills base's
// source, name and identity, adds the generator's parameters to the allowed keys; returns the
// generator (nullptr for a scan or a file).
const GeneratorInfo* heightfield_source(const toml::table& t, const std::string& path,
                                        HeightfieldSpec& base, std::set<std::string>& allowed) {
    const GeneratorInfo* gen = nullptr;
    if (t.contains("generator")) {
        base.generator = get_string(*t.get("generator"), path, "generator");
        gen = find_generator(base.generator);
        if (!gen) {
            std::string names;
            for (const auto& g : all_generators()) names += (names.empty() ? "" : ", ") + g.name;
            throw InputError(where_of(path, *t.get("generator")),
                             "unknown generator '" + base.generator + "' (known: " + names + ")");
        }
        for (const auto& p : gen->params) allowed.insert(p.name);
        base.name = base.generator;
    } else if (t.contains("scan")) {
        base.scan = get_string(*t.get("scan"), path, "scan");
        if (base.scan.rfind("scan:", 0) == 0) base.scan = base.scan.substr(5);
        // Only an imported scan (its name also picks files in heightfields/scanned/).
        std::string names;
        bool known = false;
        for (const auto& sc : list_scans()) {
            names += (names.empty() ? "" : ", ") + sc.name;
            known |= sc.name == base.scan;
        }
        if (!known)
            throw InputError(where_of(path, *t.get("scan")),
                             "unknown scan '" + base.scan + "' (known: " + names + ")");
        base.name = "scan:" + base.scan;
        const std::string png =
            std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/" + base.scan + ".png";
        base.source_path = png;
        base.source_sha256 = sha256_file(png);
        base.identity = "scan:" + base.scan + " sha256:" + base.source_sha256;
    } else {
        const std::string f = get_string(*t.get("file"), path, "file");
        fs::path fp(f);
        if (fp.is_relative()) fp = fs::path(path).parent_path() / fp;
        base.file = fp.lexically_normal().string();
        base.file_written = fs::path(f).lexically_normal().string();
        base.name = fp.stem().string();
    }
    return gen;
}

// Name, size and channel; a generated field within the image loader's limit.
void heightfield_size(const toml::table& t, const std::string& path, bool has_gen,
                      HeightfieldSpec& base) {
    const std::string& where = base.where;
    if (auto n = t.get("name")) {
        base.name = get_string(*n, path, "name");
        check_safe_name(base.name, where_of(path, *n), "heightfield name", false);
    }
    const int max_side = int(kMaxImageSide);
    if (auto n = t.get("size")) base.width = base.height = get_int(*n, path, "size", 1, max_side);
    if (auto n = t.get("width")) base.width = get_int(*n, path, "width", 1, max_side);
    if (auto n = t.get("height")) base.height = get_int(*n, path, "height", 1, max_side);
    if (auto n = t.get("channel")) base.channel = get_int(*n, path, "channel", 0, 64);
    if (!has_gen && (t.contains("size") || t.contains("width") || t.contains("height")))
        throw InputError(where,
                         "'size'/'width'/'height' apply to generators, not to files or scans");
    // Generated fields obey the image loader's limit (a 16384^2 field is 1 GiB of floats
    // before its truths and Embree's copy).
    if ((long long)base.width * base.height > kMaxImageTexels)
        throw InputError(where, "generated field " + std::to_string(base.width) + " x " +
                                    std::to_string(base.height) + " has more than " +
                                    std::to_string(kMaxImageTexels) +
                                    " texels, the limit for height fields (as for image files)");
}

// A file is identified by its bytes; read now, so a missing or unreadable file is named
// before any work (and a FIFO is not opened: it would block).
void hash_heightfield_file(HeightfieldSpec& base) {
    std::error_code ec;
    const auto st = fs::status(base.file, ec);
    std::string problem;
    if (!fs::exists(st)) problem = "no such file";
    else if (!fs::is_regular_file(st)) problem = "not a regular file";
    if (!problem.empty()) throw InputError(base.where, file_problem(base.file, problem));
    try {
        base.source_path = base.file;
        base.source_sha256 = sha256_file(base.file);
        base.identity = "file:" + base.file_written + " channel:" + std::to_string(base.channel) +
                        " sha256:" + base.source_sha256;
    } catch (const InputError& e) {
        throw InputError(base.where, file_problem(base.file, e.what()));
    }
}

// The entry's scales and biases (a value or a sweep each), checked; scales whose errors
// saturate within the views go into large_scales.
std::pair<std::vector<double>, std::vector<double>> heightfield_scales(const toml::table& t,
                                                                       const std::string& path,
                                                                       const Experiment& ex,
                                                                       LargeScales& large_scales) {
    std::vector<double> scales{0.05}, biases{1.0};
    if (auto n = t.get("scale")) scales = get_numbers(*n, path, "scale");
    if (auto n = t.get("bias")) biases = get_numbers(*n, path, "bias");
    for (double s : scales) {
        if (!(s > 0) || !std::isfinite(s))
            throw InputError(where_of(path, *t.get("scale")),
                             "scale must be > 0 (got " + format_number(s) + ")");
        // Tiny and denormal scales: no parallax to measure, and 1 / s overflows in the truths.
        if (s < kMinScale)
            throw InputError(where_of(path, *t.get("scale")),
                             "scale = " + format_number(s) + " is below " +
                                 format_number(kMinScale) +
                                 ": a relief that thin offsets no sample by a measurable part of "
                                 "a texel (and a denormal scale overflows the ground truth)");
    }
    for (double b : biases)
        if (!(b >= 0 && b <= 1))
            throw InputError(where_of(path, *t.get("bias")),
                             "bias must lie in [0, 1] (got " + format_number(b) + ")");
    // Errors are measured modulo one tile, so they saturate once the true hit can lie half a
    // tile from its sample: the parallax offset s tan(theta) reaches 0.5 at theta =
    // atan(0.5 / s). Warn when that happens within the experiment's views and at or below
    // 45 degrees (s >= 0.5): grazing views with an ordinary scale are a deliberate study.
    const double theta_max = ex.theta_deg.empty() ? 0 : ex.theta_deg.back();
    for (double s : scales)
        if (s >= 0.5 && theta_max >= std::atan(0.5 / s) * 180 / M_PI)
            large_scales[s].push_back(where_of(path, *t.get("scale")));
    return {scales, biases};
}

void parse_heightfield(const toml::table& t, const toml::node& node, const std::string& path,
                       Experiment& ex, LargeScales& large_scales, ParseState& state) {
    const std::string where = where_of(path, node);
    const bool has_gen = t.contains("generator"), has_file = t.contains("file");
    const bool has_scan = t.contains("scan");
    if (int(has_gen) + int(has_file) + int(has_scan) != 1)
        throw InputError(where,
                         "a [[heightfields]] entry needs exactly one of 'generator', "
                         "'file' or 'scan'");
    HeightfieldSpec base;
    base.where = where;
    std::set<std::string> allowed{"name",  "generator", "file",  "scan", "size",
                                  "width", "height",    "scale", "bias", "channel"};
    const GeneratorInfo* gen = heightfield_source(t, path, base, allowed);
    check_keys(t, allowed, path, "[[heightfields]]");
    heightfield_size(t, path, has_gen, base);
    if (has_file) hash_heightfield_file(base);
    const auto [scales, biases] = heightfield_scales(t, path, ex, large_scales);
    std::vector<std::pair<std::string, std::vector<ParamValue>>> sweeps;
    if (gen)
        for (const auto& p : gen->params)
            if (auto n = t.get(p.name))
                sweeps.emplace_back(p.name,
                                    get_param_values(*n, path, p, "generator '" + gen->name + "'"));
    RowProduct rows;  // at least one method setting on each of its fields
    for (const auto& [key, values] : sweeps)
        if (values.size() > 1) rows.times(values.size(), key);
    rows.times(scales.size(), "scale");
    rows.times(biases.size(), "bias");
    rows.times(ex.theta_deg.size(), "theta");
    rows.times(ex.phi_deg.size(), "phi");
    rows.times(variants_per_setting(ex, state.limits, false), "backend variant(s)");
    rows.times(1, "method setting (at least)");
    check_entry_rows(state.field_rows, rows, where, "[[heightfields]]", state.limits);
    const auto combos = expand(sweeps);
    for (const auto& given : combos) {
        HeightfieldSpec hs = base;
        if (gen) {
            hs.gen_params =
                resolve_params(gen->params, given, where, "generator '" + gen->name + "'");
            if (gen->problem)
                if (const std::string why = gen->problem(hs.gen_params); !why.empty())
                    throw InputError(where, "generator '" + gen->name + "' [" +
                                                hs.gen_params.canonical() + "]: " + why);
            hs.identity = "generator:" + gen->name + " " + std::to_string(hs.width) + "x" +
                          std::to_string(hs.height) + " [" + hs.gen_params.canonical() + "]";
        }
        if (combos.size() > 1) hs.name = base.name + "[" + hs.gen_params.canonical() + "]";
        for (double s : scales)
            for (double b : biases) {
                hs.scale = s;
                hs.bias = b;
                ex.heightfields.push_back(hs);
            }
    }
}

// A [[methods]] entry with `shader = FILE`: a GLSL-only method from the user's file (relative
// to the experiment), its uniforms from the `uniforms` table (each p_NAME; a number, bool or a
// list sweeping them; an integer value makes an int uniform), its declared fetch bound.
const MethodInfo* make_plugin(const toml::table& t, const std::string& path,
                              const std::string& name, Experiment& ex,
                              const toml::table*& param_table) {
    const toml::node& sn = *t.get("shader");
    const std::string where = where_of(path, sn);
    if (find_method(name))
        throw InputError(
            where_of(path, *t.get("name")),
            "'" + name + "' is a built-in method; a plug-in shader needs a name of its own");
    for (const auto& p : ex.plugins)
        if (p->name == name)
            throw InputError(where_of(path, *t.get("name")),
                             "plug-in '" + name + "' is defined twice");
    check_safe_name(name, where_of(path, *t.get("name")), "method name", false);
    for (const auto& [k, v] : t) {
        static const std::set<std::string> keys = {"name",        "shader",    "uniforms",
                                                   "max_fetches", "reference", "reference_params",
                                                   "heightfields"};
        if (!keys.count(std::string(k.str())))
            throw InputError(where_of(path, v),
                             "unknown key '" + std::string(k.str()) +
                                 "' in a plug-in [[methods]] entry (known: name, "
                                 "shader, uniforms, max_fetches, reference, "
                                 "reference_params, heightfields)");
    }
    const std::string rel = get_string(sn, path, "shader");
    // Inside the experiment's folder, a regular UTF-8 text file under 1 MiB, read once here.
    PluginSource src = read_plugin_source(path, rel, where);
    if (const auto problems = plugin_source_problems(src.display, src.text,
                                                     shader_source("methods/common.glsl", "").text);
        !problems.empty()) {
        const size_t colon = problems[0].find(": ");  // "FILE:LINE:COL: why"
        throw InputError(problems[0].substr(0, colon), problems[0].substr(colon + 2));
    }
    if (std::find(ex.backends.begin(), ex.backends.end(), "glsl") == ex.backends.end())
        throw InputError(where_of(path, *t.get("name")),
                         "plug-in '" + name +
                             "' is a GLSL shader (it has no CPU rows) and the "
                             "experiment's backends are " +
                             join_names(ex.backends) + ": add \"glsl\" to backends");
    if (!t.contains("max_fetches"))
        throw InputError(
            where_of(path, *t.get("name")),
            "plug-in '" + name + "' needs max_fetches (its bound on texture fetches per sample)");
    auto info = std::make_shared<MethodInfo>();
    info->name = name;
    info->citation = "plug-in shader " + rel + " (from " + path + ")";
    info->summary = "GLSL only: " + rel;
    info->order = 1000;
    info->plugin_shader = src.resolved;
    info->shader_path = src.resolved;
    info->plugin_source = std::move(src.text);
    info->plugin_display = src.display;
    info->declared_max_fetches = get_int(*t.get("max_fetches"), path, "max_fetches", 1, 1000000);
    static const toml::table kNone;
    param_table = &kNone;
    if (const toml::node* u = t.get("uniforms")) {
        param_table = u->as_table();
        if (!param_table) throw InputError(where_of(path, *u), "'uniforms' must be a table");
        for (const auto& [k, v] : *param_table) {
            const std::string key(k.str());
            bool ident = key.size() > 2 && key.rfind("p_", 0) == 0;
            for (char c : key)
                ident = ident && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
            if (!ident)
                throw InputError(where_of(path, v),
                                 "uniform '" + key +
                                     "': plug-in uniforms are named p_NAME (letters, digits, _)");
            const toml::node* first =
                v.is_array() && !v.as_array()->empty() ? v.as_array()->get(0) : &v;
            ParamSpec spec =
                first->is_boolean() ? ParamSpec::boolean(key, false, "plug-in uniform")
                : first->is_integer()
                    ? ParamSpec::integer(key, std::nullopt, -2147483647.0, 2147483647.0,
                                         "plug-in uniform")
                    // What a GLSL float holds: 1e300 would reach the shader as inf.
                    : ParamSpec::real(key, std::nullopt, -double(FLT_MAX), double(FLT_MAX),
                                      "plug-in uniform (a GLSL float)");
            spec.default_value.reset();
            spec.to_uniform(key);
            info->params.push_back(spec);
        }
    }
    ex.plugins.push_back(info);
    return info.get();
}

void parse_method(const toml::table& t, const toml::node& node, const std::string& path,
                  Experiment& ex, ParseState& state) {
    const std::string where = where_of(path, node);
    if (!t.contains("name")) throw InputError(where, "a [[methods]] entry needs 'name'");
    const std::string name = get_string(*t.get("name"), path, "name");
    const toml::table* param_table = &t;  // where the parameters are (a plug-in: `uniforms`)
    const MethodInfo* m =
        t.contains("shader") ? make_plugin(t, path, name, ex, param_table) : find_method(name);
    if (!m) {
        std::string names;
        for (const auto& mi : all_methods()) names += (names.empty() ? "" : ", ") + mi.name;
        throw InputError(where_of(path, *t.get("name")),
                         "unknown method '" + name + "' (known: " + names + ")");
    }
    std::vector<std::string> fields;  // `heightfields`: the entries it runs on (empty: all)
    if (const toml::node* n = t.get("heightfields")) {
        fields = get_strings(*n, path, "heightfields");
        for (const auto& f : fields) {
            bool known = false;
            for (const auto& h : ex.heightfields) known = known || h.name == f;
            if (!known)
                throw InputError(where_of(path, *n),
                                 "method '" + name + "': no heightfield named '" + f + "'");
        }
    }
    if (!std::isnan(m->required_bias))
        for (const auto& h : ex.heightfields) {
            const bool runs =
                fields.empty() || std::find(fields.begin(), fields.end(), h.name) != fields.end();
            if (runs && h.bias != m->required_bias)
                throw InputError(where_of(path, *t.get("name")),
                                 "method '" + name +
                                     "' needs bias = " + format_number(m->required_bias) + " (" +
                                     m->bias_reason + "); heightfield '" + h.name +
                                     "' has bias = " + format_number(h.bias));
        }
    std::vector<std::pair<std::string, std::vector<ParamValue>>> sweeps;
    for (const auto& [k, v] : *param_table) {
        const std::string key(k.str());
        if (param_table == &t && (key == "name" || key == "heightfields")) continue;
        const ParamSpec* spec = nullptr;
        for (const auto& p : m->params)
            if (p.name == key) spec = &p;
        if (!spec) {
            std::string names;
            for (const auto& p : m->params) names += (names.empty() ? "" : ", ") + p.name;
            throw InputError(where_of(path, v),
                             "unknown parameter '" + key + "' for method '" + name + "'" +
                                 (names.empty() ? " (it takes none)" : " (known: " + names + ")"));
        }
        sweeps.emplace_back(key, get_param_values(v, path, *spec, "method '" + name + "'"));
    }
    MethodSpec proto{m, {}, fields};
    if (const toml::node* r = t.get("reference")) {  // a plug-in's CPU twin to compare with
        const std::string rn = get_string(*r, path, "reference");
        proto.reference = find_method(rn);
        if (!proto.reference || !proto.reference->run_float)
            throw InputError(where_of(path, *r), "reference '" + rn + "' is not a built-in method");
        GivenParams given;
        if (const toml::node* rp = t.get("reference_params")) {
            const toml::table* rt = rp->as_table();
            if (!rt) throw InputError(where_of(path, *rp), "'reference_params' must be a table");
            for (const auto& [k, v] : *rt) {
                const ParamSpec* spec = nullptr;
                for (const auto& p : proto.reference->params)
                    if (p.name == k.str()) spec = &p;
                if (!spec)
                    throw InputError(where_of(path, v), "unknown parameter '" +
                                                            std::string(k.str()) +
                                                            "' for reference '" + rn + "'");
                const auto vals = get_param_values(v, path, *spec, "reference '" + rn + "'");
                if (vals.size() != 1)
                    throw InputError(where_of(path, v), "reference parameters take one value");
                given.emplace(std::string(k.str()), vals[0]);
            }
        }
        proto.reference_params = resolve_method_params(*proto.reference, given, where);
    } else if (t.contains("reference_params")) {
        throw InputError(where_of(path, *t.get("reference_params")),
                         "'reference_params' without 'reference'");
    }
    // Its rows from its factors, before the sweep is expanded.
    RowProduct rows;
    for (const auto& [key, values] : sweeps)
        if (values.size() > 1) rows.times(values.size(), key);
    size_t fields_run = 0;
    for (const auto& h : ex.heightfields) fields_run += proto.runs_on(h.name);
    rows.times(fields_run, "heightfield(s)");
    rows.times(ex.theta_deg.size(), "theta");
    rows.times(ex.phi_deg.size(), "phi");
    rows.times(variants_per_setting(ex, state.limits, !m->plugin_shader.empty()),
               "backend variant(s)");
    check_entry_rows(state.method_rows, rows, where, "[[methods]]", state.limits);
    // A setting given twice (a repeated value, or two entries) is measured once: its rows
    // would repeat, and pxh compare refuses repeated rows.
    size_t repeats = 0;
    std::string first_repeat;
    for (const auto& given : expand(sweeps)) {
        MethodSpec ms = proto;
        ms.params = resolve_method_params(*m, given, where);
        std::string key = m->name + "\x1f" + ms.params.canonical();
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
            first_repeat = "[" + ms.params.canonical() + "], as at " + it->second.second;
    }
    if (repeats)
        warn(ex, where + ": " + std::to_string(repeats) + " setting(s) of method '" + name +
                     "' repeat one given before (first: " + first_repeat +
                     "): each setting is measured once, one row per view");
}

// One name, one field: a name shared by different fields would merge them into one series
// of the report. The same field at the same scale and bias twice (under any names) would
// repeat rows. One entry swept over scale/bias keeps its name (the columns tell rows apart).
void check_heightfield_names(const Experiment& ex) {
    std::map<std::string, size_t> by_name;
    std::map<std::tuple<std::string, double, double>, size_t> by_field;
    for (size_t k = 0; k < ex.heightfields.size(); ++k) {
        const HeightfieldSpec& h = ex.heightfields[k];
        const auto [named, fresh_name] = by_name.emplace(h.name, k);
        const HeightfieldSpec& a = ex.heightfields[named->second];
        if (!fresh_name && a.identity != h.identity)
            throw InputError(
                h.where, "heightfield name '" + h.name + "' is given to two different fields: " +
                             describe_field(a) + " (" + a.where + ") and " + describe_field(h) +
                             " (" + h.where + "); give one of them its own name = \"...\"");
        const auto [same, fresh_field] =
            by_field.emplace(std::make_tuple(h.identity, h.scale, h.bias), k);
        if (fresh_field) continue;
        const HeightfieldSpec& b = ex.heightfields[same->second];
        const std::string what = describe_field(h) + " at scale " + format_number(h.scale) +
                                 ", bias " + format_number(h.bias);
        if (b.where == h.where)
            throw InputError(h.where, "this entry lists " + what + " twice (a repeated value)");
        throw InputError(h.where, "duplicate height field: " + what + " is also the entry at " +
                                      b.where + " (as '" + b.name + "'); its rows would repeat");
    }
}

}  // namespace

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

namespace {

// The top-level settings: name, sizes, backends, flags (in the order they are checked).
void parse_settings(const toml::table& root, const std::string& path, Experiment& ex) {
    if (auto n = root.get("name")) {
        ex.name = get_string(*n, path, "name");
        check_safe_name(ex.name, where_of(path, *n), "experiment name", true);
    }
    if (auto n = root.get("description")) get_string(*n, path, "description");
    if (auto n = root.get("samples")) ex.samples = get_int(*n, path, "samples", 1, 8192);
    if (auto n = root.get("timing_repeats"))
        ex.timing_repeats = get_int(*n, path, "timing_repeats", 0, 1000);
    if (auto n = root.get("backends")) {
        ex.backends = get_strings(*n, path, "backends");
        for (const auto& b : ex.backends) check_backend_name(b, where_of(path, *n));
    }
    if (auto n = root.get("sweep_dt_deg")) {
        ex.sweep_dt_deg = get_number(*n, path, "sweep_dt_deg");
        if (!(ex.sweep_dt_deg > 0 && ex.sweep_dt_deg < 10))
            throw InputError(where_of(path, *n), "sweep_dt_deg must lie in (0, 10)");
    }
    if (auto n = root.get("maps")) {
        if (!n->is_boolean()) throw InputError(where_of(path, *n), "'maps' must be true or false");
        ex.maps = *n->value<bool>();
    }
    if (auto n = root.get("exclude_filled")) {
        if (!n->is_boolean())
            throw InputError(where_of(path, *n), "'exclude_filled' must be true or false");
        ex.exclude_filled = *n->value<bool>();
    }
}

// The reference and the number formats: ground truth, texture formats, precisions.
void parse_choices(const toml::table& root, const std::string& path, Experiment& ex) {
    if (auto n = root.get("ground_truth")) {
        ex.ground_truth = get_string(*n, path, "ground_truth");
        const auto known = tracer_names();
        if (std::find(known.begin(), known.end(), ex.ground_truth) == known.end())
            throw InputError(where_of(path, *n), "unknown ground_truth '" + ex.ground_truth +
                                                     "' (known: " + join_names(known) + ")");
    }
    if (auto n = root.get("gl")) {
        ex.gl = get_string(*n, path, "gl");
        if (!find_gl_context(ex.gl))
            throw InputError(where_of(path, *n), "unknown GL context '" + ex.gl +
                                                     "' (known: " + gl_context_names() + ")");
    }
    if (auto n = root.get("gl_time_limit_s")) {
        ex.gl_time_limit_s = get_number(*n, path, "gl_time_limit_s");
        if (!(ex.gl_time_limit_s > 0 && ex.gl_time_limit_s <= kMaxGlTimeLimitS))
            throw InputError(where_of(path, *n),
                             "gl_time_limit_s = " + format_number(ex.gl_time_limit_s) +
                                 " is outside (0, 86400] (seconds per row)");
    }
    if (auto n = root.get("texture_format")) {
        ex.texture_formats = get_strings(*n, path, "texture_format");
        for (const auto& f : ex.texture_formats)
            if (f != "r32f" && f != "r16" && f != "r8")
                throw InputError(where_of(path, *n),
                                 "unknown texture_format '" + f + "' (known: r32f, r16, r8)");
    }
    if (auto n = root.get("precision")) {
        ex.precisions = get_strings(*n, path, "precision");
        for (const auto& p : ex.precisions)
            if (p != "float" && p != "double")
                throw InputError(where_of(path, *n),
                                 "unknown precision '" + p + "' (known: float, double)");
    }
}

// [views] theta_deg: in degrees, [0, 90), increasing, each once (warned and fixed otherwise).
void parse_theta(const toml::table& vt, const std::string& path, Experiment& ex) {
    ex.theta_deg = get_angles(*vt.get("theta_deg"), path, "theta_deg");
    const std::string theta_where = where_of(path, *vt.get("theta_deg"));
    for (double t : ex.theta_deg)
        if (!(t >= 0 && t < 90))
            throw InputError(theta_where,
                             "theta_deg = " + format_number(t) +
                                 " is impossible: the polar angle must lie in [0, 90)");
    const bool all_small =
        std::all_of(ex.theta_deg.begin(), ex.theta_deg.end(), [](double t) { return t < 1.6; });
    const bool all_whole = std::all_of(ex.theta_deg.begin(), ex.theta_deg.end(),
                                       [](double t) { return t == std::floor(t); });
    if (all_small && !all_whole)
        warn(ex, theta_where +
                     ": theta_deg values are all below 1.6 and not all whole "
                     "numbers: they look like radians, but theta_deg is in degrees");
    // Sweeps (sliding, shimmering) pair consecutive views: increasing, each view once.
    if (!std::is_sorted(ex.theta_deg.begin(), ex.theta_deg.end()) ||
        std::adjacent_find(ex.theta_deg.begin(), ex.theta_deg.end()) != ex.theta_deg.end()) {
        const bool sorted = std::is_sorted(ex.theta_deg.begin(), ex.theta_deg.end());
        const size_t before = ex.theta_deg.size();
        std::sort(ex.theta_deg.begin(), ex.theta_deg.end());
        ex.theta_deg.erase(std::unique(ex.theta_deg.begin(), ex.theta_deg.end()),
                           ex.theta_deg.end());
        const size_t dropped = before - ex.theta_deg.size();
        std::string what = sorted ? "" : "is not in increasing order (sorted";
        if (dropped)
            what += std::string(sorted ? "repeats values (" : ", ") + std::to_string(dropped) +
                    " duplicate(s) dropped";
        warn(ex, theta_where + ": theta_deg " + what +
                     "): views are measured in increasing theta, each once");
    }
}

// [views] phi_deg: normalised into [0, 360), each once (warned).
void parse_phi(const toml::node& n, const std::string& path, Experiment& ex) {
    ex.phi_deg = get_angles(n, path, "phi_deg");
    const std::string phi_where = where_of(path, n);
    std::string changed;
    for (double& p : ex.phi_deg) {
        if (!std::isfinite(p)) throw InputError(phi_where, "phi_deg must be finite");
        if (p >= 0 && p < 360) continue;
        double q = std::fmod(p, 360.0);
        if (q < 0) q += 360;
        if (q >= 360) q = 0;  // -1e-20 + 360 rounds to 360
        changed += (changed.empty() ? "" : ", ") + format_number(p) + " -> " + format_number(q);
        p = q;
    }
    if (!changed.empty()) warn(ex, phi_where + ": phi_deg outside [0, 360) normalised: " + changed);
    std::vector<double> unique;
    for (double p : ex.phi_deg)
        if (std::find(unique.begin(), unique.end(), p) == unique.end()) unique.push_back(p);
    if (unique.size() != ex.phi_deg.size())
        warn(ex, phi_where + ": phi_deg repeats an azimuth (" +
                     std::to_string(ex.phi_deg.size() - unique.size()) +
                     " duplicate(s) dropped): each view is measured once");
    ex.phi_deg = std::move(unique);
}

void parse_views(const toml::table& root, const std::string& path, Experiment& ex) {
    const toml::node* views = root.get("views");
    if (!views || !views->is_table())
        throw InputError(path, "missing [views] table (theta_deg = [...])");
    const auto& vt = *views->as_table();
    check_keys(vt, {"theta_deg", "phi_deg", "camera"}, path, "[views]");
    if (!vt.contains("theta_deg"))
        throw InputError(where_of(path, *views), "[views] needs theta_deg");
    parse_theta(vt, path, ex);
    if (auto n = vt.get("phi_deg")) parse_phi(*n, path, ex);
    if (auto n = vt.get("camera")) {
        ex.camera = get_string(*n, path, "camera");
        const auto known = camera_names();
        if (std::find(known.begin(), known.end(), ex.camera) == known.end())
            throw InputError(where_of(path, *n), "unknown camera '" + ex.camera +
                                                     "' (known: " + join_names(known) + ")");
    }
}

void parse_light(const toml::node& n, const std::string& path, Experiment& ex) {
    const auto* lt = n.as_table();
    if (!lt) throw InputError(where_of(path, n), "'light' must be a table ([light])");
    check_keys(*lt, {"theta_deg", "phi_deg", "layers_min", "layers_max"}, path, "[light]");
    LightSpec l;
    if (auto v = lt->get("theta_deg")) l.theta_deg = get_number(*v, path, "theta_deg");
    if (auto v = lt->get("phi_deg")) l.phi_deg = get_number(*v, path, "phi_deg");
    if (auto v = lt->get("layers_min")) l.layers_min = get_number(*v, path, "layers_min");
    if (auto v = lt->get("layers_max")) l.layers_max = get_number(*v, path, "layers_max");
    if (!(l.theta_deg >= 0 && l.theta_deg < 90))
        throw InputError(where_of(path, n), "light theta_deg = " + format_number(l.theta_deg) +
                                                " is impossible: it must lie in [0, 90)");
    if (!std::isfinite(l.phi_deg))
        throw InputError(where_of(path, n), "light phi_deg must be finite");
    if (!(l.layers_min >= 1 && l.layers_max >= l.layers_min && l.layers_max <= 4096))
        throw InputError(where_of(path, n),
                         "light layers need 1 <= layers_min <= layers_max <= 4096");
    ex.light = l;
}

// [render], read after the fields and methods it names: every name, angle and method must be
// one the experiment has.
void parse_render(const toml::node& n, const std::string& path, Experiment& ex) {
    const auto* t = n.as_table();
    if (!t) throw InputError(where_of(path, n), "'render' must be a table ([render])");
    check_keys(*t, {"heightfields", "phi_deg", "theta_deg", "strip_method"}, path, "[render]");
    for (const char* k : {"heightfields", "theta_deg"})
        if (!t->contains(k))
            throw InputError(where_of(path, n), std::string("[render] needs ") + k);
    RenderSpec r;
    r.heightfields = get_strings(*t->get("heightfields"), path, "heightfields");
    for (const auto& f : r.heightfields)
        if (std::none_of(ex.heightfields.begin(), ex.heightfields.end(),
                         [&](const HeightfieldSpec& h) { return h.name == f; }))
            throw InputError(
                where_of(path, *t->get("heightfields")),
                "[render] heightfield '" + f + "' is no [[heightfields]] entry's name");
    auto in = [](const std::vector<double>& v, double x) {
        return std::find(v.begin(), v.end(), x) != v.end();
    };
    r.phi_deg = ex.phi_deg.front();
    if (auto v = t->get("phi_deg")) {
        r.phi_deg = get_number(*v, path, "phi_deg");
        if (!in(ex.phi_deg, r.phi_deg))
            throw InputError(where_of(path, *v), "[render] phi_deg = " + format_number(r.phi_deg) +
                                                     " is not one of [views] phi_deg");
    }
    r.theta_deg = get_numbers(*t->get("theta_deg"), path, "theta_deg");
    for (double th : r.theta_deg)
        if (!in(ex.theta_deg, th))
            throw InputError(
                where_of(path, *t->get("theta_deg")),
                "[render] theta_deg = " + format_number(th) + " is not one of [views] theta_deg");
    if (auto v = t->get("strip_method")) {
        r.strip_method = get_string(*v, path, "strip_method");
        const auto m = std::find_if(ex.methods.begin(), ex.methods.end(), [&](const MethodSpec& s) {
            return s.method->name == r.strip_method;
        });
        if (m == ex.methods.end())
            throw InputError(where_of(path, *v), "[render] strip_method '" + r.strip_method +
                                                     "' is no [[methods]] entry");
        r.strip_params = m->params.canonical();
    }
    ex.render = r;
}

// The entries of [[KEY]]: a non-empty list of tables.
const toml::array& tables_of(const toml::table& root, const std::string& path, const char* key) {
    const toml::node* n = root.get(key);
    if (!n) throw InputError(path, std::string("no [[") + key + "]] entries");
    const auto* arr = n->as_array();
    if (!arr || arr->empty() || !arr->is_array_of_tables())
        throw InputError(where_of(path, *n),
                         std::string("'") + key + "' must be a list of tables ([[" + key + "]])");
    return *arr;
}

// One warning per scale whose errors saturate within the views.
void warn_large_scales(const LargeScales& large_scales, Experiment& ex) {
    for (const auto& [s, wheres] : large_scales) {
        std::string also;
        for (size_t k = 1; k < wheres.size(); ++k)
            also +=
                (k == 1 ? " (also on lines " : ", ") + wheres[k].substr(wheres[k].rfind(':') + 1);
        if (!also.empty()) also += ")";
        const double onset = std::atan(0.5 / s) * 180 / M_PI;
        warn(ex, wheres[0] + ": scale = " + format_number(s) + also +
                     ": the parallax offset s*tan(theta) reaches half a tile at theta = " +
                     format_number(std::round(onset * 10) / 10) +
                     " deg (<= 45, and within the views up to " +
                     format_number(ex.theta_deg.back()) +
                     "); beyond it errors, measured modulo one tile, saturate near half the "
                     "field's size and searches take huge step counts: use a scale below 0.5");
    }
}

// Every eye ray (views, sweep companions) and light ray within the ground truths' travel
// limit (kMaxRayTravelTiles, harness/truth/travel_limit.h), reported at the field's entry.
void check_ray_travel(const Experiment& ex) {
    for (const HeightfieldSpec& h : ex.heightfields) {
        auto check = [&](double theta, const std::string& what) {
            if (const std::string why = ray_travel_problem(h.scale, theta); !why.empty())
                throw InputError(h.where, what + why);
        };
        for (double t : ex.theta_deg) {
            check(t, "");
            if (ex.sweep_dt_deg > 0 && t + ex.sweep_dt_deg < 90)
                check(t + ex.sweep_dt_deg, "sweep companion view: ");
        }
        if (ex.light) check(ex.light->theta_deg, "light: ");
    }
}

}  // namespace

Experiment parse_experiment(const std::string& text, const std::string& path,
                            const ParseLimits& limits) {
    // run.json records the path and the text: both must be UTF-8, checked before any work.
    if (const std::string why = utf8_problem(path); !why.empty())
        throw InputError(path,
                         "the experiment file's name is not UTF-8 (" + why + "): rename the file");
    if (const std::string why = utf8_problem(text); !why.empty())
        throw InputError(path + ":" + why.substr(5, why.find(',') - 5),
                         why.substr(why.find(',') + 2) +
                             " (experiment files are UTF-8 text: re-save it as UTF-8)");
    toml::table root;
    try {
        root = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << path << ":" << e.source().begin.line;
        throw InputError(os.str(), "TOML syntax error: " + std::string(e.description()));
    }
    Experiment ex;
    ex.path = path;
    ex.text = text;
    ex.name = safe_default_name(fs::path(path).stem().string());
    check_keys(root,
               {"name", "description", "samples", "backends", "precision", "timing_repeats",
                "texture_format", "ground_truth", "sweep_dt_deg", "maps", "exclude_filled", "gl",
                "gl_time_limit_s", "views", "heightfields", "methods", "light", "render"},
               path, "the experiment");
    parse_settings(root, path, ex);
    parse_choices(root, path, ex);
    parse_views(root, path, ex);
    if (auto n = root.get("light")) parse_light(*n, path, ex);
    LargeScales large_scales;
    ParseState state{limits, 0, 0, {}};
    for (const auto& e : tables_of(root, path, "heightfields"))
        parse_heightfield(*e.as_table(), e, path, ex, large_scales, state);
    warn_large_scales(large_scales, ex);
    check_heightfield_names(ex);
    for (const auto& e : tables_of(root, path, "methods"))
        parse_method(*e.as_table(), e, path, ex, state);
    if (auto n = root.get("render")) parse_render(*n, path, ex);
    check_ray_travel(ex);
    return ex;
}

Experiment load_experiment(const std::string& path, const ParseLimits& limits) {
    std::error_code ec;
    const auto st = fs::status(path, ec);  // follows symlinks
    if (!fs::exists(st)) throw InputError(path, "no such file");
    if (fs::is_directory(st)) throw InputError(path, "is a directory, not an experiment file");
    // A FIFO or device would block or never end: only regular files are read.
    if (!fs::is_regular_file(st))
        throw InputError(path,
                         "not a regular file (a FIFO, socket or device?): an experiment "
                         "must be a regular file");
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "cannot open");
    std::stringstream ss;
    ss << f.rdbuf();
    Experiment ex = parse_experiment(ss.str(), path, limits);
    for (const auto& w : ex.warnings) std::cerr << "pxh: warning: " << one_line(w) << "\n";
    return ex;
}

HeightField make_heightfield(const HeightfieldSpec& spec) {
    HeightField hf;
    if (!spec.generator.empty()) {
        hf = generate_heightfield(*find_generator(spec.generator), spec.width, spec.height,
                                  spec.gen_params);
        hf.validate(spec.where);
    } else if (!spec.scan.empty()) {
        hf = load_scan(spec.scan, spec.where);
    } else {
        try {
            hf = load_heightfield_file(spec.file, spec.channel);
        } catch (const std::exception& e) {
            throw InputError(spec.where, file_problem(spec.file, e.what()));
        }
    }
    hf.name = spec.name;
    return hf;
}

FieldSize field_size(const HeightfieldSpec& spec) {
    if (!spec.generator.empty()) return {size_t(spec.width), size_t(spec.height), false};
    if (!spec.scan.empty()) {
        for (const auto& sc : list_scans())
            if (sc.name == spec.scan)  // as tiled when loaded (mirrored: 2W x 2H)
                return {size_t(sc.tile_width), size_t(sc.tile_height), true};
    } else {
        // Through pxh's hardened loader (never OpenImageIO on the raw file: a hostile header
        // can make a library allocate gigabytes); bounded by the image limits, freed at once.
        try {
            const HeightField hf = load_heightfield_file(spec.file, spec.channel);
            return {size_t(hf.width), size_t(hf.height), false};
        } catch (const std::exception&) {
        }
    }
    // Unknown (the run will refuse it): the largest field the loader accepts.
    return {size_t(kMaxImageSide), size_t(kMaxImageTexels / kMaxImageSide), false};
}

namespace {

std::string mib(size_t bytes) { return format_bytes(bytes); }

}  // namespace

std::string format_bytes(size_t bytes) {
    std::ostringstream os;
    os << std::fixed;
    if (bytes < (size_t(1) << 30))
        os << std::setprecision(1) << double(bytes) / double(1 << 20) << " MiB";
    else os << std::setprecision(1) << double(bytes) / double(size_t(1) << 30) << " GiB";
    return os.str();
}

void apply_only(Experiment& ex, const std::string& spec) {
    std::map<std::string, std::vector<std::string>> want;
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const auto eq = item.find('=');
        const std::string key = item.substr(0, eq);
        static const std::set<std::string> keys = {"method",  "heightfield", "backend", "theta_deg",
                                                   "phi_deg", "scale",       "bias"};
        if (eq == std::string::npos || eq + 1 == item.size() || !keys.count(key))
            throw InputError("--only", "'" + item +
                                           "' is not KEY=VALUE[|VALUE] with KEY one of method, "
                                           "heightfield, backend, theta_deg, phi_deg, scale, bias");
        std::stringstream vs(item.substr(eq + 1));
        std::string v;
        while (std::getline(vs, v, '|')) want[key].push_back(v);
    }
    auto text_ok = [&](const char* key, const std::string& v) {
        const auto it = want.find(key);
        return it == want.end() ||
               std::find(it->second.begin(), it->second.end(), v) != it->second.end();
    };
    auto num_ok = [&](const char* key, double v) {
        const auto it = want.find(key);
        if (it == want.end()) return true;
        for (const auto& w : it->second) {
            char* end = nullptr;
            const double d = std::strtod(w.c_str(), &end);
            if (end && *end == '\0' && !w.empty() &&
                std::abs(d - v) <= 1e-9 * std::max(1.0, std::abs(v)))
                return true;
        }
        return false;
    };
    auto keep = [](auto& list, auto pred, const char* what, auto name_of) {
        std::string known;
        std::remove_reference_t<decltype(list)> kept;
        for (const auto& x : list) {
            const std::string n = name_of(x);
            if (known.find(n) == std::string::npos) known += (known.empty() ? "" : ", ") + n;
            if (pred(x)) kept.push_back(x);
        }
        if (kept.empty())
            throw InputError("--only", std::string("no ") + what +
                                           " matches (the experiment has: " + known + ")");
        list = std::move(kept);
    };
    keep(
        ex.methods, [&](const MethodSpec& m) { return text_ok("method", m.method->name); },
        "method", [](const MethodSpec& m) { return m.method->name; });
    keep(
        ex.heightfields,
        [&](const HeightfieldSpec& h) {
            return text_ok("heightfield", h.name) && num_ok("scale", h.scale) &&
                   num_ok("bias", h.bias);
        },
        "heightfield",
        [](const HeightfieldSpec& h) {
            return h.name + " (s=" + format_number(h.scale) + " b=" + format_number(h.bias) + ")";
        });
    keep(
        ex.theta_deg, [&](double t) { return num_ok("theta_deg", t); }, "theta_deg",
        [](double t) { return format_number(t); });
    keep(
        ex.phi_deg, [&](double p) { return num_ok("phi_deg", p); }, "phi_deg",
        [](double p) { return format_number(p); });
    keep(
        ex.backends, [&](const std::string& b) { return text_ok("backend", b); }, "backend",
        [](const std::string& b) { return b; });
}

BackendSettings backend_settings(const Experiment& ex) {
    BackendSettings s;
    s.precisions = ex.precisions;
    s.texture_formats = ex.texture_formats;
    s.timing_repeats = ex.timing_repeats;
    s.gl = ex.gl;
    s.gl_time_limit_s = ex.gl_time_limit_s;
    return s;
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

RunEstimate estimate_run(const Experiment& ex, const std::vector<std::string>& backends_override) {
    // The model's constants (see experiment.h), measured on this project's machine (peak
    // RSS of pxh run, fbm, samples 8: 181 MiB at 16^2; +52 to +55 bytes per texel from 1024^2
    // to 8192^2, of which 10 are the field and its mipmap; samples 2048, 6 rows per view:
    // 290 bytes per sample, which the terms below overestimate by a third).
    constexpr size_t kBaseBytes = size_t(192) << 20;
    constexpr size_t kEmbreeBytesPerTexel = 45;
    constexpr size_t kViewBytesPerSample = 16 + 40 + 16 + 8;  // P, exact hits, Embree hits, gap
    constexpr size_t kOutputBytesPerSample = 16 + 4 + 8 + 8;  // uv, fetches, shadows, scoring
    const auto& backends = backends_override.empty() ? ex.backends : backends_override;
    const BackendSettings settings = backend_settings(ex);
    size_t per_method = 0;  // rows per method setting: every backend's variants
    for (const auto& b : backends) per_method += backend_variants(b, settings).size();
    size_t rows_per_view = 0;  // the largest view's (a method may run on some fields only)
    RunEstimate est;
    for (const auto& h : ex.heightfields) {
        size_t methods = 0;
        for (const auto& m : ex.methods) methods += m.runs_on(h.name);
        rows_per_view = std::max(rows_per_view, methods * per_method);
        est.rows += ex.theta_deg.size() * ex.phi_deg.size() * methods * per_method;
    }

    size_t field = 0;  // the largest field's own bytes, its truths' and Embree's
    std::set<std::string> seen;
    for (const auto& spec : ex.heightfields) {
        if (!seen.insert(spec.identity).second) continue;  // scale/bias sweeps: same size
        const FieldSize sz = field_size(spec);
        const size_t texels = sz.width * sz.height;
        field = std::max(field, texels * (4 + (sz.mask ? 1 : 0) + 6 + kEmbreeBytesPerTexel));
    }
    const size_t n2 = size_t(ex.samples) * size_t(ex.samples);
    const size_t views_alive = ex.sweep_dt_deg > 0 ? 3 : 2;
    const size_t view = n2 * (kViewBytesPerSample + rows_per_view * 16 * views_alive +
                              3 * kOutputBytesPerSample + (ex.maps ? 16 : 0));
    const size_t results = est.rows * kBytesPerRow;
    est.peak_bytes = kBaseBytes + field + view + results;
    est.detail = "process " + mib(kBaseBytes) + " + largest field with its truths and Embree " +
                 mib(field) + " + one view's sample buffers " + mib(view) + " + result rows " +
                 mib(results);
    return est;
}

}  // namespace pxh
