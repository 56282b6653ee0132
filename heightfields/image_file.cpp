// Height maps from image files through OpenImageIO.
#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "harness/error.h"
#include "heightfields/heightfields.h"

namespace pxh {
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

std::string one_line(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ';';
    while (!s.empty() && (s.back() == ';' || s.back() == ' ')) s.pop_back();
    return s;
}

}  // namespace

HeightField load_heightfield_file(const std::string& path, int channel) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path, "no such file");
    if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a directory");
    if (std::filesystem::file_size(path, ec) == 0) throw InputError(path, "empty file");
    QuietStderr quiet;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string msg = one_line(OIIO::geterror());
        if (msg.empty()) msg = "unknown format";
        throw InputError(path, "not a readable image (" + msg + ")");
    }
    const OIIO::ImageSpec spec = in->spec();
    const long long w = spec.width, h = spec.height;
    if (w < 1 || h < 1 || spec.nchannels < 1) throw InputError(path, "image has zero size");
    if (spec.depth > 1) throw InputError(path, "volume images are not height maps");
    if (w > kMaxImageSide || h > kMaxImageSide || w * h > kMaxImageTexels)
        throw InputError(path, "image is " + std::to_string(w) + " x " + std::to_string(h) +
                                   ", larger than the accepted " + std::to_string(kMaxImageSide) +
                                   " per side / " + std::to_string(kMaxImageTexels) + " texels");
    if (channel < 0 || channel >= spec.nchannels)
        throw InputError(path, "channel " + std::to_string(channel) + " requested, image has " +
                                   std::to_string(spec.nchannels));
    HeightField hf(int(w), int(h), std::filesystem::path(path).stem().string());
    // Integer formats are converted to float 0..max -> [0,1] by OpenImageIO; floats pass as is.
    if (!in->read_image(0, 0, channel, channel + 1, OIIO::TypeDesc::FLOAT, hf.texels.data())) {
        std::string msg = one_line(in->geterror());
        throw InputError(path, "cannot read pixels (truncated or corrupt?): " +
                                   (msg.empty() ? std::string("read failed") : msg));
    }
    in->close();
    const std::string fmt = in->format_name();
    // OpenImageIO presents PFM top row first; a PFM stores the bottom row first. The spec
    // takes the first stored row as j = 0, so undo OpenImageIO's flip for PFM.
    if (fmt == "pnm" && (spec.format == OIIO::TypeDesc::FLOAT)) {
        for (int j = 0; j < hf.height / 2; ++j)
            for (int i = 0; i < hf.width; ++i) std::swap(hf.at(i, j), hf.at(i, hf.height - 1 - j));
    }
    hf.validate(path);
    return hf;
}

void save_heightfield_file(const HeightField& hf, const std::string& path) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw InputError(path, "cannot write this image format: " + OIIO::geterror());
    const std::string ext = std::filesystem::path(path).extension().string();
    const bool integer = ext == ".png" || ext == ".tif" || ext == ".tiff";
    OIIO::ImageSpec spec(hf.width, hf.height, 1,
                         integer ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::FLOAT);
    if (!out->open(path, spec) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, hf.texels.data()) || !out->close())
        throw InputError(path, "cannot write image: " + out->geterror());
}

}  // namespace pxh
