#include "harness/report/report_data.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/columns.h"
#include "harness/results/error_maps.h"
#include "harness/scene/view.h"

namespace pxh {

namespace fs = std::filesystem;

namespace {

const BudgetMetric kBudgetMetrics[] = {
    {"p95",
     "err_p95",
     "p95 budget (texels)",
     "95th-percentile texel error",
     {0.1, 0.25, 0.5, 1, 2, 4}},
    {"p99",
     "err_p99",
     "p99 budget (texels)",
     "99th-percentile texel error",
     {0.1, 0.25, 0.5, 1, 2, 4}},
    {"frac_gt_1",
     "frac_gt_1",
     "frac_gt_1 budget (fraction of samples)",
     "fraction of samples more than one texel off",
     {0.001, 0.003, 0.01, 0.03, 0.1}},
};

}  // namespace

const BudgetMetric& budget_metric(const std::string& name) {
    for (const auto& m : kBudgetMetrics)
        if (name == m.name) return m;
    throw InputError("--budget-metric", "'" + name + "' is not one of p95, p99, frac_gt_1");
}

void Acc::add(const ResultRow& r, const char* budget_column) {
    err_mean.add(r.num("err_mean"));
    err_p50.add(r.num("err_p50"));
    const double p95 = r.num("err_p95");
    err_p95.add(p95);
    if (std::isfinite(p95)) worst_p95 = std::isfinite(worst_p95) ? std::max(worst_p95, p95) : p95;
    fetches.add(r.num("fetches_mean"));
    const std::string& unit = r.text("time_unit");
    if (!unit.empty()) {
        TimeMeans& t = time[unit];
        t.time.add(r.num("time"));
        t.min.add(r.num("time_min"));
        t.max.add(r.num("time_max"));
    }
    sliding.add(r.num("sliding"));
    shimmering.add(r.num("shimmering"));
    budget.add(r.num(budget_column));
    px_mean.add(r.num("err_px_mean"));
    px_p95.add(r.num("err_px_p95"));
    sliding_dist.add(r.num("sliding_dist"));
    shimmering_dist.add(r.num("shimmering_dist"));
    px_budget.add(r.num("err_px_p95"));
    nonfinite = nonfinite || r.num("nonfinite") > 0;
}

const TimeMeans* Acc::times_in(const std::string& unit) const {
    auto it = time.find(unit);
    return it == time.end() ? nullptr : &it->second;
}

double Acc::time_in(const std::string& unit) const {
    const TimeMeans* t = times_in(unit);
    return t ? t->time.get() : NAN;
}

namespace {

bool is_camera_key(const std::string& name) {
    return std::any_of(camera_key_columns().begin(), camera_key_columns().end(),
                       [&](const CameraKey& k) { return k.name == name; });
}

}  // namespace

std::string ReportData::view_of(const ResultRow& r) const {
    std::string v;
    for (const std::string& k : context_keys) {
        const std::string c = r.cell(k);
        if (!c.empty()) v += (v.empty() ? "" : " ") + k + "=" + c;
    }
    return v;
}

std::string ReportData::tag_of(const ResultRow& r) const {
    std::string t = camera_name_part(r);
    for (const std::string& k : context_keys) {
        if (is_camera_key(k)) continue;  // camera_name_part has them
        std::string c = r.cell(k);
        if (c.empty()) continue;
        for (char& ch : c)
            if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '.' && ch != '-') ch = '-';
        const ColumnSpec* spec = find_column(k);
        t += "_" + (spec ? spec->shown_as() : k) + "-" + c;
    }
    return t;
}

std::string ReportData::view_title(const std::string& view) {
    if (view.empty()) return "no context keys (orthographic)";
    std::string t;
    std::stringstream ss(view);
    for (std::string kv; ss >> kv;) {
        const size_t eq = kv.find('=');
        const ColumnSpec* spec = find_column(kv.substr(0, eq));
        t += (t.empty() ? "" : ", ") + (spec ? spec->shown_as() : kv.substr(0, eq)) + " = " +
             kv.substr(eq + 1);
    }
    return t;
}

