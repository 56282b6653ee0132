// pxh compare's output: the printed report (verdict, summary, regressions, the tables per
// method setting and theta band and per changed row, rows found in one run only) and the
// machine-readable verdict (--junit, --json).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "harness/core/error.h"
#include "harness/report/compare_parts.h"

namespace pxh::compare_detail {
namespace {

void write_table(const TextTable& t, bool markdown, std::ostream& out) {
    if (markdown) {
        out << t.markdown() << "\n";
        return;
    }
    std::vector<size_t> w(t.header.size(), 0);
    auto widen = [&](const std::vector<std::string>& row) {
        for (size_t i = 0; i < row.size() && i < w.size(); ++i)
            w[i] = std::max(w[i], row[i].size());
    };
    widen(t.header);
    for (const auto& r : t.rows) widen(r);
    auto line = [&](const std::vector<std::string>& row) {
        std::string s;
        for (size_t i = 0; i < row.size(); ++i) {
            const std::string pad(w[i] - std::min(w[i], row[i].size()), ' ');
            s += (i ? "  " : "") + (t.align[i] == 'r' ? pad + row[i] : row[i] + pad);
        }
        while (!s.empty() && s.back() == ' ') s.pop_back();
        out << s << "\n";
    };
    line(t.header);
    for (const auto& r : t.rows) line(r);
    for (const auto& n : t.notes) out << n << "\n";
    out << "\n";
}

TextTable band_table(const Tally& tally, const Bands& bands) {
    TextTable t;
    t.header = {"method [backend]", "theta band",    "rows",         "d err_mean", "d err_p95",
                "d err_max",        "d err_px_mean", "d err_px_p95", "d fetches",  "time ratio"};
    t.align = "llrrrrrrrr";
    for (const auto& [k, a] : tally.bands) {
        std::string ratio = "-";
        if (a.n_ratio) {
            ratio = sig(std::exp(a.log_ratio / a.n_ratio)) + "x";
            if (a.slower || a.faster)
                ratio += " (" + std::to_string(a.slower) + " slower, " + std::to_string(a.faster) +
                         " faster of " + std::to_string(a.n_ratio) + ")";
            else if (a.noise == a.n_ratio) ratio += " (noise)";
            else if (a.noise == 0) ratio += " (no verdict: too few repeats)";
            else ratio += " (noise; " + std::to_string(a.no_verdict) + " without a verdict)";
        }
        t.rows.push_back({k.first, bands.edges(size_t(k.second)), std::to_string(a.rows),
                          signed_sig(a.d[0].get()), signed_sig(a.d[1].get()),
                          signed_sig(a.d[2].get()), signed_sig(a.d[4].get()),
                          signed_sig(a.d[5].get()), signed_sig(a.d[3].get()), ratio});
    }
    t.notes.push_back(
        "method [backend] names KEY=VALUE for each context key whose values vary between "
        "BASE's rows (base, radius, a camera's keys, ...): rows that differ in one are never "
        "pooled; d: mean over the band's rows of NEW - BASE (err: texels; err_px: screen "
        "pixels; "
        "fetches per sample); time ratio: "
        "geometric mean of NEW / BASE medians of time (each row in its backend's time_unit); a row "
        "is "
        "slower or faster when a two-sided Mann-Whitney U test over its timed repeats is "
        "significant after Holm's correction over every timed row (a false alarm in 5% of "
        "comparisons of unchanged code, not in 5% of rows), noise otherwise.");
    return t;
}

TextTable row_table(Tally& tally) {
    trim(tally.rows);
    TextTable t;
    t.header = {"changed row", "err_mean",   "err_p95", "err_max",
                "err_px_mean", "err_px_p95", "fetches", "time ratio"};
    t.align = "lrrrrrrr";
    for (const Changed& c : tally.rows) t.rows.push_back(c.cells);
    if (tally.rows_changed == 0)
        t.notes.push_back(
            "No row's errors, fetches, status or time (Holm-corrected U test) changed.");
    else if (tally.rows.size() < tally.rows_changed)
        t.notes.push_back(
            "... and " + std::to_string(tally.rows_changed - tally.rows.size()) +
            " more changed rows (largest change of err_p95 first; then significant time changes).");
    return t;
}

// "0.1.0 (28c5cbf-dirty)" from a folder's run.json; "unknown" without one.
std::string pxh_version_of(const std::string& dir) {
    std::error_code ec;
    const auto p = std::filesystem::path(dir) / "run.json";
    if (!std::filesystem::is_regular_file(p, ec)) return "unknown (no run.json)";
    try {
        std::ifstream f(p, std::ios::binary);
        const auto j = nlohmann::json::parse(f);
        if (j.is_object() && j.contains("pxh_version") && j["pxh_version"].is_string())
            return one_line(j["pxh_version"].get<std::string>());
    } catch (const std::exception&) {
    }
    return "unknown";
}

void list(std::ostream& out, bool markdown, const std::string& title, const Capped& v) {
    if (v.total == 0) return;
    out << (markdown ? "#### " : "") << title << " (" << v.total << ")\n";
    for (const std::string& s : v.items) out << (markdown ? "- " : "  ") << s << "\n";
    if (v.items.size() < v.total) out << "  ... and " << v.total - v.items.size() << " more\n";
    out << "\n";
}

// The lines under the verdict: the folders, the counts, timing, versions, shader changes.
void write_summary(const std::string& base_dir, const std::string& new_dir,
                   const CompareOptions& opt, const Tally& tally, const Capped& only_base,
                   std::ostream& out) {
    const bool md = opt.markdown;
    const std::string br = md ? "  \n" : "\n";  // a Markdown line break
    out << "BASE " << base_dir << " -> NEW " << new_dir << br;
    for (const std::string& n : opt.notes) out << n << br;
    out << tally.matched << " rows matched (" << tally.changed
        << " with changed errors or status), " << only_base.total << " only in BASE, "
        << tally.only_new << " only in NEW" << br;
    if (!opt.only.empty())
        out << "--only " << opt.only << ": " << tally.base_left_out << " rows of BASE and "
            << tally.new_left_out << " of NEW left out" << br;
    if (opt.common)
        out << "--common: " << only_base.total << " rows only in BASE and " << tally.only_new
            << " only in NEW left out" << br;
    const Holm& h = tally.family;
    out << "timing (two-sided Mann-Whitney U over the timed repeats, Holm over the " << h.m
        << (std::isfinite(h.pooled_p) ? " tests (rows, and the pooled one below)" : " rows tested")
        << ": at most a 5% chance of any false slower/faster): " << tally.t_slower << " slower, "
        << tally.t_faster << " faster, " << tally.t_noise << " no significant change, "
        << tally.t_too_few << " too few repeats for a verdict, " << tally.t_no_repeats
        << " without repeats" << br;
    if (std::isfinite(h.pooled_p))
        out << "timing, pooled: the " << h.pooled_n
            << " rows with too few repeats for a verdict of their own, together: x"
            << sig(h.pooled_ratio) << " (geometric mean of the median ratios), one-sided "
            << "Wilcoxon signed-rank p=" << sig(h.pooled_p)
            << (h.pooled_slower
                    ? ": slower beyond the margin (their rows past it are regressions)"
                    : ": not slower beyond the margin (their rows are not judged one by "
                      "one)")
            << br;
    if (tally.t_too_few_family)
        out << "timing: " << tally.t_too_few_family
            << " row(s) have too few repeats for Holm's first level p <= " << sig(h.alpha_m())
            << " (5 + 5 repeats give at best p = 0.007937, 10 + 10 give 1.083e-05): time more "
               "repeats (timing_repeats) or fewer rows"
            << br;
    const std::string vb = pxh_version_of(base_dir), vn = pxh_version_of(new_dir);
    out << "pxh version: "
        << (vb == vn ? vb + " (both)" : "BASE " + vb + ", NEW " + vn + " (changed)") << br;
    out << "shader changes: "
        << (tally.shader_changes.empty() ? "none" : std::to_string(tally.shader_changes.size()))
        << "\n";
    for (const std::string& c : tally.shader_changes) out << (md ? "- " : "  ") << c << "\n";
    out << "\n";
}

}  // namespace

void write_report(const std::string& base_dir, const std::string& new_dir,
                  const CompareOptions& opt, const std::string& verdict, Tally& tally,
                  const Bands& bands, const Capped& only_base, std::ostream& out) {
    const bool md = opt.markdown;
    const std::string h = md ? "### " : "";
    // The verdict first.
    out << h << "pxh compare: " << verdict << "\n\n";
    write_summary(base_dir, new_dir, opt, tally, only_base, out);
    if (!opt.fail_on.empty() && tally.regressions.total) {
        Capped shown;
        for (const auto& r : tally.regressions.items) shown.add(r.second);
        shown.total = tally.regressions.total;
        list(out, md, "Regressions beyond --fail-on (largest change first)", shown);
    }
    // The details.
    if (md)
        out << "<details><summary>Details: per method and theta band, per changed "
               "row</summary>\n\n";
    write_table(band_table(tally, bands), md, out);
    write_table(row_table(tally), md, out);
    list(out, md, std::string("Rows only in BASE") + (opt.common ? " (left out: --common)" : ""),
         only_base);
    list(out, md, std::string("Rows only in NEW") + (opt.common ? " (left out: --common)" : ""),
         tally.only_new_names);
    if (md) out << "</details>\n\n";
}

Verdict verdict_of(const std::string& base_dir, const std::string& new_dir, int rc,
                   const std::string& verdict, const Tally& tally, const Capped& only_base,
                   bool gate_missing) {
    Verdict v{"pxh compare", base_dir + " -> " + new_dir, rc, verdict, {}};
    for (const auto& [series, g] : tally.groups) {
        VerdictCase c{series,
                      "pxh.compare",
                      g.regressions == 0,
                      "",
                      g.details,
                      {{"rows", double(g.rows)}, {"regressions", double(g.regressions)}}};
        if (g.regressions)
            c.message = std::to_string(g.regressions) + " of " + std::to_string(g.rows) +
                        " matched rows regress beyond --fail-on";
        v.cases.push_back(std::move(c));
    }
    if (!tally.unjudged.empty())
        v.cases.push_back({"gated columns in both runs",
                           "pxh.compare",
                           false,
                           tally.unjudged.front(),
                           tally.unjudged,
                           {{"columns_missing", double(tally.unjudged.size())}}});
    if (gate_missing || only_base.total) {
        VerdictCase c{"rows of BASE found in NEW",
                      "pxh.compare",
                      !gate_missing || !only_base.total,
                      "",
                      {},
                      {{"missing", double(only_base.total)}}};
        if (!c.passed) {
            c.message = std::to_string(only_base.total) + " rows of BASE are missing from NEW";
            c.details = only_base.items;
        }
        v.cases.push_back(std::move(c));
    }
    return v;
}

void write_verdict_files(const CompareOptions& opt, const Verdict& v) {
    if (!opt.junit.empty()) write_verdict_file(opt.junit, junit_xml(v), "--junit");
    if (!opt.json.empty()) write_verdict_file(opt.json, verdict_json(v), "--json");
}

}  // namespace pxh::compare_detail
