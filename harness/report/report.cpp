#include "harness/report/report.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <optional>
#include <vector>

#include "harness/core/error.h"
#include "harness/report/families.h"
#include "harness/report/report_data.h"

namespace pxh {

int run_report(const std::string& dir, const ReportOptions& options) {
    const ReportData d(dir, options);
    // A file-size limit fails the write (reported, non-zero exit) instead of killing pxh.
    std::signal(SIGXFSZ, SIG_IGN);
    const OwnedFolder folder = OwnedFolder::open(d.out, "pxh report");
    folder.folder("data");
    // The figures' data first; the plot script draws while the tables are written.
    write_plot_data(d);
    write_families(d);
    std::optional<Plotter> plotter;
    if (options.plots) plotter.emplace(folder, options.figure_width, options.formats);
    write_summary(d);
    write_fields(d);
    write_legend(d);
    write_failed(d);
    write_sweep(d);
    write_precision(d);
    write_budget(d);
    if (plotter) plotter->finish();
    return 0;
}

void parse_figure_formats(const std::string& text) {
    std::vector<std::string> seen;
    size_t at = 0;
    while (true) {
        const size_t comma = text.find(',', at);
        const std::string f = text.substr(at, comma == std::string::npos ? comma : comma - at);
        if ((f != "png" && f != "pdf" && f != "svg") ||
            std::find(seen.begin(), seen.end(), f) != seen.end())
            throw InputError("--formats", "'" + text +
                                              "' is not a comma list of png, pdf, svg (each at "
                                              "most once)");
        seen.push_back(f);
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
}

double parse_figure_width(const std::string& text) {
    if (text == "single") return 3.5;
    if (text == "double") return 7.0;
    size_t used = 0;
    double v = NAN;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !(v >= 2 && v <= 20))
        throw InputError("--figure-width", "'" + text +
                                               "' is not single, double or a width in inches "
                                               "in [2, 20]");
    return v;
}

int run_report(const std::string& dir, bool plots) {
    ReportOptions o;
    o.plots = plots;
    return run_report(dir, o);
}

}  // namespace pxh
