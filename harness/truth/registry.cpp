#include "harness/core/registry.h"

#include <algorithm>
#include <stdexcept>

#include "harness/truth/curved_tracer.h"
#include "harness/truth/tracer.h"

namespace pxh {

std::unique_ptr<Tracer> make_exact_tracer(const HeightField&, double scale, double bias);
std::unique_ptr<Tracer> make_embree_tracer(const HeightField&, double scale, double bias);

const std::vector<TracerEntry>& tracer_registry() {
    static const std::vector<TracerEntry> entries = {
        {"exact", &make_exact_tracer, TracerRole::exact_reference},
        {"embree", &make_embree_tracer, TracerRole::cross_check},
    };
    return entries;
}

std::vector<std::string> tracer_names() { return entry_names(tracer_registry()); }

void check_tracer_name(const std::string& name, const std::string& where) {
    find_entry(tracer_registry(), name, "tracer", where);
}

std::unique_ptr<Tracer> make_tracer(const std::string& name, const HeightField& hf, double scale,
                                    double bias) {
    return find_entry(tracer_registry(), name, "tracer", "tracer").make(hf, scale, bias);
}

std::unique_ptr<Tracer> make_tracer(TracerRole role, const HeightField& hf, double scale,
                                    double bias) {
    for (const TracerEntry& e : tracer_registry())
        if (e.role == role) return e.make(hf, scale, bias);
    throw std::logic_error("no tracer of this role is registered");
}

std::unique_ptr<CurvedTracer> make_curved_truth(const HeightField& hf, double scale, double bias,
                                                const BaseSurface& base) {
    return std::make_unique<CurvedTracer>(hf, scale, bias, base, 0.25, CurvedMethod::pyramid);
}

bool Tracer::occluded(Vec2d, double, Vec3d) const {
    throw std::logic_error("the " + name() + " tracer has no true-shadow query");
}

}  // namespace pxh
