// `pxh import`: the scanned height fields from Debian packages (the work is heightfields/scanned).
#include <memory>

#include "harness/commands/commands.h"
#include "heightfields/scanned.h"

namespace pxh {

Command add_import_command(CLI::App& app) {
    auto* import = app.add_subcommand("import",
                                      "import the scanned height fields from Debian "
                                      "packages into heightfields/scanned/");
    auto io = std::make_shared<ImportOptions>();
    import->add_option("--out", io->out_dir, "output folder (default heightfields/scanned)");
    import->add_option("--cache", io->cache_dir, "package cache (default build/scan-cache)");
    import->add_flag("--check", io->check,
                     "re-import and compare with the committed files (exit 1 "
                     "if they differ)");
    return {import, [io] { return run_import(*io); }};
}

}  // namespace pxh
