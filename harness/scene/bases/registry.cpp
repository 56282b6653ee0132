// The base surfaces' registry: one line per base (docs/conventions.md section 12).
#include "harness/core/registry.h"

#include <algorithm>
#include <stdexcept>

#include "harness/core/param_dict.h"
#include "harness/core/params.h"
#include "harness/scene/bases/bases.h"
#include "harness/scene/curved_view.h"

namespace pxh {

std::unique_ptr<BaseSurface> make_plane_base(double radius);
std::unique_ptr<BaseSurface> make_cylinder_base(double radius);
std::unique_ptr<BaseSurface> make_sphere_base(double radius);

namespace {

// A base without keys: one setting.
std::vector<double> read_no_keys(const ParamDict&, const std::string&) { return {NAN}; }

// A curved base's `radius` (tiles), a value or a list: one setting per radius.
std::vector<double> read_radius(const ParamDict& t, const std::string& name) {
    if (!t.has("radius"))
        throw InputError(t.where("base"), "base '" + name + "' needs a radius (tiles)");
    const std::vector<double> radii = t.numbers("radius", {});
    for (double r : radii)
        if (const std::string why = radius_problem(name, r); !why.empty())
            throw InputError(t.where("radius"), why);
    return radii;
}

std::vector<BaseEntry>& entries() {
    static std::vector<BaseEntry> e = {
        {"plane", false, &make_plane_base, &read_no_keys, &flat_view, "exact"},
        {"cylinder", true, &make_cylinder_base, &read_radius, &curved_view, "curved_walk"},
        {"sphere", true, &make_sphere_base, &read_radius, &curved_view, "curved_walk"},
    };
    return e;
}

}  // namespace

const std::vector<BaseEntry>& base_registry() { return entries(); }

std::vector<std::string> base_names() { return entry_names(base_registry()); }

std::string default_base_name() { return base_registry().front().name; }

const BaseEntry* find_base(const std::string& name) {
    for (const BaseEntry& e : base_registry())
        if (name == e.name) return &e;
    return nullptr;
}

const BaseEntry& base_entry(const std::string& name, const std::string& where) {
    return find_entry(base_registry(), name, "base", where);
}

std::string radius_problem(const std::string& name, double radius, double scale, double bias) {
    if (!(radius > 0) || !std::isfinite(radius))
        return "radius must be a finite number > 0 (got " + format_number(radius) + ")";
    if (!(radius > scale * bias))  // the relief's bottom shell has radius R - s b
        return "radius = " + format_number(radius) + " on base '" + name +
               "' must exceed scale * bias = " + format_number(scale * bias) +
               " (the relief would reach the axis)";
    return "";
}

std::unique_ptr<BaseSurface> make_base(const std::string& name, double radius) {
    const BaseEntry* e = find_base(name);
    if (!e) throw std::invalid_argument("unknown base '" + name + "'");
    if (e->curved)
        if (const std::string why = radius_problem(name, radius); !why.empty())
            throw std::invalid_argument("base '" + name + "': " + why);
    return e->make(radius);
}

BaseRegistration::BaseRegistration(BaseEntry entry) : name_(entry.name) {
    if (find_base(name_)) throw std::logic_error("base '" + name_ + "' is registered twice");
    entries().push_back(entry);
}

BaseRegistration::~BaseRegistration() {
    auto& e = entries();
    e.erase(std::remove_if(e.begin(), e.end(), [&](const BaseEntry& b) { return name_ == b.name; }),
            e.end());
}

}  // namespace pxh
