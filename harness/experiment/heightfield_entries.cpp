// [[heightfields]] entries: where each field comes from (generator, image file, imported
// scan), its size, scales and biases, the generator's parameter sweeps; one name, one field.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>

#include "harness/core/error.h"
#include "harness/core/registry.h"
#include "harness/core/sha256.h"
#include "harness/experiment/entries.h"
#include "harness/scene/base_surface.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

// The smallest scale accepted: at 1e-6 the parallax offset s tan(theta) is below 1/30 of a
// texel of the largest field (16384 texels) up to theta = 60 degrees.
constexpr double kMinScale = 1e-6;

// An identity without its hash, for messages: the part a reader tells fields apart by.
std::string describe_field(const HeightfieldSpec& h) {
    return h.identity.substr(0, h.identity.find(" sha256:"));
}

// Where the entry's field comes from (generator, scan or file): fills base's source, name and
// identity; returns the generator (nullptr for a scan or a file).
const GeneratorInfo* heightfield_source(const ParamDict& t, const std::string& path,
                                        HeightfieldSpec& base) {
    const GeneratorInfo* gen = nullptr;
    if (t.has("generator")) {
        base.generator = *t.string("generator");
        gen = find_generator(base.generator);
        if (!gen) {
            std::string names;
            for (const auto& g : all_generators()) names += (names.empty() ? "" : ", ") + g.name;
            throw InputError(t.where("generator"),
                             "unknown generator '" + base.generator + "' (known: " + names + ")");
        }
        base.name = base.generator;
    } else if (t.has("scan")) {
        base.scan = *t.string("scan");
        if (base.scan.rfind("scan:", 0) == 0) base.scan = base.scan.substr(5);
        // Only an imported scan (its name also picks files in heightfields/scanned/).
        std::string names;
        bool known = false;
        for (const auto& sc : list_scans()) {
            names += (names.empty() ? "" : ", ") + sc.name;
            known |= sc.name == base.scan;
        }
        if (!known)
            throw InputError(t.where("scan"),
                             "unknown scan '" + base.scan + "' (known: " + names + ")");
        base.name = "scan:" + base.scan;
        const std::string png =
            std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/" + base.scan + ".png";
        base.source_path = png;
        base.source_sha256 = sha256_file(png);
        base.identity = "scan:" + base.scan + " sha256:" + base.source_sha256;
    } else {
        const std::string f = *t.string("file");
        fs::path fp(f);
        if (fp.is_relative()) fp = fs::path(path).parent_path() / fp;
        base.file = fp.lexically_normal().string();
        base.file_written = fs::path(f).lexically_normal().string();
        base.name = fp.stem().string();
    }
    return gen;
}

// Name, size and channel; a generated field within the image loader's limit.
void heightfield_size(const ParamDict& t, bool has_gen, HeightfieldSpec& base) {
    const std::string& where = base.where;
    if (auto n = t.string("name")) {
        base.name = *n;
        check_safe_name(base.name, t.where("name"), "heightfield name", false);
    }
    const int max_side = int(kMaxImageSide);
    if (auto n = t.integer("size", 1, max_side)) base.width = base.height = *n;
    base.width = t.integer("width", base.width, 1, max_side);
    base.height = t.integer("height", base.height, 1, max_side);
    base.channel = t.integer("channel", base.channel, 0, 64);
    if (!has_gen && (t.has("size") || t.has("width") || t.has("height")))
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
    if (!problem.empty())
        throw InputError(base.where, heightfield_file_problem(base.file, problem));
    try {
        base.source_path = base.file;
        base.source_sha256 = sha256_file(base.file);
        base.identity = "file:" + base.file_written + " channel:" + std::to_string(base.channel) +
                        " sha256:" + base.source_sha256;
    } catch (const InputError& e) {
        throw InputError(base.where, heightfield_file_problem(base.file, e.what()));
    }
}

// The entry's base surfaces (`base`, a name or a list; default the registry's first, the
// plane) and their settings as (base, radius) pairs: each base reads its own keys
// (BaseEntry::read: the plane none, a curved base its radii, one setting each). A key that no
// base of the list reads is refused here, naming the bases that read it.
std::vector<std::pair<std::string, double>> heightfield_bases(const ParamDict& t) {
    const std::vector<std::string> bases = t.strings("base", {default_base_name()});
    std::vector<std::pair<std::string, double>> out;
    bool takes_radius = false;
    for (const std::string& b : bases) {
        const BaseEntry& e = base_entry(b, t.where("base"));
        takes_radius = takes_radius || e.curved;
        for (double r : e.read(t, b)) out.push_back({b, r});
    }
    if (t.has("radius") && !takes_radius) {
        std::string curved;
        for (const BaseEntry& e : base_registry())
            if (e.curved)
                curved += (curved.empty() ? "base = \"" : "\" or \"") + std::string(e.name);
        throw InputError(t.where("radius"), "radius applies to a curved base (" + curved +
                                                "\"); this entry's base is the " + bases.front());
    }
    return out;
}