ReportData::ReportData(const std::string& d, const ReportOptions& o)
    : dir(d),
      out(fs::path(d) / "report"),
      bands(o.bands),
      metric(budget_metric(o.budget_metric)),
      file(read_results((fs::path(d) / "results.csv").string())) {
    for (const char* c : {"method", "theta_deg", "err_mean", "err_p95", "status"})
        if (!file.has(c))
            throw InputError(file.path,
                             std::string("no column '") + c + "' (not a pxh results file?)");
    for (size_t r = 0; r < file.rows.size(); ++r)
        (file.rows[r].ok() ? all_ok : failed).push_back(r);
    if (all_ok.empty()) throw InputError(file.path, "has no ok rows to report");
    find_context();
    filter_rows();
    assign_bands();
    collect();
    name_settings();
}

void ReportData::find_context() {
    for (const ColumnSpec* c : row_axes()) {
        if (!context_key(*c)) continue;
        const bool camera_key = is_camera_key(c->name);
        std::set<std::string> values;
        for (size_t r : all_ok) values.insert(row(r).cell(c->name));
        const bool some = values.size() > 1 || !values.begin()->empty();
        if (camera_key ? some : values.size() > 1) context_keys.push_back(c->name);
    }
}

std::vector<size_t> ReportData::held_rows(
    std::vector<size_t> rows, const std::string& family,
    std::vector<std::pair<std::string, std::string>>* held) const {
    for (const ColumnSpec* c : row_axes()) {
        if (c->can_change(family) || rows.empty()) continue;
        const std::string first = row(rows.front()).cell(c->name);
        std::vector<size_t> kept;
        for (size_t r : rows)
            if (row(r).cell(c->name) == first) kept.push_back(r);
        if (kept.size() != rows.size()) held->emplace_back(c->name, first);
        rows = std::move(kept);
    }
    return rows;
}

void ReportData::filter_rows() { ok = held_rows(all_ok, "texel", &filtered); }

void ReportData::assign_bands() {
    size_t outside = 0;
    for (size_t r : ok) {
        const double theta = row(r).num("theta_deg");
        const int b = bands.of(theta);
        if (b >= 0) bands.add_view(b, theta);
        outside += b < 0;
    }
    if (outside)
        std::cerr << "pxh: warning: " << outside << " rows have θ outside the bands ("
                  << bands.range() << "): they count only in the 'all' figures\n";
}

