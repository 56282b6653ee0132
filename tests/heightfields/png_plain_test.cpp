// The plain PNG layouts read by libpng (heightfields/image_png.cpp) give OpenImageIO's floats to
// the bit: every 16-bit value, every 8-bit value in each RGB channel, an interlaced file, and
// every PNG pxh ships; the other layouts still go to OpenImageIO; a corrupt stream is one line
// naming the file.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "heightfields/image_read.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
    const fs::path d = fs::temp_directory_path() / ("pxh_png_plain_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

// Channel `c` of the file as OpenImageIO reads it to float (what pxh read before the libpng
// path, and still reads for every other layout).
std::vector<float> oiio_channel(const std::string& path, int c, int& w, int& h) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    const OIIO::ImageSpec& s = in->spec();
    w = s.width;
    h = s.height;
    std::vector<float> px(size_t(w) * size_t(h));
    EXPECT_TRUE(in->read_image(0, 0, c, c + 1, OIIO::TypeDesc::FLOAT, px.data()));
    in->close();
    return px;
}

// A PNG written by libpng: `channels` 1 or 3, 8 or 16 bits, interlaced (Adam7) or not.
void write_png(const std::string& path, int w, int h, int channels, int depth, bool interlace,
               const std::vector<uint16_t>& samples) {
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), depth,
                 channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const size_t row = size_t(w) * size_t(channels) * size_t(depth / 8);
    std::vector<unsigned char> bytes(row * size_t(h));
    for (size_t i = 0; i < samples.size(); ++i) {
        if (depth == 8) {
            bytes[i] = static_cast<unsigned char>(samples[i]);
        } else {  // big-endian, as PNG stores it
            bytes[2 * i] = static_cast<unsigned char>(samples[i] >> 8);
            bytes[2 * i + 1] = static_cast<unsigned char>(samples[i] & 0xff);
        }
    }
    std::vector<png_bytep> rows(static_cast<size_t>(h));
    for (int j = 0; j < h; ++j) rows[size_t(j)] = bytes.data() + size_t(j) * row;
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
}

image_detail::PngLayout layout_of(const std::string& path) {
    FILE* f = std::fopen(path.c_str(), "rb");
    EXPECT_NE(f, nullptr);
    std::fseek(f, 0, SEEK_END);
    const long size = std::ftell(f);
    std::rewind(f);
    image_detail::Reader r(f, size, path);
    const image_detail::PngLayout p = image_detail::check_png_chunks(r);
    std::fclose(f);
    return p;
}

void expect_same_bits(const std::string& path, int channel) {
    int w = 0, h = 0;
    const std::vector<float> want = oiio_channel(path, channel, w, h);
    const HeightField got = load_heightfield_file(path, channel);
    ASSERT_EQ(got.width, w);
    ASSERT_EQ(got.height, h);
    size_t apart = 0, first = 0;
    for (size_t i = 0; i < want.size(); ++i)
        if (std::memcmp(&want[i], &got.texels[i], sizeof(float)) != 0 && apart++ == 0) first = i;
    EXPECT_EQ(apart, 0u) << path << " channel " << channel << ": first at " << first << ", "
                         << got.texels[first] << " vs OpenImageIO " << want[first];
}

TEST(PngPlain, EverySixteenBitValueAsOpenImageIoReadsIt) {
    const fs::path d = temp_dir();
    std::vector<uint16_t> all(65536);
    for (size_t i = 0; i < all.size(); ++i) all[i] = uint16_t(i);
    const std::string grey = (d / "all16.png").string();
    write_png(grey, 256, 256, 1, 16, false, all);
    ASSERT_TRUE(image_detail::png_plain(layout_of(grey)));
    expect_same_bits(grey, 0);
    // interlaced: the same values through Adam7's passes
    const std::string adam = (d / "all16_adam7.png").string();
    write_png(adam, 256, 256, 1, 16, true, all);
    EXPECT_EQ(layout_of(adam).interlace, 1);
    expect_same_bits(adam, 0);
    fs::remove_all(d);
}

TEST(PngPlain, EveryEightBitValueInEachRgbChannel) {
    const fs::path d = temp_dir();
    std::vector<uint16_t> rgb(256 * 3 * 3);  // 256 x 3 pixels: each channel walks 0..255
    for (size_t p = 0; p < 256 * 3; ++p)
        for (size_t c = 0; c < 3; ++c) rgb[p * 3 + c] = uint16_t((p * (c + 1) + 17 * c) % 256);
    const std::string path = (d / "rgb8.png").string();
    write_png(path, 256, 3, 3, 8, false, rgb);
    ASSERT_TRUE(image_detail::png_plain(layout_of(path)));
    for (int c = 0; c < 3; ++c) expect_same_bits(path, c);
    std::vector<uint16_t> rgb16(5 * 4 * 3);
    for (size_t i = 0; i < rgb16.size(); ++i) rgb16[i] = uint16_t(i * 4099 % 65536);
    const std::string p16 = (d / "rgb16_adam7.png").string();
    write_png(p16, 5, 4, 3, 16, true, rgb16);
    for (int c = 0; c < 3; ++c) expect_same_bits(p16, c);
    fs::remove_all(d);
}

TEST(PngPlain, EveryShippedPngReadsAsOpenImageIoReadsIt) {
    int plain = 0;
    for (const auto& e :
         fs::directory_iterator(std::string(PXH_SOURCE_DIR) + "/heightfields/scanned")) {
        if (e.path().extension() != ".png") continue;
        plain += image_detail::png_plain(layout_of(e.path().string()));
        expect_same_bits(e.path().string(), 0);
    }
    EXPECT_GE(plain, 10);  // the scans and their masks take the libpng path
}

TEST(PngPlain, OtherLayoutsGoToOpenImageIo) {
    image_detail::PngLayout p;
    p.bit_depth = 16;
    p.color_type = PNG_COLOR_TYPE_GRAY;
    EXPECT_TRUE(image_detail::png_plain(p));
    p.trns = true;  // transparency: OpenImageIO adds an alpha channel
    EXPECT_FALSE(image_detail::png_plain(p));
    p.trns = false;
    for (int ct : {PNG_COLOR_TYPE_PALETTE, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB_ALPHA}) {
        p.color_type = ct;
        EXPECT_FALSE(image_detail::png_plain(p)) << ct;
    }
    p.color_type = PNG_COLOR_TYPE_GRAY;
    for (int depth : {1, 2, 4}) {
        p.bit_depth = depth;
        EXPECT_FALSE(image_detail::png_plain(p)) << depth;
    }
}

TEST(PngPlain, ACorruptStreamIsOneLineNamingTheFile) {
    const fs::path d = temp_dir();
    std::vector<uint16_t> v(64 * 64);
    for (size_t i = 0; i < v.size(); ++i) v[i] = uint16_t(i * 37);
    const std::string good = (d / "good.png").string();
    write_png(good, 64, 64, 1, 16, false, v);
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const size_t idat = bytes.find("IDAT");
    ASSERT_NE(idat, std::string::npos);
    bytes[idat + 4 + 10] ^= 0x5a;  // inside the compressed data: the chunk's CRC no longer holds
    const std::string bad = (d / "bad.png").string();
    std::ofstream(bad, std::ios::binary) << bytes;
    try {
        (void)load_heightfield_file(bad);
        ADD_FAILURE() << "a corrupt PNG was read";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("bad.png"), std::string::npos) << msg;
        EXPECT_NE(msg.find("cannot read pixels"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
    fs::remove_all(d);
}

}  // namespace
}  // namespace pxh
