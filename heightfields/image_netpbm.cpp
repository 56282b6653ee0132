// Netpbm files read here (not through OpenImageIO, which went through 8 or 16 bits for other
// maxvals, clamped samples above maxval, read maxval 0 as ones and a PFM scale of 0 as zeros):
// the header, then the raster (plain or raw, bitmap, gray, colour or PFM floats), every length
// checked against the file before anything is allocated.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "heightfields/image_read.h"

namespace pxh::image_detail {

// ---- netpbm: PBM, PGM, PPM (plain P1-P3 and raw P4-P6) and PFM (Pf gray, PF colour) ----
// (netpbm.sourceforge.net/doc/pgm.html etc.; PFM: a text header "Pf"/"PF", width, height and
// a scale whose sign gives the byte order, then 32-bit floats, bottom row first.)

bool pnm_space(int c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

namespace {

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

}  // namespace

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

}  // namespace pxh::image_detail