// Means per series and band over the ok rows only; failed rows only mark their setting's band
// (no budget is met where a row failed).
void ReportData::collect() {
    for (size_t r : ok) {
        const ResultRow& rr = row(r);
        const std::string s = series_of(rr), set = setting_of(rr);
        if (!series.count(s)) {
            series_order.push_back(s);
            series[s] = {set, rr.text("method"), group_of(rr), r, {}, {}};
            if (!settings.count(set)) setting_order.push_back(set);
            settings[set].series.push_back(s);
        }
        const std::string field = field_of(rr);
        if (!field_series.count(field)) field_order.push_back(field);
        auto& per_field = field_series[field];
        if (!per_field.count(s)) per_field[s] = {set, rr.text("method"), group_of(rr), r, {}, {}};
        if (std::find(group_order.begin(), group_order.end(), group_of(rr)) == group_order.end())
            group_order.push_back(group_of(rr));
        const std::string& unit = rr.text("time_unit");
        if (!unit.empty() &&
            std::find(time_units.begin(), time_units.end(), unit) == time_units.end())
            time_units.push_back(unit);
        Series& ser = series[s];
        Series& fser = per_field[s];
        ser.all.add(rr, metric.column);
        fser.all.add(rr, metric.column);
        // the view's parts: all fields, and this field
        const std::string v = view_of(rr);
        pixel_error =
            pixel_error || (!camera_name_part(rr).empty() && std::isfinite(rr.num("err_px_mean")));
        if (std::find(view_order.begin(), view_order.end(), v) == view_order.end())
            view_order.push_back(v);
        Part* parts[] = {&views[v], &field_views[field][v]};
        for (Part* p : parts) {
            if (!p->series.count(s)) {
                p->series[s] = {set, rr.text("method"), group_of(rr), r, {}, {}};
                p->settings[set].series.push_back(s);
            }
            p->series[s].all.add(rr, metric.column);
        }
        const int b = bands.of(rr.num("theta_deg"));
        if (b < 0) continue;
        ser.band[size_t(b)].add(rr, metric.column);
        fser.band[size_t(b)].add(rr, metric.column);
        settings[set].band[size_t(b)].add(rr, metric.column);
        for (Part* p : parts) {
            p->series[s].band[size_t(b)].add(rr, metric.column);
            p->settings[set].band[size_t(b)].add(rr, metric.column);
        }
    }
    for (size_t r : failed) {
        const int b = bands.of(row(r).num("theta_deg"));
        if (b < 0) continue;
        const std::string set = setting_of(row(r)), v = view_of(row(r));
        settings[set].failed_bands.insert(size_t(b));
        views[v].settings[set].failed_bands.insert(size_t(b));
        field_views[field_of(row(r))][v].settings[set].failed_bands.insert(size_t(b));
    }
    // views in ascending order of their keys' values (distance 1, 4, 16; not 1, 16, 4)
    const auto values = [](const std::string& v) {
        std::vector<std::pair<double, std::string>> x;  // numbers as numbers, then text
        std::stringstream ss(v);
        for (std::string kv; ss >> kv;) {
            const std::string value = kv.substr(kv.find('=') + 1);
            char* end = nullptr;
            const double d = std::strtod(value.c_str(), &end);
            const bool number = !value.empty() && end && *end == '\0';
            x.emplace_back(number ? d : NAN, number ? "" : value);
        }
        return x;
    };
    const auto less = [](const std::vector<std::pair<double, std::string>>& a,
                         const std::vector<std::pair<double, std::string>>& b) {
        for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
            if (a[i].second != b[i].second) return a[i].second < b[i].second;
            if (a[i].first != b[i].first && !(std::isnan(a[i].first) && std::isnan(b[i].first)))
                return std::isnan(a[i].first)   ? false
                       : std::isnan(b[i].first) ? true
                                                : a[i].first < b[i].first;
        }
        return a.size() < b.size();
    };
    std::stable_sort(
        view_order.begin(), view_order.end(),
        [&](const std::string& a, const std::string& b) { return less(values(a), values(b)); });
}

namespace {

// "k=v;k=v" as (key, value) pairs, in order.
std::vector<std::pair<std::string, std::string>> split_params(const std::string& params) {
    std::vector<std::pair<std::string, std::string>> kv;
    std::stringstream ss(params);
    for (std::string part; std::getline(ss, part, ';');) {
        if (part.empty()) continue;
        const size_t eq = part.find('=');
        kv.emplace_back(part.substr(0, eq), eq == std::string::npos ? "" : part.substr(eq + 1));
    }
    return kv;
}

constexpr size_t kMaxLabelValues = 16;  // characters of values in "method (values)"

}  // namespace

