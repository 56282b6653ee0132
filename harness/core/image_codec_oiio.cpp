// The module libpxh_images.so: every call pxh makes to OpenImageIO (harness/core/image_codec.h
// says why it is a module). Plain data in and out; no exception leaves it.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <memory>
#include <string>

#include "harness/core/image_codec.h"

namespace pxh {

struct ImageReader {
    std::unique_ptr<OIIO::Filesystem::IOFile> proxy;  // the caller's FILE (open_file)
    std::unique_ptr<OIIO::ImageInput> in;
    bool quiet = false;  // image libraries' stderr silenced while reading
};

namespace {

// Image libraries (libpng) print to stderr on corrupt files before returning an error that
// OpenImageIO also reports: the stream is silenced while reading so the user sees one line.
class QuietStderr {
  public:
    explicit QuietStderr(bool on) {
        if (!on) return;
        std::fflush(stderr);
        saved_ = dup(STDERR_FILENO);
        const int null = open("/dev/null", O_WRONLY);
        if (saved_ >= 0 && null >= 0) dup2(null, STDERR_FILENO);
        if (null >= 0) close(null);
    }
    ~QuietStderr() {
        if (saved_ < 0) return;
        std::fflush(stderr);
        dup2(saved_, STDERR_FILENO);
        close(saved_);
    }
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

  private:
    int saved_ = -1;
};

// OpenImageIO's messages on one line.
std::string flat(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

OIIO::TypeDesc type_of(const char* name) {
    const std::string n = name;
    if (n == "uint8") return OIIO::TypeDesc::UINT8;
    if (n == "uint16") return OIIO::TypeDesc::UINT16;
    return OIIO::TypeDesc::FLOAT;
}

void describe(const OIIO::ImageSpec& s, ImageFileInfo& info) {
    info.width = s.width;
    info.height = s.height;
    info.channels = s.nchannels;
    info.depth = s.depth;
    info.deep = s.deep;
    info.tile_width = s.tile_width;
    info.tile_height = s.tile_height;
    info.pixel_bytes = s.pixel_bytes(true);
    info.floating = s.format.is_floating_point();
    info.type = s.format.c_str();
}

ImageReader* open_file(FILE* f, const char* format, const std::string& path, ImageFileInfo& info,
                       std::string& why) {
    QuietStderr quiet(true);
    std::rewind(f);
    auto r = std::make_unique<ImageReader>();
    r->quiet = true;
    r->proxy = std::make_unique<OIIO::Filesystem::IOFile>(f, OIIO::Filesystem::IOProxy::Read);
    OIIO::ImageSpec config;
    // Channel 0 as stored: without this hint OpenImageIO multiplies colour by alpha (PNG,
    // TIFF with unassociated alpha), so a gray image with an alpha ramp would read as a ramp.
    config.attribute("oiio:UnassociatedAlpha", 1);
    r->in = OIIO::ImageInput::create(format, false, &config, r->proxy.get());
    OIIO::ImageSpec spec;
    if (!r->in || !r->in->open(path, spec, config)) {
        why = flat(r->in ? r->in->geterror() : OIIO::geterror());
        if (why.empty()) why = "unknown error";
        return nullptr;
    }
    describe(spec, info);
    return r.release();
}

ImageReader* open_path(const std::string& path, ImageFileInfo& info, std::string& why) {
    auto r = std::make_unique<ImageReader>();
    r->in = OIIO::ImageInput::open(path);
    if (!r->in) {
        why = flat(OIIO::geterror());
        if (why.empty()) why = "unknown error";
        return nullptr;
    }
    describe(r->in->spec(), info);
    return r.release();
}

bool read(ImageReader* r, int first, int end, bool as_stored, void* dst, std::string& why) {
    QuietStderr quiet(r->quiet);
    const OIIO::TypeDesc t = as_stored ? r->in->spec().format : OIIO::TypeDesc::FLOAT;
    // Readers can return "success" with an error recorded (a truncated TIFF or JPEG), so the
    // error state is checked as well.
    const bool ok = r->in->read_image(0, 0, first, end, t, dst);
    if (ok && !r->in->has_error()) return true;
    why = flat(r->in->geterror());
    if (why.empty()) why = "read failed";
    return false;
}

bool close_reader(ImageReader* r, std::string& why) {
    std::unique_ptr<ImageReader> owned(r);
    QuietStderr quiet(r->quiet);
    r->in->close();
    if (!r->in->has_error()) return true;
    why = flat(r->in->geterror());
    return false;
}

bool write_file(const std::string& path, int width, int height, int channels, const char* type,
                const float* px, std::string& why) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
        why = "cannot write this image format: " + flat(OIIO::geterror());
        return false;
    }
    const OIIO::ImageSpec spec(width, height, channels, type_of(type));
    if (out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, px) && out->close())
        return true;
    why = "cannot write image: " + flat(out->geterror());
    return false;
}

bool encode(const std::string& path, int width, int height, int channels, const char* type,
            const float* px, std::string& bytes, std::string& why) {
    OIIO::ImageBuf img(OIIO::ImageSpec(width, height, channels, type_of(type)));
    if (!img.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px)) {
        why = flat(img.geterror());
        return false;
    }
    OIIO::Filesystem::IOVecOutput mem;
    img.set_write_ioproxy(&mem);
    const bool ok = img.write(path);
    img.set_write_ioproxy(nullptr);
    if (!ok) {
        why = flat(img.geterror());
        return false;
    }
    const auto& b = mem.buffer();
    bytes.assign(reinterpret_cast<const char*>(b.data()), b.size());
    return true;
}

bool render_text(std::vector<float>& px, int width, int height, int x, int y,
                 const std::string& text, int size, const std::string& font, const float rgb[3],
                 std::string& why) {
    OIIO::ImageBuf img(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT), px.data());
    if (OIIO::ImageBufAlgo::render_text(img, x, y, text, size, font, {rgb, 3})) return true;
    why = flat(img.geterror());
    return false;
}

const ImageCodec kCodec = {open_file,  open_path, read,       close_reader,
                           write_file, encode,    render_text};

}  // namespace
}  // namespace pxh

extern "C" __attribute__((visibility("default"))) const pxh::ImageCodec* pxh_image_codec() {
    return &pxh::kCodec;
}
