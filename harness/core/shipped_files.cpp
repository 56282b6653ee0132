#include "harness/core/shipped_files.h"

#include <filesystem>
#include <stdexcept>
#include <system_error>

#ifndef PXH_INSTALL_DATA_REL
#define PXH_INSTALL_DATA_REL "../share/pxh"  // CMake passes it: CMAKE_INSTALL_DATADIR/pxh from bin
#endif

namespace pxh {

std::string shipped_file(const std::string& name) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw std::runtime_error("cannot find " + name + ": /proc/self/exe: " + ec.message());
    const fs::path beside = exe.parent_path() / name;
    const fs::path installed = (exe.parent_path() / PXH_INSTALL_DATA_REL / name).lexically_normal();
    for (const fs::path& p : {beside, installed})
        if (fs::is_regular_file(p, ec)) return p.string();
    throw std::runtime_error(
        name + " not found: looked for " + beside.string() + " (build tree) and " +
        installed.string() +
        " (installed tree); rebuild, or reinstall with "
        "cmake --install (the tables are written; --no-plots skips the plots)");
}

}  // namespace pxh
