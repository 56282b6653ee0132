// `pxh compare BASE NEW`: what changed between two runs (the work is harness/report/compare).
#include <iostream>
#include <memory>

#include "harness/commands/commands.h"
#include "harness/experiment/only_rows.h"
#include "harness/report/compare.h"
#include "harness/report/verdict.h"
#include "harness/results/run_folder.h"

namespace pxh {

Command add_compare_command(CLI::App& app) {
    auto* cmp = app.add_subcommand(
        "compare",
        "compare two results folders row by row (matched by every key: method, params, field, "
        "s, b, base, radius, view, camera keys, lod, depth, cut, backend, precision, format); "
        "exit 1 with --fail-on when "
        "NEW regresses, exit 2 when no row matched");
    struct Args {
        std::string base, now, fail_on, junit, json, only;
        bool markdown = false, accept_edited = false, common = false;
        std::vector<double> bands;
        std::vector<std::string> pairs;
    };
    auto a = std::make_shared<Args>();
    cmp->add_option("base", a->base, "the baseline results folder")->required();
    cmp->add_option("new", a->now, "the results folder to compare with it")->required();
    auto* fail_on = cmp->add_option(
        "--fail-on", a->fail_on,
        "tolerances, e.g. err_p95=+5%,err_mean=+0.01,fetches_mean=+0: exit 1 when a "
        "matched row grows beyond one (relative with %, else absolute), a row that "
        "was ok failed, or a BASE row is missing from NEW; time (in the row's "
        "time_unit) only when its repeats show it slower (Mann-Whitney U, Holm-corrected over "
        "the comparison: 5% false alarms per comparison) and its median grew beyond the "
        "margin; a gated column a run lacks fails the gate");
    cmp->add_flag("--markdown", a->markdown,
                  "Markdown output for a pull-request comment (the verdict first, the tables in a "
                  "collapsible <details> block)");
    cmp->add_flag("--common", a->common,
                  "compare only the rows both runs have (how many were left out is said; a BASE "
                  "row missing from NEW is then no regression)");
    cmp->add_option("--bands", a->bands,
                    "view-angle band edges in degrees (default 0,30,60,75,85,90)")
        ->delimiter(',');
    cmp->add_option("--only", a->only,
                    "compare only the rows of both runs that match: KEY=VALUE[|VALUE],... with "
                    "the keys and ranges of pxh run --only (e.g. base=cylinder,radius=1.5..4, "
                    "depth=hit,cut=0.3, distance_max=4); the rows left out are counted");
    cmp->add_option("--pair", a->pairs,
                    "NEW=BASE: match NEW's rows of method NEW with BASE's rows of method BASE "
                    "(a plug-in with the preset it reproduces; params are left out of the "
                    "match, so each side needs one setting per remaining key); repeatable");
    cmp->add_flag("--accept-edited", a->accept_edited, kAcceptEditedHelp);
    cmp->add_option("--junit", a->junit,
                    "also write the verdict as JUnit XML to FILE (a testcase per method setting "
                    "and backend variant; failures list the regressions with their values)");
    cmp->add_option("--json", a->json, "also write the verdict as JSON to FILE");
    return {cmp, [a, fail_on] {
                check_verdict_paths(a->junit, a->json);
                CompareOptions opt;
                opt.markdown = a->markdown;
                opt.common = a->common;
                opt.band_edges = a->bands;
                opt.junit = a->junit;
                opt.json = a->json;
                opt.only = a->only;
                for (const std::string& p : a->pairs) opt.pairs.push_back(parse_pair(p));
                if (!a->only.empty()) OnlyRows check(a->only);  // a bad spec: exit 2 first
                // Given is given: --fail-on "" is an error, not a gate switched off.
                if (fail_on->count()) opt.fail_on = parse_fail_on(a->fail_on);
                for (const std::string& d : {a->base, a->now})  // printed under the verdict
                    opt.notes.push_back(verify_results_folder(d, a->accept_edited));
                return run_compare(a->base, a->now, opt, std::cout);
            }};
}

}  // namespace pxh
