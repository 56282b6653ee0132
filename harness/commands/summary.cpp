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

namespace pxh {
namespace {

// Four significant digits ("12.35", "0.8125", "1234").
std::string time_cell(double v) {
    std::ostringstream os;
    os << std::setprecision(4) << v;
    return os.str();
}

}  // namespace

void print_summary(const std::vector<ResultRow>& rows) {
    struct Acc {
        double sum_mean = 0, worst_p95 = 0, fetches = 0, time = 0, shadow = 0;
        int n = 0, n_time = 0, n_shadow = 0, failed = 0;
        std::string unit;  // the series' time_unit (one backend: one unit)
    };
    std::vector<std::string> order;
    std::map<std::string, Acc> acc;
    for (const auto& r : rows) {
        const std::string key = series_of(r);
        if (!acc.count(key)) order.push_back(key);
        Acc& a = acc[key];
        if (!r.ok()) {
            ++a.failed;
            continue;
        }
        a.sum_mean += r.num("err_mean");
        a.worst_p95 = std::max(a.worst_p95, r.num("err_p95"));
        a.fetches += r.num("fetches_mean");
        ++a.n;
        if (!std::isnan(r.num("time")) && (a.unit.empty() || a.unit == r.text("time_unit"))) {
            a.time += r.num("time");
            a.unit = r.text("time_unit");
            ++a.n_time;
        }
        if (!std::isnan(r.num("shadow_err"))) {
            a.shadow += r.num("shadow_err");
            ++a.n_shadow;
        }
    }
    auto cell = [](double sum, int n, int prec) {
        std::ostringstream os;
        if (n == 0) os << "-";
        else os << std::fixed << std::setprecision(prec) << sum / n;
        return os.str();
    };
    std::cout << std::left << std::setw(46) << "method [backend/precision or texture]" << std::right
              << std::setw(10) << "mean err" << std::setw(11) << "worst p95" << std::setw(9)
              << "fetches" << std::setw(20) << "time" << std::setw(8) << "shadow" << std::setw(8)
              << "failed"
              << "\n";
    for (const auto& k : order) {
        const Acc& a = acc[k];
        std::cout << std::left << std::setw(46) << k << std::right << std::setw(10)
                  << cell(a.sum_mean, a.n, 3) << std::setw(11) << cell(a.worst_p95, a.n ? 1 : 0, 3)
                  << std::setw(9) << cell(a.fetches, a.n, 1) << std::setw(20)
                  << (a.n_time ? time_cell(a.time / a.n_time) + " " + a.unit : "-") << std::setw(8)
                  << cell(a.shadow, a.n_shadow, 3) << std::setw(8) << a.failed << "\n";
    }
    std::cout << "mean err: texel distance between the sampled and the truly visible point, "
                 "averaged over rows; worst p95: largest per-row 95th percentile;\n"
                 "time: mean over rows of the median timed repeat, in the backend's unit (cpu: "
                 "single-thread ns/sample; glsl: ms/frame); shadow: fraction of samples with a "
                 "wrong hard shadow\n";
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
