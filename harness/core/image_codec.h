// Image files through OpenImageIO, loaded on first use. Debian's OpenImageIO brings about 260
// shared libraries (OpenCV, GDCM, FFmpeg, ...) whose loading and relocation took half a second of
// every pxh process's start, also of the runs, tools and GL workers that read or write no image.
// So pxh does not link it: every call to OpenImageIO lives in the module libpxh_images.so
// (harness/core/image_codec_oiio.cpp), which image_codec() loads with dlopen the first time an
// image is read or written, from the folder of the running binary or, installed, from
// ../lib/pxh beside it. The interface passes plain data only: no exception and no OpenImageIO
// type crosses it, so the module holds no pxh code.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace pxh {

// What an image file says of itself (OpenImageIO's ImageSpec, in plain fields).
struct ImageFileInfo {
    int width = 0, height = 0, channels = 0;
    int depth = 1;  // > 1: a volume
    bool deep = false;
    int tile_width = 0, tile_height = 0;  // 0: scanlines
    size_t pixel_bytes = 0;               // bytes of one pixel, all channels, as stored
    bool floating = false;                // the stored type is a floating-point one
    std::string type;                     // the stored type: "uint8", "int16", "float", ...
};

struct ImageReader;  // an open image file (the module's)

// The module's functions. Each reports failure by returning false (or nullptr) with `why` set to
// OpenImageIO's message on one line; none throws.
struct ImageCodec {
    // The file already opened (and checked) as `f`, read through a proxy as `format` ("png",
    // "tiff", "openexr", "jpeg"), its channels as stored (no association with alpha); the
    // image libraries' own messages on stderr are silenced while it is read.
    ImageReader* (*open_file)(FILE* f, const char* format, const std::string& path,
                              ImageFileInfo& info, std::string& why);
    // A file by its name.
    ImageReader* (*open_path)(const std::string& path, ImageFileInfo& info, std::string& why);
    // Channels [first, end) of the whole image into dst, as float (integer types scaled to
    // [0, 1]) or, with `as_stored`, in the file's own type; false where the reader failed or
    // recorded an error (a truncated file).
    bool (*read)(ImageReader* r, int first, int end, bool as_stored, void* dst, std::string& why);
    // Closes and frees it; false where closing recorded an error.
    bool (*close)(ImageReader* r, std::string& why);
    // W x H pixels of `channels` channels (float, row-major, channels interleaved) written to the
    // file `path` in the format of its extension, stored as `type` ("uint8", "uint16", "float").
    bool (*write_file)(const std::string& path, int width, int height, int channels,
                       const char* type, const float* px, std::string& why);
    // The same image encoded in memory (the format of `path`'s extension) into `bytes`.
    bool (*encode)(const std::string& path, int width, int height, int channels, const char* type,
                   const float* px, std::string& bytes, std::string& why);
    // `text` drawn at (x, y) (the baseline's left end) in `font` at `size` pixels, colour `rgb`
    // (0..1), onto W x H pixels of 3 float channels.
    bool (*render_text)(std::vector<float>& px, int width, int height, int x, int y,
                        const std::string& text, int size, const std::string& font,
                        const float rgb[3], std::string& why);
};

// The module's entry point, `pxh_image_codec` (C linkage): its codec.
using ImageCodecEntry = const ImageCodec* (*)();

// The codec, loaded on first use (thread-safe). A module that cannot be found or loaded is a
// std::runtime_error naming the paths tried and dlopen's reason.
const ImageCodec& image_codec();

// Whole images, for callers that want every channel as float: its info and pixels.
struct ImagePixels {
    ImageFileInfo info;
    std::vector<float> px;  // width x height x channels
};
// Reads `path` whole (as float); false with `why` on failure (nothing thrown): "holds no
// pixels", "is larger than MAX_SIDE pixels a side" (before any pixel is read) or the reader's.
bool read_image_pixels(const std::string& path, ImagePixels& out, std::string& why,
                       int max_side = 16384);

}  // namespace pxh
