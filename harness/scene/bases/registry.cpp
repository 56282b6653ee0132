// The base surfaces' registry: one line per base (docs/conventions.md section 12).
#include "harness/core/registry.h"

#include <stdexcept>

#include "harness/scene/bases/bases.h"

namespace pxh {

const std::vector<BaseEntry>& base_registry() {
    static const std::vector<BaseEntry> entries = {
        {"plane", false, &make_plane_base},
        {"cylinder", true, &make_cylinder_base},
        {"sphere", true, &make_sphere_base},
    };
    return entries;
}

std::vector<std::string> base_names() { return entry_names(base_registry()); }

const BaseEntry* find_base(const std::string& name) {
    for (const BaseEntry& e : base_registry())
        if (name == e.name) return &e;
    return nullptr;
}

std::unique_ptr<BaseSurface> make_base(const std::string& name, double radius) {
    const BaseEntry* e = find_base(name);
    if (!e) throw std::invalid_argument("unknown base '" + name + "'");
    if (e->curved && !(std::isfinite(radius) && radius > 0))
        throw std::invalid_argument("base '" + name + "' needs a finite radius > 0");
    return e->make(radius);
}

}  // namespace pxh
