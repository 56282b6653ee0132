#include "heightfields/scan_io.h"

#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "harness/core/error.h"

namespace pxh {
namespace {

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "cannot open");
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

uint32_t u32(const std::string& s, size_t at) {
    uint32_t v;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}
uint16_t u16(const std::string& s, size_t at) {
    uint16_t v;
    std::memcpy(&v, s.data() + at, 2);
    return v;
}

std::string inflate_raw(const std::string& in, size_t expected, const std::string& where) {
    std::string out(expected, '\0');
    z_stream zs{};
    if (inflateInit2(&zs, -MAX_WBITS) != Z_OK) throw InputError(where, "zlib init failed");
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    zs.avail_in = uInt(in.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = uInt(out.size());
    const int rc = inflate(&zs, Z_FINISH);
    inflateEnd(&zs);
    if (rc != Z_STREAM_END || zs.total_out != expected)
        throw InputError(where, "corrupt deflate data");
    return out;
}

NpyArray parse_npy(const std::string& d, const std::string& where) {
    if (d.size() < 10 || d.compare(0, 6, "\x93NUMPY") != 0)
        throw InputError(where, "not an .npy array");
    const int major = (unsigned char)d[6];
    const size_t hlen = major == 1 ? u16(d, 8) : u32(d, 8);
    const size_t hstart = major == 1 ? 10 : 12;
    if (hstart + hlen > d.size()) throw InputError(where, "truncated .npy header");
    const std::string header = d.substr(hstart, hlen);
    auto field = [&](const std::string& key) {
        const auto p = header.find("'" + key + "'");
        if (p == std::string::npos) throw InputError(where, "npy header lacks " + key);
        return header.substr(header.find(':', p) + 1);
    };
    std::string descr = field("descr");
    descr = descr.substr(descr.find('\'') + 1);
    descr = descr.substr(0, descr.find('\''));
    if (field("fortran_order").find("True") < field("fortran_order").find(','))
        throw InputError(where, "Fortran-order arrays are not supported");
    std::string shape = field("shape");
    shape = shape.substr(shape.find('(') + 1, shape.find(')') - shape.find('(') - 1);
    NpyArray a;
    size_t count = 1;
    std::stringstream ss(shape);
    for (std::string tok; std::getline(ss, tok, ',');) {
        if (tok.find_first_of("0123456789") == std::string::npos) continue;
        a.shape.push_back(std::stoull(tok));
        count *= a.shape.back();
    }
    const char* p = d.data() + hstart + hlen;
    const size_t avail = d.size() - hstart - hlen;
    auto need = [&](size_t bytes) {
        if (avail < count * bytes) throw InputError(where, "truncated .npy data");
    };
    a.values.resize(count);
    if (descr == "<f8") {
        need(8);
        for (size_t i = 0; i < count; ++i) {
            double v;
            std::memcpy(&v, p + 8 * i, 8);
            a.values[i] = v;
        }
    } else if (descr == "<f4") {
        need(4);
        for (size_t i = 0; i < count; ++i) {
            float v;
            std::memcpy(&v, p + 4 * i, 4);
            a.values[i] = v;
        }
    } else if (descr == "<i2") {
        need(2);
        for (size_t i = 0; i < count; ++i) {
            int16_t v;
            std::memcpy(&v, p + 2 * i, 2);
            a.values[i] = v;
        }
    } else if (descr == "<i4") {
        need(4);
        for (size_t i = 0; i < count; ++i) {
            int32_t v;
            std::memcpy(&v, p + 4 * i, 4);
            a.values[i] = v;
        }
    } else if (descr == "|u1") {
        need(1);
        for (size_t i = 0; i < count; ++i) a.values[i] = (unsigned char)p[i];
    } else throw InputError(where, "unsupported dtype " + descr);
    return a;
}

}  // namespace

NpyArray read_npz_array(const std::string& path, const std::string& member) {
    const std::string z = slurp(path);
    // Walk the local file headers (PK\3\4).
    size_t at = 0;
    while (at + 30 <= z.size() && u32(z, at) == 0x04034b50) {
        const uint16_t method = u16(z, at + 8), flags = u16(z, at + 6);
        uint32_t csize = u32(z, at + 18), usize = u32(z, at + 22);
        const uint16_t nlen = u16(z, at + 26), xlen = u16(z, at + 28);
        const std::string name = z.substr(at + 30, nlen);
        size_t data = at + 30 + nlen + xlen;
        // ZIP64 sizes live in the extra field (numpy writes them for large members).
        if (csize == 0xFFFFFFFFu || usize == 0xFFFFFFFFu) {
            size_t x = at + 30 + nlen;
            while (x + 4 <= at + 30 + nlen + xlen) {
                const uint16_t id = u16(z, x), sz = u16(z, x + 2);
                if (id == 1 && sz >= 16) {
                    uint64_t u, c;
                    std::memcpy(&u, z.data() + x + 4, 8);
                    std::memcpy(&c, z.data() + x + 12, 8);
                    usize = uint32_t(u);
                    csize = uint32_t(c);
                }
                x += 4 + sz;
            }
        }
        if (flags & 8) throw InputError(path, "zip data descriptors are not supported");
        if (data + csize > z.size()) throw InputError(path, "truncated archive");
        if (name == member) {
            const std::string raw = z.substr(data, csize);
            if (method == 0) return parse_npy(raw, path + ":" + member);
            if (method == 8) return parse_npy(inflate_raw(raw, usize, path), path + ":" + member);
            throw InputError(path, "unsupported zip compression method " + std::to_string(method));
        }
        at = data + csize;
    }
    throw InputError(path, "no member '" + member + "'");
}

std::vector<std::array<double, 3>> read_ply_points(const std::string& path) {
    const std::string d = slurp(path);
    const size_t end = d.find("end_header\n");
    if (d.compare(0, 3, "ply") != 0 || end == std::string::npos)
        throw InputError(path, "not a PLY file");
    std::stringstream hs(d.substr(0, end));
    std::string line, format;
    size_t count = 0;
    bool in_vertex = false;
    struct Prop {
        std::string name, type;
    };
    std::vector<Prop> props;
    while (std::getline(hs, line)) {
        std::stringstream ls(line);
        std::string kw;
        ls >> kw;
        if (kw == "format") ls >> format;
        else if (kw == "element") {
            std::string el;
            ls >> el;
            in_vertex = el == "vertex";
            if (in_vertex) ls >> count;
            else if (count == 0)
                throw InputError(path, "elements before 'vertex' are not supported");
        } else if (kw == "property" && in_vertex) {
            Prop p;
            ls >> p.type;
            if (p.type == "list") throw InputError(path, "list properties on vertices");
            ls >> p.name;
            props.push_back(p);
        }
    }
    auto size_of = [&](const std::string& t) -> size_t {
        if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
        if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
        if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
            t == "float32")
            return 4;
        if (t == "double" || t == "float64") return 8;
        throw InputError(path, "unknown PLY type " + t);
    };
    int ix = -1, iy = -1, iz = -1;
    for (size_t i = 0; i < props.size(); ++i) {
        if (props[i].name == "x") ix = int(i);
        if (props[i].name == "y") iy = int(i);
        if (props[i].name == "z") iz = int(i);
    }
    if (ix < 0 || iy < 0 || iz < 0) throw InputError(path, "vertices lack x, y, z");
    std::vector<std::array<double, 3>> pts(count);
    const size_t body = end + 11;
    if (format == "ascii") {
        std::stringstream bs(d.substr(body));
        for (size_t v = 0; v < count; ++v) {
            std::vector<double> vals(props.size());
            for (auto& x : vals)
                if (!(bs >> x)) throw InputError(path, "truncated ASCII vertex data");
            pts[v] = {vals[size_t(ix)], vals[size_t(iy)], vals[size_t(iz)]};
        }
    } else if (format == "binary_little_endian") {
        size_t stride = 0;
        std::vector<size_t> off;
        for (const auto& p : props) {
            off.push_back(stride);
            stride += size_of(p.type);
        }
        if (body + count * stride > d.size())
            throw InputError(path, "truncated binary vertex data");
        auto read = [&](size_t v, int i) {
            const char* q = d.data() + body + v * stride + off[size_t(i)];
            if (props[size_t(i)].type == "double" || props[size_t(i)].type == "float64") {
                double x;
                std::memcpy(&x, q, 8);
                return x;
            }
            if (props[size_t(i)].type == "float" || props[size_t(i)].type == "float32") {
                float x;
                std::memcpy(&x, q, 4);
                return double(x);
            }
            throw InputError(path, "coordinates must be float or double");
        };
        for (size_t v = 0; v < count; ++v) pts[v] = {read(v, ix), read(v, iy), read(v, iz)};
    } else {
        throw InputError(path, "unsupported PLY format '" + format + "'");
    }
    return pts;
}

