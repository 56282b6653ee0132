#include "harness/core/params.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "harness/core/error.h"
#include "harness/core/registry.h"

namespace pxh {

std::string format_number(double v) {
    std::ostringstream os;
    os.precision(10);
    os << v;
    return os.str();
}

// ---- ParamValue ----

double ParamValue::number() const {
    if (kind_ != Kind::Number)
        throw std::logic_error("parameter value is not a number: " + spelled());
    return number_;
}

bool ParamValue::boolean() const {
    if (kind_ != Kind::Bool) throw std::logic_error("parameter value is not a bool: " + spelled());
    return number_ != 0;
}

const std::string& ParamValue::name() const {
    if (kind_ != Kind::Name) throw std::logic_error("parameter value is not a name: " + spelled());
    return name_;
}

std::string ParamValue::spelled() const {
    switch (kind_) {
        case Kind::Number:
            return format_number(number_);
        case Kind::Bool:
            return number_ != 0 ? "true" : "false";
        case Kind::Name:
            return name_;
    }
    return "";
}

std::string ParamValue::kind_name() const {
    switch (kind_) {
        case Kind::Number:
            return "a number";
        case Kind::Bool:
            return "a bool";
        case Kind::Name:
            return "a string";
    }
    return "";
}

// ---- ParamSpec ----

ParamSpec::ParamSpec(std::string name_, std::optional<double> default_, double min_, double max_,
                     bool integer_, std::string help_, std::string unset_spelling_)
    : name(std::move(name_)),
      type(integer_ ? ParamType::Integer : ParamType::Real),
      min(min_),
      max(max_),
      help(std::move(help_)),
      unset_spelling(std::move(unset_spelling_)) {
    if (default_) default_value = ParamValue(*default_);
}

ParamSpec ParamSpec::real(std::string name, std::optional<double> def, double lo, double hi,
                          std::string help) {
    return ParamSpec(std::move(name), def, lo, hi, false, std::move(help));
}

ParamSpec ParamSpec::integer(std::string name, std::optional<double> def, double lo, double hi,
                             std::string help) {
    return ParamSpec(std::move(name), def, lo, hi, true, std::move(help));
}

ParamSpec ParamSpec::boolean(std::string name, bool def, std::string help) {
    ParamSpec s;
    s.name = std::move(name);
    s.type = ParamType::Bool;
    s.default_value = ParamValue(def);
    s.help = std::move(help);
    return s;
}

ParamSpec ParamSpec::choice(std::string name, std::vector<std::string> names,
                            std::optional<std::string> def, std::string help) {
    ParamSpec s;
    s.name = std::move(name);
    s.type = ParamType::Choice;
    s.names = std::move(names);
    if (def) {
        if (std::find(s.names.begin(), s.names.end(), *def) == s.names.end())
            throw std::logic_error("choice parameter '" + s.name + "': default '" + *def +
                                   "' is not one of its names");
        s.default_value = ParamValue(*def);
    }
    s.help = std::move(help);
    return s;
}

std::string ParamSpec::type_name() const {
    switch (type) {
        case ParamType::Real:
            return "real";
        case ParamType::Integer:
            return "integer";
        case ParamType::Bool:
            return "bool";
        case ParamType::Choice:
            return "choice";
    }
    return "";
}

namespace {

std::string quoted_names(const std::vector<std::string>& names, const char* last) {
    std::string out;
    for (size_t k = 0; k < names.size(); ++k) {
        if (k) out += k + 1 == names.size() ? last : ", ";
        out += "\"" + names[k] + "\"";
    }
    return out;
}

}  // namespace

std::string ParamSpec::accepted() const {
    switch (type) {
        case ParamType::Bool:
            return "true or false";
        case ParamType::Choice:
            return "one of " + quoted_names(names, ", ");
        case ParamType::Real:
        case ParamType::Integer: {
            std::string out = std::string(type == ParamType::Integer ? "an integer" : "a number") +
                              " in [" + format_number(min) + ", " + format_number(max) + "]";
            if (!names.empty()) out += " or " + quoted_names(names, " or ");
            return out;
        }
    }
    return "";
}

std::string ParamSpec::problem(const ParamValue& v) const {
    const bool named =
        v.is_name() && std::find(names.begin(), names.end(), v.name()) != names.end();
    bool ok = false;
    switch (type) {
        case ParamType::Real:
        case ParamType::Integer:
            ok = v.is_number() || named;
            break;
        case ParamType::Bool:
            ok = v.is_bool();
            break;
        case ParamType::Choice:
            ok = named;
            break;
    }
    if (ok) return "";
    return "must be " + accepted() + " (got " + v.kind_name() + ")";
}

// ---- ParamValues ----

const ParamValue& ParamValues::value(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) throw std::logic_error("parameter not set: " + name);
    return it->second;
}

