#include "harness/report.h"

#include <algorithm>
#include <array>
#include <optional>
#include <tuple>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "harness/csv_table.h"
#include "harness/error.h"
#include "harness/params.h"
#include "harness/results.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

struct Band {
    const char* name;
    double lo, hi;  // lo <= theta < hi (the last band also takes hi)
};
const Band kBands[] = {{"0-30", 0, 30}, {"30-60", 30, 60}, {"60-75", 60, 75},
                       {"75-85", 75, 85.0000001}, {"85-90", 85.0000001, 90}};

// Mean of the finite values.
struct Mean {
    double sum = 0;
    int n = 0;
    void add(double v) {
        if (std::isfinite(v)) { sum += v; ++n; }
    }
    double get() const { return n ? sum / n : NAN; }
};

std::string series_of(const CsvTable& t, size_t r) {
    const std::string& params = t.get(r, "params");
    const std::string& fmt = t.get(r, "texture_format");
    return t.get(r, "method") + (params.empty() ? "" : " " + params) + " [" + t.get(r, "backend") +
           "/" + (fmt.empty() ? t.get(r, "precision") : fmt) + "]";
}

std::string field_of(const CsvTable& t, size_t r) {
    return t.get(r, "heightfield") + " s=" + t.get(r, "scale") + " b=" + t.get(r, "bias");
}

std::string fmt(double v, int prec = 3) {
    if (!std::isfinite(v)) return "-";
    std::ostringstream os;
    os << std::fixed << std::setprecision(prec) << v;
    return os.str();
}

std::string tex_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '_' || c == '%' || c == '&' || c == '#' || c == '$') o += '\\';
        o += c;
    }
    return o;
}

void write_file(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
    if (!f) throw InputError(p.string(), "cannot write");
}

// Indices of the points on the lower-left Pareto front of (cost, error): no other point is
// at most as costly and at most as wrong, and strictly better in one.
std::vector<bool> pareto(const std::vector<double>& cost, const std::vector<double>& err) {
    std::vector<bool> front(cost.size(), false);
    for (size_t i = 0; i < cost.size(); ++i) {
        if (!std::isfinite(cost[i]) || !std::isfinite(err[i])) continue;
        bool dominated = false;
        for (size_t j = 0; j < cost.size() && !dominated; ++j) {
            if (j == i || !std::isfinite(cost[j]) || !std::isfinite(err[j])) continue;
            dominated = cost[j] <= cost[i] && err[j] <= err[i] && (cost[j] < cost[i] || err[j] < err[i]);
        }
        front[i] = !dominated;
    }
    return front;
}

}  // namespace

