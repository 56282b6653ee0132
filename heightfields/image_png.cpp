// The plain PNG layouts read by libpng itself (heightfields/image_read.h, png_plain): grey or
// RGB, 8 or 16 bits a sample, no transparency, interlaced or not. Every other PNG (palette,
// alpha, tRNS, 1, 2 and 4 bits) is read by OpenImageIO, which adds or associates an alpha
// channel or expands a palette there. The floats are OpenImageIO's to the bit: the integer
// sample times 1 / 255 or 1 / 65535 in float, as its conversion to float computes it
// (tests/heightfields/png_plain_test.cpp compares the two readers on every 16-bit value and on
// every PNG pxh ships). No transform: no gamma, no sBIT, as OpenImageIO reads them.
//
// libpng reports errors by longjmp: the frame that calls setjmp (read_rows) holds no C++ object
// with a destructor, and the caller allocates every buffer before it.
#include <png.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include "heightfields/image_read.h"

namespace pxh::image_detail {

namespace {

struct PngError {
    char msg[320] = {};
};

[[noreturn]] void on_error(png_structp png, png_const_charp msg) {
    auto* e = static_cast<PngError*>(png_get_error_ptr(png));
    std::snprintf(e->msg, sizeof e->msg, "%s", msg ? msg : "libpng error");
    png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // a warning is not a failure (nor there)

// The whole image into `rows` (one pointer a row, each rowbytes long), after libpng's own
// reading of IHDR agrees with `p`; false with err->msg set otherwise.
bool read_rows(FILE* f, const PngLayout& p, png_bytep* rows, PngError* err) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, err, on_error, on_warning);
    if (!png) {
        std::snprintf(err->msg, sizeof err->msg, "libpng could not start (out of memory?)");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        std::snprintf(err->msg, sizeof err->msg, "libpng could not start (out of memory?)");
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_init_io(png, f);
    png_read_info(png, info);
    if (png_get_image_width(png, info) != png_uint_32(p.width) ||
        png_get_image_height(png, info) != png_uint_32(p.height) ||
        png_get_bit_depth(png, info) != p.bit_depth ||
        png_get_color_type(png, info) != p.color_type)
        png_error(png, "the header libpng read disagrees with the IHDR chunk");
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    if (p.bit_depth == 16) png_set_swap(png);  // PNG's big-endian samples to this machine's order
#endif
    (void)png_set_interlace_handling(png);
    png_read_update_info(png, info);
    png_read_image(png, rows);
    png_read_end(png, nullptr);  // the chunks after the pixels checked too (as OpenImageIO's)
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

}  // namespace

bool png_plain(const PngLayout& p) {
    return (p.color_type == PNG_COLOR_TYPE_GRAY || p.color_type == PNG_COLOR_TYPE_RGB) &&
           (p.bit_depth == 8 || p.bit_depth == 16) && !p.trns && p.interlace <= 1;
}

HeightField read_png_plain(FILE* f, const PngLayout& p, const std::string& where,
                           const std::string& name, int channel) {
    const int channels = p.color_type == PNG_COLOR_TYPE_RGB ? 3 : 1;
    const int bytes = p.bit_depth / 8;
    check_size(where, "image", p.width, p.height, channels, (long long)channels * bytes);
    check_channel(where, channel, channels);
    const size_t w = size_t(p.width), h = size_t(p.height);
    const size_t rowbytes = w * size_t(channels * bytes);
    std::vector<unsigned char> px(rowbytes * h);
    std::vector<png_bytep> rows(h);
    for (size_t j = 0; j < h; ++j) rows[j] = px.data() + j * rowbytes;
    if (std::fseek(f, 0, SEEK_SET) != 0) throw InputError(where, "cannot read pixels: seek failed");
    PngError err;
    if (!read_rows(f, p, rows.data(), &err))
        throw InputError(where, "cannot read pixels (truncated or corrupt?): " + flat(err.msg));
    HeightField hf(int(w), int(h), name);
    const size_t stride = size_t(channels);
    if (bytes == 1) {
        constexpr float k = 1.0f / 255.0f;
        for (size_t i = 0; i < w * h; ++i)
            hf.texels[i] = float(px[i * stride + size_t(channel)]) * k;
    } else {
        constexpr float k = 1.0f / 65535.0f;
        for (size_t i = 0; i < w * h; ++i) {
            uint16_t v;
            std::memcpy(&v, px.data() + 2 * (i * stride + size_t(channel)), 2);
            hf.texels[i] = float(v) * k;
        }
    }
    return hf;
}

}  // namespace pxh::image_detail
