// Headers walked before OpenImageIO sees the file: an OpenEXR header (every attribute and the
// chunk offset tables checked against the file's length and the size limits: OpenEXR believes
// the sizes its header states) and a PNG's chunk lengths (libpng allocates what they claim).
#include <algorithm>

#include "heightfields/image_read.h"

namespace pxh::image_detail {
namespace {

// ---- OpenEXR header (openexr.com, "OpenEXR File Layout") ----
// magic 76 2f 31 01, a version word (2, plus flags), then per part attributes
// name\0 type\0 size(int32 LE) value, ended by an empty name; multi-part files end the list
// of headers with one more empty name. The chunk offset tables follow: 8 bytes per chunk.

struct ExrPart {
    bool has_window = false, has_channels = false, tiled = false;
    long long w = 0, h = 0, channels = 0, pixel_bytes = 0;
    int compression = -1;
    long long tile_w = 0, tile_h = 0, chunk_count = -1;
};

// Lines per chunk of each OpenEXR compression (none, rle, zips, zip, piz, pxr24, b44, b44a,
// dwaa, dwab).
constexpr int kExrLinesPerChunk[10] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};

void exr_expect(Reader& r, const std::string& name, const std::string& type, long long size,
                const char* want_type, long long want_size) {
    if (type != want_type || (want_size >= 0 && size != want_size))
        r.fail("OpenEXR attribute '" + name + "' is " + type + " of " + num(size) +
               " bytes, expected " + want_type +
               (want_size >= 0 ? " of " + num(want_size) + " bytes" : std::string()));
}

// One attribute's value; `size` is known to fit in the file.
void exr_attribute(Reader& r, ExrPart& p, const std::string& name, const std::string& type,
                   long long size) {
    const std::string what = "OpenEXR attribute '" + name + "'";
    if (name == "dataWindow") {
        exr_expect(r, name, type, size, "box2i", 16);
        const long long x0 = r.i32le(what), y0 = r.i32le(what), x1 = r.i32le(what),
                        y1 = r.i32le(what);
        p.w = x1 - x0 + 1;
        p.h = y1 - y0 + 1;
        p.has_window = true;
    } else if (name == "channels") {
        exr_expect(r, name, type, size, "chlist", -1);
        // Each channel: name\0, pixel type (int32), pLinear + 3 reserved bytes, x and y
        // sampling (int32 each); an empty name ends the list.
        p.has_channels = true;
        const long long end = r.left() - size;
        for (;;) {
            if (r.left() <= end) r.fail(what + " has no end");
            const std::string ch = r.cstring(255, what);
            if (ch.empty()) break;
            if (++p.channels > kMaxImageChannels)
                r.fail("image has more than the accepted " + num(kMaxImageChannels) + " channels");
            const int32_t type_code = r.i32le(what);
            if (type_code < 0 || type_code > 2)
                r.fail("OpenEXR channel '" + ch + "' has unknown pixel type " + num(type_code));
            p.pixel_bytes += type_code == 1 ? 2 : 4;  // half: 2 bytes; uint, float: 4
            r.skip(4, what);
            const int32_t xs = r.i32le(what), ys = r.i32le(what);
            if (xs != 1 || ys != 1)
                r.fail("OpenEXR channel '" + ch + "' is subsampled (" + num(xs) + " x " + num(ys) +
                       "); subsampled channels are not supported");
        }
        if (r.left() != end) r.fail(what + " does not match its stated size");
    } else if (name == "compression") {
        exr_expect(r, name, type, size, "compression", 1);
        p.compression = r.get();
        if (p.compression < 0 || p.compression > 9)
            r.fail("unknown OpenEXR compression " + num(p.compression));
    } else if (name == "tiles") {
        exr_expect(r, name, type, size, "tiledesc", 9);
        p.tile_w = r.u32le(what);
        p.tile_h = r.u32le(what);
        r.skip(1, what);
    } else if (name == "chunkCount") {
        exr_expect(r, name, type, size, "int", 4);
        p.chunk_count = r.i32le(what);
        if (p.chunk_count < 0) r.fail(what + " is negative");
    } else if (name == "type") {
        exr_expect(r, name, type, size, "string", -1);
        if (size > 32) r.fail(what + " is not a known image type");
        std::string t(size_t(size), '\0');
        r.read(t.data(), size, what);
        if (t == "deepscanline" || t == "deeptile") r.fail("deep OpenEXR data is not a height map");
        p.tiled = t == "tiledimage";
    } else if (type == "preview") {
        // width, height (uint32 each), then width * height RGBA bytes: OpenEXR allocates from
        // the width and height alone.
        if (size < 8) r.fail(what + " is shorter than its header");
        const uint64_t pw = r.u32le(what), ph = r.u32le(what);  // the product fits in 64 bits
        if ((size - 8) % 4 != 0 || pw * ph != uint64_t(size - 8) / 4)
            r.fail(what + " claims a " + std::to_string(pw) + " x " + std::to_string(ph) +
                   " preview in " + num(size) + " bytes");
        r.skip(size - 8, what);
    } else if (type == "stringvector") {
        // Strings as int32 length + characters: OpenEXR allocates each length it reads.
        long long rest = size;
        while (rest > 0) {
            if (rest < 4) r.fail(what + " does not match its stated size");
            const long long n = r.i32le(what);
            rest -= 4;
            if (n < 0 || n > rest) r.fail(what + " holds a string longer than the attribute");
            r.skip(n, what);
            rest -= n;
        }
    } else {
        r.skip(size, what);  // any other attribute: its size is all OpenEXR allocates
    }
}

// OpenEXR keeps every attribute in memory (about a hundred bytes of bookkeeping each): a
// real header has tens, the limit is far above them and far below a memory problem.
constexpr int kMaxExrAttributes = 10000;

// Reads one part's header; false when it is the empty header ending a multi-part list.
// `attributes` counts the attributes of all parts so far.
bool exr_header(Reader& r, ExrPart& p, bool single_part_tiled, int& attributes) {
    p.tiled = single_part_tiled;
    for (int count = 0;; ++count) {
        const std::string name = r.cstring(255, "an OpenEXR attribute name");
        if (name.empty()) return count > 0;
        if (++attributes > kMaxExrAttributes)
            r.fail("OpenEXR header has more than " + num(kMaxExrAttributes) + " attributes");
        const std::string type = r.cstring(255, "the type of OpenEXR attribute '" + name + "'");
        const long long size = r.i32le("the size of OpenEXR attribute '" + name + "'");
        if (size < 0 || size > r.left())
            r.fail("OpenEXR attribute '" + name + "' claims " + num(size) +
                   " bytes, more than the file holds (" + num(r.left()) + " left)");
        exr_attribute(r, p, name, type, size);
    }
}

}  // namespace

