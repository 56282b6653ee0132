// Declared, checked parameters for methods and generators (an unknown or out-of-range key is
// an InputError naming the file and the key).
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pxh {

struct ParamSpec {
    std::string name;
    std::optional<double> default_value;  // nullopt: unset unless given
    double min = -1e300, max = 1e300;
    bool integer = false;
    std::string help;
};

// Resolved values in declaration order: given ones, then defaults.
class ParamValues {
  public:
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    double get(const std::string& name) const;
    int get_int(const std::string& name) const { return int(get(name)); }
    double get_or(const std::string& name, double fallback) const {
        return has(name) ? get(name) : fallback;
    }
    void set(const std::string& name, double v);
    // "a=1;b=2.5" in declaration order; "" when empty.
    std::string canonical() const;
    const std::vector<std::pair<std::string, double>>& items() const { return order_; }

  private:
    std::map<std::string, double> values_;
    std::vector<std::pair<std::string, double>> order_;
};

// Checks given values against specs and fills defaults. `where` names the file (and entry).
ParamValues resolve_params(const std::vector<ParamSpec>& specs,
                           const std::map<std::string, double>& given, const std::string& where,
                           const std::string& owner);

// "name (default 32, integer in [1, 4096]): help" for `pxh list`.
std::string describe_param(const ParamSpec& spec);

std::string format_number(double v);

}  // namespace pxh
