// Shared by the image-file readers (heightfields/image_file.cpp and the image_*.cpp beside it):
// a file read without believing a size (Reader), the size limits, library errors on one line,
// and each format's reader or header check.
#pragma once
#include <sys/types.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"

namespace pxh::image_detail {

inline std::string num(long long v) { return std::to_string(v); }

// Error text from a library on one line: line breaks become "; " (InputError escapes any
// other control character), and at most 400 characters are kept (a reader can report one
// error per strip).
std::string flat(const std::string& s);

// The size limits of harness/scene/heightfield.h for a W x H image of `channels` channels taking
// `pixel_bytes` bytes per pixel (all channels, as stored). `what` is "image" or "tile".
void check_size(const std::string& where, const char* what, long long w, long long h,
                long long channels, long long pixel_bytes);
void check_channel(const std::string& where, int channel, int channels);

// Sequential reading of an open regular file that never believes a size: every read is
// checked against the file's length first, so a field claiming more bytes than the file
// holds is refused before anything is allocated for it.
class Reader {
  public:
    Reader(FILE* f, long long size, std::string where)
        : f_(f), size_(size), where_(std::move(where)) {}
    long long left() const { return size_ - pos_; }
    const std::string& where() const { return where_; }
    [[noreturn]] void fail(const std::string& what) const { throw InputError(where_, what); }
    [[noreturn]] void truncated(const std::string& what) const {
        fail(what + " runs past the end of the file (truncated or corrupt)");
    }
    // -1 at the end of the file.
    int get() {
        const int c = std::getc(f_);
        if (c != EOF) ++pos_;
        return c;
    }
    int peek() {
        const int c = std::getc(f_);
        if (c != EOF) std::ungetc(c, f_);
        return c;
    }
    void read(void* out, long long n, const std::string& what) {
        if (n < 0 || n > left()) truncated(what);
        if (std::fread(out, 1, size_t(n), f_) != size_t(n)) truncated(what);
        pos_ += n;
    }
    void skip(long long n, const std::string& what) {
        if (n < 0 || n > left()) truncated(what);
        if (fseeko(f_, off_t(pos_ + n), SEEK_SET) != 0) truncated(what);
        pos_ += n;
    }
    uint32_t u32le(const std::string& what) {
        unsigned char b[4];
        read(b, 4, what);
        return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    }
    int32_t i32le(const std::string& what) { return int32_t(u32le(what)); }
    // A NUL-terminated string of at most `max` characters.
    std::string cstring(size_t max, const std::string& what) {
        std::string s;
        for (;;) {
            const int c = get();
            if (c == EOF) truncated(what);
            if (c == 0) return s;
            if (s.size() == max)
                fail(what + " is longer than " + num(static_cast<long long>(max)) + " characters");
            s += char(c);
        }
    }

  private:
    FILE* f_;
    long long size_, pos_ = 0;
    std::string where_;
};

// OpenEXR (image_headers.cpp): the header walked, every size checked against the file's length
// and the limits, before OpenImageIO (which believes them) reads it.
void check_exr_header(Reader& r);
// PNG (image_headers.cpp): every chunk's length fits in the file. Returns what its IHDR says
// and whether a tRNS chunk (transparency: OpenImageIO adds an alpha channel) is present.
struct PngLayout {
    long long width = 0, height = 0;
    int bit_depth = 0, color_type = -1, interlace = 0;
    bool trns = false;
};
PngLayout check_png_chunks(Reader& r);

// PNG read by libpng itself (image_png.cpp), only for the layouts where OpenImageIO's numbers
// are known to the bit (png_plain: grey or RGB, 8 or 16 bits, no transparency; every other PNG
// goes to OpenImageIO): no 0.4 s of loading OpenImageIO's libraries for the scans pxh ships.
bool png_plain(const PngLayout& p);
HeightField read_png_plain(FILE* f, const PngLayout& p, const std::string& where,
                           const std::string& name, int channel);

// Netpbm (image_netpbm.cpp): white space as its headers take it, and a PBM, PGM, PPM or PFM
// file read whole.
bool pnm_space(int c);
HeightField read_netpbm(Reader& r, const std::string& name, int channel);

// PNG, TIFF, OpenEXR, JPEG through OpenImageIO (image_oiio.cpp), from the file already opened
// and checked; `format` is OpenImageIO's name for it.
HeightField read_with_oiio(FILE* f, const char* format, const std::string& path,
                           const std::string& where, const std::string& name, int channel);

}  // namespace pxh::image_detail