Mesh read_off(const std::string& path) {
    std::ifstream f(path);
    if (!f) throw InputError(path, "cannot open");
    std::string magic;
    f >> magic;
    if (magic != "OFF") throw InputError(path, "not an OFF file");
    size_t nv = 0, nf = 0, ne = 0;
    if (!(f >> nv >> nf >> ne)) throw InputError(path, "bad OFF counts");
    Mesh m;
    m.vertices.resize(nv);
    for (auto& v : m.vertices)
        if (!(f >> v[0] >> v[1] >> v[2])) throw InputError(path, "truncated vertices");
    for (size_t i = 0; i < nf; ++i) {
        size_t k;
        if (!(f >> k) || k < 3) throw InputError(path, "bad face");
        std::vector<unsigned> idx(k);
        for (auto& x : idx)
            if (!(f >> x) || x >= nv) throw InputError(path, "bad face index");
        for (size_t t = 1; t + 1 < k; ++t) m.triangles.push_back({idx[0], idx[t], idx[t + 1]});
        std::string rest;
        std::getline(f, rest);  // optional colour
    }
    return m;
}

namespace {

// Bytes of s at `at`, in the file's byte order (big = most significant first).
uint64_t uint_at(const std::string& s, size_t at, int bytes, bool big) {
    uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) {
        const uint64_t b = (unsigned char)s[at + size_t(big ? k : bytes - 1 - k)];
        v = (v << 8) | b;
    }
    return v;
}

