#include "harness/commands/summary.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/columns.h"
#include "harness/results/results.h"

namespace pxh {
namespace {

// Four significant digits ("12.35", "0.8125", "1234").
std::string time_cell(double v) {
    std::ostringstream os;
    os << std::setprecision(4) << v;
    return os.str();
}

// Every column as wide as its widest cell: aligned whatever the parameters' lengths; the
// columns from first_number on right-aligned.
void print_aligned(const std::vector<std::vector<std::string>>& table, size_t first_number) {
    std::vector<size_t> width(table.front().size(), 0);
    for (const auto& line : table)
        for (size_t i = 0; i < line.size(); ++i) width[i] = std::max(width[i], line[i].size());
    for (const auto& line : table) {
        std::string out;
        for (size_t i = 0; i < line.size(); ++i) {
            const std::string pad(width[i] - line[i].size(), ' ');
            out += (i ? "  " : "") + (i < first_number ? line[i] + pad : pad + line[i]);
        }
        while (!out.empty() && out.back() == ' ') out.pop_back();
        std::cout << out << "\n";
    }
}

// Per method, its row farthest from the CPU twin among those with differing samples: where the
// first samples differ (cpu_diff_first: index, both uv, both fetch counts), so that a plug-in's
// disagreement with its reference is seen without opening results.csv.
void print_first_differences(const std::vector<ResultRow>& rows) {
    std::map<std::string, const ResultRow*> worst;
    std::map<std::string, int> count;
    std::vector<std::string> order;
    for (const ResultRow& r : rows) {
        if (r.text("cpu_diff_first").empty()) continue;
        const std::string m = r.text("method");
        if (!count[m]++) order.push_back(m);
        const ResultRow*& w = worst[m];
        if (!w || r.num("cpu_diff_max") > w->num("cpu_diff_max")) w = &r;
    }
    if (order.empty()) return;
    std::cout << "samples more than 1e-3 texel from the CPU twin or with another fetch count "
                 "(cpu_diff_first: 'k: GLSL uv | CPU uv fetches GLSL | CPU'), the worst row "
                 "per method:\n";
    constexpr size_t kShownMethods = 8;
    for (size_t i = 0; i < order.size(); ++i) {
        if (i == kShownMethods) {
            std::cout << "  ... and " << order.size() - i << " more method(s): results.csv\n";
            break;
        }
        const std::string& m = order[i];
        const ResultRow& r = *worst[m];
        std::string first = r.text("cpu_diff_first");
        size_t cut = 0;
        for (int k = 0; k < 3 && cut != std::string::npos; ++k) cut = first.find("; ", cut + 1);
        if (cut != std::string::npos) first = first.substr(0, cut) + "; ...";
        std::cout << "  " << row_name(r) << " (" << count[m] << " row(s) with such samples; "
                  << "cpu_diff_max " << time_cell(r.num("cpu_diff_max")) << " texel): " << first
                  << "\n";
    }
}

// One line of the summary: its rows' sums.
struct Acc {
    double sum_mean = 0, worst_p95 = 0, fetches = 0, shadow = 0, flip = 0;
    int n = 0, n_shadow = 0, n_flip = 0, failed = 0;
    std::map<std::string, std::pair<double, int>> time;  // time_unit -> sum, n
    std::vector<std::string> context;
    // An ok row; a time unit not yet in `units` is appended.
    void add(const ResultRow& r, std::vector<std::string>& units) {
        sum_mean += r.num("err_mean");
        worst_p95 = std::max(worst_p95, r.num("err_p95"));
        fetches += r.num("fetches_mean");
        ++n;
        const std::string& unit = r.text("time_unit");
        if (!std::isnan(r.num("time")) && !unit.empty()) {
            if (std::find(units.begin(), units.end(), unit) == units.end()) units.push_back(unit);
            time[unit].first += r.num("time");
            ++time[unit].second;
        }
        if (!std::isnan(r.num("shadow_err"))) {
            shadow += r.num("shadow_err");
            ++n_shadow;
        }
        if (std::isfinite(r.num("flip_mean"))) {  // [shading]
            flip += r.num("flip_mean");
            ++n_flip;
        }
    }
};

}  // namespace

void print_summary(const std::vector<ResultRow>& rows) {
    // A line per series and context (the keys that vary between the rows and are neither a
    // series, field nor sweep key: a base, a radius, a camera distance): never a mean across
    // them.
    const std::vector<std::string> context = varying_context_keys(
        rows.size(), [&](size_t r, const std::string& c) { return rows[r].cell(c); });
    std::vector<std::string> order, units;
    std::map<std::string, Acc> acc;
    for (const auto& r : rows) {
        std::string key = series_of(r);
        std::vector<std::string> ctx;
        for (const std::string& c : context) {
            ctx.push_back(r.cell(c).empty() ? "-" : r.cell(c));
            key += "\t" + ctx.back();
        }
        if (!acc.count(key)) {
            order.push_back(key);
            acc[key].context = ctx;
        }
        Acc& a = acc[key];
        if (!r.ok()) {
            ++a.failed;
            continue;
        }
        a.add(r, units);
    }
    auto cell = [](double sum, int n, int prec) {
        std::ostringstream os;
        if (n == 0) os << "-";
        else os << std::fixed << std::setprecision(prec) << sum / n;
        return os.str();
    };
    bool shadows = false;
    bool flips = false;
    for (const auto& [k, a] : acc) {
        shadows = shadows || a.n_shadow > 0;
        flips = flips || a.n_flip > 0;
    }
    std::vector<std::string> header = {"method [backend/precision or texture]"};
    for (const std::string& c : context) {
        const ColumnSpec* spec = find_column(c);
        header.push_back(spec ? spec->shown_as() : c);
    }
    const size_t first_number = header.size();
    for (const char* h : {"mean err", "worst p95", "fetches"}) header.push_back(h);
    for (const std::string& u : units) header.push_back("time " + u);
    if (shadows) header.push_back("shadow");
    if (flips) header.push_back("flip_mean");
    header.push_back("failed");
    std::vector<std::vector<std::string>> table = {header};
    for (const auto& k : order) {
        const Acc& a = acc[k];
        std::vector<std::string> line = {k.substr(0, k.find('\t'))};
        line.insert(line.end(), a.context.begin(), a.context.end());
        line.push_back(cell(a.sum_mean, a.n, 3));
        line.push_back(cell(a.worst_p95, a.n ? 1 : 0, 3));
        line.push_back(cell(a.fetches, a.n, 1));
        for (const std::string& u : units) {
            auto it = a.time.find(u);
            line.push_back(it == a.time.end() ? "-"
                                              : time_cell(it->second.first / it->second.second));
        }
        if (shadows) line.push_back(cell(a.shadow, a.n_shadow, 3));
        if (flips) line.push_back(cell(a.flip, a.n_flip, 4));
        line.push_back(std::to_string(a.failed));
        table.push_back(line);
    }
    print_aligned(table, first_number);
    std::cout << "mean err: texel distance between the sampled and the truly visible point, "
                 "averaged over rows; worst p95: largest per-row 95th percentile;\n"
                 "time UNIT: mean over rows of the median timed repeat (cpu: single-thread "
                 "ns/sample; glsl: ms/frame)"
              << (shadows ? "; shadow: fraction of samples with a wrong hard shadow" : "")
              << (flips ? ";\nflip_mean: mean over rows of the mean LDR-FLIP of the shaded "
                          "images ([shading]; 0: alike)"
                        : "")
              << (context.empty() ? ""
                                  : ";\nrows that differ in a base, radius or camera setting "
                                    "are apart (never averaged together)")
              << "\n";
    print_first_differences(rows);
}

}  // namespace pxh

