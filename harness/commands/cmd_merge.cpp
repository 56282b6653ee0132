// `pxh merge OUT DIR...`: its options and help; the merge itself is harness/run/merge.h's.
#include <memory>

#include "harness/commands/commands.h"
#include "harness/run/merge.h"

namespace pxh {

Command add_merge_command(CLI::App& app, const std::string& command_line) {
    auto* merge = app.add_subcommand(
        "merge",
        "join the slices of a sharded run (pxh run --shard I/N) into one results folder "
        "(exit 0: all rows ok; 1: some row failed, results written; 2: bad input, nothing "
        "written)");
    auto a = std::make_shared<MergeRequest>();
    merge
        ->add_option("out", a->out,
                     "results folder to write; must not exist, be empty, or (with --force) "
                     "hold earlier pxh results")
        ->required();
    merge->add_option("dirs", a->dirs, "the slices' results folders, every shard 0..N-1 once")
        ->required();
    merge->add_flag("--force", a->force,
                    "replace the earlier pxh results in OUT (only pxh's own files there)");
    return {merge, [a, &command_line] { return merge_slices(*a, command_line); }};
}

}  // namespace pxh
