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
    // How `params` spells this parameter when it is neither given nor defaulted (an optional
    // parameter whose absence means something, e.g. "adaptive"); empty: "unset".
    std::string unset_spelling;
};

// Resolved values in declaration order: given ones, then defaults. A declared parameter left
// unset is listed too (declare_unset), so canonical() names every parameter of its owner.
class ParamValues {
  public:
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    double get(const std::string& name) const;
    int get_int(const std::string& name) const { return int(get(name)); }
    double get_or(const std::string& name, double fallback) const {
        return has(name) ? get(name) : fallback;
    }
    void set(const std::string& name, double v);
    // Records a declared parameter without a value: canonical() writes it as name=SPELLING
    // (a later set() gives it a value in the same place).
    void declare_unset(const std::string& name, const std::string& spelling);
    // "a=1;b=2.5;c=adaptive" in declaration order, every declared parameter, numbers as
    // format_number writes them; "" when there are none.
    std::string canonical() const;
    // The parameters that have a value, in declaration order.
    const std::vector<std::pair<std::string, double>>& items() const { return order_; }

  private:
    std::map<std::string, double> values_;
    std::vector<std::pair<std::string, double>> order_;
    // Every parameter in declaration order, with its spelling when unset ("" when set).
    std::vector<std::pair<std::string, std::string>> listed_;
};

// Checks given values against specs and fills defaults. `where` names the file (and entry).
ParamValues resolve_params(const std::vector<ParamSpec>& specs,
                           const std::map<std::string, double>& given, const std::string& where,
                           const std::string& owner);

// "name (default 32, integer in [1, 4096]): help" for `pxh list`.
std::string describe_param(const ParamSpec& spec);

std::string format_number(double v);

}  // namespace pxh
