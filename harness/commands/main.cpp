// pxh: measures how wrong parallax-mapping methods are against exact ground truth.
#include <cstdlib>
#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/backends/gl_worker.h"
#include "harness/commands/commands.h"
#include "harness/core/error.h"
#include "harness/core/safe_files.h"
#include "harness/results/provenance.h"
#include "harness/truth/exact_tracer.h"

using namespace pxh;

int main(int argc, char** argv) {
    // A GL process that pxh started (harness/backends/gl_worker.h): nothing else of main's.
    if (argc == 3 && std::string(argv[1]) == kGlWorkerArg) gl_worker_main(argv[2]);
    // pxh's GL work runs in a fresh pxh of its own.
    set_gl_worker_program("/proc/self/exe");
    // A closed pipe or a file-size limit fails the write (reported), never ends pxh silently.
    ignore_write_signals();
    CLI::App app{
        "pxh: measures how far parallax-mapping methods are from the true displaced "
        "surface, and what they cost"};
    app.require_subcommand(1);
    app.set_version_flag("--version", [] { return "pxh " + pxh_version(); });

    std::string command_line;  // as typed (run.json records it)
    for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
    // In the order --help lists them.
    const std::vector<Command> commands = {add_run_command(app, command_line),
                                           add_list_command(app),
                                           add_bench_command(app),
                                           add_report_command(app),
                                           add_check_command(app),
                                           add_compare_command(app),
                                           add_merge_command(app, command_line),
                                           add_import_command(app)};

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line in pxh's own format, like every other error.
        std::cerr << "pxh: error: " << one_line(e.what()) << " (see pxh --help)\n";
        return 2;
    }
    // The environment's tracer path is input like the command line: a value that names no
    // path is refused before any work (exit 2), whichever command would trace.
    if (const char* env = std::getenv("PXH_TRACER_PATH"); env && *env) {
        try {
            ExactTracer::default_path();
        } catch (const std::invalid_argument& e) {
            std::cerr << "pxh: error: " << one_line(e.what())
                      << " (unset it for the CPU's best path)\n";
            return 2;
        }
    }
    try {
        for (const auto& c : commands)
            if (*c.app) return c.run();
    } catch (const InputError& e) {
        std::cerr << "pxh: error: " << one_line(e.what()) << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "pxh: error: " << one_line(e.what()) << "\n";
        return 1;
    }
    return 0;
}
