// pxh run --only KEY=V[|V...],...: the experiment narrowed to the matching entries, views,
// camera settings, level modes and backend variants. The keys are the rows' axes
// (harness/metrics/columns.h, row_axes()), each numeric one also as a range KEY_min=V and
// KEY_max=V (theta's: theta_min, theta_max).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <type_traits>

#include "harness/core/error.h"
#include "harness/core/registry.h"
#include "harness/experiment/experiment.h"
#include "harness/experiment/only_rows.h"
#include "harness/metrics/columns.h"
#include "harness/metrics/row.h"
#include "harness/scene/base_surface.h"

namespace pxh {
namespace {

// What --only asks of one axis: any of the listed values, and within the range.
struct Want {
    std::vector<std::string> values;
    std::optional<double> lo, hi;
    std::string given;  // as typed, for messages
    bool text_ok(const std::string& v) const {
        return values.empty() || std::find(values.begin(), values.end(), v) != values.end();
    }
    bool num_ok(double v) const;
};

// A --only value as a number: the whole text, not nan.
std::optional<double> only_number(const std::string& w) {
    const auto d = parse_number(w);
    if (!d || std::isnan(*d)) return std::nullopt;
    return d;
}

bool same_number(double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b));
}

bool Want::num_ok(double v) const {
    if (std::isnan(v)) return false;
    if ((lo && v < *lo) || (hi && v > *hi)) return false;
    if (values.empty()) return true;
    for (const auto& s : values)
        if (same_number(v, *only_number(s))) return true;
    return false;
}

// The axes --only selects by, each with how to narrow the experiment (nullptr: an axis a run
// cannot be narrowed by, with the reason).
struct Selector {
    std::function<void(Experiment&, const Want&, const std::function<bool(const std::string&)>&,
                       const std::function<bool(double)>&)>
        apply;
    const char* why_not = nullptr;
};

template <class List, class Pred, class Name>
void keep(List& list, Pred pred, const std::string& what, Name name_of) {
    std::string known;
    List kept;
    for (const auto& x : list) {
        const std::string n = name_of(x);
        if (known.find(n) == std::string::npos) known += (known.empty() ? "" : ", ") + n;
        if (pred(x)) kept.push_back(x);
    }
    if (kept.empty())
        throw InputError("--only", "no " + what + " matches (the experiment has: " + known + ")");
    list = std::move(kept);
}

// A field entry as --only lists them: "bricks (s=0.05 b=1)".
std::string field_entry_name(const HeightfieldSpec& h) {
    return h.name + " (s=" + format_number(h.scale) + " b=" + format_number(h.bias) +
           (base_entry(h.base).curved ? " " + h.base + " R=" + format_number(h.radius) : "") + ")";
}

