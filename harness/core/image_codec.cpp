// Loads libpxh_images.so on first use (harness/core/image_codec.h).
#include "harness/core/image_codec.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <filesystem>
#include <stdexcept>

namespace pxh {
namespace {

namespace fs = std::filesystem;

// The folder of the running binary (pxh, a test binary or the GL worker).
std::string binary_folder() {
    char buf[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return ".";
    buf[n] = 0;
    return fs::path(buf).parent_path().string();
}

const ImageCodec* load() {
    const std::string dir = binary_folder();
    // beside the binary (the build folder), then where install puts it (PXH_IMAGES_INSTALLED:
    // the library folder relative to the binaries' folder)
    const std::string tried[] = {dir + "/libpxh_images.so",
                                 dir + "/" PXH_IMAGES_INSTALLED "/libpxh_images.so"};
    std::string why;
    for (const std::string& path : tried) {
        if (!fs::exists(path)) continue;
        void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!h) {
            why += std::string("; ") + dlerror();
            continue;
        }
        const auto entry = reinterpret_cast<ImageCodecEntry>(dlsym(h, "pxh_image_codec"));
        if (!entry) {
            why += "; " + path + " has no pxh_image_codec";
            continue;
        }
        return entry();
    }
    throw std::runtime_error("cannot load pxh's image module (OpenImageIO): tried " + tried[0] +
                             " and " + tried[1] + (why.empty() ? ": neither exists" : why) +
                             "; rebuild (./run.sh) or reinstall pxh");
}

}  // namespace

const ImageCodec& image_codec() {
    static const ImageCodec* const codec = load();  // a throw leaves it to the next call
    return *codec;
}

bool read_image_pixels(const std::string& path, ImagePixels& out, std::string& why, int max_side) {
    const ImageCodec& c = image_codec();
    ImageReader* r = c.open_path(path, out.info, why);
    if (!r) return false;
    std::string ignored;
    if (out.info.width < 1 || out.info.height < 1 || out.info.channels < 1) {
        why = "holds no pixels";
        c.close(r, ignored);
        return false;
    }
    if (out.info.width > max_side || out.info.height > max_side) {
        why = "is larger than " + std::to_string(max_side) + " pixels a side";
        c.close(r, ignored);
        return false;
    }
    out.px.assign(size_t(out.info.width) * size_t(out.info.height) * size_t(out.info.channels), 0);
    const bool ok = c.read(r, 0, out.info.channels, false, out.px.data(), why);
    std::string close_why;
    const bool closed = c.close(r, close_why);
    if (ok && !closed) why = close_why;
    return ok && closed;
}

}  // namespace pxh
