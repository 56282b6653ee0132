// Fuzz target: height images through pxh::load_heightfield_file, as an experiment's
// `file = "..."` (with `channel`) is read. The loader recognises the format from the content
// (netpbm read by pxh; PNG, TIFF, OpenEXR, JPEG through OpenImageIO), not from the name. The
// FIRST BYTE of an input is the requested channel (its low 2 bits: 0-3); the rest of the
// input is the file. fuzz/make_image_seeds.sh writes the seeds in this form.
#include <OpenImageIO/imageio.h>

#include <exception>
#include <string>

#include "fuzz/fuzz_target.h"
#include "heightfields/heightfields.h"

PXH_FUZZ_TARGET(image) {
    if (size < 1) return 0;
    const int channel = data[0] & 3;
    const std::string path = pxh::fuzz::write_scratch("height.img", data + 1, size - 1);
    try {
        (void)pxh::load_heightfield_file(path, channel);
    } catch (const std::exception&) {
        // Not an image, truncated, out of range, too large: refused (InputError), expected.
    }
    (void)OIIO::geterror();  // OpenImageIO keeps unread errors per thread: clear them
    return 0;
}
