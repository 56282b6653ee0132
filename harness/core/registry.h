// What every registry (backends, tracers, cameras) shares: a table of entries with a `name`,
// the names in table order, and a lookup whose miss is one line naming the known entries.
#pragma once
#include <string>
#include <vector>

#include "harness/core/error.h"

namespace pxh {

// "a, b, c": the known names in an error message.
inline std::string join_names(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

template <class Entry>
std::vector<std::string> entry_names(const std::vector<Entry>& entries) {
    std::vector<std::string> out;
    for (const auto& e : entries) out.push_back(e.name);
    return out;
}

// The entry called `name`; otherwise InputError(where, "unknown KIND 'name' (known: a, b)").
template <class Entry>
const Entry& find_entry(const std::vector<Entry>& entries, const std::string& name,
                        const std::string& kind, const std::string& where) {
    for (const auto& e : entries)
        if (name == e.name) return e;
    throw InputError(where, "unknown " + kind + " '" + name +
                                "' (known: " + join_names(entry_names(entries)) + ")");
}

}  // namespace pxh
