// Height maps from image files. PNG, TIFF, OpenEXR and JPEG are read through OpenImageIO; the
// netpbm family (PGM, PPM, PBM and PFM) is read here. Nothing else is accepted.
//
// Every file is treated as possibly hostile. Before a reader sees it:
// - it must be a regular file (after following symlinks): a FIFO would block forever and
//   /dev/zero would be read forever;
// - its format is recognised from its first bytes, not its name;
// - the size it claims is checked against the limits in harness/scene/heightfield.h. OpenImageIO
//   reports the header of PNG, TIFF and JPEG without allocating pixels; OpenEXR believes the
//   sizes its header states (an attribute claiming 2 GB is allocated before the read fails),
//   so an OpenEXR header is walked here first, every size checked against the file's length.
// Pixels are read into a zero-filled field, and the reader's error state is checked after the
// read: a truncated TIFF or JPEG returns "success" with an error recorded. Alpha never scales
// the height. Netpbm files are read here because OpenImageIO went through 8 or 16 bits for
// other maxvals (5 of 10 read as 0.498), clamped samples above maxval, read maxval 0 as ones
// and a PFM scale of 0 as zeros.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

#include "harness/core/error.h"
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

// Error text from a library on one line: line breaks become "; " (InputError escapes any
// other control character), and at most 400 characters are kept (a reader can report one
// error per strip).
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

std::string num(long long v) { return std::to_string(v); }

// The size limits of harness/scene/heightfield.h for a W x H image of `channels` channels taking
// `pixel_bytes` bytes per pixel (all channels, as stored). `what` is "image" or "tile".
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

// ---- netpbm: PBM, PGM, PPM (plain P1-P3 and raw P4-P6) and PFM (Pf gray, PF colour) ----
// (netpbm.sourceforge.net/doc/pgm.html etc.; PFM: a text header "Pf"/"PF", width, height and
// a scale whose sign gives the byte order, then 32-bit floats, bottom row first.)