const std::map<std::string, Selector>& selectors() {
    using Text = std::function<bool(const std::string&)>;
    using Num = std::function<bool(double)>;
    static const std::map<std::string, Selector> s = {
        {"method", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(
                 ex.methods, [&](const MethodSpec& m) { return ok(m.method->name); }, "method",
                 [](const MethodSpec& m) { return m.method->name; });
         }}},
        {"params", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(
                 ex.methods, [&](const MethodSpec& m) { return ok(m.params.canonical()); },
                 "params", [](const MethodSpec& m) { return m.params.canonical(); });
         }}},
        {"lod", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(
                 ex.methods, [&](const MethodSpec& m) { return ok(lod_name(m.lod)); }, "lod",
                 [](const MethodSpec& m) { return std::string(lod_name(m.lod)); });
         }}},
        {"depth", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(
                 ex.methods, [&](const MethodSpec& m) { return ok(depth_name(m.depth)); }, "depth",
                 [](const MethodSpec& m) { return std::string(depth_name(m.depth)); });
         }}},
        {"cut", {[](Experiment& ex, const Want&, const Text&, const Num& ok) {
             keep(
                 ex.methods, [&](const MethodSpec& m) { return ok(m.cut); }, "cut",
                 [](const MethodSpec& m) { return format_number(m.cut); });
         }}},
        {"heightfield", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(
                 ex.heightfields, [&](const HeightfieldSpec& h) { return ok(h.name); },
                 "heightfield", field_entry_name);
         }}},
        {"scale", {[](Experiment& ex, const Want&, const Text&, const Num& ok) {
             keep(
                 ex.heightfields, [&](const HeightfieldSpec& h) { return ok(h.scale); }, "scale",
                 field_entry_name);
         }}},
        {"bias", {[](Experiment& ex, const Want&, const Text&, const Num& ok) {
             keep(
                 ex.heightfields, [&](const HeightfieldSpec& h) { return ok(h.bias); }, "bias",
                 field_entry_name);
         }}},
        // The base surface, by name ("plane" selects the plane's rows).
        {"base", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(
                 ex.heightfields, [&](const HeightfieldSpec& h) { return ok(h.base); }, "base",
                 [](const HeightfieldSpec& h) { return h.base; });
         }}},
        {"radius", {[](Experiment& ex, const Want&, const Text&, const Num& ok) {
             keep(
                 ex.heightfields, [&](const HeightfieldSpec& h) { return ok(h.radius); }, "radius",
                 field_entry_name);
         }}},
        {"theta_deg", {[](Experiment& ex, const Want&, const Text&, const Num& ok) {
             keep(ex.theta_deg, ok, "theta_deg", [](double t) { return format_number(t); });
         }}},
        {"phi_deg", {[](Experiment& ex, const Want&, const Text&, const Num& ok) {
             keep(ex.phi_deg, ok, "phi_deg", [](double p) { return format_number(p); });
         }}},
        {"backend", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(ex.backends, ok, "backend", [](const std::string& b) { return b; });
         }}},
        {"precision", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(ex.backend.precisions, ok, "precision", [](const std::string& p) { return p; });
         }}},
        {"texture_format", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             keep(ex.backend.texture_formats, ok, "texture_format",
                  [](const std::string& f) { return f; });
         }}},
        {"camera", {[](Experiment& ex, const Want&, const Text& ok, const Num&) {
             std::vector<std::string> one{ex.camera};
             keep(one, ok, "camera", [](const std::string& c) { return c; });
         }}},
        {"samples", {nullptr, "a run's samples are set with --samples, not selected"}},
        {"ground_truth", {nullptr, "a run has one ground truth (the file's ground_truth)"}},
    };
    return s;
}

// A camera key's selector: the camera's settings whose value of KEY matches.
void keep_camera_settings(Experiment& ex, const std::string& key,
                          const std::function<bool(double)>& ok) {
    keep(
        ex.camera_settings, [&](const CameraSetting& c) { return ok(c.get(key)); }, key,
        [&](const CameraSetting& c) { return format_number(c.get(key)); });
}

}  // namespace

namespace {

// An axis --only selects by: every axis but those a run sets another way (samples).
bool selectable(const std::string& axis) {
    const auto s = selectors().find(axis);
    return s == selectors().end() || s->second.apply;
}

}  // namespace

std::vector<std::string> only_keys() {
    std::vector<std::string> keys;
    for (const ColumnSpec* c : row_axes())
        if (selectable(c->name)) keys.push_back(c->name);
    return keys;
}

