#include "harness/core/registry.h"

#include <algorithm>

#include "harness/backends/backend.h"

namespace pxh {

void read_cpu_settings(const ParamDict&, BackendSettings&);
std::unique_ptr<Backend> make_cpu_backend(const BackendSettings&);
std::vector<Variant> cpu_variants(const BackendSettings&);
void read_glsl_settings(const ParamDict&, BackendSettings&);
std::unique_ptr<Backend> make_glsl_backend(const BackendSettings&);
std::vector<Variant> glsl_variants(const BackendSettings&);

const std::vector<BackendEntry>& backend_registry() {
    static const std::vector<BackendEntry> entries = {
        {"cpu", &read_cpu_settings, &make_cpu_backend, &cpu_variants},
        {"glsl", &read_glsl_settings, &make_glsl_backend, &glsl_variants},
    };
    return entries;
}

std::vector<std::string> backend_names() { return entry_names(backend_registry()); }

void check_backend_name(const std::string& name, const std::string& where) {
    find_entry(backend_registry(), name, "backend", where);
}

void read_backend_settings(const ParamDict& experiment, BackendSettings& settings) {
    for (const auto& e : backend_registry()) e.read(experiment, settings);
}

std::unique_ptr<Backend> make_backend(const std::string& name, const BackendSettings& settings) {
    return find_entry(backend_registry(), name, "backend", "backend").make(settings);
}

std::vector<Variant> backend_variants(const std::string& name, const BackendSettings& settings) {
    return find_entry(backend_registry(), name, "backend", "backend").variants(settings);
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
