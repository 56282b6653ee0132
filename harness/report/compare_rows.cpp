// pxh compare's row identity: the keys that match a row across runs, a key made of a row and
// its name read back from it, and how two runs' keys differ when no row matches; the number
// formats of the report.
#include <algorithm>
#include <cstdio>

#include "harness/metrics/columns.h"
#include "harness/report/compare_parts.h"
#include "harness/results/results.h"
#include "harness/scene/view.h"

namespace pxh::compare_detail {
namespace {

size_t key_index(const std::string& c) {
    return size_t(std::find(keys().begin(), keys().end(), c) - keys().begin());
}

// The key's fields, in keys() order.
std::vector<std::string> fields_of_key(const std::string& key) {
    std::vector<std::string> f;
    size_t at = 0;
    for (size_t end; (end = key.find('\x1f', at)) != std::string::npos; at = end + 1)
        f.push_back(key.substr(at, end - at));
    return f;
}

std::string listed(const std::set<std::string>& v) {
    std::string s;
    size_t n = 0;
    for (const std::string& x : v) {
        if (n++ == 4) return s + ", ...";
        s += (s.empty() ? "" : ", ") + (x.empty() ? std::string("(empty)") : x);
    }
    return s.empty() ? "(no rows)" : s;
}

}  // namespace

const std::vector<std::string>& keys() {
    static const std::vector<std::string> k = [] {
        std::vector<std::string> all;
        for (const ColumnSpec* c : row_axes())
            if (c->name != "ground_truth") all.push_back(c->name);
        return all;
    }();
    return k;
}

std::string key_cell(const ResultRow& r, const std::string& c) {
    std::string v = r.cell(c);
    if (!v.empty()) return v;
    if (c == "camera") return "orthographic";
    if (c == "lod" || c == "depth") return "base";
    for (const CameraEntry& e : camera_registry())
        for (const CameraKey& k : e.keys)
            if (k.name == c && !k.default_column.empty() && r.text("camera") == e.name)
                return r.cell(k.default_column);
    return v;
}

std::string key_of(const ResultRow& r) {
    std::string k;
    for (const std::string& c : keys()) k += key_cell(r, c) + '\x1f';
    return k;
}

std::string sig(double v) {
    if (std::isnan(v)) return "-";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}
std::string signed_sig(double v) {
    if (!std::isfinite(v)) return "-";
    return (v > 0 ? "+" : "") + sig(v);
}

std::string name_of_key(const std::string& key) {
    const std::vector<std::string> f = fields_of_key(key);
    if (f.size() != keys().size()) return key;
    return row_name([&](const std::string& c) {
        const size_t i = key_index(c);
        return i < f.size() ? f[i] : std::string();
    });
}

std::vector<std::string> varying_context(const KeyValues& v) {
    std::vector<std::string> out;
    for (size_t i = 0; i < keys().size(); ++i) {
        if (v.values[i].size() < 2) continue;
        for (const ColumnSpec* axis : row_axes())
            if (axis->name == keys()[i] && context_key(*axis)) out.push_back(keys()[i]);
    }
    return out;
}

std::string key_differences(const KeyValues& b, const KeyValues& n) {
    std::string s;
    for (size_t i = 0; i < keys().size(); ++i) {
        if (b.values[i] == n.values[i]) continue;
        s += (s.empty() ? "" : "; ") + keys()[i] + " " + listed(b.values[i]) + " vs " +
             listed(n.values[i]);
    }
    return s.empty() ? "no key's values (each run's rows combine them differently)" : s;
}

}  // namespace pxh::compare_detail
