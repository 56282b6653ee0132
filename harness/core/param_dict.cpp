#include "harness/core/param_dict.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <set>

#include "harness/core/error.h"
#include "harness/core/registry.h"

namespace pxh {

struct ParamDict::Table {
    std::shared_ptr<const toml::table> doc;  // keeps the parsed file alive
    const toml::table* t = nullptr;
    std::string file, context, where;
    std::mutex m;  // a component may read its keys again later, from any thread
    std::set<std::string> read;
    std::vector<std::string> asked;

    // The key's node (nullptr when absent); asks for it, and reads it when `mark`.
    const toml::node* get(const std::string& key, bool mark) {
        std::lock_guard<std::mutex> lock(m);
        if (std::find(asked.begin(), asked.end(), key) == asked.end()) asked.push_back(key);
        const toml::node* n = t ? t->get(key) : nullptr;
        if (n && mark) read.insert(key);
        return n;
    }
    std::string where_of(const toml::node& n) const {
        const auto line = n.source().begin.line;
        return line ? file + ":" + std::to_string(line) : where;
    }
};

namespace {

std::shared_ptr<ParamDict::Table> make_table(std::shared_ptr<const toml::table> doc,
                                             const toml::table* t, std::string file,
                                             std::string context, std::string where) {
    auto tab = std::make_shared<ParamDict::Table>();
    tab->doc = std::move(doc);
    tab->t = t;
    tab->file = std::move(file);
    tab->context = std::move(context);
    tab->where = std::move(where);
    return tab;
}

// The one rule for numbers: integers to the nearest double, floats as written.
std::optional<double> number_of(const toml::node& n) {
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    if (const auto* f = n.as_floating_point()) return f->get();
    return std::nullopt;
}

}  // namespace

ParamDict::ParamDict() : t_(make_table(nullptr, nullptr, "", "", "")) {}

ParamDict::ParamDict(std::shared_ptr<Table> t) : t_(std::move(t)) {}

ParamDict ParamDict::parse(const std::string& text, const std::string& file,
                           const std::string& context) {
    auto doc = std::make_shared<toml::table>();
    try {
        *doc = toml::parse(text, file);
    } catch (const toml::parse_error& e) {
        throw InputError(file + ":" + std::to_string(e.source().begin.line),
                         "TOML syntax error: " + std::string(e.description()));
    }
    const toml::table* t = doc.get();
    return ParamDict(make_table(std::move(doc), t, file, context, file));
}

const std::string& ParamDict::file() const { return t_->file; }
const std::string& ParamDict::context() const { return t_->context; }
std::string ParamDict::where() const { return t_->where; }

std::string ParamDict::where(const std::string& key) const {
    const toml::node* n = t_->t ? t_->t->get(key) : nullptr;
    return n ? t_->where_of(*n) : t_->where;
}

bool ParamDict::has(const std::string& key) const { return t_->get(key, false) != nullptr; }

std::vector<std::string> ParamDict::keys() const {
    std::vector<std::string> out;
    if (t_->t)
        for (const auto& [k, v] : *t_->t) out.emplace_back(k.str());
    return out;
}

std::optional<double> ParamDict::number(const std::string& key) const {
    const toml::node* n = t_->get(key, true);
    if (!n) return std::nullopt;
    if (const auto v = number_of(*n)) return v;
    throw InputError(t_->where_of(*n), "'" + key + "' must be a number");
}

double ParamDict::number(const std::string& key, double def) const {
    return number(key).value_or(def);
}

std::optional<int> ParamDict::integer(const std::string& key, int lo, int hi) const {
    const toml::node* n = t_->get(key, true);
    if (!n) return std::nullopt;
    const auto* i = n->as_integer();
    if (!i) throw InputError(t_->where_of(*n), "'" + key + "' must be an integer");
    const int64_t v = i->get();
    if (v < lo || v > hi)
        throw InputError(t_->where_of(*n), "'" + key + "' = " + std::to_string(v) +
                                               " is outside [" + std::to_string(lo) + ", " +
                                               std::to_string(hi) + "]");
    return int(v);
}

int ParamDict::integer(const std::string& key, int def, int lo, int hi) const {
    return integer(key, lo, hi).value_or(def);
}

std::optional<std::string> ParamDict::string(const std::string& key) const {
    const toml::node* n = t_->get(key, true);
    if (!n) return std::nullopt;
    if (const auto* s = n->as_string()) return s->get();
    throw InputError(t_->where_of(*n), "'" + key + "' must be a string");
}

std::string ParamDict::string(const std::string& key, const std::string& def) const {
    return string(key).value_or(def);
}

std::optional<bool> ParamDict::boolean(const std::string& key) const {
    const toml::node* n = t_->get(key, true);
    if (!n) return std::nullopt;
    if (const auto* b = n->as_boolean()) return b->get();
    throw InputError(t_->where_of(*n), "'" + key + "' must be true or false");
}

bool ParamDict::boolean(const std::string& key, bool def) const {
    return boolean(key).value_or(def);
}

std::vector<ParamDict::Element> ParamDict::elements(const std::string& key) const {
    const toml::node* n = t_->get(key, true);
    std::vector<Element> out;
    if (!n) return out;
    auto one = [&](const toml::node& e) {
        Element el;
        el.where = t_->where_of(e);
        if (const auto* i = e.as_integer()) {
            el.value = ParamValue((long long)i->get());
            el.integer = true;
        } else if (const auto* f = e.as_floating_point()) {
            el.value = ParamValue(f->get());
        } else if (const auto* b = e.as_boolean()) {
            el.value = ParamValue(b->get());
        } else if (const auto* s = e.as_string()) {
            el.value = ParamValue(s->get());
        }
        out.push_back(std::move(el));
    };
    if (const auto* arr = n->as_array()) {
        if (arr->empty()) throw InputError(t_->where_of(*n), "'" + key + "' is an empty list");
        for (const auto& e : *arr) one(e);
    } else {
        one(*n);
    }
    return out;
}

bool ParamDict::is_list(const std::string& key) const {
    const toml::node* n = t_->get(key, false);
    return n && n->is_array();
}

std::vector<double> ParamDict::numbers(const std::string& key,
                                       const std::vector<double>& def) const {
    if (!t_->get(key, false)) return def;
    std::vector<double> out;
    for (const Element& e : elements(key)) {
        if (!e.value || !e.value->is_number())
            throw InputError(e.where, "'" + key + "' must be a number");
        out.push_back(e.value->number());
    }
    return out;
}

std::vector<std::string> ParamDict::strings(const std::string& key,
                                            const std::vector<std::string>& def) const {
    if (!t_->get(key, false)) return def;
    std::vector<std::string> out;
    for (const Element& e : elements(key)) {
        if (!e.value || !e.value->is_name())
            throw InputError(e.where, "'" + key + "' must be a string");
        out.push_back(e.value->name());
    }
    return out;
}

std::vector<double> ParamDict::angles(const std::string& key,
                                      const std::vector<double>& def) const {
    const toml::node* n = t_->get(key, false);
    if (!n) return def;
    if (!n->is_table()) return numbers(key, def);
    const ParamDict range = *table(key, "'" + key + "'");
    const std::string at = where(key);
    for (const char* k : {"from", "to", "step"})
        if (!range.has(k)) throw InputError(at, "'" + key + "' range needs '" + k + "'");
    const double from = *range.number("from");
    const double to = *range.number("to");
    const double step = *range.number("step");
    range.report_unused();
    if (!std::isfinite(from) || !std::isfinite(to) || !std::isfinite(step))
        throw InputError(at, "'" + key + "' range needs finite from, to and step");
    if (!(step > 0)) throw InputError(at, "'" + key + "' step must be > 0");
    if (!(to >= from)) throw InputError(at, "'" + key + "' needs to >= from");
    const double span = std::floor((to - from) / step + 1e-9) + 1;  // counted in double first
    if (!(span <= 100000)) throw InputError(at, "'" + key + "' has too many angles");
    const long long count = (long long)span;
    std::vector<double> out;
    for (long long k = 0; k < count; ++k) out.push_back(from + double(k) * step);
    return out;
}

std::optional<ParamDict> ParamDict::table(const std::string& key, const std::string& context,
                                          const std::string& not_table) const {
    const toml::node* n = t_->get(key, true);
    if (!n) return std::nullopt;
    const toml::table* sub = n->as_table();
    if (!sub)
        throw InputError(t_->where_of(*n),
                         not_table.empty() ? "'" + key + "' must be a table" : not_table);
    return ParamDict(make_table(t_->doc, sub, t_->file, context, t_->where_of(*n)));
}

std::vector<ParamDict> ParamDict::tables(const std::string& key, const std::string& context) const {
    const toml::node* n = t_->get(key, true);
    if (!n) throw InputError(t_->where, "no [[" + key + "]] entries");
    const auto* arr = n->as_array();
    if (!arr || arr->empty() || !arr->is_array_of_tables())
        throw InputError(t_->where_of(*n),
                         "'" + key + "' must be a list of tables ([[" + key + "]])");
    std::vector<ParamDict> out;
    for (const auto& e : *arr)
        out.push_back(
            ParamDict(make_table(t_->doc, e.as_table(), t_->file, context, t_->where_of(e))));
    return out;
}

std::vector<std::string> ParamDict::asked() const {
    std::lock_guard<std::mutex> lock(t_->m);
    return t_->asked;
}

void ParamDict::report_unused(const UnusedMessage& message) const {
    if (!t_->t) return;
    std::string unread;
    {
        std::lock_guard<std::mutex> lock(t_->m);
        for (const auto& [k, v] : *t_->t)
            if (!t_->read.count(std::string(k.str()))) {
                unread = std::string(k.str());
                break;
            }
    }
    if (unread.empty()) return;
    std::string known;
    for (const auto& a : asked()) known += (known.empty() ? "" : ", ") + a;
    const std::string near = did_you_mean(unread, asked());
    std::string msg = message ? message(unread, known)
                              : "unknown key '" + unread + "' in " + t_->context + " (known: " +
                                    known + ")";
    // The nearest known key, right after the unknown one's name.
    const std::string quoted = "'" + unread + "'";
    if (const size_t at = msg.find(quoted); !near.empty() && at != std::string::npos)
        msg.insert(at + quoted.size(), near);
    throw InputError(where(unread), msg);
}

}  // namespace pxh
