// The GL process's wire (harness/backends/gl_worker.h): every type that crosses the socket as
// one visit(A&, T&) that both writes (Out) and reads (In) it, a draw as it travels, and frames
// (a length, then the bytes) sent and received under a deadline.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/backends/glsl_backend.h"

namespace pxh::gl_wire {

// ---- The wire: one function per type, visit(A&, T&), both writes (Out) and reads (In) ----

class Out {
  public:
    std::string buf;
    void raw(const void* p, size_t n) { buf.append(static_cast<const char*>(p), n); }
    template <class T>
    void operator()(const T& v) {
        if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
            raw(&v, sizeof v);
        } else {
            visit(*this, const_cast<T&>(v));  // visit only reads through an Out
        }
    }
    void operator()(const std::string& s) {
        (*this)(uint64_t(s.size()));
        raw(s.data(), s.size());
    }
    template <class T>
    void operator()(const std::vector<T>& v) {
        (*this)(uint64_t(v.size()));
        if constexpr (std::is_trivially_copyable_v<T>) raw(v.data(), v.size() * sizeof(T));
        else
            for (const T& e : v) (*this)(e);
    }
    void operator()(const std::map<std::string, std::string>& m) {
        (*this)(uint64_t(m.size()));
        for (const auto& [k, v] : m) {
            (*this)(k);
            (*this)(v);
        }
    }
};

class In {
  public:
    explicit In(const std::string& s) : p_(s.data()), end_(s.data() + s.size()) {}
    void raw(void* d, size_t n) {
        if (size_t(end_ - p_) < n) throw std::runtime_error("GL process: a truncated message");
        if (n == 0) return;  // an empty vector's data() may be null: memcpy must not see it
        std::memcpy(d, p_, n);
        p_ += n;
    }
    template <class T>
    void operator()(T& v) {
        if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) raw(&v, sizeof v);
        else visit(*this, v);
    }
    size_t count(size_t element) {
        uint64_t n = 0;
        (*this)(n);
        if (element && n > size_t(end_ - p_) / element)
            throw std::runtime_error("GL process: a message with a bad length");
        return size_t(n);
    }
    void operator()(std::string& s) {
        s.resize(count(1));
        raw(s.data(), s.size());
    }
    template <class T>
    void operator()(std::vector<T>& v) {
        if constexpr (std::is_trivially_copyable_v<T>) {
            v.resize(count(sizeof(T)));
            raw(v.data(), v.size() * sizeof(T));
        } else {
            v.resize(count(1));
            for (T& e : v) (*this)(e);
        }
    }
    void operator()(std::map<std::string, std::string>& m) {
        const size_t n = count(2 * sizeof(uint64_t));
        for (size_t i = 0; i < n; ++i) {
            std::string k, v;
            (*this)(k);
            (*this)(v);
            m[k] = v;
        }
    }

  private:
    const char* p_;
    const char* end_;
};

static_assert(std::is_trivially_copyable_v<Vec2d> && std::is_trivially_copyable_v<Vec3d>);
static_assert(std::is_trivially_copyable_v<Footprint>);

template <class A>
void visit(A& a, Vec3d& v) {
    a(v.x), a(v.y), a(v.z);
}
template <class A>
void visit(A& a, Scene<double>& s) {
    a(s.scale), a(s.bias), a(s.V), a(s.width), a(s.height), a(s.curvature.x), a(s.curvature.y);
}
template <class A>
void visit(A& a, LightSpec& l) {
    a(l.theta_deg), a(l.phi_deg), a(l.layers_min), a(l.layers_max);
}
template <class A>
void visit(A& a, GlUniform& u) {
    a(u.name), a(u.type), a(u.value);
}
template <class A>
void visit(A& a, ResourceSpec& r) {  // what the GL side uses of it
    a(r.name), a(r.format), a(r.filter), a(r.wrap);
}
template <class A>
void visit(A& a, ResourceLevel& l) {
    a(l.width), a(l.height), a(l.texels);
}
template <class A>
void visit(A& a, HeightField& f) {  // what the GL side uses of it
    a(f.width), a(f.height), a(f.texels);
}
template <class A>
void visit(A& a, GlslMethod& m) {
    a(m.name), a(m.shader_file), a(m.has_builtin_text), a(m.builtin_text), a(m.declarations);
    a(m.plugin_shader), a(m.plugin_source), a(m.plugin_display), a(m.plugin_files);
    a(m.plugin_original), a(m.plugin_original_display);
    a(m.resources);
}

template <class A>
void visit(A& a, Spread& s) {
    a(s.median), a(s.min), a(s.max);
}
template <class A>
void visit(A& a, Timing& t) {
    a(t.unit), a(t.repeats), a(t.stats);
}
template <class A>
void visit(A& a, Counter& c) {  // a counter travels whole: a new one needs no line here
    a(c.name), a(c.value);
}
template <class A>
void visit(A& a, GlslDepth& d) {
    a(d.mode), a(d.hit), a(d.axis), a(d.span);
}
// Every field of MethodOutput, in one place: adding a field to it is one line here.
template <class A>
void visit(A& a, MethodOutput& o) {
    a(o.uv), a(o.fetches);
    a(o.shadow_hard), a(o.shadow_soft);
    a(o.timing), a(o.counters);
    a(o.shader), a(o.shader_sha256), a(o.samples_discarded);
    a(o.depth), a(o.depth_tol);
    a(o.hit_z), a(o.engine_z), a(o.depth_span), a(o.discarded);
    a(o.shaded);
}
// A MethodOutput that grew without a line above would come back from the child without the
// new field: update visit(MethodOutput) and then this size.
static_assert(sizeof(MethodOutput) == 424, "MethodOutput changed: update visit(MethodOutput)");

// A draw as it travels: the request owns what GlslDraw points to.
struct DrawData {
    GlslDraw d;
    HeightField hf;
    LightSpec light;
    MethodResources res;
    std::vector<Vec3d> V;
    std::vector<Vec2d> P;
    std::vector<uint8_t> inside;
    TextureLevels levels;
    std::vector<double> lambda;
    std::vector<Footprint> J;
    std::vector<Vec3d> axes;
    AlbedoLevels albedo;
};

enum : uint8_t { kDraw = 1, kCheck = 2 };

void write_draw(Out& o, const GlslDraw& d);
void read_draw(In& in, DrawData& x);

// What the GL process needs of the settings: its first message.
template <class A>
void visit(A& a, BackendSettings& s) {
    a(s.shader_dir), a(s.gl_frames), a(s.texture_formats), a(s.gl);
}

// ---- Frames: a length, then the bytes ----

bool send_frame(int fd, const std::string& payload);

enum class Got { frame, closed, timeout };

// Reads one frame; deadline_ms < 0: no deadline.
Got recv_frame(int fd, std::string& out, std::chrono::steady_clock::time_point deadline,
               bool has_deadline);

}  // namespace pxh::gl_wire
