#include "harness/report/report.h"

#include <filesystem>

#include "harness/report/report_data.h"

namespace pxh {

int run_report(const std::string& dir, const ReportOptions& options) {
    const ReportData d(dir, options);
    std::filesystem::create_directories(d.out / "data");
    write_summary(d);
    write_failed(d);
    write_sweep(d);
    write_precision(d);
    write_budget(d);
    write_plot_data(d);
    if (options.plots) run_plotter(d.out);
    return 0;
}

int run_report(const std::string& dir, bool plots) {
    ReportOptions o;
    o.plots = plots;
    return run_report(dir, o);
}

}  // namespace pxh
