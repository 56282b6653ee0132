// PNG, TIFF, OpenEXR and JPEG read through OpenImageIO (from the file already opened and
// checked, library chatter on stderr silenced, the error state checked after the read), and a
// height field written as an image file.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <filesystem>

#include "heightfields/image_read.h"

namespace pxh {
namespace image_detail {
namespace {

// Image libraries (libpng) print to stderr on corrupt files before returning an error that
// OpenImageIO also reports: silence the stream while reading so the user sees one line.
class QuietStderr {
  public:
    QuietStderr() {
        std::fflush(stderr);
        saved_ = dup(STDERR_FILENO);
        const int null = open("/dev/null", O_WRONLY);
        if (saved_ >= 0 && null >= 0) dup2(null, STDERR_FILENO);
        if (null >= 0) close(null);
    }
    ~QuietStderr() {
        std::fflush(stderr);
        if (saved_ >= 0) {
            dup2(saved_, STDERR_FILENO);
            close(saved_);
        }
    }

  private:
    int saved_ = -1;
};

}  // namespace

HeightField read_with_oiio(FILE* f, const char* format, const std::string& path,
                           const std::string& where, const std::string& name, int channel) {
    QuietStderr quiet;
    std::rewind(f);
    // OpenImageIO reads the file already opened (and checked) here, through a proxy.
    OIIO::Filesystem::IOFile proxy(f, OIIO::Filesystem::IOProxy::Read);
    OIIO::ImageSpec config;
    // Channel 0 as stored: without this hint OpenImageIO multiplies colour by alpha (PNG,
    // TIFF with unassociated alpha), so a gray image with an alpha ramp would read as a ramp.
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::create(format, false, &config, &proxy);
    OIIO::ImageSpec spec;
    if (!in || !in->open(path, spec, config)) {
        std::string msg = flat(in ? in->geterror() : OIIO::geterror());
        if (msg.empty()) msg = "unknown error";
        throw InputError(where, "not a readable image (" + msg + ")");
    }
    if (spec.deep) throw InputError(where, "deep images are not height maps");
    if (spec.depth > 1) throw InputError(where, "volume images are not height maps");
    check_size(where, "image", spec.width, spec.height, spec.nchannels, spec.pixel_bytes(true));
    if (spec.tile_width > 0)
        check_size(where, "tile", spec.tile_width, spec.tile_height, spec.nchannels,
                   spec.pixel_bytes(true));
    check_channel(where, channel, spec.nchannels);
    // The field starts zero-filled; integer formats are converted to float 0..max -> [0,1] by
    // OpenImageIO, floats pass as they are. Readers can return "success" with an error
    // recorded (a truncated TIFF or JPEG), so the error state is checked as well.
    HeightField hf(spec.width, spec.height, name);
    const bool ok =
        in->read_image(0, 0, channel, channel + 1, OIIO::TypeDesc::FLOAT, hf.texels.data());
    if (!ok || in->has_error()) {
        std::string msg = flat(in->geterror());
        throw InputError(where, "cannot read pixels (truncated or corrupt?): " +
                                    (msg.empty() ? std::string("read failed") : msg));
    }
    in->close();
    if (in->has_error()) throw InputError(where, "cannot read pixels: " + flat(in->geterror()));
    return hf;
}

}  // namespace image_detail

void save_heightfield_file(const HeightField& hf, const std::string& path) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out)
        throw InputError(path,
                         "cannot write this image format: " + image_detail::flat(OIIO::geterror()));
    const std::string ext = std::filesystem::path(path).extension().string();
    const bool integer = ext == ".png" || ext == ".tif" || ext == ".tiff";
    OIIO::ImageSpec spec(hf.width, hf.height, 1,
                         integer ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::FLOAT);
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, hf.texels.data()) ||
        !out->close())
        throw InputError(path, "cannot write image: " + image_detail::flat(out->geterror()));
}

}  // namespace pxh
