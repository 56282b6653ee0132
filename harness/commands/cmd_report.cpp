// `pxh report DIR`: tables and plots from a results folder (the work is harness/report).
#include <iostream>
#include <memory>

#include "harness/commands/commands.h"
#include "harness/report/report.h"
#include "harness/results/run_folder.h"

namespace pxh {

Command add_report_command(CLI::App& app) {
    auto* report =
        app.add_subcommand("report",
                           "tables (Markdown, LaTeX, CSV) and plots (PNG and PDF; SVG on request) "
                           "from a results folder, into DIR/report/");
    struct Args {
        std::string dir;
        bool no_plots = false;
        std::string figure_width = "double";
        ReportOptions ro;
    };
    auto a = std::make_shared<Args>();
    report->add_option("dir", a->dir, "results folder (holding results.csv)")->required();
    report->add_flag("--no-plots", a->no_plots, "tables only (no matplotlib needed)");
    report->add_flag("--accept-edited", a->ro.accept_edited, kAcceptEditedHelp);
    report
        ->add_option("--bands", a->ro.bands,
                     "view-angle band edges in degrees, ascending in [0, 90] (default "
                     "0,30,60,75,85,90); bands are [lo, hi), the last one closed")
        ->delimiter(',');
    report->add_option("--budget-metric", a->ro.budget_metric,
                       "error the budget table ranks by: p95, p99 (texels) or frac_gt_1 "
                       "(fraction of samples more than 1 texel off); default p95");
    report->add_option("--figure-width", a->figure_width,
                       "figure width: single (3.5 in), double (7 in, default) or inches in "
                       "[2, 20]; fonts stay 8 pt");
    report->add_option("--formats", a->ro.formats,
                       "figure files: a comma list of png, pdf, svg (default png,pdf: PNG for "
                       "the screen, PDF for papers; the vector figure is written once)");
    return {report, [a] {
                a->ro.figure_width = parse_figure_width(a->figure_width);
                parse_figure_formats(a->ro.formats);
                std::cout << verify_results_folder(a->dir, a->ro.accept_edited) << "\n";
                a->ro.plots = !a->no_plots;
                return run_report(a->dir, a->ro);
            }};
}

}  // namespace pxh
