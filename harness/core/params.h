// Declared, checked, typed parameters for methods and generators (an unknown key, a value of
// the wrong type, an unknown name or an out-of-range number is an InputError naming the file,
// the key and what is accepted).
//
// Types: real (a number), integer, bool, choice (one of a fixed set of names). A real or
// integer parameter may also accept a few names in place of a number (layers = "adaptive",
// max_offset = "scale": a mode that is not a number). A parameter that reaches the shader
// names its GLSL uniform (ParamSpec::uniform); its GLSL type follows from its type (real:
// float, integer: int, bool: bool, choice: int = the index of the name in `names`).
#pragma once
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pxh {

enum class ParamType { Real, Integer, Bool, Choice };

// One value: a number (real or integer parameters), a bool, or a name (a choice, or a name a
// number parameter accepts in place of a number).
class ParamValue {
  public:
    enum class Kind { Number, Bool, Name };
    ParamValue() = default;
    ParamValue(double v) : kind_(Kind::Number), number_(v) {}
    ParamValue(int v) : kind_(Kind::Number), number_(v) {}
    ParamValue(long long v) : kind_(Kind::Number), number_(double(v)) {}
    ParamValue(bool v) : kind_(Kind::Bool), number_(v ? 1 : 0) {}
    ParamValue(const char* name) : kind_(Kind::Name), name_(name) {}
    ParamValue(std::string name) : kind_(Kind::Name), name_(std::move(name)) {}
    Kind kind() const { return kind_; }
    bool is_number() const { return kind_ == Kind::Number; }
    bool is_bool() const { return kind_ == Kind::Bool; }
    bool is_name() const { return kind_ == Kind::Name; }
    double number() const;            // throws std::logic_error unless is_number()
    bool boolean() const;             // throws std::logic_error unless is_bool()
    const std::string& name() const;  // throws std::logic_error unless is_name()
    // As `params` writes it: numbers as format_number, true/false, the name as is.
    std::string spelled() const;
    // "a number", "a bool", "a string" (for messages).
    std::string kind_name() const;
    bool operator==(const ParamValue& o) const = default;

  private:
    Kind kind_ = Kind::Number;
    double number_ = 0;
    std::string name_;
};

struct ParamSpec {
    std::string name;
    ParamType type = ParamType::Real;
    std::optional<ParamValue> default_value;  // nullopt: unset unless given (or completed)
    double min = -1e300, max = 1e300;         // real, integer
    // choice: the accepted names, in order (the uniform gets the index); real/integer: names
    // accepted in place of a number (e.g. "adaptive").
    std::vector<std::string> names;
    std::string help;
    // How `params` spells this parameter when it is neither given nor defaulted (an optional
    // parameter whose absence means something, e.g. "adaptive"); empty: "unset".
    std::string unset_spelling;
    // The GLSL uniform that receives the value (set by the backend with the call for its
    // type); empty: the parameter does not reach the shader directly.
    std::string uniform;

    ParamSpec() = default;
    // A number (integer = true: an integer), as generators declare them.
    ParamSpec(std::string name_, std::optional<double> default_, double min_, double max_,
              bool integer, std::string help_, std::string unset_spelling_ = "");

    static ParamSpec real(std::string name, std::optional<double> def, double lo, double hi,
                          std::string help);
    static ParamSpec integer(std::string name, std::optional<double> def, double lo, double hi,
                             std::string help);
    static ParamSpec boolean(std::string name, bool def, std::string help);
    static ParamSpec choice(std::string name, std::vector<std::string> names,
                            std::optional<std::string> def, std::string help);
    // Chained modifiers.
    ParamSpec& to_uniform(std::string u) {
        uniform = std::move(u);
        return *this;
    }
    ParamSpec& or_names(std::vector<std::string> n) {
        names = std::move(n);
        return *this;
    }
    ParamSpec& unset_as(std::string s) {
        unset_spelling = std::move(s);
        return *this;
    }
    ParamSpec& defaults_to(ParamValue v) {
        default_value = std::move(v);
        return *this;
    }

    // "real", "integer", "bool", "choice".
    std::string type_name() const;
    // What the parameter accepts, for messages: "a number in [1, 4096] or \"adaptive\"".
    std::string accepted() const;
    // "" when v has an acceptable kind and value for this parameter, else the problem
    // ("must be ..."; "'x' is not one of ...").
    std::string problem(const ParamValue& v) const;
};

// Values given for parameters (from an experiment file or code). Brace lists of numbers,
// bools and names, and maps of numbers, convert.
struct GivenParams : std::map<std::string, ParamValue> {
    using std::map<std::string, ParamValue>::map;
    GivenParams() = default;
    GivenParams(const std::map<std::string, double>& numbers) {
        for (const auto& [k, v] : numbers) emplace(k, ParamValue(v));
    }
};

// Resolved values in declaration order: given ones, then defaults. A declared parameter left
// unset is listed too (declare_unset), so canonical() names every parameter of its owner.
class ParamValues {
  public:
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    const ParamValue& value(const std::string& name) const;  // logic_error when unset
    double get(const std::string& name) const { return value(name).number(); }
    int get_int(const std::string& name) const { return int(get(name)); }
    bool get_bool(const std::string& name) const { return value(name).boolean(); }
    const std::string& get_name(const std::string& name) const { return value(name).name(); }
    double get_or(const std::string& name, double fallback) const {
        return has(name) ? get(name) : fallback;
    }
    // Has a number (not unset, not a name).
    bool is_number(const std::string& name) const { return has(name) && value(name).is_number(); }
    // Holds the name `what` (a choice, or a name in place of a number).
    bool is_name(const std::string& name, const std::string& what) const {
        return has(name) && value(name).is_name() && value(name).name() == what;
    }
    void set(const std::string& name, ParamValue v);
    // Records a declared parameter without a value: canonical() writes it as name=SPELLING
    // (a later set() gives it a value in the same place).
    void declare_unset(const std::string& name, const std::string& spelling);
    // "a=1;b=2.5;c=adaptive" in declaration order, every declared parameter, numbers as
    // format_number writes them, bools as true/false, names as they are; "" when none.
    std::string canonical() const;
    // The parameters that have a value, in declaration order.
    const std::vector<std::pair<std::string, ParamValue>>& items() const { return order_; }

  private:
    std::map<std::string, ParamValue> values_;
    std::vector<std::pair<std::string, ParamValue>> order_;
    // Every parameter in declaration order, with its spelling when unset ("" when set).
    std::vector<std::pair<std::string, std::string>> listed_;
};

// Checks given values against specs and fills defaults. `where` names the file (and entry).
ParamValues resolve_params(const std::vector<ParamSpec>& specs, const GivenParams& given,
                           const std::string& where, const std::string& owner);

// "owner parameter 'key' = VALUE: must be ... (accepted: ...)" as one InputError at `where`
// unless v is acceptable for spec (type and names only; ranges are checked by resolve_params).
void check_param_kind(const ParamSpec& spec, const ParamValue& v, const std::string& where,
                      const std::string& owner);

// "name (default 32, integer in [1, 4096]): help" for `pxh list`.
std::string describe_param(const ParamSpec& spec);

std::string format_number(double v);
// The whole text as a number (decimal or scientific notation, inf, -inf, nan; no spaces, no
// hexadecimal); nullopt otherwise, and for an empty text.
std::optional<double> parse_number(const std::string& text);

}  // namespace pxh