void check_exr_header(Reader& r) {
    r.skip(4, "the OpenEXR magic number");
    const uint32_t version = r.u32le("the OpenEXR version");
    if ((version & 0xff) != 2)
        r.fail("OpenEXR version " + num(version & 0xff) + " is not supported");
    const uint32_t flags = version & ~0xffu;
    if (flags & ~0x1e00u) r.fail("unknown OpenEXR version flags " + num(flags));
    if (flags & 0x800) r.fail("deep OpenEXR data is not a height map");
    const bool multipart = flags & 0x1000;
    long long chunks = 0;
    int attributes = 0;
    for (int part = 0;; ++part) {
        ExrPart p;
        if (!exr_header(r, p, (flags & 0x200) != 0, attributes)) {
            if (part == 0 || !multipart) r.fail("OpenEXR header has no attributes");
            break;
        }
        if (!p.has_window || !p.has_channels || p.compression < 0)
            r.fail("OpenEXR header lacks dataWindow, channels or compression");
        check_size(r.where(), "image", p.w, p.h, p.channels, p.pixel_bytes);
        long long part_chunks;
        if (p.tiled) {
            check_size(r.where(), "tile", p.tile_w, p.tile_h, p.channels, p.pixel_bytes);
            part_chunks = ((p.w + p.tile_w - 1) / p.tile_w) * ((p.h + p.tile_h - 1) / p.tile_h);
        } else {
            const int lines = kExrLinesPerChunk[p.compression];
            part_chunks = (p.h + lines - 1) / lines;
        }
        chunks += std::max(part_chunks, p.chunk_count);
        if (chunks > r.left()) break;  // refused below; stop before the sum can overflow
        if (!multipart) break;
    }
    // OpenEXR allocates every part's offset table (8 bytes per chunk; tiled files with
    // mipmaps hold more) before reading it.
    if (chunks * 8 > r.left())
        r.fail("OpenEXR chunk offset table (" + num(chunks) + " entries) " +
               "runs past the end of the file (truncated or corrupt)");
}

// PNG: every chunk's length must fit in the file before libpng sees it (libpng allocates what
// a tEXt/zTXt/iTXt/iCCP chunk's length claims: a 344-byte file claiming 2 GB made it allocate
// 2 GB; found by scripts/fuzz.sh, fuzz/corpus/image/png_text_chunk_length_2gb).
PngLayout check_png_chunks(Reader& r) {
    PngLayout p;
    r.skip(8, "PNG signature");
    bool first = true;
    while (r.left() > 0) {
        unsigned char h[8];
        r.read(h, 8, "PNG chunk header");
        const unsigned long long len =
            (unsigned long long)h[0] << 24 | h[1] << 16 | h[2] << 8 | h[3];
        const std::string type(reinterpret_cast<const char*>(h + 4), 4);
        if (len > 0x7fffffffULL)
            r.fail("PNG chunk '" + one_line(type) + "' has an impossible length");
        const std::string what =
            "PNG chunk '" + one_line(type) + "' (" + std::to_string(len) + " bytes)";
        if (first && type == "IHDR" && len == 13) {  // the layout; its CRC is libpng's to check
            unsigned char d[13];
            r.read(d, 13, what);
            auto be32 = [&](int o) {
                return (long long)d[o] << 24 | (long long)d[o + 1] << 16 |
                       (long long)d[o + 2] << 8 | (long long)d[o + 3];
            };
            p.width = be32(0);
            p.height = be32(4);
            p.bit_depth = d[8];
            p.color_type = d[9];
            p.interlace = d[12];
            r.skip(4, what);
        } else {
            r.skip((long long)len + 4, what);
        }
        first = false;
        if (type == "tRNS") p.trns = true;
        if (type == "IEND") break;
    }
    return p;
}

}  // namespace pxh::image_detail
