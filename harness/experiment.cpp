#include "harness/experiment.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "harness/error.h"
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

void check_keys(const toml::table& t, const std::set<std::string>& allowed,
                const std::string& path, const std::string& context) {
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
        if (!(step > 0)) throw InputError(where_of(path, n), "'" + key + "' step must be > 0");
        if (!(to >= from)) throw InputError(where_of(path, n), "'" + key + "' needs to >= from");
        const long long count = (long long)std::floor((to - from) / step + 1e-9) + 1;
        if (count > 100000) throw InputError(where_of(path, n), "'" + key + "' has too many angles");
        std::vector<double> out;
        for (long long k = 0; k < count; ++k) out.push_back(from + double(k) * step);
        return out;
    }
    return get_numbers(n, path, key);
}

// Cartesian product of parameter sweeps: {a: [1,2], b: [3]} -> [{a:1,b:3}, {a:2,b:3}].
std::vector<std::map<std::string, double>> expand(
    const std::vector<std::pair<std::string, std::vector<double>>>& sweeps) {
    std::vector<std::map<std::string, double>> out{{}};
    for (const auto& [key, values] : sweeps) {
        std::vector<std::map<std::string, double>> next;
        for (const auto& partial : out)
            for (double v : values) {
                auto m = partial;
                m[key] = v;
                next.push_back(std::move(m));
            }
        out = std::move(next);
    }
    return out;
}

void parse_heightfield(const toml::table& t, const toml::node& node, const std::string& path,
                       Experiment& ex) {
    const std::string where = where_of(path, node);
    const bool has_gen = t.contains("generator"), has_file = t.contains("file");
    const bool has_scan = t.contains("scan");
    if (int(has_gen) + int(has_file) + int(has_scan) != 1)
        throw InputError(where, "a [[heightfields]] entry needs exactly one of 'generator', "
                                "'file' or 'scan'");
    HeightfieldSpec base;
    base.where = where;
    std::set<std::string> allowed{"name", "generator", "file", "scan", "size", "width",
                                  "height", "scale", "bias", "channel"};
    const GeneratorInfo* gen = nullptr;
    if (has_gen) {
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
    } else if (has_scan) {
        base.scan = get_string(*t.get("scan"), path, "scan");
        if (base.scan.rfind("scan:", 0) == 0) base.scan = base.scan.substr(5);
        base.name = "scan:" + base.scan;
    } else {
        const std::string f = get_string(*t.get("file"), path, "file");
        fs::path fp(f);
        if (fp.is_relative()) fp = fs::path(path).parent_path() / fp;
        base.file = fp.lexically_normal().string();
        base.name = fp.stem().string();
    }
    check_keys(t, allowed, path, "[[heightfields]]");
    if (auto n = t.get("name")) base.name = get_string(*n, path, "name");
    if (auto n = t.get("size")) base.width = base.height = get_int(*n, path, "size", 1, 16384);
    if (auto n = t.get("width")) base.width = get_int(*n, path, "width", 1, 16384);
    if (auto n = t.get("height")) base.height = get_int(*n, path, "height", 1, 16384);
    if (auto n = t.get("channel")) base.channel = get_int(*n, path, "channel", 0, 64);
    if (!has_gen && (t.contains("size") || t.contains("width") || t.contains("height")))
        throw InputError(where, "'size'/'width'/'height' apply to generators, not to files or scans");

    std::vector<double> scales{0.05}, biases{1.0};
    if (auto n = t.get("scale")) scales = get_numbers(*n, path, "scale");
    if (auto n = t.get("bias")) biases = get_numbers(*n, path, "bias");
    for (double s : scales)
        if (!(s > 0) || !std::isfinite(s))
            throw InputError(where_of(path, *t.get("scale")), "scale must be > 0 (got " +
                                                                  format_number(s) + ")");
    for (double b : biases)
        if (!(b >= 0 && b <= 1))
            throw InputError(where_of(path, *t.get("bias")), "bias must lie in [0, 1] (got " +
                                                                 format_number(b) + ")");
    std::vector<std::pair<std::string, std::vector<double>>> sweeps;
    if (gen)
        for (const auto& p : gen->params)
            if (auto n = t.get(p.name)) sweeps.emplace_back(p.name, get_numbers(*n, path, p.name));
    const auto combos = expand(sweeps);
    for (const auto& given : combos) {
        HeightfieldSpec hs = base;
        if (gen) hs.gen_params = resolve_params(gen->params, given, where, "generator '" + gen->name + "'");
        if (combos.size() > 1) hs.name = base.name + "[" + hs.gen_params.canonical() + "]";
        for (double s : scales)
            for (double b : biases) {
                hs.scale = s;
                hs.bias = b;
                ex.heightfields.push_back(hs);
            }
    }
}

void parse_method(const toml::table& t, const toml::node& node, const std::string& path,
                  Experiment& ex) {
    const std::string where = where_of(path, node);
    if (!t.contains("name")) throw InputError(where, "a [[methods]] entry needs 'name'");
    const std::string name = get_string(*t.get("name"), path, "name");
    const MethodInfo* m = find_method(name);
    if (!m) {
        std::string names;
        for (const auto& mi : all_methods()) names += (names.empty() ? "" : ", ") + mi.name;
        throw InputError(where_of(path, *t.get("name")),
                         "unknown method '" + name + "' (known: " + names + ")");
    }
    std::vector<std::pair<std::string, std::vector<double>>> sweeps;
    for (const auto& [k, v] : t) {
        const std::string key(k.str());
        if (key == "name") continue;
        bool known = false;
        for (const auto& p : m->params) known |= p.name == key;
        if (!known) {
            std::string names;
            for (const auto& p : m->params) names += (names.empty() ? "" : ", ") + p.name;
            throw InputError(where_of(path, v), "unknown parameter '" + key + "' for method '" +
                                                    name + "'" +
                                                    (names.empty() ? " (it takes none)"
                                                                   : " (known: " + names + ")"));
        }
        sweeps.emplace_back(key, get_numbers(v, path, key));
    }
    for (const auto& given : expand(sweeps)) {
        MethodSpec ms{m, resolve_params(m->params, given, where, "method '" + name + "'")};
        m->check(ms.params, where);
        ex.methods.push_back(std::move(ms));
    }
}

}  // namespace

