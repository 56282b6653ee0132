// Files pxh ships beside its binary (the plot script): found relative to the running
// executable, never through a source path compiled in, so a build tree and an installed tree
// (cmake --install) both work wherever they are moved.
#pragma once
#include <string>

namespace pxh {

// The path of NAME shipped with pxh: EXE_DIR/NAME (the build tree: CMake copies it next to
// the binaries at configure time), else EXE_DIR/PXH_INSTALL_DATA_REL/NAME (an installed tree:
// PREFIX/bin/pxh and PREFIX/share/pxh/NAME). EXE_DIR is the folder of /proc/self/exe. Throws
// std::runtime_error, one line naming both places, when neither holds it.
std::string shipped_file(const std::string& name);

}  // namespace pxh