int run_report(const std::string& dir, bool plots) {
    const CsvTable t = read_csv((fs::path(dir) / "results.csv").string());
    for (const char* c : {"method", "theta_deg", "err_mean", "err_p95", "status"})
        if (t.index(c) < 0)
            throw InputError((fs::path(dir) / "results.csv").string(),
                             std::string("no column '") + c + "' (not a pxh results file?)");
    const fs::path out = fs::path(dir) / "report";
    fs::create_directories(out / "data");

    // Per series (and band): means over the ok rows.
    struct Acc {
        Mean err_mean, err_p50, err_p95, fetches, ns, ms, sliding, shimmering;
        double worst_p95 = NAN;
    };
    std::vector<std::string> series_order;
    std::map<std::string, std::map<std::string, Acc>> by_band;  // series -> band -> acc
    std::map<std::string, Acc> overall;
    std::map<std::string, std::string> series_method;
    std::set<std::string> bands_present;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        if (t.get(r, "status") != "ok") continue;
        const std::string s = series_of(t, r);
        if (!overall.count(s)) series_order.push_back(s);
        series_method[s] = t.get(r, "method");
        const double theta = t.number(r, "theta_deg");
        const char* band = nullptr;
        for (const Band& b : kBands)
            if (theta >= b.lo && (theta < b.hi || (b.hi == 90 && theta <= 90))) band = b.name;
        for (Acc* a : {&overall[s], band ? &by_band[s][band] : nullptr}) {
            if (!a) continue;
            a->err_mean.add(t.number(r, "err_mean"));
            a->err_p50.add(t.number(r, "err_p50"));
            a->err_p95.add(t.number(r, "err_p95"));
            const double p95 = t.number(r, "err_p95");
            if (std::isfinite(p95)) a->worst_p95 = std::isfinite(a->worst_p95) ? std::max(a->worst_p95, p95) : p95;
            a->fetches.add(t.number(r, "fetches_mean"));
            a->ns.add(t.number(r, "ns_per_sample"));
            a->ms.add(t.number(r, "ms_per_frame"));
            a->sliding.add(t.number(r, "sliding"));
            a->shimmering.add(t.number(r, "shimmering"));
        }
        if (band) bands_present.insert(band);
    }
    if (series_order.empty()) throw InputError(dir, "results.csv has no ok rows to report");
    std::vector<const Band*> bands;
    for (const Band& b : kBands)
        if (bands_present.count(b.name)) bands.push_back(&b);

    // summary.csv
    std::ostringstream csv;
    csv << "series,method,band,err_mean,err_p50,err_p95,err_p95_worst,fetches_mean,"
           "ns_per_sample,ms_per_frame,sliding,shimmering\n";
    auto csv_line = [&](const std::string& s, const std::string& band, const Acc& a) {
        csv << csv_quote(s) << "," << series_method[s] << "," << band << ","
            << format_number(a.err_mean.get()) << "," << format_number(a.err_p50.get()) << ","
            << format_number(a.err_p95.get()) << "," << format_number(a.worst_p95) << ","
            << format_number(a.fetches.get()) << "," << format_number(a.ns.get()) << ","
            << format_number(a.ms.get()) << "," << format_number(a.sliding.get()) << ","
            << format_number(a.shimmering.get()) << "\n";
    };
    for (const auto& s : series_order) {
        for (const Band* b : bands)
            if (by_band[s].count(b->name)) csv_line(s, b->name, by_band[s][b->name]);
        csv_line(s, "all", overall[s]);
    }
    write_file(out / "summary.csv", csv.str());

    // summary.md / summary.tex: mean / p95 per band, cost.
    std::ostringstream md, tex;
    md << "| method | ";
    for (const Band* b : bands) md << "θ " << b->name << " mean / p95 | ";
    md << "fetches | CPU ns/sample | GLSL ms/frame |\n|---|";
    for (size_t i = 0; i < bands.size() + 3; ++i) md << "---:|";
    md << "\n";
    tex << "% Generated by pxh report from " << dir << "/results.csv\n"
        << "\\begin{tabular}{l" << std::string(bands.size() + 3, 'r') << "}\n\\toprule\n"
        << "method";
    for (const Band* b : bands) tex << " & $\\theta$ " << b->name << "$^\\circ$";
    tex << " & fetches & ns/sample & ms/frame \\\\\n\\midrule\n";
    for (const auto& s : series_order) {
        md << "| " << s << " | ";
        tex << tex_escape(s);
        for (const Band* b : bands) {
            auto it = by_band[s].find(b->name);
            const std::string cell = it == by_band[s].end()
                                         ? "-"
                                         : fmt(it->second.err_mean.get()) + " / " +
                                               fmt(it->second.err_p95.get());
            md << cell << " | ";
            tex << " & " << cell;
        }
        const Acc& a = overall[s];
        md << fmt(a.fetches.get(), 1) << " | " << fmt(a.ns.get(), 1) << " | " << fmt(a.ms.get(), 2)
           << " |\n";
        tex << " & " << fmt(a.fetches.get(), 1) << " & " << fmt(a.ns.get(), 1) << " & "
            << fmt(a.ms.get(), 2) << " \\\\\n";
    }
    tex << "\\bottomrule\n\\end{tabular}\n";
    md << "\nTexel error, mean over rows of the per-row mean / 95th percentile, per band of the "
          "view angle θ (degrees).\n";
    write_file(out / "summary.md", md.str());
    write_file(out / "summary.tex", tex.str());

    // Sliding / shimmering table (when measured).
    bool any_sweep = false;
    for (const auto& s : series_order) any_sweep |= overall[s].shimmering.n > 0;
    if (any_sweep) {
        std::ostringstream sm;
        sm << "| method | ";
        for (const Band* b : bands) sm << "θ " << b->name << " sliding / shimmering | ";
        sm << "\n|---|";
        for (size_t i = 0; i < bands.size(); ++i) sm << "---:|";
        sm << "\n";
        for (const auto& s : series_order) {
            sm << "| " << s << " | ";
            for (const Band* b : bands) {
                auto it = by_band[s].find(b->name);
                sm << (it == by_band[s].end() ? "-"
                                              : fmt(it->second.sliding.get()) + " / " +
                                                    fmt(it->second.shimmering.get()))
                   << " | ";
            }
            sm << "\n";
        }
        sm << "\nTexels per degree of view change (spec section 5): sliding = |mean change of "
              "the error vector| / dt, shimmering = mean |change - mean change| / dt.\n";
        write_file(out / "sweep.md", sm.str());
    }

    // precision.md: what float precision itself costs, per method and view angle (worst over
    // the rows of each angle of |uv_float - uv_double|, texels), when both precisions ran.
    if (t.index("double_diff_max") >= 0) {
        std::vector<double> thetas;
        std::map<std::string, std::map<double, double>> worst;
        std::vector<std::string> order;
        for (size_t r = 0; r < t.rows.size(); ++r) {
            const double d = t.number(r, "double_diff_max");
            if (!std::isfinite(d)) continue;
            const double th = t.number(r, "theta_deg");
            if (std::find(thetas.begin(), thetas.end(), th) == thetas.end()) thetas.push_back(th);
            const std::string m = t.get(r, "method") + (t.get(r, "params").empty() ? "" : " " + t.get(r, "params"));
            if (!worst.count(m)) order.push_back(m);
            auto& w = worst[m][th];
            w = std::max(w, d);
        }
        if (!order.empty()) {
            std::sort(thetas.begin(), thetas.end());
            std::ostringstream pm;
            pm << "| method | ";
            for (double th : thetas) pm << "θ " << format_number(th) << " | ";
            pm << "\n|---|";
            for (size_t i = 0; i < thetas.size(); ++i) pm << "---:|";
            pm << "\n";
            for (const auto& m : order) {
                pm << "| " << m << " | ";
                for (double th : thetas) {
                    auto it = worst[m].find(th);
                    char buf[32];
                    std::snprintf(buf, sizeof buf, "%.2g", it == worst[m].end() ? NAN : it->second);
                    pm << (it == worst[m].end() ? "-" : buf) << " | ";
                }
                pm << "\n";
            }
            pm << "\nLargest |uv_float - uv_double| over the samples, in texels (CPU reference in "
                  "float vs double on the same samples).\n";
            write_file(out / "precision.md", pm.str());
        }
    }

    // budget.md / budget.tex: per band, the cheapest setting (by fetches, then CPU time) whose
    // mean p95 error is within the budget.
    const double budgets[] = {0.1, 0.25, 0.5, 1, 2, 4};
    std::ostringstream bm, bt;
    bm << "| p95 budget (texels) | ";
    for (const Band* b : bands) bm << "θ " << b->name << " | ";
    bm << "\n|---:|";
    for (size_t i = 0; i < bands.size(); ++i) bm << "---|";
    bm << "\n";
    bt << "\\begin{tabular}{r" << std::string(bands.size(), 'l') << "}\n\\toprule\nbudget";
    for (const Band* b : bands) bt << " & $\\theta$ " << b->name << "$^\\circ$";
    bt << " \\\\\n\\midrule\n";
    for (double budget : budgets) {
        bm << "| " << format_number(budget) << " | ";
        bt << format_number(budget);
        for (const Band* b : bands) {
            std::string best;
            double best_f = INFINITY, best_ns = INFINITY;
            for (const auto& s : series_order) {
                auto it = by_band[s].find(b->name);
                if (it == by_band[s].end() || !(it->second.err_p95.get() <= budget)) continue;
                const double f = it->second.fetches.get(), ns = it->second.ns.get();
                const double nsk = std::isfinite(ns) ? ns : INFINITY;
                if (f < best_f || (f == best_f && nsk < best_ns)) {
                    best_f = f;
                    best_ns = nsk;
                    best = s + " (" + fmt(f, 1) + " fetches)";
                }
            }
            bm << (best.empty() ? "none" : best) << " | ";
            bt << " & " << tex_escape(best.empty() ? "none" : best);
        }
        bm << "\n";
        bt << " \\\\\n";
    }
    bt << "\\bottomrule\n\\end{tabular}\n";
    bm << "\nCheapest method setting (fewest height fetches per sample, then CPU time) whose mean "
          "95th-percentile texel error in the band is within the budget.\n";
    write_file(out / "budget.md", bm.str());
    write_file(out / "budget.tex", bt.str());

    // Plot data: error and sweeps vs theta per field and series (means over phi).
    {
        std::map<std::tuple<std::string, std::string, double>, std::array<Mean, 4>> acc;
        std::vector<std::tuple<std::string, std::string, double>> order;
        for (size_t r = 0; r < t.rows.size(); ++r) {
            if (t.get(r, "status") != "ok") continue;
            const auto key = std::make_tuple(field_of(t, r), series_of(t, r), t.number(r, "theta_deg"));
            if (!acc.count(key)) order.push_back(key);
            auto& a = acc[key];
            a[0].add(t.number(r, "err_p50"));
            a[1].add(t.number(r, "err_p95"));
            a[2].add(t.number(r, "sliding"));
            a[3].add(t.number(r, "shimmering"));
        }
        std::ostringstream d;
        d << "heightfield,series,theta_deg,err_p50,err_p95,sliding,shimmering\n";
        for (const auto& k : order) {
            const auto& a = acc[k];
            d << csv_quote(std::get<0>(k)) << "," << csv_quote(std::get<1>(k)) << ","
              << format_number(std::get<2>(k)) << "," << format_number(a[0].get()) << ","
              << format_number(a[1].get()) << "," << format_number(a[2].get()) << ","
              << format_number(a[3].get()) << "\n";
        }
        write_file(out / "data" / "vs_theta.csv", d.str());
    }
    // Cost against error, with the Pareto fronts per cost measure.
    {
        std::vector<double> err, fetches, ns, ms;
        for (const auto& s : series_order) {
            err.push_back(overall[s].err_mean.get());
            fetches.push_back(overall[s].fetches.get());
            ns.push_back(overall[s].ns.get());
            ms.push_back(overall[s].ms.get());
        }
        const auto pf = pareto(fetches, err), pn = pareto(ns, err), pm = pareto(ms, err);
        std::ostringstream d;
        d << "series,method,err_mean,err_p95,fetches_mean,ns_per_sample,ms_per_frame,"
             "pareto_fetches,pareto_ns,pareto_ms\n";
        for (size_t i = 0; i < series_order.size(); ++i) {
            const auto& s = series_order[i];
            d << csv_quote(s) << "," << series_method[s] << "," << format_number(err[i]) << ","
              << format_number(overall[s].err_p95.get()) << "," << format_number(fetches[i]) << ","
              << format_number(ns[i]) << "," << format_number(ms[i]) << "," << int(pf[i]) << ","
              << int(pn[i]) << "," << int(pm[i]) << "\n";
        }
        write_file(out / "data" / "cost_vs_error.csv", d.str());
    }
    // Error maps for a montage: the first field and azimuth, every series x theta.
    {
        std::ostringstream d;
        d << "series,theta_deg,map\n";
        std::string first_field, first_phi;
        int n = 0;
        for (size_t r = 0; r < t.rows.size(); ++r) {
            const std::string& map = t.get(r, "map");
            if (map.empty()) continue;
            if (first_field.empty()) {
                first_field = field_of(t, r);
                first_phi = t.get(r, "phi_deg");
            }
            if (field_of(t, r) != first_field || t.get(r, "phi_deg") != first_phi) continue;
            d << csv_quote(series_of(t, r)) << "," << t.get(r, "theta_deg") << ","
              << csv_quote((fs::absolute(fs::path(dir)) / map).string()) << "\n";
            ++n;
        }
        if (n) write_file(out / "data" / "maps.csv", d.str());
    }
    std::cout << "tables: " << (out / "summary.md").string() << ", summary.tex, summary.csv, "
              << "budget.md, budget.tex" << (any_sweep ? ", sweep.md" : "") << "\n";
    std::cout << std::flush;
    if (!plots) return 0;
    const std::string script = std::string(PXH_SOURCE_DIR) + "/harness/plot_report.py";
    const std::string cmd = "/usr/bin/python3 '" + script + "' '" + out.string() + "'";
    const int rc = std::system(cmd.c_str());
    if (rc != 0)
        throw std::runtime_error("plotting failed (" + cmd + "); the tables are written. Is "
                                 "python3-matplotlib installed? (./run.sh installs it)");
    return 0;
}

