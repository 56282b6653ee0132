#include <algorithm>
#include <stdexcept>

#include "harness/core/error.h"
#include "harness/truth/tracer.h"

namespace pxh {

std::unique_ptr<Tracer> make_exact_tracer(const HeightField&, double scale, double bias);
std::unique_ptr<Tracer> make_embree_tracer(const HeightField&, double scale, double bias);

const std::vector<TracerEntry>& tracer_registry() {
    static const std::vector<TracerEntry> entries = {
        {"exact", &make_exact_tracer},
        {"embree", &make_embree_tracer},
    };
    return entries;
}

std::vector<std::string> tracer_names() {
    std::vector<std::string> out;
    for (const auto& e : tracer_registry()) out.push_back(e.name);
    return out;
}

void check_tracer_name(const std::string& name, const std::string& where) {
    const auto names = tracer_names();
    if (std::find(names.begin(), names.end(), name) != names.end()) return;
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    throw InputError(where, "unknown tracer '" + name + "' (known: " + known + ")");
}

std::unique_ptr<Tracer> make_tracer(const std::string& name, const HeightField& hf, double scale,
                                    double bias) {
    check_tracer_name(name, "tracer");
    for (const auto& e : tracer_registry())
        if (name == e.name) return e.make(hf, scale, bias);
    return nullptr;  // unreachable: checked above
}

bool Tracer::occluded(Vec2d, double, Vec3d) const {
    throw std::logic_error("the " + name() + " tracer has no true-shadow query");
}

}  // namespace pxh
