// The one reader of pxh's TOML files (experiments, thresholds): a table of keys with typed
// getters and defaults, every value remembering its FILE:LINE, and every key remembering
// whether a consumer read it (pbrt-v4's ParameterDictionary is the model). Each component
// reads its own keys; report_unused() then makes a key nobody read an InputError naming its
// FILE:LINE, the key and the keys that were asked for. No list of allowed keys is kept
// anywhere else.
//
// Numbers: an integer read where a number is read becomes the nearest double (beyond 2^53 it
// is rounded, 2^53 + 1 reads as 2^53), as a float literal with as many digits would; an
// integer getter takes integers only, exactly, within its range.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/core/params.h"

namespace pxh {

class ParamDict {
  public:
    // An empty table: every getter gives its default (a component made without a file).
    ParamDict();
    // Parses `text` (the file `file`; a syntax error is "FILE:LINE: TOML syntax error: ...").
    // `context` names the table in messages ("the experiment", "[[limit]]").
    static ParamDict parse(const std::string& text, const std::string& file,
                           const std::string& context);

    const std::string& file() const;
    const std::string& context() const;
    // FILE:LINE of this table (FILE when the line is unknown).
    std::string where() const;
    // FILE:LINE of the key's value (where() when it has no line or is absent).
    std::string where(const std::string& key) const;
    // Whether the key is there; the key counts as asked for (one this consumer accepts) but
    // stays unread: read it with a getter, elements() or table() before report_unused().
    bool has(const std::string& key) const;
    // The keys in the table's order (asks for none).
    std::vector<std::string> keys() const;

    // Typed getters: an absent key gives the default (or nullopt); a present one is read
    // (marked), and a value of the wrong type is an InputError at its FILE:LINE.
    std::optional<double> number(const std::string& key) const;  // "'KEY' must be a number"
    double number(const std::string& key, double def) const;
    // "'KEY' must be an integer", "'KEY' = V is outside [LO, HI]"
    std::optional<int> integer(const std::string& key, int lo, int hi) const;
    int integer(const std::string& key, int def, int lo, int hi) const;
    std::optional<std::string> string(const std::string& key) const;  // "'KEY' must be a string"
    std::string string(const std::string& key, const std::string& def) const;
    std::optional<bool> boolean(const std::string& key) const;  // "'KEY' must be true or false"
    bool boolean(const std::string& key, bool def) const;
    // A value or a non-empty list of them ("'KEY' is an empty list").
    std::vector<double> numbers(const std::string& key, const std::vector<double>& def) const;
    std::vector<std::string> strings(const std::string& key,
                                     const std::vector<std::string>& def) const;
    // Angles: a list, or { from, to, step } (inclusive of `to` within rounding).
    std::vector<double> angles(const std::string& key, const std::vector<double>& def) const;

    // A value or each element of a list, as it is written, with its FILE:LINE: what a typed
    // parameter (ParamSpec) or a filter checks itself. `value` is empty for an element that is
    // no number, bool or string (a table, a date, a nested list); `integer` tells an integer
    // from a float. An empty list is "'KEY' is an empty list"; an absent key gives no values.
    struct Element {
        std::optional<ParamValue> value;
        bool integer = false;
        std::string where;
    };
    std::vector<Element> elements(const std::string& key) const;
    // Whether the value is a list (asks for the key, reads nothing).
    bool is_list(const std::string& key) const;

    // The sub-table KEY ([KEY] or KEY = { ... }): nullopt when absent; a value that is no
    // table is an InputError at its line (`not_table`, default "'KEY' must be a table").
    // Its keys are tracked by the sub-table's own report_unused().
    std::optional<ParamDict> table(const std::string& key, const std::string& context,
                                   const std::string& not_table = "") const;
    // [[KEY]]: a non-empty list of tables ("no [[KEY]] entries", "'KEY' must be a list of
    // tables ([[KEY]])").
    std::vector<ParamDict> tables(const std::string& key, const std::string& context) const;

    // The keys asked for so far (read or tested with has()), in the order first asked.
    std::vector<std::string> asked() const;
    // A key nobody read: InputError at its FILE:LINE, by default "unknown key 'KEY' in
    // CONTEXT (known: the keys asked for)"; `message(key, known)` words it otherwise.
    using UnusedMessage =
        std::function<std::string(const std::string& key, const std::string& known)>;
    void report_unused(const UnusedMessage& message = {}) const;

    struct Table;  // the table, its file and what was read (param_dict.cpp)

  private:
    explicit ParamDict(std::shared_ptr<Table> t);
    std::shared_ptr<Table> t_;
};

}  // namespace pxh
