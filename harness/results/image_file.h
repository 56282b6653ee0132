// An image written as a new file of pxh's own: OpenImageIO encodes it into memory (an IOProxy),
// and harness/core/safe_files.h creates the file (never through a link, never over a file).
#pragma once
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>

#include <stdexcept>
#include <string>
#include <string_view>

#include "harness/core/safe_files.h"

namespace pxh {

// The format follows the file name's extension (.png, .exr). Throws std::runtime_error naming
// the file when encoding or writing fails.
inline void write_new_image(OIIO::ImageBuf& img, const std::string& path) {
    OIIO::Filesystem::IOVecOutput mem;
    img.set_write_ioproxy(&mem);
    const bool ok = img.write(path);
    img.set_write_ioproxy(nullptr);
    if (!ok) throw std::runtime_error(path + ": " + img.geterror());
    const auto& bytes = mem.buffer();
    create_new_file(path,
                    std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace pxh