int run_check(const std::string& dir, const std::string& file) {
    const CsvTable t = read_csv((fs::path(dir) / "results.csv").string());
    toml::table root;
    try {
        root = toml::parse_file(file);
    } catch (const toml::parse_error& e) {
        throw InputError(file + ":" + std::to_string(e.source().begin.line),
                         "TOML syntax error: " + std::string(e.description()));
    }
    for (const auto& [k, v] : root)
        if (k.str() != "limit")
            throw InputError(file, "unknown key '" + std::string(k.str()) + "' (a thresholds "
                                   "file holds [[limit]] tables)");
    const toml::array* limits = root["limit"].as_array();
    if (!limits || limits->empty() || !limits->is_array_of_tables())
        throw InputError(file, "no [[limit]] tables");
    const std::vector<std::string> filters = {"method",    "params",         "heightfield",
                                              "backend",   "precision",      "texture_format",
                                              "ground_truth"};
    auto is_filter = [&](const std::string& k) {
        return std::find(filters.begin(), filters.end(), k) != filters.end();
    };
    struct Outcome { std::string what, column, limit; double worst; size_t rows; bool pass; std::string note; };
    std::vector<Outcome> outcomes;
    for (const auto& node : *limits) {
        const toml::table& lt = *node.as_table();
        const std::string where = file + ":" + std::to_string(node.source().begin.line);
        for (const auto& [k, v] : lt) {
            const std::string key(k.str());
            if (!is_filter(key) && key != "column" && key != "min" && key != "max" &&
                key != "theta_min" && key != "theta_max" && key != "note")
                throw InputError(where, "unknown key '" + key + "' in [[limit]]");
        }
        auto str = [&](const char* key) -> std::optional<std::string> {
            if (auto n = lt.get(key)) {
                if (!n->is_string()) throw InputError(where, std::string("'") + key + "' must be a string");
                return *n->value<std::string>();
            }
            return std::nullopt;
        };
        auto num = [&](const char* key) -> std::optional<double> {
            if (auto n = lt.get(key)) {
                if (!(n->is_integer() || n->is_floating_point()))
                    throw InputError(where, std::string("'") + key + "' must be a number");
                return *n->value<double>();
            }
            return std::nullopt;
        };
        const auto column = str("column");
        if (!column) throw InputError(where, "[[limit]] needs 'column'");
        if (t.index(*column) < 0) throw InputError(where, "results.csv has no column '" + *column + "'");
        const auto lo = num("min"), hi = num("max");
        if (!lo && !hi) throw InputError(where, "[[limit]] needs 'min' or 'max'");
        const double tmin = num("theta_min").value_or(-1), tmax = num("theta_max").value_or(1e9);
        std::string what;
        std::vector<size_t> match;
        for (const auto& f : filters)
            if (auto v = str(f.c_str())) what += (what.empty() ? "" : " ") + f + "=" + *v;
        if (lt.contains("theta_min") || lt.contains("theta_max"))
            what += std::string(what.empty() ? "" : " ") + "theta in [" +
                    format_number(tmin < 0 ? 0 : tmin) + ", " +
                    (tmax > 1e8 ? std::string("90") : format_number(tmax)) + "]";
        for (size_t r = 0; r < t.rows.size(); ++r) {
            bool ok = true;
            for (const auto& f : filters)
                if (auto v = str(f.c_str())) ok = ok && t.get(r, f) == *v;
            const double th = t.number(r, "theta_deg");
            ok = ok && th >= tmin && th <= tmax;
            if (ok) match.push_back(r);
        }
        if (match.empty())
            throw InputError(where, "limit on '" + *column + "' (" + what +
                                        ") matches no row: a limit that checks nothing is an error");
        Outcome o{what.empty() ? "all rows" : what, *column, "", NAN, match.size(), true, ""};
        o.limit = (lo ? ">= " + format_number(*lo) : "") + (lo && hi ? ", " : "") +
                  (hi ? "<= " + format_number(*hi) : "");
        double worst_hi = -INFINITY, worst_lo = INFINITY;
        for (size_t r : match) {
            if (t.get(r, "status") != "ok") {
                o.pass = false;
                o.note = "a matching row failed: " + t.get(r, "error");
                continue;
            }
            const double v = t.number(r, *column);
            if (!std::isfinite(v)) {
                o.pass = false;
                o.note = "non-finite or empty value";
                continue;
            }
            worst_hi = std::max(worst_hi, v);
            worst_lo = std::min(worst_lo, v);
        }
        if (hi && worst_hi > *hi) o.pass = false;
        if (lo && worst_lo < *lo) o.pass = false;
        o.worst = hi ? worst_hi : worst_lo;
        outcomes.push_back(o);
    }
    int failed = 0;
    std::cout << std::left << std::setw(4) << "#" << std::setw(72) << "rows selected"
              << std::setw(22) << "column" << std::setw(12) << "limit" << std::setw(12)
              << "worst" << std::setw(6) << "rows" << "result\n";
    for (size_t i = 0; i < outcomes.size(); ++i) {
        const auto& o = outcomes[i];
        failed += !o.pass;
        char worst[32];
        std::snprintf(worst, sizeof worst, "%.4g", o.worst);
        std::cout << std::left << std::setw(4) << i + 1 << std::setw(72) << o.what
                  << std::setw(22) << o.column << std::setw(12) << o.limit << std::setw(12)
                  << worst << std::setw(6) << o.rows << (o.pass ? "pass" : "FAIL")
                  << (o.note.empty() ? "" : "  (" + o.note + ")") << "\n";
    }
    std::cout << outcomes.size() - failed << " passed, " << failed << " failed\n";
    return failed ? 1 : 0;
}

}  // namespace pxh