namespace pxh {

void print_run(const std::vector<ResultRow>& rows, double seconds, const std::filesystem::path& dir,
               bool quiet) {
    size_t failed = 0, shown = 0;
    for (const auto& r : rows) failed += !r.ok();
    if (!quiet) print_summary(rows);
    std::cout << rows.size() << " rows (" << failed << " failed) in " << std::setprecision(1)
              << std::fixed << seconds << " s -> " << dir.string() << std::endl;
    // A closed pipe (SIGPIPE is ignored): the results are complete, the output is not.
    if (!std::cout)
        throw std::runtime_error(
            "cannot write to standard output (a closed pipe?); the results "
            "are complete in " +
            dir.string());
    for (const auto& r : rows) {
        if (r.ok()) continue;
        if (++shown > 10) {
            std::cerr << "pxh: ... and " << failed - 10
                      << " more failed rows (status=failed in results.csv)\n";
            break;
        }
        std::cerr << "pxh: failed row: " << setting_of(r) << " | " << r.text("heightfield")
                  << " | theta " << format_number(r.num("theta_deg")) << " phi "
                  << format_number(r.num("phi_deg")) << " | " << group_of(r) << ": "
                  << one_line(r.text("error")) << "\n";
    }
}

namespace {

// "0:07", "12:34", "1:02:03": a duration in seconds as the progress line shows it.
std::string clock_time(double secs) {
    const long t = long(secs + 0.5), h = t / 3600, m = t / 60 % 60, sec = t % 60;
    char b[32];
    if (h) std::snprintf(b, sizeof b, "%ld:%02ld:%02ld", h, m, sec);
    else std::snprintf(b, sizeof b, "%ld:%02ld", m, sec);
    return b;
}

}  // namespace

std::function<void(size_t, size_t, const std::string&)> progress_printer() {
    const bool tty = isatty(STDERR_FILENO);
    const auto t0 = std::chrono::steady_clock::now();
    return [tty, t0](size_t step, size_t steps, const std::string& what) {
        const double secs =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::string line =
            "[" + std::to_string(step) + "/" + std::to_string(steps) + " " + clock_time(secs);
        if (step > 1)
            line +=
                ", ~" + clock_time(secs / double(step - 1) * double(steps - step + 1)) + " left";
        line += "] " + what;
        if (tty) std::cerr << "\r\033[K" << line << std::flush;
        else std::cerr << line << "\n";
    };
}

void end_progress() {
    if (isatty(STDERR_FILENO)) std::cerr << "\r\033[K";
}

void print_slice(const Slice& s, const nlohmann::json& rec) {
    std::cout << "shard " << s.shard.text() << ": " << s.mine.size() << " of " << s.units.size()
              << " units, " << std::setprecision(1) << std::fixed
              << 100.0 * rec["cost"].get<double>() / rec["cost_total"].get<double>()
              << "% of the estimated cost (pxh merge OUT DIR... joins the slices)\n";
}

}  // namespace pxh
