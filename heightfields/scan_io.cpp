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

}  // namespace pxh