double double_at(const std::string& s, size_t at, bool big) {
    const uint64_t u = uint_at(s, at, 8, big);
    double d;
    std::memcpy(&d, &u, 8);
    return d;
}

}  // namespace

GtxGrid read_gtx(const std::string& path) {
    const std::string d = slurp(path);
    if (d.size() < 40) throw InputError(path, "shorter than a .gtx header (40 bytes)");
    GtxGrid g;
    g.lat0 = double_at(d, 0, true);
    g.lon0 = double_at(d, 8, true);
    g.dlat = double_at(d, 16, true);
    g.dlon = double_at(d, 24, true);
    g.rows = int32_t(uint32_t(uint_at(d, 32, 4, true)));
    g.cols = int32_t(uint32_t(uint_at(d, 36, 4, true)));
    if (g.rows <= 0 || g.cols <= 0 || g.rows > 65536 || g.cols > 65536)
        throw InputError(path, ".gtx header claims " + std::to_string(g.rows) + " x " +
                                   std::to_string(g.cols) + " values");
    const size_t n = size_t(g.rows) * size_t(g.cols);
    if (d.size() != 40 + 4 * n)
        throw InputError(path, ".gtx is " + std::to_string(d.size()) + " bytes, its header " +
                                   "needs " + std::to_string(40 + 4 * n));
    g.values.resize(n);
    for (size_t k = 0; k < n; ++k) {
        const uint32_t u = uint32_t(uint_at(d, 40 + 4 * k, 4, true));
        float f;
        std::memcpy(&f, &u, 4);
        g.values[k] = f;
    }
    return g;
}

TiffTag read_tiff_tag(const std::string& path, int tag) {
    const std::string d = slurp(path);
    if (d.size() < 8 || !(d.compare(0, 4, "II*\0", 4) == 0 || d.compare(0, 4, "MM\0*", 4) == 0))
        throw InputError(path, "not a (classic) TIFF file");
    const bool big = d[0] == 'M';
    const size_t ifd = uint_at(d, 4, 4, big);
    if (ifd + 2 > d.size()) throw InputError(path, "TIFF IFD beyond the end of the file");
    const size_t entries = uint_at(d, ifd, 2, big);
    if (ifd + 2 + 12 * entries > d.size()) throw InputError(path, "truncated TIFF IFD");
    TiffTag t;
    for (size_t e = 0; e < entries; ++e) {
        const size_t at = ifd + 2 + 12 * e;
        if (int(uint_at(d, at, 2, big)) != tag) continue;
        const int type = int(uint_at(d, at + 2, 2, big));
        const size_t count = uint_at(d, at + 4, 4, big);
        // Sizes of TIFF types 1..12 (0: unsupported here).
        static const int kSize[13] = {0, 1, 1, 2, 4, 0, 1, 1, 2, 4, 0, 0, 8};
        const int size = type >= 1 && type <= 12 ? kSize[type] : 0;
        if (size == 0)
            throw InputError(path, "TIFF tag " + std::to_string(tag) + " has type " +
                                       std::to_string(type) + " (not read here)");
        const size_t bytes = size_t(size) * count;
        const size_t data = bytes <= 4 ? at + 8 : uint_at(d, at + 8, 4, big);
        if (count > d.size() || data + bytes > d.size())
            throw InputError(path, "TIFF tag " + std::to_string(tag) + " beyond the file");
        t.found = true;
        if (type == 2) {
            t.ascii = d.substr(data, bytes);
            while (!t.ascii.empty() && t.ascii.back() == '\0') t.ascii.pop_back();
            return t;
        }
        for (size_t k = 0; k < count; ++k) {
            const size_t p = data + size_t(size) * k;
            if (type == 12) t.values.push_back(double_at(d, p, big));
            else if (type == 6) t.values.push_back(double(int8_t(uint_at(d, p, 1, big))));
            else if (type == 8) t.values.push_back(double(int16_t(uint_at(d, p, 2, big))));
            else if (type == 9) t.values.push_back(double(int32_t(uint_at(d, p, 4, big))));
            else t.values.push_back(double(uint_at(d, p, size, big)));
        }
        return t;
    }
    return t;
}

}  // namespace pxh