Experiment parse_experiment(const std::string& text, const std::string& path) {
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
    ex.name = fs::path(path).stem().string();
    check_keys(root,
               {"name", "description", "samples", "backends", "precision", "timing_repeats",
                "texture_format", "ground_truth", "sweep_dt_deg", "maps", "exclude_filled",
                "views", "heightfields", "methods", "light"},
               path, "the experiment");
    if (auto n = root.get("name")) ex.name = get_string(*n, path, "name");
    if (auto n = root.get("description")) get_string(*n, path, "description");
    if (auto n = root.get("samples")) ex.samples = get_int(*n, path, "samples", 1, 8192);
    if (auto n = root.get("timing_repeats"))
        ex.timing_repeats = get_int(*n, path, "timing_repeats", 0, 1000);
    if (auto n = root.get("backends")) {
        ex.backends = get_strings(*n, path, "backends");
        for (const auto& b : ex.backends)
            if (b != "cpu" && b != "glsl")
                throw InputError(where_of(path, *n),
                                 "unknown backend '" + b + "' (known: cpu, glsl)");
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
    if (auto n = root.get("ground_truth")) {
        ex.ground_truth = get_string(*n, path, "ground_truth");
        if (ex.ground_truth != "exact" && ex.ground_truth != "embree")
            throw InputError(where_of(path, *n), "unknown ground_truth '" + ex.ground_truth +
                                                     "' (known: exact, embree)");
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

    const toml::node* views = root.get("views");
    if (!views || !views->is_table())
        throw InputError(path, "missing [views] table (theta_deg = [...])");
    const auto& vt = *views->as_table();
    check_keys(vt, {"theta_deg", "phi_deg"}, path, "[views]");
    if (!vt.contains("theta_deg")) throw InputError(where_of(path, *views), "[views] needs theta_deg");
    ex.theta_deg = get_angles(*vt.get("theta_deg"), path, "theta_deg");
    for (double t : ex.theta_deg)
        if (!(t >= 0 && t < 90))
            throw InputError(where_of(path, *vt.get("theta_deg")),
                             "theta_deg = " + format_number(t) +
                                 " is impossible: the polar angle must lie in [0, 90)");
    if (auto n = vt.get("phi_deg")) ex.phi_deg = get_angles(*n, path, "phi_deg");
    for (double p : ex.phi_deg)
        if (!std::isfinite(p))
            throw InputError(where_of(path, *vt.get("phi_deg")), "phi_deg must be finite");

    if (auto n = root.get("light")) {
        const auto* lt = n->as_table();
        if (!lt) throw InputError(where_of(path, *n), "'light' must be a table ([light])");
        check_keys(*lt, {"theta_deg", "phi_deg", "layers_min", "layers_max"}, path, "[light]");
        LightSpec l;
        if (auto v = lt->get("theta_deg")) l.theta_deg = get_number(*v, path, "theta_deg");
        if (auto v = lt->get("phi_deg")) l.phi_deg = get_number(*v, path, "phi_deg");
        if (auto v = lt->get("layers_min")) l.layers_min = get_number(*v, path, "layers_min");
        if (auto v = lt->get("layers_max")) l.layers_max = get_number(*v, path, "layers_max");
        if (!(l.theta_deg >= 0 && l.theta_deg < 90))
            throw InputError(where_of(path, *n), "light theta_deg = " + format_number(l.theta_deg) +
                                                     " is impossible: it must lie in [0, 90)");
        if (!std::isfinite(l.phi_deg))
            throw InputError(where_of(path, *n), "light phi_deg must be finite");
        if (!(l.layers_min >= 1 && l.layers_max >= l.layers_min && l.layers_max <= 4096))
            throw InputError(where_of(path, *n), "light layers need 1 <= layers_min <= layers_max <= 4096");
        ex.light = l;
    }
    auto tables_of = [&](const char* key) {
        const toml::node* n = root.get(key);
        if (!n) throw InputError(path, std::string("no [[") + key + "]] entries");
        const auto* arr = n->as_array();
        if (!arr || arr->empty() || !arr->is_array_of_tables())
            throw InputError(where_of(path, *n), std::string("'") + key +
                                                     "' must be a list of tables ([[" + key + "]])");
        return arr;
    };
    for (const auto& e : *tables_of("heightfields")) parse_heightfield(*e.as_table(), e, path, ex);
    for (const auto& e : *tables_of("methods")) parse_method(*e.as_table(), e, path, ex);
    return ex;
}

Experiment load_experiment(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(path, "no such file");
    if (fs::is_directory(path, ec)) throw InputError(path, "is a directory, not an experiment file");
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "cannot open");
    std::stringstream ss;
    ss << f.rdbuf();
    return parse_experiment(ss.str(), path);
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
        hf = load_heightfield_file(spec.file, spec.channel);
    }
    hf.name = spec.name;
    return hf;
}

}  // namespace pxh
