// PNG, TIFF, OpenEXR and JPEG read through OpenImageIO (harness/core/image_codec.h: from the
// file already opened and checked, library chatter on stderr silenced, the error state checked
// after the read), and a height field written as an image file.
#include <filesystem>

#include "harness/core/image_codec.h"
#include "heightfields/image_read.h"

namespace pxh {
namespace image_detail {

HeightField read_with_oiio(FILE* f, const char* format, const std::string& path,
                           const std::string& where, const std::string& name, int channel) {
    const ImageCodec& codec = image_codec();
    ImageFileInfo spec;
    std::string why;
    ImageReader* in = codec.open_file(f, format, path, spec, why);
    if (!in) throw InputError(where, "not a readable image (" + why + ")");
    struct Closer {  // closes the reader on every way out
        const ImageCodec& c;
        ImageReader*& r;
        ~Closer() {
            std::string ignored;
            if (r) c.close(r, ignored);
        }
    } closer{codec, in};
    if (spec.deep) throw InputError(where, "deep images are not height maps");
    if (spec.depth > 1) throw InputError(where, "volume images are not height maps");
    check_size(where, "image", spec.width, spec.height, spec.channels, spec.pixel_bytes);
    if (spec.tile_width > 0)
        check_size(where, "tile", spec.tile_width, spec.tile_height, spec.channels,
                   spec.pixel_bytes);
    check_channel(where, channel, spec.channels);
    // The field starts zero-filled; integer formats are converted to float 0..max -> [0,1] by
    // OpenImageIO, floats pass as they are.
    HeightField hf(spec.width, spec.height, name);
    if (!codec.read(in, channel, channel + 1, false, hf.texels.data(), why))
        throw InputError(where, "cannot read pixels (truncated or corrupt?): " + why);
    ImageReader* done = in;
    in = nullptr;
    if (!codec.close(done, why)) throw InputError(where, "cannot read pixels: " + why);
    return hf;
}

}  // namespace image_detail

void save_heightfield_file(const HeightField& hf, const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    const bool integer = ext == ".png" || ext == ".tif" || ext == ".tiff";
    std::string why;
    if (!image_codec().write_file(path, hf.width, hf.height, 1, integer ? "uint16" : "float",
                                  hf.texels.data(), why))
        throw InputError(path, why);
}

}  // namespace pxh
