// pxh run --only KEY=V[|V...],...: the experiment narrowed to the matching entries, views and
// backends.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"

namespace pxh {

void apply_only(Experiment& ex, const std::string& spec) {
    std::map<std::string, std::vector<std::string>> want;
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const auto eq = item.find('=');
        const std::string key = item.substr(0, eq);
        static const std::set<std::string> keys = {"method",  "heightfield", "backend", "theta_deg",
                                                   "phi_deg", "scale",       "bias"};
        if (eq == std::string::npos || eq + 1 == item.size() || !keys.count(key))
            throw InputError("--only", "'" + item +
                                           "' is not KEY=VALUE[|VALUE] with KEY one of method, "
                                           "heightfield, backend, theta_deg, phi_deg, scale, bias");
        std::stringstream vs(item.substr(eq + 1));
        std::string v;
        while (std::getline(vs, v, '|')) want[key].push_back(v);
    }
    auto text_ok = [&](const char* key, const std::string& v) {
        const auto it = want.find(key);
        return it == want.end() ||
               std::find(it->second.begin(), it->second.end(), v) != it->second.end();
    };
    auto num_ok = [&](const char* key, double v) {
        const auto it = want.find(key);
        if (it == want.end()) return true;
        for (const auto& w : it->second) {
            char* end = nullptr;
            const double d = std::strtod(w.c_str(), &end);
            if (end && *end == '\0' && !w.empty() &&
                std::abs(d - v) <= 1e-9 * std::max(1.0, std::abs(v)))
                return true;
        }
        return false;
    };
    auto keep = [](auto& list, auto pred, const char* what, auto name_of) {
        std::string known;
        std::remove_reference_t<decltype(list)> kept;
        for (const auto& x : list) {
            const std::string n = name_of(x);
            if (known.find(n) == std::string::npos) known += (known.empty() ? "" : ", ") + n;
            if (pred(x)) kept.push_back(x);
        }
        if (kept.empty())
            throw InputError("--only", std::string("no ") + what +
                                           " matches (the experiment has: " + known + ")");
        list = std::move(kept);
    };
    keep(
        ex.methods, [&](const MethodSpec& m) { return text_ok("method", m.method->name); },
        "method", [](const MethodSpec& m) { return m.method->name; });
    keep(
        ex.heightfields,
        [&](const HeightfieldSpec& h) {
            return text_ok("heightfield", h.name) && num_ok("scale", h.scale) &&
                   num_ok("bias", h.bias);
        },
        "heightfield",
        [](const HeightfieldSpec& h) {
            return h.name + " (s=" + format_number(h.scale) + " b=" + format_number(h.bias) + ")";
        });
    keep(
        ex.theta_deg, [&](double t) { return num_ok("theta_deg", t); }, "theta_deg",
        [](double t) { return format_number(t); });
    keep(
        ex.phi_deg, [&](double p) { return num_ok("phi_deg", p); }, "phi_deg",
        [](double p) { return format_number(p); });
    keep(
        ex.backends, [&](const std::string& b) { return text_ok("backend", b); }, "backend",
        [](const std::string& b) { return b; });
}

}  // namespace pxh
