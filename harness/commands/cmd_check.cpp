// `pxh check DIR --thresholds FILE`: the accuracy gate (the work is harness/report).
#include <iostream>
#include <memory>

#include "harness/commands/commands.h"
#include "harness/report/report.h"
#include "harness/report/verdict.h"
#include "harness/results/run_folder.h"

namespace pxh {

Command add_check_command(CLI::App& app) {
    auto* check = app.add_subcommand("check",
                                     "check a results folder against accuracy limits; "
                                     "exit 1 if any fails");
    struct Args {
        std::string dir, thresholds, junit, json;
        bool accept_edited = false;
    };
    auto a = std::make_shared<Args>();
    check->add_option("dir", a->dir, "results folder (holding results.csv)")->required();
    check->add_option("--thresholds", a->thresholds, "thresholds file (TOML, [[limit]] tables)")
        ->required();
    check->add_flag("--accept-edited", a->accept_edited, kAcceptEditedHelp);
    check->add_option("--junit", a->junit,
                      "also write the verdict as JUnit XML to FILE (a testcase per limit; a "
                      "failure names the worst row and its value)");
    check->add_option("--json", a->json, "also write the verdict as JSON to FILE");
    return {check, [a] {
                check_verdict_paths(a->junit, a->json);
                // A CI gate passes only on the results a run wrote (run.json's sha256 and rows).
                const std::string verified = verify_results_folder(a->dir, a->accept_edited);
                std::cout << verified << "\n";
                const int rc = run_check(a->dir, a->thresholds, {a->junit, a->json});
                if (verified.rfind("NOT VERIFIED", 0) == 0)
                    std::cout << "results NOT VERIFIED: " << a->dir
                              << " differs from its run.json\n";
                return rc;
            }};
}

}  // namespace pxh
