#include <algorithm>
#include <stdexcept>

#include "methods/method.h"

namespace pxh {

static std::vector<MethodInfo>& registry() {
    static std::vector<MethodInfo> methods;
    return methods;
}

bool register_method(MethodInfo info) {
    auto& r = registry();
    for (const auto& m : r)
        if (m.name == info.name) throw std::logic_error("method registered twice: " + info.name);
    r.push_back(std::move(info));
    std::stable_sort(r.begin(), r.end(), [](const MethodInfo& a, const MethodInfo& b) {
        return a.order != b.order ? a.order < b.order : a.name < b.name;
    });
    return true;
}

const std::vector<MethodInfo>& all_methods() { return registry(); }

const MethodInfo* find_method(const std::string& name) {
    for (const auto& m : registry())
        if (m.name == name) return &m;
    return nullptr;
}

}  // namespace pxh
