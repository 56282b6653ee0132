// Fuzz target: height images through pxh::load_heightfield_file (OpenImageIO), as an
// experiment's `file = "..."` is read. OpenImageIO picks its reader by the file name's
// extension (and probes the others when that one refuses the content), so the FIRST BYTE of an
// input chooses the name: its low 4 bits the extension (table below; the last entry, no
// extension, makes OpenImageIO probe every reader), bits 4-5 the requested channel. The rest
// of the input is the file. fuzz/make_image_seeds.sh writes the seeds in this form.
#include <OpenImageIO/imageio.h>

#include <exception>
#include <string>

#include "fuzz/fuzz_target.h"
#include "heightfields/heightfields.h"

namespace {
const char* const kExtensions[16] = {".png", ".pgm", ".pfm", ".exr", ".tif", ".hdr",
                                     ".ppm", ".bmp", ".tga", ".jpg", ".dds", ".psd",
                                     ".sgi", ".fits", ".rla", ""};
}  // namespace

PXH_FUZZ_TARGET(image) {
    if (size < 1) return 0;
    const std::string path = pxh::fuzz::write_scratch(
        std::string("height") + kExtensions[data[0] & 15], data + 1, size - 1);
    const int channel = (data[0] >> 4) & 3;
    try {
        (void)pxh::load_heightfield_file(path, channel);
    } catch (const std::exception&) {
        // Not an image, truncated, out of range, too large: refused (InputError), expected.
    }
    (void)OIIO::geterror();  // OpenImageIO keeps unread errors per thread: clear them
    return 0;
}