bool pnm_space(int c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// The next header token, after white space and # comments. The single white-space character
// that ends it is consumed too (netpbm: exactly one follows the last header field).
std::string pnm_token(Reader& r, const std::string& what) {
    for (int c = r.peek();; c = r.peek()) {
        if (c == '#') {
            while (c != '\n' && c != '\r' && c != EOF) c = r.get();
        } else if (pnm_space(c)) {
            r.get();
        } else {
            break;
        }
    }
    if (r.peek() == EOF) r.truncated("the header (" + what + ")");
    std::string t;
    for (int c = r.peek(); c != EOF && !pnm_space(c) && c != '#'; c = r.peek()) {
        if (t.size() == 40) r.fail(what + " in the header is too long");
        t += char(r.get());
    }
    if (pnm_space(r.peek())) r.get();
    return t;
}

// A header number: decimal digits, saturating far above every limit.
long long pnm_number(Reader& r, const std::string& what) {
    const std::string t = pnm_token(r, what);
    long long v = 0;
    for (char c : t) {
        if (c < '0' || c > '9') r.fail(what + " '" + t + "' is not a number");
        v = std::min(v * 10 + (c - '0'), 1ll << 40);
    }
    return v;
}

// Whole texels (i, j) of sample k in a W-wide image of `nch` channels, for messages.
std::string pnm_texel(long long k, long long w, int nch) {
    return "texel (" + num(k / nch % w) + ", " + num(k / nch / w) + ")";
}

// A netpbm/PFM header, read up to the raster.
struct PnmHeader {
    char kind = 0;  // the magic number's digit or f/F
    bool pfm = false, bitmap = false, plain = false;
    int nch = 1;  // channels
    long long w = 0, h = 0, maxval = 1, sample_bytes = 0;
    double scale = 1;  // PFM's
    long long samples() const { return w * h * nch; }
};

PnmHeader read_pnm_header(Reader& r) {
    PnmHeader p;
    char magic[2];
    r.read(magic, 2, "the magic number");
    p.kind = magic[1];
    const char kind = p.kind;
    p.pfm = kind == 'f' || kind == 'F';
    p.bitmap = kind == '1' || kind == '4';
    p.plain = kind == '1' || kind == '2' || kind == '3';
    p.nch = kind == '3' || kind == '6' || kind == 'F' ? 3 : 1;
    p.w = pnm_number(r, "width");
    p.h = pnm_number(r, "height");
    if (p.pfm) {
        const std::string t = pnm_token(r, "scale");
        char* end = nullptr;
        p.scale = std::strtod(t.c_str(), &end);
        if (end != t.c_str() + t.size() || !std::isfinite(p.scale) || p.scale == 0)
            r.fail("PFM scale '" + t + "' is not a finite non-zero number");
    } else if (!p.bitmap) {
        p.maxval = pnm_number(r, "maxval");
        if (p.maxval < 1 || p.maxval > 65535)
            r.fail("maxval " + num(p.maxval) + " is outside 1..65535");
    }
    p.sample_bytes = p.pfm ? 4 : p.bitmap ? 0 : p.maxval < 256 ? 1 : 2;
    return p;
}

// Each raster reader hands every sample k (row-major, channels interleaved) to store(k, v)
// (a template parameter: one call per sample, inlined).

// PFM: values are multiplied by |scale| (as OpenImageIO reads PFM); the first stored row (the
// bottom one in PFM's own convention) is j = 0.
template <class Store>
void read_pfm_raster(Reader& r, const PnmHeader& p, const Store& store) {
    const bool little = p.scale < 0;
    const float factor = float(std::fabs(p.scale));
    std::vector<unsigned char> row(size_t(p.w * p.nch * 4));
    for (long long j = 0; j < p.h; ++j) {
        r.read(row.data(), static_cast<long long>(row.size()), "pixel data");
        for (long long s = 0; s < p.w * p.nch; ++s) {
            const unsigned char* b = &row[size_t(s * 4)];
            uint32_t bits = 0;
            for (int q = 0; q < 4; ++q) bits |= uint32_t(b[little ? q : 3 - q]) << (8 * q);
            float v;
            std::memcpy(&v, &bits, 4);
            store(j * p.w * p.nch + s, v * factor);
        }
    }
}

// Raw bitmap: rows of (w + 7) / 8 bytes, most significant bit first; 1 is black (0).
template <class Store>
void read_raw_bitmap(Reader& r, const PnmHeader& p, const Store& store) {
    std::vector<unsigned char> row(size_t((p.w + 7) / 8));
    for (long long j = 0; j < p.h; ++j) {
        r.read(row.data(), static_cast<long long>(row.size()), "pixel data");
        for (long long i = 0; i < p.w; ++i)
            store(j * p.w + i, (row[size_t(i / 8)] >> (7 - i % 8)) & 1 ? 0.0f : 1.0f);
    }
}

// Raw gray or colour: 1 byte per sample, or 2 (big-endian) when maxval > 255.
template <class Store>
void read_raw_samples(Reader& r, const PnmHeader& p, const Store& store) {
    std::vector<unsigned char> row(size_t(p.w * p.nch * p.sample_bytes));
    for (long long j = 0; j < p.h; ++j) {
        r.read(row.data(), static_cast<long long>(row.size()), "pixel data");
        for (long long s = 0; s < p.w * p.nch; ++s) {
            const long long v = p.sample_bytes == 1
                                    ? row[size_t(s)]
                                    : row[size_t(2 * s)] << 8 | row[size_t(2 * s + 1)];
            const long long k = j * p.w * p.nch + s;
            if (v > p.maxval)
                r.fail("sample " + num(v) + " at " + pnm_texel(k, p.w, p.nch) +
                       " is above maxval " + num(p.maxval));
            store(k, float(v) / float(p.maxval));
        }
    }
}

// Plain (ASCII): decimal samples separated by white space; a plain bitmap's 0s and 1s need
// none.
template <class Store>
void read_plain_samples(Reader& r, const PnmHeader& p, const Store& store) {
    const long long samples = p.samples();
    for (long long k = 0; k < samples; ++k) {
        int c = r.get();
        while (pnm_space(c)) c = r.get();
        if (c == EOF)
            r.fail("truncated: " + num(k) + " of the " + num(samples) +
                   " samples the header promises");
        long long v = 0;
        if (p.kind == '1') {
            if (c != '0' && c != '1')
                r.fail("bitmap sample '" + std::string(1, char(c)) + "' at " +
                       pnm_texel(k, p.w, p.nch) + " is not 0 or 1");
            store(k, c == '1' ? 0.0f : 1.0f);
            continue;
        }
        std::string t;  // for messages, cut short
        bool digits = true;
        for (; c != EOF && !pnm_space(c); c = r.get()) {
            if (t.size() < 12) t += char(c);
            digits = digits && c >= '0' && c <= '9';
            if (digits) v = std::min(v * 10 + (c - '0'), 1ll << 40);  // digits only: no overflow
        }
        if (!digits)
            r.fail("sample '" + t + "' at " + pnm_texel(k, p.w, p.nch) + " is not a number");
        if (v > p.maxval)
            r.fail("sample " + t + " at " + pnm_texel(k, p.w, p.nch) + " is above maxval " +
                   num(p.maxval));
        store(k, float(v) / float(p.maxval));
    }
}

HeightField read_netpbm(Reader& r, const std::string& name, int channel) {
    const std::string where = r.where();
    const PnmHeader p = read_pnm_header(r);
    check_size(where, "image", p.w, p.h, p.nch, std::max(p.sample_bytes, 1ll) * p.nch);
    check_channel(where, channel, p.nch);
    const long long samples = p.samples();
    // Check the length before allocating anything: raw rasters have an exact size; a plain
    // sample takes at least one character, and all but a bitmap's need a separator.
    const long long raster = p.plain    ? (p.kind == '1' ? samples : 2 * samples - 1)
                             : p.bitmap ? (p.w + 7) / 8 * p.h
                                        : samples * p.sample_bytes;
    if (raster > r.left())
        r.fail("truncated: " + num(r.left()) + " bytes of pixel data, the header promises " +
               (p.plain ? "at least " : "") + num(raster));

    HeightField hf(int(p.w), int(p.h), name);
    const auto store = [&](long long k, float v) {
        if (k % p.nch == channel) hf.texels[size_t(k / p.nch)] = v;
    };
    if (p.pfm) read_pfm_raster(r, p, store);
    else if (p.kind == '4') read_raw_bitmap(r, p, store);
    else if (!p.plain) read_raw_samples(r, p, store);
    else read_plain_samples(r, p, store);
    return hf;
}

// PNG: every chunk's length must fit in the file before libpng sees it (libpng allocates what
// a tEXt/zTXt/iTXt/iCCP chunk's length claims: a 344-byte file claiming 2 GB made it allocate
// 2 GB; found by scripts/fuzz.sh, fuzz/corpus/image/png_text_chunk_length_2gb).
void check_png_chunks(Reader& r) {
    r.skip(8, "PNG signature");
    while (r.left() > 0) {
        unsigned char h[8];
        r.read(h, 8, "PNG chunk header");
        const unsigned long long len =
            (unsigned long long)h[0] << 24 | h[1] << 16 | h[2] << 8 | h[3];
        const std::string type(reinterpret_cast<const char*>(h + 4), 4);
        if (len > 0x7fffffffULL)
            r.fail("PNG chunk '" + one_line(type) + "' has an impossible length");
        r.skip((long long)len + 4,
               "PNG chunk '" + one_line(type) + "' (" + std::to_string(len) + " bytes)");
        if (type == "IEND") break;
    }
}

// ---- PNG, TIFF, OpenEXR, JPEG through OpenImageIO ----

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
            check_png_chunks(reader);
            hf = read_with_oiio(file.get(), "png", path, where, name, channel);
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

void save_heightfield_file(const HeightField& hf, const std::string& path) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw InputError(path, "cannot write this image format: " + flat(OIIO::geterror()));
    const std::string ext = std::filesystem::path(path).extension().string();
    const bool integer = ext == ".png" || ext == ".tif" || ext == ".tiff";
    OIIO::ImageSpec spec(hf.width, hf.height, 1,
                         integer ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::FLOAT);
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, hf.texels.data()) ||
        !out->close())
        throw InputError(path, "cannot write image: " + flat(out->geterror()));
}

}  // namespace pxh
