#include <algorithm>

#include "harness/backends/backend.h"
#include "harness/core/error.h"

namespace pxh {

std::unique_ptr<Backend> make_cpu_backend(const BackendSettings&);
std::unique_ptr<Backend> make_glsl_backend(const BackendSettings&);

const std::vector<BackendEntry>& backend_registry() {
    static const std::vector<BackendEntry> entries = {
        {"cpu", &make_cpu_backend},
        {"glsl", &make_glsl_backend},
    };
    return entries;
}

std::vector<std::string> backend_names() {
    std::vector<std::string> out;
    for (const auto& e : backend_registry()) out.push_back(e.name);
    return out;
}

void check_backend_name(const std::string& name, const std::string& where) {
    const auto names = backend_names();
    if (std::find(names.begin(), names.end(), name) != names.end()) return;
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    throw InputError(where, "unknown backend '" + name + "' (known: " + known + ")");
}

std::unique_ptr<Backend> make_backend(const std::string& name, const BackendSettings& settings) {
    check_backend_name(name, "backend");
    for (const auto& e : backend_registry())
        if (name == e.name) return e.make(settings);
    return nullptr;  // unreachable: checked above
}

Spread spread(std::vector<double> times) {
    Spread s;
    if (times.empty()) return s;
    std::sort(times.begin(), times.end());
    const size_t m = times.size();
    s.median = m % 2 ? times[m / 2] : 0.5 * (times[m / 2 - 1] + times[m / 2]);
    s.min = times.front();
    s.max = times.back();
    return s;
}

}  // namespace pxh