void ParamValues::set(const std::string& name, ParamValue v) {
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
    values_[name] = std::move(v);
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
        out += k + "=" + (values_.count(k) ? values_.at(k).spelled() : unset);
    }
    return out;
}

// ---- resolving ----

void check_param_kind(const ParamSpec& spec, const ParamValue& v, const std::string& where,
                      const std::string& owner) {
    const std::string why = spec.problem(v);
    if (why.empty()) return;
    const std::string shown = v.is_name() ? "\"" + v.name() + "\"" : v.spelled();
    throw InputError(where, owner + " parameter '" + spec.name + "' = " + shown + " " + why);
}

ParamValues resolve_params(const std::vector<ParamSpec>& specs, const GivenParams& given,
                           const std::string& where, const std::string& owner) {
    for (const auto& [key, value] : given) {
        bool known = false;
        for (const auto& s : specs) known |= (s.name == key);
        if (!known) {
            std::string names;
            std::vector<std::string> all;
            for (const auto& s : specs) {
                names += (names.empty() ? "" : ", ") + s.name;
                all.push_back(s.name);
            }
            throw InputError(where,
                             "unknown parameter '" + key + "'" + did_you_mean(key, all) + " for " +
                                 owner +
                                 (names.empty() ? " (it takes none)" : " (known: " + names + ")"));
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
        const ParamValue& v = it->second;
        check_param_kind(s, v, where, owner);
        if (v.is_number()) {
            const double x = v.number();
            if (!std::isfinite(x) || x < s.min || x > s.max)
                throw InputError(where, owner + " parameter '" + s.name +
                                            "' = " + format_number(x) + " is outside [" +
                                            format_number(s.min) + ", " + format_number(s.max) +
                                            "]");
            if (s.type == ParamType::Integer && x != std::floor(x))
                throw InputError(where, owner + " parameter '" + s.name +
                                            "' = " + format_number(x) + " must be an integer");
        }
        out.set(s.name, v);
    }
    return out;
}

std::string describe_param(const ParamSpec& s) {
    std::ostringstream os;
    os << s.name << " (";
    if (s.default_value) os << "default " << s.default_value->spelled();
    else
        os << "unset by default (params: " << s.name << "="
           << (s.unset_spelling.empty() ? "unset" : s.unset_spelling) << ")";
    switch (s.type) {
        case ParamType::Real:
        case ParamType::Integer:
            os << ", " << (s.type == ParamType::Integer ? "integer" : "number") << " in ["
               << format_number(s.min) << ", " << format_number(s.max) << "]";
            if (!s.names.empty()) os << " or " << quoted_names(s.names, " or ");
            break;
        case ParamType::Bool:
            os << ", bool";
            break;
        case ParamType::Choice:
            os << ", one of " << quoted_names(s.names, ", ");
            break;
    }
    os << "): " << s.help;
    return os.str();
}

std::optional<double> parse_number(const std::string& text) {
    double v = 0;
    const char* end = text.data() + text.size();
    // from_chars: no leading spaces or '+', no hexadecimal in the general format.
    const auto [ptr, ec] = std::from_chars(text.data(), end, v, std::chars_format::general);
    if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
    return v;
}

}  // namespace pxh
