// The GL process's wire: a draw written and read back (what GlslDraw points to travels with
// it), and frames sent and received over the socket (harness/backends/gl_wire.h).
#include "harness/backends/gl_wire.h"

#include <poll.h>
#include <sys/socket.h>

#include <cerrno>

namespace pxh::gl_wire {

void write_draw(Out& o, const GlslDraw& d) {
    o(uint8_t(kDraw));
    o(d.method), o(d.uniforms), o(d.scene);
    o(d.hf->width), o(d.hf->height), o(d.hf->texels);
    o(d.samples), o(d.texture_format), o(d.frames);
    o(bool(d.light));
    if (d.light) o(*d.light);
    o(bool(d.resources));
    if (d.resources) {
        o(uint64_t(d.resources->items.size()));
        for (const BuiltResource& r : d.resources->items) o(r.image->levels);
    }
    o(bool(d.V));
    if (d.V) o(*d.V);
    o(bool(d.P));
    if (d.P) o(*d.P);
    o(bool(d.inside));
    if (d.inside) o(*d.inside);
    o(d.lod);
    o(d.depth);
    o(bool(d.levels));
    if (d.levels) o(d.levels->levels);
    o(bool(d.lambda));
    if (d.lambda) o(*d.lambda);
    o(bool(d.J));
    if (d.J) o(*d.J);
    o(bool(d.axes));
    if (d.axes) o(*d.axes);
    o(bool(d.albedo));
    if (d.albedo) {
        o(d.albedo->width), o(d.albedo->height);
        for (const TextureLevels& c : d.albedo->channel) o(c.levels);
        o(d.light_dir);
    }
}

void read_draw(In& in, DrawData& x) {
    GlslDraw& d = x.d;
    in(d.method), in(d.uniforms), in(d.scene);
    in(x.hf.width), in(x.hf.height), in(x.hf.texels);
    d.hf = &x.hf;
    in(d.samples), in(d.texture_format), in(d.frames);
    bool has = false;
    in(has);
    if (has) {
        in(x.light);
        d.light = &x.light;
    }
    in(has);
    if (has) {
        const size_t n = in.count(sizeof(uint64_t));
        if (n != d.method.resources.size())
            throw std::runtime_error("GL process: resources do not match the method's");
        for (size_t k = 0; k < n; ++k) {
            auto img = std::make_shared<ResourceImage>();
            in(img->levels);
            x.res.items.push_back({&d.method.resources[k], img, 0, 0});
        }
        d.resources = &x.res;
    }
    in(has);
    if (has) {
        in(x.V);
        d.V = &x.V;
    }
    in(has);
    if (has) {
        in(x.P);
        d.P = &x.P;
    }
    in(has);
    if (has) {
        in(x.inside);
        d.inside = &x.inside;
    }
    in(d.lod);
    in(d.depth);
    in(has);
    if (has) {
        in(x.levels.levels);
        d.levels = &x.levels;
    }
    in(has);
    if (has) {
        in(x.lambda);
        d.lambda = &x.lambda;
    }
    in(has);
    if (has) {
        in(x.J);
        d.J = &x.J;
    }
    in(has);
    if (has) {
        in(x.axes);
        d.axes = &x.axes;
    }
    in(has);
    if (has) {
        in(x.albedo.width), in(x.albedo.height);
        for (TextureLevels& c : x.albedo.channel) in(c.levels);
        in(d.light_dir);
        d.albedo = &x.albedo;
    }
}

namespace {

bool send_all(int fd, const char* p, size_t n) {
    while (n > 0) {
        const ssize_t w = ::send(fd, p, n, MSG_NOSIGNAL);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= size_t(w);
    }
    return true;
}

}  // namespace

bool send_frame(int fd, const std::string& payload) {
    const uint64_t n = payload.size();
    return send_all(fd, reinterpret_cast<const char*>(&n), sizeof n) &&
           send_all(fd, payload.data(), payload.size());
}

Got recv_frame(int fd, std::string& out, std::chrono::steady_clock::time_point deadline,
               bool has_deadline) {
    auto read_n = [&](char* p, size_t n) -> Got {
        while (n > 0) {
            if (has_deadline) {
                const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                                      deadline - std::chrono::steady_clock::now())
                                      .count();
                if (left <= 0) return Got::timeout;
                pollfd pfd{fd, POLLIN, 0};
                const int r = ::poll(&pfd, 1, int(std::min<long long>(left, 1 << 30)));
                if (r < 0 && errno == EINTR) continue;
                if (r == 0) return Got::timeout;
                if (r < 0) return Got::closed;
            }
            const ssize_t got = ::recv(fd, p, n, 0);
            if (got < 0 && errno == EINTR) continue;
            if (got <= 0) return Got::closed;
            p += got;
            n -= size_t(got);
        }
        return Got::frame;
    };
    uint64_t n = 0;
    if (const Got g = read_n(reinterpret_cast<char*>(&n), sizeof n); g != Got::frame) return g;
    if (n > (uint64_t(1) << 40)) return Got::closed;
    out.resize(size_t(n));
    return read_n(out.data(), out.size());
}

}  // namespace pxh::gl_wire