// The entry's scales and biases (a value or a sweep each), checked; scales whose errors
// saturate within the views go into large_scales.
std::pair<std::vector<double>, std::vector<double>> heightfield_scales(const ParamDict& t,
                                                                       const Experiment& ex,
                                                                       LargeScales& large_scales) {
    const std::vector<double> scales = t.numbers("scale", {0.05});
    const std::vector<double> biases = t.numbers("bias", {1.0});
    for (double s : scales) {
        if (!(s > 0) || !std::isfinite(s))
            throw InputError(t.where("scale"), "scale must be > 0 (got " + format_number(s) + ")");
        // Tiny and denormal scales: no parallax to measure, and 1 / s overflows in the truths.
        if (s < kMinScale)
            throw InputError(t.where("scale"),
                             "scale = " + format_number(s) + " is below " +
                                 format_number(kMinScale) +
                                 ": a relief that thin offsets no sample by a measurable part of "
                                 "a texel (and a denormal scale overflows the ground truth)");
    }
    for (double b : biases)
        if (!(b >= 0 && b <= 1))
            throw InputError(t.where("bias"),
                             "bias must lie in [0, 1] (got " + format_number(b) + ")");
    // Errors are measured modulo one tile, so they saturate once the true hit can lie half a
    // tile from its sample: the parallax offset s tan(theta) reaches 0.5 at theta =
    // atan(0.5 / s). Warn when that happens within the experiment's views and at or below
    // 45 degrees (s >= 0.5): grazing views with an ordinary scale are a deliberate study.
    const double theta_max = ex.theta_deg.empty() ? 0 : ex.theta_deg.back();
    for (double s : scales)
        if (s >= 0.5 && theta_max >= std::atan(0.5 / s) * 180 / M_PI)
            large_scales[s].push_back(t.where("scale"));
    return {scales, biases};
}

}  // namespace

void parse_heightfield(const ParamDict& t, Experiment& ex, LargeScales& large_scales,
                       ParseState& state) {
    const std::string where = t.where();
    const bool has_gen = t.has("generator"), has_file = t.has("file");
    const bool has_scan = t.has("scan");
    if (int(has_gen) + int(has_file) + int(has_scan) != 1)
        throw InputError(where,
                         "a [[heightfields]] entry needs exactly one of 'generator', "
                         "'file' or 'scan'");
    HeightfieldSpec base;
    base.where = where;
    const GeneratorInfo* gen = heightfield_source(t, ex.path, base);
    heightfield_size(t, has_gen, base);
    const auto [scales, biases] = heightfield_scales(t, ex, large_scales);
    const auto bases = heightfield_bases(t);
    for (const auto& [name, r] : bases)
        for (double s : scales)
            for (double b : biases)
                if (base_entry(name).curved)
                    if (const std::string why = radius_problem(name, r, s, b); !why.empty())
                        throw InputError(t.where("radius"), why);
    Sweeps sweeps;  // the generator's parameters, in its order
    if (gen)
        for (const auto& p : gen->params)
            if (t.has(p.name))
                sweeps.emplace_back(p.name,
                                    param_values(t, p.name, p, "generator '" + gen->name + "'"));
    t.report_unused();
    if (has_file) hash_heightfield_file(base);
    RowProduct rows;  // at least one method setting on each of its fields
    for (const auto& [key, values] : sweeps)
        if (values.size() > 1) rows.times(values.size(), key);
    rows.times(scales.size(), "scale");
    rows.times(biases.size(), "bias");
    if (bases.size() > 1) rows.times(bases.size(), "base and radius");
    rows.times(ex.theta_deg.size(), "theta");
    rows.times(ex.phi_deg.size(), "phi");
    if (ex.camera_settings.size() > 1) rows.times(ex.camera_settings.size(), "camera settings");
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
        for (const auto& [name, r] : bases)
            for (double s : scales)
                for (double b : biases) {
                    hs.base = name;
                    hs.radius = r;
                    hs.scale = s;
                    hs.bias = b;
                    ex.heightfields.push_back(hs);
                }
    }
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

// One name, one field: a name shared by different fields would merge them into one series
// of the report. The same field at the same scale and bias twice (under any names) would
// repeat rows. One entry swept over scale/bias keeps its name (the columns tell rows apart).
void check_heightfield_names(const Experiment& ex) {
    std::map<std::string, size_t> by_name;
    std::map<std::tuple<std::string, double, double, std::string, double>, size_t> by_field;
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
            by_field.emplace(std::make_tuple(h.identity, h.scale, h.bias, h.base,
                                             std::isfinite(h.radius) ? h.radius : 0.0),
                             k);
        if (fresh_field) continue;
        const HeightfieldSpec& b = ex.heightfields[same->second];
        const std::string what =
            describe_field(h) + " at scale " + format_number(h.scale) + ", bias " +
            format_number(h.bias) +
            (base_entry(h.base).curved ? ", base " + h.base + " radius " + format_number(h.radius)
                                       : "");
        if (b.where == h.where)
            throw InputError(h.where, "this entry lists " + what + " twice (a repeated value)");
        throw InputError(h.where, "duplicate height field: " + what + " is also the entry at " +
                                      b.where + " (as '" + b.name + "'); its rows would repeat");
    }
}

}  // namespace pxh
