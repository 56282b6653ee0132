#include "harness/core/registry.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "harness/backends/backend.h"

namespace pxh {

// THE list of backends, in registry order: one line X(NAME) each, for the file
// harness/backends/NAME_backend.cpp defining `const BackendEntry& NAME_backend_entry()` (its
// name, the reader of its keys, its factory, variants, timing and repeats).
#define PXH_BACKENDS(X) \
    X(cpu)              \
    X(glsl)

#define PXH_DECLARE_BACKEND(NAME) const BackendEntry& NAME##_backend_entry();
PXH_BACKENDS(PXH_DECLARE_BACKEND)
#undef PXH_DECLARE_BACKEND

const std::vector<BackendEntry>& backend_registry() {
#define PXH_LIST_BACKEND(NAME) NAME##_backend_entry(),
    static const std::vector<BackendEntry> entries = {PXH_BACKENDS(PXH_LIST_BACKEND)};
#undef PXH_LIST_BACKEND
    return entries;
}

std::vector<std::string> backend_names() { return entry_names(backend_registry()); }

const BackendEntry& backend_entry(const std::string& name) {
    return find_entry(backend_registry(), name, "backend", "backend");
}

void check_backend_name(const std::string& name, const std::string& where) {
    find_entry(backend_registry(), name, "backend", where);
}

void read_backend_settings(const ParamDict& experiment, BackendSettings& settings) {
    for (const auto& e : backend_registry()) e.read(experiment, settings);
}

std::unique_ptr<Backend> make_backend(const std::string& name, const BackendSettings& settings) {
    return find_entry(backend_registry(), name, "backend", "backend").make(settings);
}

std::unique_ptr<Backend> make_reference_backend(const BackendSettings& settings) {
    for (const auto& e : backend_registry())
        if (e.reference) return e.make(settings);
    throw std::logic_error("no reference backend is registered");
}

std::vector<Variant> backend_variants(const std::string& name, const BackendSettings& settings) {
    return find_entry(backend_registry(), name, "backend", "backend").variants(settings);
}

int backend_repeats(const std::string& name, const BackendSettings& settings) {
    return find_entry(backend_registry(), name, "backend", "backend").repeats(settings);
}

const TimingSpec& backend_timing(const std::string& name) {
    return find_entry(backend_registry(), name, "backend", "backend").timing();
}

std::string backend_skips(const std::string& name, const MethodSpec& m) {
    const BackendEntry& e = find_entry(backend_registry(), name, "backend", "backend");
    return e.skips ? e.skips(m) : std::string();
}

std::vector<CounterSpec> backend_counters() {
    std::vector<CounterSpec> out;
    for (const auto& e : backend_registry())
        for (const CounterSpec& c : e.timing().counters) out.push_back(c);
    return out;
}

nlohmann::json Backend::record(const BackendSettings& settings) const {
    const BackendEntry& e = backend_entry(name());
    const TimingSpec& t = e.timing();
    nlohmann::json counters = nlohmann::json::array();
    for (const CounterSpec& c : t.counters)
        counters.push_back({{"name", c.name}, {"unit", c.unit}, {"meaning", c.meaning}});
    nlohmann::json block = {{"timing",
                             {{"unit", t.unit},
                              {"measures", t.measures},
                              {"repeats", e.repeats(settings)},
                              {"counters", counters}}},
                            {"facts", facts()},
                            {"sources", sources()}};
    if (e.record) e.record(*this, settings, block);
    return block;
}

Timing timing_of(std::string unit, std::vector<double> repeats) {
    Timing t;
    if (repeats.empty()) return t;
    t.unit = std::move(unit);
    t.stats = spread(repeats);
    t.repeats = std::move(repeats);
    return t;
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
