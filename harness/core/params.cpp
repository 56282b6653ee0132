#include "harness/core/params.h"

#include <cmath>
#include <sstream>

#include "harness/core/error.h"

namespace pxh {

std::string format_number(double v) {
    std::ostringstream os;
    os.precision(10);
    os << v;
    return os.str();
}

double ParamValues::get(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) throw std::logic_error("parameter not set: " + name);
    return it->second;
}

void ParamValues::set(const std::string& name, double v) {
    if (values_.count(name)) {
        for (auto& kv : order_)
            if (kv.first == name) kv.second = v;
    } else {
        // Keep declaration order: insert before the first parameter listed after this one.
        size_t listed = 0;
        while (listed < listed_.size() && listed_[listed].first != name) ++listed;
        if (listed == listed_.size()) listed_.emplace_back(name, "");
        listed_[listed].second.clear();
        size_t pos = 0;
        for (size_t k = 0; k < listed; ++k) pos += values_.count(listed_[k].first);
        order_.insert(order_.begin() + std::ptrdiff_t(pos), {name, v});
    }
    values_[name] = v;
}

void ParamValues::declare_unset(const std::string& name, const std::string& spelling) {
    if (values_.count(name)) throw std::logic_error("parameter already set: " + name);
    for (auto& kv : listed_)
        if (kv.first == name) {
            kv.second = spelling;
            return;
        }
    listed_.emplace_back(name, spelling);
}

std::string ParamValues::canonical() const {
    std::string out;
    for (const auto& [k, unset] : listed_) {
        if (!out.empty()) out += ';';
        out += k + "=" + (values_.count(k) ? format_number(values_.at(k)) : unset);
    }
    return out;
}

ParamValues resolve_params(const std::vector<ParamSpec>& specs,
                           const std::map<std::string, double>& given, const std::string& where,
                           const std::string& owner) {
    for (const auto& [key, value] : given) {
        bool known = false;
        for (const auto& s : specs) known |= (s.name == key);
        if (!known) {
            std::string names;
            for (const auto& s : specs) names += (names.empty() ? "" : ", ") + s.name;
            throw InputError(where, "unknown parameter '" + key + "' for " + owner +
                                        (names.empty() ? " (it takes none)"
                                                       : " (known: " + names + ")"));
        }
    }
    ParamValues out;
    for (const auto& s : specs) {
        auto it = given.find(s.name);
        if (it == given.end()) {
            if (s.default_value) out.set(s.name, *s.default_value);
            else out.declare_unset(s.name, s.unset_spelling.empty() ? "unset" : s.unset_spelling);
            continue;
        }
        const double v = it->second;
        if (!std::isfinite(v) || v < s.min || v > s.max)
            throw InputError(where, owner + " parameter '" + s.name + "' = " + format_number(v) +
                                        " is outside [" + format_number(s.min) + ", " +
                                        format_number(s.max) + "]");
        if (s.integer && v != std::floor(v))
            throw InputError(where, owner + " parameter '" + s.name + "' = " +
                                        format_number(v) + " must be an integer");
        out.set(s.name, v);
    }
    return out;
}

std::string describe_param(const ParamSpec& s) {
    std::ostringstream os;
    os << s.name << " (";
    if (s.default_value)
        os << "default " << format_number(*s.default_value);
    else
        os << "unset by default (params: " << s.name << "="
           << (s.unset_spelling.empty() ? "unset" : s.unset_spelling) << ")";
    os << ", " << (s.integer ? "integer" : "number") << " in [" << format_number(s.min) << ", "
       << format_number(s.max) << "]): " << s.help;
    return os.str();
}

}  // namespace pxh
