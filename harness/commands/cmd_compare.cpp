// `pxh compare BASE NEW`: what changed between two runs (the work is harness/report/compare).
#include <iostream>
#include <memory>

#include "harness/commands/commands.h"
#include "harness/report/compare.h"
#include "harness/results/run_folder.h"

namespace pxh {

Command add_compare_command(CLI::App& app) {
    auto* cmp = app.add_subcommand(
        "compare",
        "compare two results folders row by row (matched by method, params, field, s, b, view, "
        "backend, precision, format); exit 1 with --fail-on when NEW regresses");
    struct Args {
        std::string base, now, fail_on;
        bool markdown = false, accept_edited = false;
        std::vector<double> bands;
    };
    auto a = std::make_shared<Args>();
    cmp->add_option("base", a->base, "the baseline results folder")->required();
    cmp->add_option("new", a->now, "the results folder to compare with it")->required();
    cmp->add_option("--fail-on", a->fail_on,
                    "tolerances, e.g. err_p95=+5%,err_mean=+0.01,fetches_mean=+0: exit 1 when a "
                    "matched row grows beyond one (relative with %, else absolute), a row that "
                    "was ok failed, or a BASE row is missing from NEW");
    cmp->add_flag("--markdown", a->markdown, "Markdown output (e.g. for a pull-request comment)");
    cmp->add_option("--bands", a->bands,
                    "view-angle band edges in degrees (default 0,30,60,75,85,90)")
        ->delimiter(',');
    cmp->add_flag("--accept-edited", a->accept_edited, kAcceptEditedHelp);
    return {cmp, [a] {
                CompareOptions opt;
                opt.markdown = a->markdown;
                opt.band_edges = a->bands;
                if (!a->fail_on.empty()) opt.fail_on = parse_fail_on(a->fail_on);
                for (const std::string& d : {a->base, a->now})
                    std::cout << verify_results_folder(d, a->accept_edited) << "\n";
                return run_compare(a->base, a->now, opt, std::cout);
            }};
}

}  // namespace pxh