namespace {

// --only's text, KEY=V[|V...] or KEY=LO..HI (numeric keys; either end may be left out) or
// KEY_min=V / KEY_max=V, comma-separated: what each axis asks for, by axis name.
std::map<std::string, Want> parse_only(const std::string& spec) {
    // Every key --only knows, from the registry's axes, and the camera's own keys.
    std::vector<std::string> known;
    std::map<std::string, const ColumnSpec*> axis_of;  // KEY and KEY_min / KEY_max -> the axis
    std::map<std::string, int> range_end;              // KEY_min -> -1, KEY_max -> +1
    for (const ColumnSpec* c : row_axes()) {
        known.push_back(c->name);
        axis_of[c->name] = c;
        if (c->numeric()) {
            axis_of[range_key(*c, false)] = c;
            axis_of[range_key(*c, true)] = c;
            range_end[range_key(*c, false)] = -1;
            range_end[range_key(*c, true)] = +1;
        }
    }
    const auto listed = [&] {
        std::string s;
        for (const std::string& k : known) {
            if (!selectable(k)) continue;  // said when given
            const ColumnSpec* c = axis_of[k];
            s += (s.empty() ? "" : ", ") + k;
            if (c->numeric())
                s += " (and " + range_key(*c, false) + ", " + range_key(*c, true) + ")";
        }
        return s;
    };
    std::map<std::string, Want> want;  // by axis name
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const auto eq = item.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
            throw InputError("--only",
                             "'" + item + "' is not KEY=VALUE[|VALUE] (keys: " + listed() + ")");
        const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
        const auto a = axis_of.find(key);
        if (a == axis_of.end()) {
            std::vector<std::string> all;
            for (const auto& [k, c] : axis_of) all.push_back(k);
            const std::string near = nearest_name(key, all);
            throw InputError("--only", "unknown key '" + key + "'" +
                                           (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                                           "; the keys are the rows' axes: " + listed());
        }
        const ColumnSpec& axis = *a->second;
        Want& w = want[axis.name];
        w.given += (w.given.empty() ? "" : ",") + item;
        if (const size_t dots = value.find(".."); dots != std::string::npos && axis.numeric()) {
            // KEY=LO..HI: both ends inclusive, either may be left out (not both).
            const std::string lo = value.substr(0, dots), hi = value.substr(dots + 2);
            const auto l = only_number(lo), h = only_number(hi);
            if ((lo.empty() && hi.empty()) || (!lo.empty() && !l) || (!hi.empty() && !h))
                throw InputError("--only", "'" + item + "': a range is " + key +
                                               "=LO..HI with numbers (either end may be left "
                                               "out, e.g. " +
                                               key + "=1.5..4)");
            if (l) w.lo = *l;
            if (h) w.hi = *h;
            continue;
        }
        if (const auto r = range_end.find(key); r != range_end.end()) {
            const auto v = only_number(value);
            if (!v) throw InputError("--only", "'" + item + "': " + key + " must be a number");
            (r->second < 0 ? w.lo : w.hi) = *v;
            continue;
        }
        std::stringstream vs(value);
        std::string v;
        while (std::getline(vs, v, '|')) {
            if (axis.numeric() && !only_number(v))
                throw InputError("--only",
                                 "'" + item + "': " + key + " takes numbers, not '" + v + "'");
            w.values.push_back(v);
        }
    }
    return want;
}

}  // namespace

void apply_only(Experiment& ex, const std::string& spec) {
    const std::map<std::string, Want> want = parse_only(spec);
    for (const auto& [name, w] : want) {
        const ColumnSpec& axis = *find_column(name);
        const auto text_ok = [&w](const std::string& v) { return w.text_ok(v); };
        const auto num_ok = [&w](double v) { return w.num_ok(v); };
        const auto sel = selectors().find(name);
        if (sel != selectors().end()) {
            if (!sel->second.apply)
                throw InputError(
                    "--only",
                    "'" + w.given + "': " + name +
                        " is an axis of the rows but not one to select by: " + sel->second.why_not);
            sel->second.apply(ex, w, text_ok, num_ok);
            continue;
        }
        // A camera's own key: the settings of the experiment's camera with a matching value.
        const CameraEntry& cam = camera_entry(ex.camera, "camera");
        const bool own = std::any_of(cam.keys.begin(), cam.keys.end(),
                                     [&](const CameraKey& k) { return k.name == name; });
        if (!own)
            throw InputError("--only", "'" + w.given + "': the experiment's camera '" + ex.camera +
                                           "' has no key " + name + " (its rows leave it empty)");
        if (!axis.numeric())
            throw InputError("--only", "'" + w.given + "': " + name + " cannot be selected");
        keep_camera_settings(ex, name, num_ok);
    }
}

std::string empty_axis_means(const std::string& axis) {
    if (axis == "base") return default_base_name();
    if (axis == "lod" || axis == "depth") return "base";
    if (axis == "camera") return "orthographic";
    return "";
}

OnlyRows::OnlyRows(const std::string& spec) {
    if (spec.empty()) return;
    for (auto& [name, w] : parse_only(spec)) {
        const ColumnSpec& axis = *find_column(name);
        if (axis.numeric())
            tests_.push_back([name, w](const ResultRow& r) { return w.num_ok(r.num(name)); });
        else
            tests_.push_back([name, w](const ResultRow& r) {
                const std::string& v = r.text(name);
                return w.text_ok(v.empty() ? empty_axis_means(name) : v);
            });
    }
}

bool OnlyRows::matches(const ResultRow& row) const {
    return std::all_of(tests_.begin(), tests_.end(), [&](const auto& t) { return t(row); });
}

}  // namespace pxh
