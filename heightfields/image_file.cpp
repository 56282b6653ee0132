// Height maps from image files: the file opened and its format recognised here, then read by
// OpenImageIO (PNG, TIFF, OpenEXR, JPEG: image_oiio.cpp), by libpng (the plain PNG layouts,
// grey or RGB at 8 or 16 bits without transparency, to the same floats as OpenImageIO:
// image_png.cpp) or by pxh (the netpbm family, PGM, PPM, PBM and PFM: image_netpbm.cpp).
// Nothing else is accepted.
//
// Every file is treated as possibly hostile. Before a reader sees it:
// - it must be a regular file (after following symlinks): a FIFO would block forever and
//   /dev/zero would be read forever;
// - its format is recognised from its first bytes, not its name;
// - the size it claims is checked against the limits in harness/scene/heightfield.h. OpenImageIO
//   reports the header of PNG, TIFF and JPEG without allocating pixels; OpenEXR believes the
//   sizes its header states (an attribute claiming 2 GB is allocated before the read fails),
//   so an OpenEXR header is walked first (image_headers.cpp), every size checked against the file's
//   length.
// Pixels are read into a zero-filled field, and the reader's error state is checked after the
// read: a truncated TIFF or JPEG returns "success" with an error recorded. Alpha never scales
// the height. Netpbm files are read by pxh because OpenImageIO went through 8 or 16 bits for
// other maxvals (5 of 10 read as 0.498), clamped samples above maxval, read maxval 0 as ones
// and a PFM scale of 0 as zeros.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "heightfields/image_read.h"

namespace pxh {
namespace image_detail {

std::string flat(const std::string& s) {
    constexpr size_t kMax = 400;
    std::string r;
    for (char c : s) {
        if (c == '\n' || c == '\r') {
            if (!r.empty() && r.back() != ' ') r += "; ";
        } else {
            r += c;
        }
    }
    while (!r.empty() && (r.back() == ' ' || r.back() == ';')) r.pop_back();
    if (r.size() > kMax) r = r.substr(0, kMax) + " ...";
    return r;
}

void check_size(const std::string& where, const char* what, long long w, long long h,
                long long channels, long long pixel_bytes) {
    if (w < 1 || h < 1 || channels < 1)
        throw InputError(where, std::string(what) + " has zero size");
    if (w > kMaxImageSide || h > kMaxImageSide || w * h > kMaxImageTexels)
        throw InputError(where, std::string(what) + " is " + num(w) + " x " + num(h) +
                                    ", larger than the accepted " + num(kMaxImageSide) +
                                    " per side / " + num(kMaxImageTexels) + " texels");
    if (channels > kMaxImageChannels)
        throw InputError(where, "image has " + num(channels) +
                                    " channels, more than the accepted " + num(kMaxImageChannels));
    if (w * h * pixel_bytes > kMaxImageBytes)
        throw InputError(where, std::string(what) + " holds " + num(w * h * pixel_bytes) +
                                    " bytes uncompressed (" + num(channels) +
                                    " channels), more than the accepted " + num(kMaxImageBytes));
}

void check_channel(const std::string& where, int channel, int channels) {
    if (channel < 0 || channel >= channels)
        throw InputError(where,
                         "channel " + num(channel) + " requested, image has " + num(channels));
}

}  // namespace image_detail

namespace {

using namespace image_detail;

struct FileCloser {
    void operator()(FILE* f) const { std::fclose(f); }
};

// Opens `path` for reading if it is a non-empty regular file (symlinks followed).
std::unique_ptr<FILE, FileCloser> open_regular_file(const std::string& path,
                                                    const std::string& where, long long& size) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw InputError(where, "no such file");
        throw InputError(where, std::string("cannot open: ") + std::strerror(errno));
    }
    auto kind = [](const struct stat& s) -> const char* {
        if (S_ISREG(s.st_mode)) return nullptr;
        if (S_ISDIR(s.st_mode)) return "is a directory";
        if (S_ISFIFO(s.st_mode)) return "is a FIFO, not a regular file";
        if (S_ISCHR(s.st_mode)) return "is a character device, not a regular file";
        if (S_ISBLK(s.st_mode)) return "is a block device, not a regular file";
        if (S_ISSOCK(s.st_mode)) return "is a socket, not a regular file";
        return "is not a regular file";
    };
    if (const char* k = kind(st)) throw InputError(where, k);
    // O_NONBLOCK: should the path have become a FIFO since stat, open does not wait; fstat
    // below refuses it.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw InputError(where, std::string("cannot open: ") + std::strerror(errno));
    if (::fstat(fd, &st) != 0 || kind(st) != nullptr) {
        ::close(fd);
        throw InputError(where, "is not a regular file");
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::unique_ptr<FILE, FileCloser> f(::fdopen(fd, "rb"));
    if (!f) {
        ::close(fd);
        throw InputError(where, std::string("cannot open: ") + std::strerror(errno));
    }
    size = st.st_size;
    if (size == 0) throw InputError(where, "empty file");
    return f;
}

}  // namespace

HeightField load_heightfield_file(const std::string& path, int channel) {
    const std::string& where = path;
    long long size = 0;
    auto file = open_regular_file(path, where, size);
    unsigned char m[8] = {};
    const size_t got = std::fread(m, 1, sizeof m, file.get());
    std::rewind(file.get());
    auto starts = [&](const char* magic, size_t n) {
        return got >= n && std::memcmp(m, magic, n) == 0;
    };
    const std::string name = std::filesystem::path(path).stem().string();
    Reader reader(file.get(), size, where);
    HeightField hf;
    try {
        if (got >= 3 && m[0] == 'P' && m[1] != 0 && std::strchr("123456fF", m[1]) &&
            pnm_space(m[2])) {
            hf = read_netpbm(reader, name, channel);
        } else if (starts("\x89PNG\r\n\x1a\n", 8)) {
            const PngLayout layout = check_png_chunks(reader);
            hf = png_plain(layout) ? read_png_plain(file.get(), layout, where, name, channel)
                                   : read_with_oiio(file.get(), "png", path, where, name, channel);
        } else if (starts("II*\0", 4) || starts("MM\0*", 4) || starts("II+\0", 4) ||
                   starts("MM\0+", 4)) {
            hf = read_with_oiio(file.get(), "tiff", path, where, name, channel);
        } else if (starts("\x76\x2f\x31\x01", 4)) {
            check_exr_header(reader);
            hf = read_with_oiio(file.get(), "openexr", path, where, name, channel);
        } else if (starts("\xff\xd8\xff", 3)) {
            hf = read_with_oiio(file.get(), "jpeg", path, where, name, channel);
        } else {
            throw InputError(where,
                             "not a readable image (not a PNG, TIFF, OpenEXR, JPEG, "
                             "PGM/PPM/PBM or PFM file)");
        }
    } catch (const std::bad_alloc&) {
        throw InputError(where, "not enough memory to read the image");
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(where, "cannot read the image (" + flat(e.what()) + ")");
    }
    hf.validate(where);
    return hf;
}

}  // namespace pxh
