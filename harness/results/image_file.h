// An image written as a new file of pxh's own: OpenImageIO (harness/core/image_codec.h) encodes
// it into memory, and harness/core/safe_files.h creates the file (never through a link, never
// over a file).
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/core/image_codec.h"
#include "harness/core/safe_files.h"

namespace pxh {

// W x H pixels of `channels` float channels (row-major, interleaved), stored as `type` ("uint8"
// or "float"); the format follows the file name's extension (.png, .exr). Throws
// std::runtime_error naming the file when encoding or writing fails.
inline void write_new_image(const std::vector<float>& px, int width, int height, int channels,
                            const char* type, const std::string& path) {
    std::string bytes, why;
    if (!image_codec().encode(path, width, height, channels, type, px.data(), bytes, why))
        throw std::runtime_error(path + ": " + why);
    create_new_file(path, bytes);
}

}  // namespace pxh