std::vector<std::string> compact_labels(
    const std::vector<std::pair<std::string, std::string>>& settings) {
    std::vector<std::string> labels(settings.size());
    std::map<std::string, std::vector<size_t>> by_method;
    std::vector<std::string> methods;
    for (size_t i = 0; i < settings.size(); ++i) {
        if (!by_method.count(settings[i].first)) methods.push_back(settings[i].first);
        by_method[settings[i].first].push_back(i);
    }
    for (const auto& m : methods) {
        const auto& members = by_method[m];
        if (members.size() == 1) {
            labels[members[0]] = m;
            continue;
        }
        // value[k][key]: each setting's parameters; keys in order of first appearance
        std::vector<std::map<std::string, std::string>> value;
        std::vector<std::string> keys;
        for (size_t i : members) {
            value.emplace_back();
            for (const auto& [k, v] : split_params(settings[i].second)) {
                if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
                value.back()[k] = v;
            }
        }
        const auto of = [&](size_t k, const std::string& key) {
            auto it = value[k].find(key);
            return it == value[k].end() ? std::string("-") : it->second;
        };
        // Greedy: add the key that tells the most settings apart, until all are apart (or no
        // key helps: settings whose parameters are all alike, which setting_of never makes).
        std::vector<std::string> chosen;
        const auto distinct = [&](const std::vector<std::string>& ks) {
            std::set<std::vector<std::string>> seen;
            for (size_t k = 0; k < members.size(); ++k) {
                std::vector<std::string> t;
                for (const auto& key : ks) t.push_back(of(k, key));
                seen.insert(t);
            }
            return seen.size();
        };
        for (size_t have = 1; have < members.size();) {
            size_t best = 0;
            std::string best_key;
            for (const auto& key : keys) {
                if (std::find(chosen.begin(), chosen.end(), key) != chosen.end()) continue;
                auto ks = chosen;
                ks.push_back(key);
                const size_t n = distinct(ks);
                if (n > best) {
                    best = n;
                    best_key = key;
                }
            }
            if (best <= have) break;
            chosen.push_back(best_key);
            have = best;
        }
        // in the order the parameters are written
        std::vector<std::string> ordered;
        for (const auto& key : keys)
            if (std::find(chosen.begin(), chosen.end(), key) != chosen.end())
                ordered.push_back(key);
        std::vector<std::string> vals(members.size());
        bool long_values = distinct(ordered) < members.size();
        for (size_t k = 0; k < members.size(); ++k) {
            for (const auto& key : ordered) vals[k] += (vals[k].empty() ? "" : ", ") + of(k, key);
            long_values = long_values || vals[k].size() > kMaxLabelValues;
        }
        for (size_t k = 0; k < members.size(); ++k) {
            std::string tag = vals[k];
            if (long_values) {  // a, b, ..., z, aa, ab, ...
                tag.clear();
                for (size_t n = k + 1; n > 0; n = (n - 1) / 26)
                    tag.insert(tag.begin(), char('a' + (n - 1) % 26));
            }
            labels[members[k]] = m + " (" + tag + ")";
        }
    }
    return labels;
}

void ReportData::name_settings() {
    std::vector<std::pair<std::string, std::string>> keys;
    for (const auto& set : setting_order) {
        const ResultRow& r = row(series.at(settings.at(set).series.front()).first_row);
        keys.emplace_back(r.text("method"), r.text("params"));
    }
    const auto labels = compact_labels(keys);
    for (size_t i = 0; i < setting_order.size(); ++i) tex_label[setting_order[i]] = labels[i];
}

std::string ReportData::short_group(const std::string& group) const {
    const std::string backend = group.substr(0, group.find('/'));
    for (const auto& g : group_order)
        if (g != group && g.substr(0, g.find('/')) == backend) return group;
    return backend;
}

std::vector<size_t> ReportData::present_bands() const {
    std::vector<size_t> present;
    for (size_t i = 0; i < bands.size(); ++i)
        if (bands.present(i)) present.push_back(i);
    return present;
}

std::vector<std::string> ReportData::notes(bool with_bands) const {
    std::vector<std::string> n;
    if (!failed.empty())
        n.push_back(std::to_string(failed.size()) +
                    " failed rows (status not ok) are "
                    "left out of every figure here; they are listed in failed.md.");
    if (with_bands && !bands.note().empty()) n.push_back(bands.note());
    return n;
}

void ReportData::write(const std::string& rel, const std::string& text) const {
    folder().write(rel, text);
}

std::vector<bool> pareto(const std::vector<double>& cost, const std::vector<double>& err) {
    std::vector<bool> front(cost.size(), false);
    for (size_t i = 0; i < cost.size(); ++i) {
        if (!std::isfinite(cost[i]) || !std::isfinite(err[i])) continue;
        bool dominated = false;
        for (size_t j = 0; j < cost.size() && !dominated; ++j) {
            if (j == i || !std::isfinite(cost[j]) || !std::isfinite(err[j])) continue;
            dominated =
                cost[j] <= cost[i] && err[j] <= err[i] && (cost[j] < cost[i] || err[j] < err[i]);
        }
        front[i] = !dominated;
    }
    return front;
}

}  // namespace pxh
