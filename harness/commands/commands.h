// The pxh commands: each file cmd_NAME.cpp registers one subcommand (its options and help) on
// the CLI11 app and returns what runs it. main.cpp registers them in the order --help lists
// them, parses, and runs the chosen one. One more command = one cmd_NAME.cpp + one line in
// main.cpp's list.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace pxh {

struct Command {
    CLI::App* app = nullptr;   // the subcommand (true when chosen on the command line)
    std::function<int()> run;  // its exit code; throws InputError (exit 2) on bad input
};

// `command_line` is the whole command line as typed (run.json records it); it is filled in
// before any command runs.
Command add_run_command(CLI::App& app, const std::string& command_line);
Command add_list_command(CLI::App& app);
Command add_bench_command(CLI::App& app);
Command add_report_command(CLI::App& app);
Command add_check_command(CLI::App& app);
Command add_import_command(CLI::App& app);
Command add_compare_command(CLI::App& app);
Command add_merge_command(CLI::App& app, const std::string& command_line);

// Shared by report and check.
inline constexpr const char* kAcceptEditedHelp =
    "use a results folder whose files differ from what its run recorded in run.json "
    "(e.g. a post-processed results.csv); the output then says NOT VERIFIED";

}  // namespace pxh
