// What every registry (backends, tracers, cameras) shares: a table of entries with a `name`,
// the names in table order, and a lookup whose miss is one line naming the known entries.
#pragma once
#include <algorithm>
#include <cctype>
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

// The name nearest to `name` among `known` (case-insensitive edit distance, at most a third of
// its length and at least 1), "" when none is that near.
inline std::string nearest_name(const std::string& name, const std::vector<std::string>& known) {
    const auto lower = [](char c) { return char(std::tolower(static_cast<unsigned char>(c))); };
    std::string best;
    size_t best_d = std::max<size_t>(1, name.size() / 3) + 1;
    for (const std::string& k : known) {
        std::vector<size_t> prev(k.size() + 1), cur(k.size() + 1);
        for (size_t j = 0; j <= k.size(); ++j) prev[j] = j;
        for (size_t i = 1; i <= name.size(); ++i) {
            cur[0] = i;
            for (size_t j = 1; j <= k.size(); ++j)
                cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1,
                                   prev[j - 1] + (lower(name[i - 1]) != lower(k[j - 1]) ? 1 : 0)});
            std::swap(prev, cur);
        }
        if (prev[k.size()] < best_d) best_d = prev[k.size()], best = k;
    }
    return best;
}

// " (did you mean 'pom'?)" for the nearest known name, "" when none is near.
inline std::string did_you_mean(const std::string& name, const std::vector<std::string>& known) {
    const std::string n = nearest_name(name, known);
    return n.empty() || n == name ? "" : " (did you mean '" + n + "'?)";
}

// "a, b, c" split back into names.
inline std::vector<std::string> split_names(const std::string& joined) {
    std::vector<std::string> out;
    size_t at = 0;
    while (at <= joined.size()) {
        size_t end = joined.find(", ", at);
        if (end == std::string::npos) end = joined.size();
        if (end > at) out.push_back(joined.substr(at, end - at));
        at = end + 2;
    }
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
    throw InputError(where, "unknown " + kind + " '" + name + "'" +
                                did_you_mean(name, entry_names(entries)) +
                                " (known: " + join_names(entry_names(entries)) + ")");
}

}  // namespace pxh
